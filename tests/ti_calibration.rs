//! `metamoran calibrate --import-ti` against TI's own formulas: SciPy writes a cascade
//! calibration file (`calibrateResults*.mat`, compressed and not), NumPy computes the
//! corrections `calibration_cascade.m` derives from it (`oracles/ti_calibration.py`), and the
//! imported calibration, applied to a capture of another chirp, must give the same per-sample
//! phase steps and gains.

use metamoran_bundle::calibration::TiCalibration;
use metamoran_bundle::ti::Board;
use metamoran_dsp::trig::Phase;
use metamoran_e2e::run_oracle;
use metamoran_sim::radar::{RadarKind, config};
use std::ffi::OsStr;

#[derive(serde::Deserialize)]
struct Expected {
    steps: Vec<f64>,
    gains: Vec<[f64; 2]>,
}

#[test]
fn imported_ti_calibration_matches_calibration_cascade_m() {
    // The simulator's MMWCAS board: TX in TI's chirp order (our TX t is TI's TX ID 12 − t), RX
    // in device order (TI's column r).
    let c = config(RadarKind::Mmwcas, 59.4, 2);
    let tx_ref = 12 - usize::from(c.tx_order[0]);
    for compress in ["0", "1"] {
        let dir = tempfile::tempdir().unwrap();
        let mat = dir.path().join("calibrateResults_test.mat");
        let numbers = [
            c.adc_samples.to_string(),
            c.sample_rate_hz.to_string(),
            c.slope_hz_per_s.to_string(),
            "5".to_owned(),
            tx_ref.to_string(),
        ];
        let mut args = vec![mat.as_os_str(), OsStr::new(compress)];
        args.extend(numbers.iter().map(OsStr::new));
        let Some(out) = run_oracle("ti_calibration.py", &args, "scipy") else {
            return;
        };
        let want: Expected = serde_json::from_slice(&out).unwrap();
        let ti = TiCalibration::read(&mat).unwrap();
        let file = ti.to_file(&mat, &c, Board::MmwcasRfEvm, 5.0).unwrap();
        let cal = file.for_config(&mat, &c).unwrap();
        for t in 0..12 {
            for r in 0..16 {
                let k = (11 - t) * 16 + r;
                let got = cal.get(t, r).unwrap();
                // Our step is f/N turns per sample; TI's is an angle per sample.
                let want_turns = want.steps[k] / std::f64::consts::TAU;
                let off = got.step.0.wrapping_sub(Phase::from_turns(want_turns).0) as i32;
                assert!(
                    off.abs() <= 4,
                    "compress {compress}, TX {t}, RX {r}: step {:?} vs {want_turns} turns",
                    got.step
                );
                let (g, w) = (got.gain, want.gains[k]);
                let err = (g.0 - w[0]).hypot(g.1 - w[1]) / w[0].hypot(w[1]);
                assert!(
                    err < 1e-9,
                    "compress {compress}, TX {t}, RX {r}: {g:?} vs {w:?}"
                );
            }
        }
        assert_eq!(
            (file.reference.tx, file.reference.rx),
            (usize::from(c.tx_order[0]), 0)
        );
    }
}

#[test]
fn a_file_that_is_no_ti_calibration_names_itself() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.mat");
    std::fs::write(&path, b"MATLAB 5.0 MAT-file").unwrap();
    let e = TiCalibration::read(&path).unwrap_err().to_string();
    assert!(e.contains("x.mat") && e.contains("128-byte"), "{e}");
    let mut header = vec![b' '; 128];
    header[126..].copy_from_slice(b"IM");
    // One miMATRIX element whose size runs past the end.
    header.extend_from_slice(&14u32.to_le_bytes());
    header.extend_from_slice(&4096u32.to_le_bytes());
    std::fs::write(&path, &header).unwrap();
    let e = TiCalibration::read(&path).unwrap_err().to_string();
    assert!(e.contains("runs past the end"), "{e}");
    header.truncate(128);
    std::fs::write(&path, &header).unwrap();
    let e = TiCalibration::read(&path).unwrap_err().to_string();
    assert!(e.contains("calibResult") && e.contains("missing"), "{e}");
}
