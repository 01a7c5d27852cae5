//! The module's calibrated range stage (`Edge::calibrate`, `push_calibrated`): chirps of a
//! board with per-channel gain, phase and delay errors, calibrated as they are summed, give the
//! spectra of a perfect board (f64 synthesis), as the host's per-sample calibration
//! (`AppliedCalibration::apply`) followed by the plain range stage does; without calibration
//! they do not.

use metamoran_dsp::config::{RadarConfig, SPEED_OF_LIGHT};
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::pipeline::{ChannelCoefficients, Edge, MAX_CALIBRATED_CHIRPS};
use metamoran_dsp::range::calibration::{AppliedCalibration, Calibration, Correction};
use std::f64::consts::PI;

const N: usize = 256;
const BIN_M: f64 = 0.1;

/// 2 TX × 4 RX at positions 0..8, 64 samples, 0.1 m bins, `loops` loops.
fn config(loops: u16) -> RadarConfig {
    let fs = 10.0e6;
    RadarConfig {
        start_frequency_hz: 77.0e9,
        slope_hz_per_s: SPEED_OF_LIGHT * fs / (2.0 * BIN_M * N as f64),
        sample_rate_hz: fs,
        adc_samples: N as u16,
        chirp_period_s: 10.0e-6,
        chirps_per_tx: loops,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: heapless::Vec::from_slice(&[0, 4]).unwrap(),
        rx_positions: heapless::Vec::from_slice(&[0, 1, 2, 3]).unwrap(),
        tx_order: heapless::Vec::from_slice(&[0, 1]).unwrap(),
    }
}

/// Channel `ch`'s error: gain (≤ 1, channel 0 exactly 1), phase, and a delay as bins.
fn error(ch: usize) -> (f64, f64, f64) {
    let k = ch as f64;
    (
        if ch == 0 { 1.0 } else { 0.55 + 0.05 * k },
        2.4 * k - 3.0,
        0.45 * ((1.3 * k).sin()),
    )
}

/// One chirp of channel `ch` at element position `p` from (range m, sin az, amplitude)
/// reflectors, through the channel's error when `board`.
fn chirp(points: &[(f64, f64, f64)], ch: usize, p: f64, board: bool) -> Vec<CQ15> {
    let (g, phase, bins) = if board { error(ch) } else { (1.0, 0.0, 0.0) };
    (0..N)
        .map(|n| {
            let (mut re, mut im) = (0.0, 0.0);
            for &(r, s, a) in points {
                let ph = 2.0 * PI * (r / BIN_M + bins) * n as f64 / N as f64 + PI * p * s + phase;
                re += g * a * ph.cos();
                im += g * a * ph.sin();
            }
            CQ15::from_raw(re.round() as i16, im.round() as i16)
        })
        .collect()
}

/// The calibration that undoes [`error`]: gain 1/g, phase −φ, frequency −bins.
fn calibration() -> AppliedCalibration {
    let mut cal = Calibration::identity(2, 4).unwrap();
    for ch in 0..8 {
        let (g, phase, bins) = error(ch);
        let gain = (phase.cos() / g, -phase.sin() / g);
        cal.set(ch / 4, ch % 4, Correction::from_f64(gain, -bins, N as u16))
            .unwrap();
    }
    cal.normalized()
}

/// How a frame is formed.
#[derive(Clone, Copy, PartialEq)]
enum Route {
    /// A perfect board, plain range stage.
    Perfect,
    /// The board as recorded, plain range stage.
    Recorded,
    /// The board, calibrated per sample on the host, then the plain range stage.
    HostCalibrated,
    /// The board, calibrated as the module sums (block coefficients).
    ModuleCalibrated,
}

/// Every element's spectrum in input LSB (complex f64, element-major) and the strongest peak's
/// (bin, az).
fn spectra(route: Route, loops: u16) -> (Vec<(f64, f64)>, (u16, u16)) {
    let cfg = config(loops);
    let edge = Edge::new(&cfg).unwrap();
    let points = [(2.34, 0.21, 9000.0), (4.1, -0.4, 2500.0)];
    let applied = calibration();
    let mut table = vec![0u32; edge.calibration_words()];
    let coefficients: ChannelCoefficients<'_> = edge.calibrate(&applied, &mut table).unwrap();
    let mut arena = vec![0u32; edge.arena_words()];
    let mut frame = if route == Route::ModuleCalibrated {
        edge.start_calibrated(&mut arena, &coefficients).unwrap()
    } else {
        edge.start(&mut arena).unwrap()
    };
    for chirp_no in 0..cfg.chirps_per_frame() {
        for rx in 0..4 {
            let ch = (chirp_no % 2) * 4 + rx;
            let p = f64::from(cfg.channel_position(ch).unwrap());
            let x = chirp(&points, ch, p, route != Route::Perfect);
            match route {
                Route::Perfect | Route::Recorded => edge.push(&mut frame, chirp_no, rx, &x),
                Route::HostCalibrated => {
                    let mut y = vec![CQ15::default(); N];
                    applied.apply(ch / 4, rx, &x, &mut y).unwrap();
                    edge.push(&mut frame, chirp_no, rx, &y)
                }
                Route::ModuleCalibrated => {
                    edge.push_calibrated(&mut frame, chirp_no, rx, &x, &coefficients)
                }
            }
            .unwrap();
        }
    }
    let (mut row, mut az, mut pw) = (
        vec![CQ15::default(); edge.fft_len()],
        vec![CQ15::default(); edge.azimuth_len()],
        vec![0u64; 3 * edge.azimuth_len()],
    );
    let scene = edge.finish(frame, &mut row, &mut az, &mut pw).unwrap();
    let scale = 2f64.powi(scene.spectra.exponent());
    let mut out = Vec::new();
    for e in 0..edge.array().elements() {
        for k in 0..edge.fft_len() {
            let z = scene.spectra.get(e, k);
            out.push((f64::from(z.re.0) * scale, f64::from(z.im.0) * scale));
        }
    }
    (out, (scene.peaks[0].bin, scene.peaks[0].az))
}

/// The largest difference between two spectra relative to the first's peak.
fn relative_error(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    let peak = a.iter().map(|z| z.0.hypot(z.1)).fold(0.0, f64::max);
    let worst = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x.0 - y.0).hypot(x.1 - y.1))
        .fold(0.0, f64::max);
    worst / peak
}

#[test]
fn the_modules_calibrated_sums_give_the_perfect_boards_spectra() {
    let (perfect, peak) = spectra(Route::Perfect, 2);
    let (recorded, recorded_peak) = spectra(Route::Recorded, 2);
    let (host, host_peak) = spectra(Route::HostCalibrated, 2);
    let (module, module_peak) = spectra(Route::ModuleCalibrated, 2);
    // The calibration's gains are divided by the largest (1/0.6): the calibrated spectra are
    // the perfect ones times 0.6.
    let scaled: Vec<_> = perfect.iter().map(|z| (0.6 * z.0, 0.6 * z.1)).collect();
    let (e_host, e_module, e_raw) = (
        relative_error(&scaled, &host),
        relative_error(&scaled, &module),
        relative_error(&scaled, &recorded),
    );
    // Block coefficients: the phase within a 16-sample block is off by up to π·0.45·16/256.
    assert!(e_host < 0.01, "host per-sample calibration off by {e_host}");
    assert!(
        e_module < 0.05,
        "module block calibration off by {e_module}"
    );
    assert!(e_raw > 0.5, "the recorded board must be broken: {e_raw}");
    assert_eq!(host_peak, peak);
    assert_eq!(module_peak, peak);
    assert_ne!(
        recorded_peak, peak,
        "the recorded board's strongest peak moves"
    );
}

#[test]
fn a_frame_the_calibrated_sums_cannot_hold_is_refused() {
    // One channel per element here: 256 loops give 256 chirps to one element.
    let edge = Edge::new(&config(256)).unwrap();
    let mut table = vec![0u32; edge.calibration_words()];
    let err = edge.calibrate(&calibration(), &mut table).unwrap_err();
    assert!(
        err.to_string().contains(&MAX_CALIBRATED_CHIRPS.to_string()),
        "{err}"
    );
    let edge = Edge::new(&config(255)).unwrap();
    assert!(edge.calibrate(&calibration(), &mut table).is_ok());
    // A calibration for fewer channels than the board has.
    let small = Calibration::identity(1, 4).unwrap().normalized();
    assert!(edge.calibrate(&small, &mut table).is_err());
    assert!(edge.calibrate(&calibration(), &mut table[..10]).is_err());
}
