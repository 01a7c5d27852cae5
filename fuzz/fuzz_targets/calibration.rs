//! Calibration files: our TOML (first byte even), checked against an MMWCAS-sized board, and
//! TI's MAT-file results (odd), imported for it. Either an `InputError` or a calibration that
//! covers the board.
#![no_main]
use libfuzzer_sys::fuzz_target;
use metamoran_bundle::calibration::{CalibrationFile, TiCalibration};
use metamoran_bundle::ti::Board;
use metamoran_dsp::config::RadarConfig;
use std::path::Path;

fn board() -> RadarConfig {
    let mut c = RadarConfig {
        start_frequency_hz: 77e9,
        slope_hz_per_s: 30e12,
        sample_rate_hz: 10e6,
        adc_samples: 64,
        chirp_period_s: 20e-6,
        chirps_per_tx: 2,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: heapless::Vec::new(),
        rx_positions: heapless::Vec::new(),
        tx_order: heapless::Vec::new(),
    };
    for (id, p) in [11i16, 10, 9, 32, 28, 24, 20, 16, 12, 8, 4, 0]
        .into_iter()
        .enumerate()
    {
        let _ = c.tx_positions.push(p);
        let _ = c.tx_order.push(id as u8);
    }
    for p in [
        50i16, 51, 52, 53, 0, 1, 2, 3, 46, 47, 48, 49, 11, 12, 13, 14,
    ] {
        let _ = c.rx_positions.push(p);
    }
    c
}

fuzz_target!(|bytes: &[u8]| {
    let Some((&kind, rest)) = bytes.split_first() else {
        return;
    };
    let config = board();
    let path = Path::new("cal");
    let file = if kind & 1 == 0 {
        let Ok(text) = std::str::from_utf8(rest) else {
            return;
        };
        CalibrationFile::parse(path, text)
    } else {
        TiCalibration::parse(path, rest)
            .and_then(|t| t.to_file(path, &config, Board::MmwcasRfEvm, 5.0))
    };
    if let Ok(f) = file {
        if let Ok(cal) = f.for_config(path, &config) {
            assert_eq!(cal.size(), (12, 16));
            let _ = cal.normalized();
        }
    }
});
