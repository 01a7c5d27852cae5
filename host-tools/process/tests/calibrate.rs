//! Channel calibration (issue #19, part 4) against the truth the simulator drew: the seeded
//! board's channel errors are recovered from its corner-reflector capture, and the Q15
//! correction the range stage applies makes the array coherent on another capture of the same
//! board.

use metamoran_bundle::RadarFile;
use metamoran_bundle::calibration::{CalibrationFile, ChannelId};
use metamoran_dsp::capture::IqOrder;
use metamoran_dsp::config::SPEED_OF_LIGHT;
use metamoran_process::calibrate::{CalibrateError, CalibrateOptions, ChannelMeans, calibrate};
use metamoran_sim::layout::{CORNER_RANGE_M, Preset};
use metamoran_sim::radar::RadarKind;
use metamoran_sim::signal::ChannelErrors;
use metamoran_sim::{Difficulty, Variant, simulate_scene_with};
use std::io::Write;

const BOARD: u64 = 5;

/// A corner capture of `board` (None: a perfect one) on `kind`, as a file.
fn corner(kind: RadarKind, board: Option<u64>, seed: u64) -> (RadarFile, tempfile::NamedTempFile) {
    let variant = Variant {
        difficulty: Difficulty::Standard,
        board,
        renumber: false,
    };
    let s = simulate_scene_with(Preset::Corner, kind, variant, seed, 0);
    let mut tmp = tempfile::NamedTempFile::new().unwrap();
    tmp.write_all(&s.adc).unwrap();
    let file = RadarFile::open(tmp.path(), s.radar, IqOrder::Iiqq).unwrap();
    (file, tmp)
}

fn wrap_deg(x: f64) -> f64 {
    (x + 180.0).rem_euclid(360.0) - 180.0
}

#[test]
fn calibration_recovers_the_boards_drawn_errors() {
    let (mut file, _tmp) = corner(RadarKind::Cascade, Some(BOARD), 1);
    let config = file.config().clone();
    let means = ChannelMeans::read(&mut file, true).unwrap();
    let m = calibrate(&means, CalibrateOptions::default()).unwrap();
    assert!(
        (m.file.target_range_m - CORNER_RANGE_M).abs() < 0.05,
        "{}",
        m.file.target_range_m
    );
    let truth = ChannelErrors::draw(
        BOARD,
        config.tx_positions.len(),
        config.rx_count(),
        metamoran_sim::board_bin_m(RadarKind::Cascade),
    );
    // A range offset of ΔR is 2·S·ΔR/c Hz of beat frequency: ΔR / bin bins of this chirp.
    let bin_m = SPEED_OF_LIGHT * config.sample_rate_hz
        / (2.0 * config.slope_hz_per_s * f64::from(config.adc_samples));
    let (g_ref, d_ref) = truth.get(0, 0).unwrap();
    assert_eq!(m.file.channels.len(), 192);
    let (mut worst_deg, mut worst_db, mut worst_bins) = (0f64, 0f64, 0f64);
    for c in &m.file.channels {
        let (g, d) = truth.get(c.tx, c.rx).unwrap();
        // Expected: gain g_ref / g, frequency (ΔR_ref − ΔR) / bin.
        let want_phase = (g_ref.1.atan2(g_ref.0) - g.1.atan2(g.0)).to_degrees();
        let want_db = 20.0 * (g_ref.0.hypot(g_ref.1) / g.0.hypot(g.1)).log10();
        let got_phase = c.gain[1].atan2(c.gain[0]).to_degrees();
        let got_db = 20.0 * c.gain[0].hypot(c.gain[1]).log10();
        worst_deg = worst_deg.max(wrap_deg(got_phase - want_phase).abs());
        worst_db = worst_db.max((got_db - want_db).abs());
        worst_bins = worst_bins.max((c.frequency_bins - (d_ref - d) / bin_m).abs());
    }
    // The ground clutter and the noise are all that separate them.
    assert!(worst_deg < 3.0, "phase off by {worst_deg:.2}°");
    assert!(worst_db < 0.3, "gain off by {worst_db:.3} dB");
    assert!(worst_bins < 0.03, "frequency off by {worst_bins:.4} bins");
    assert!(m.coherence_before < 0.3, "{}", m.coherence_before);
    assert!(m.coherence_after > 0.99, "{}", m.coherence_after);
}

#[test]
fn the_q15_correction_makes_another_capture_of_the_board_coherent() {
    let (mut cal_file, _a) = corner(RadarKind::Cascade, Some(BOARD), 1);
    let means = ChannelMeans::read(&mut cal_file, true).unwrap();
    let m = calibrate(&means, CalibrateOptions::default()).unwrap();
    // Round trip through the file a bundle names.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cal.toml");
    std::fs::write(&path, m.file.to_toml()).unwrap();
    let file = CalibrationFile::read(&path).unwrap();
    assert_eq!(file, m.file);
    // Another capture: other noise, another reflector phase.
    let (mut other, _b) = corner(RadarKind::Cascade, Some(BOARD), 2);
    let config = other.config().clone();
    let raw = ChannelMeans::read(&mut other, true).unwrap();
    other.calibrate(&file.for_config(&path, &config).unwrap());
    // Calibrated by the range stage's Q15 code, measured with no calibration in f64.
    let calibrated = ChannelMeans::read(&mut other, false).unwrap();
    let peak = m.peak_bin;
    let before = raw.coherence(peak, None);
    let after = calibrated.coherence(peak, None);
    assert!(before < 0.3, "{before}");
    assert!(after > 0.99, "{after}");
    // The same figure as the f64 definition of the correction on the raw capture.
    let defined = raw.coherence(peak, Some(&file));
    assert!((after - defined).abs() < 2e-3, "{after} vs {defined}");
}

#[test]
fn a_perfect_board_calibrates_to_the_identity() {
    let (mut file, _t) = corner(RadarKind::Xwr18xx, None, 3);
    let means = ChannelMeans::read(&mut file, true).unwrap();
    let m = calibrate(&means, CalibrateOptions::default()).unwrap();
    for c in &m.file.channels {
        assert!(
            (c.gain[0] - 1.0).abs() < 0.02 && c.gain[1].abs() < 0.02,
            "{c:?}"
        );
        assert!(c.frequency_bins.abs() < 0.01, "{c:?}");
    }
    assert!(m.coherence_before > 0.99);
}

#[test]
fn bad_requests_are_named() {
    let (mut file, _t) = corner(RadarKind::Xwr18xx, Some(BOARD), 3);
    let means = ChannelMeans::read(&mut file, true).unwrap();
    let off = CalibrateOptions {
        reference: ChannelId { tx: 0, rx: 4 },
        target_m: None,
    };
    assert!(matches!(
        calibrate(&means, off),
        Err(CalibrateError::Reference { rx: 4, rxs: 4, .. })
    ));
    let beyond = CalibrateOptions {
        target_m: Some(1e4),
        ..CalibrateOptions::default()
    };
    let e = calibrate(&means, beyond).unwrap_err();
    assert!(matches!(e, CalibrateError::Window { .. }));
    assert!(e.to_string().contains("--target-m"), "{e}");
    // A reference elsewhere: gains are relative to it.
    let other = CalibrateOptions {
        reference: ChannelId { tx: 1, rx: 2 },
        target_m: Some(CORNER_RANGE_M),
    };
    let m = calibrate(&means, other).unwrap();
    let r = m
        .file
        .channels
        .iter()
        .find(|c| c.tx == 1 && c.rx == 2)
        .unwrap();
    assert_eq!((r.gain, r.frequency_bins), ([1.0, 0.0], 0.0));
}

#[test]
fn a_calibration_holds_on_a_chirp_of_another_slope() {
    // Calibrated on the corner preset's 21.5 m chirp ...
    let (mut cal_file, _a) = corner(RadarKind::Cascade, Some(BOARD), 1);
    let m = calibrate(
        &ChannelMeans::read(&mut cal_file, true).unwrap(),
        CalibrateOptions::default(),
    )
    .unwrap();
    // ... applied to a reflector seen with the parking lot's 59.4 m chirp (a third of the slope):
    // the board's delays are the same metres, so a third of the bins.
    let config = metamoran_sim::radar::config(RadarKind::Cascade, 59.4, 2);
    let errors = ChannelErrors::draw(
        BOARD,
        config.tx_positions.len(),
        config.rx_count(),
        metamoran_sim::board_bin_m(RadarKind::Cascade),
    );
    let echo = metamoran_sim::signal::Echo {
        range: 23.7,
        sin_az: 0.0,
        sin_el: 0.0,
        velocity: 0.0,
        amplitude: 400.0,
        phase: 1.1,
    };
    let mut rng = <rand_pcg::Pcg64Mcg as rand::SeedableRng>::seed_from_u64(8);
    let bytes = metamoran_sim::signal::synthesize(&config, &[echo], &[], Some(&errors), &mut rng);
    let mut tmp = tempfile::NamedTempFile::new().unwrap();
    tmp.write_all(&bytes).unwrap();
    let mut file = RadarFile::open(tmp.path(), config.clone(), IqOrder::Iiqq).unwrap();
    let raw = ChannelMeans::read(&mut file, true).unwrap();
    let path = std::path::Path::new("board5.toml");
    file.calibrate(&m.file.for_config(path, &config).unwrap());
    let calibrated = ChannelMeans::read(&mut file, false).unwrap();
    let bin = raw.reflector_bin(Some(23.7)).unwrap() as f64;
    let (before, after) = (raw.coherence(bin, None), calibrated.coherence(bin, None));
    assert!(before < 0.3, "{before}");
    assert!(after > 0.99, "{after}");
    // Without the rescaling (the corner chirp's bins taken as this chirp's) it is worse.
    let wrong = raw.coherence(bin, Some(&m.file));
    assert!(wrong < after - 0.01, "{wrong} vs {after}");
}
