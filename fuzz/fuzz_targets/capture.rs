//! A bare capture: a radar config (TOML), a NUL byte, an IQ-order byte (odd: QQII) and a `.bin`
//! of any size. Either the sizes disagree (an `InputError`) or every frame the config promises
//! reads back whole.
#![no_main]
use libfuzzer_sys::fuzz_target;
use metamoran_bundle::RadarFile;
use metamoran_bundle::capture::parse_radar_config;
use metamoran_dsp::capture::IqOrder;
use std::path::{Path, PathBuf};

fn bin_path() -> PathBuf {
    std::env::temp_dir().join(format!("metamoran-fuzz-capture-{}.bin", std::process::id()))
}

fuzz_target!(|bytes: &[u8]| {
    let Some(nul) = bytes.iter().position(|&b| b == 0) else {
        return;
    };
    let (Ok(toml), Some((&flag, bin))) = (
        std::str::from_utf8(&bytes[..nul]),
        bytes[nul + 1..].split_first(),
    ) else {
        return;
    };
    let Ok(config) = parse_radar_config(Path::new("radar.toml"), toml) else {
        return;
    };
    let path = bin_path();
    if std::fs::write(&path, bin).is_err() {
        return;
    }
    let order = if flag & 1 == 1 {
        IqOrder::Qqii
    } else {
        IqOrder::Iiqq
    };
    if let Ok(mut file) = RadarFile::open(&path, config, order) {
        let (frames, per_frame) = (file.config().frames, file.config().samples_per_frame());
        assert_eq!(frames as usize * per_frame * 4, bin.len());
        let mut out = Vec::new();
        for f in 0..frames {
            file.read_frame(f, &mut out).unwrap();
            assert_eq!(out.len(), per_frame);
        }
        assert!(file.read_frame(frames, &mut out).is_err());
    }
});
