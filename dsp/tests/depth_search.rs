//! The module pipeline on chirps synthesized from the bundle signal model (f64): a contour
//! object next to a much stronger clutter point. SIC must find the clutter; the production
//! search must pick the reference's depth to a fine step, find the true depth, and spend far
//! fewer multiply-accumulates; the beam-domain cancellation must equal the time-domain one.

use metamoran_dsp::clutter::sic::Residual;
use metamoran_dsp::config::{RadarConfig, SPEED_OF_LIGHT};
use metamoran_dsp::fft::C32;
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::pipeline::{Edge, ObjectHint};
use metamoran_dsp::range::StaticSum;
use metamoran_dsp::search::Contour;
use metamoran_dsp::search::depth::{FINE_STEPS_PER_BIN, brute_force};
use metamoran_dsp::window::coefficient_f64;
use std::f64::consts::PI;

const N: usize = 64;
const BIN_M: f64 = 0.1;

/// 2 TX × 4 RX at positions 0..8, 64 samples, 0.1 m bins, 2 loops.
fn config() -> RadarConfig {
    let fs = 10.0e6;
    RadarConfig {
        start_frequency_hz: 77.0e9,
        slope_hz_per_s: SPEED_OF_LIGHT * fs / (2.0 * BIN_M * N as f64),
        sample_rate_hz: fs,
        adc_samples: N as u16,
        chirp_period_s: 10.0e-6,
        chirps_per_tx: 2,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: heapless::Vec::from_slice(&[0, 4]).unwrap(),
        rx_positions: heapless::Vec::from_slice(&[0, 1, 2, 3]).unwrap(),
        tx_order: heapless::Vec::from_slice(&[0, 1]).unwrap(),
    }
}

/// One chirp of the element at `p` from (range m, sin az, amplitude LSB) reflectors.
fn chirp(points: &[(f64, f64, f64)], p: f64) -> Vec<CQ15> {
    (0..N)
        .map(|n| {
            let (mut re, mut im) = (0.0, 0.0);
            for (i, &(r, s, a)) in points.iter().enumerate() {
                let ph = 2.0 * PI * (r / BIN_M) * n as f64 / N as f64 + PI * p * s + 1.7 * i as f64;
                re += a * ph.cos();
                im += a * ph.sin();
            }
            CQ15::from_raw(re.round() as i16, im.round() as i16)
        })
        .collect()
}

struct Run {
    edge: Edge,
    arena: Vec<u32>,
    exponent: i32,
    peaks: heapless::Vec<metamoran_dsp::clutter::peaks::Peak, 64>,
    /// Windowed f32 element sums for the reference.
    samples: Vec<C32>,
    window: Vec<f32>,
}

fn run(points: &[(f64, f64, f64)]) -> Run {
    let cfg = config();
    let edge = Edge::new(&cfg).unwrap();
    let mut arena = vec![0u32; edge.arena_words()];
    let mut samples = vec![C32::new(0.0, 0.0); edge.array().elements() * N];
    let mut sum = StaticSum::new(&mut samples, N).unwrap();
    let mut frame = edge.start(&mut arena).unwrap();
    for chirp_no in 0..cfg.chirps_per_frame() {
        for rx in 0..4 {
            let ch = (chirp_no % 2) * 4 + rx;
            let p = cfg.channel_position(ch).unwrap() as f64;
            let c = chirp(points, p);
            edge.push(&mut frame, chirp_no, rx, &c).unwrap();
            sum.push(edge.array().element_of(ch).unwrap(), &c).unwrap();
        }
    }
    let (mut row, mut az, mut pw) = (
        vec![CQ15::default(); edge.fft_len()],
        vec![CQ15::default(); edge.azimuth_len()],
        vec![0u64; 3 * edge.azimuth_len()],
    );
    let scene = edge.finish(frame, &mut row, &mut az, &mut pw).unwrap();
    let (exponent, peaks) = (scene.spectra.exponent(), scene.peaks.clone());
    let window: Vec<f32> = (0..N)
        .map(|i| coefficient_f64(Edge::WINDOW, i, N) as f32)
        .collect();
    sum.finish(&window).unwrap();
    Run {
        edge,
        arena,
        exponent,
        peaks,
        samples,
        window,
    }
}

/// A car-like contour: 5 points across 6°, 0..0.6 m deep.
const SHAPE: [(f64, f64); 5] = [
    (-0.05, 0.3),
    (-0.03, 0.1),
    (0.0, 0.0),
    (0.02, 0.15),
    (0.05, 0.6),
];

#[test]
fn pipeline_cancels_clutter_and_matches_brute_force() {
    let depth = 4.23;
    let mut points: Vec<(f64, f64, f64)> =
        SHAPE.iter().map(|&(s, r)| (depth + r, s, 150.0)).collect();
    // Clutter 15× stronger, 30° away and 2 m nearer.
    points.push((2.2, 0.5, 2250.0));
    let mut r = run(&points);
    let hint = ObjectHint {
        id: 7,
        class: 1,
        span: (-0.06, 0.06),
        prior_m: 5.0, // the search starts at 2 m, before the clutter
        window_m: (0.0, 0.0),
        contour: Contour::new(SHAPE.iter().map(|&(s, rr)| (s as f32, (rr + 11.0) as f32))),
    };
    let mut scene = metamoran_dsp::pipeline::FrameScene::resume(
        &r.edge,
        &mut r.arena,
        r.exponent,
        r.peaks.clone(),
    )
    .unwrap();
    let reflectors = r.edge.cancel(&scene, &hint);
    assert!(
        reflectors
            .first()
            .is_some_and(|c| (c.sin_az - 0.5).abs() < 0.03 && (c.range_bins - 22.0).abs() < 0.2),
        "{reflectors:?}"
    );
    let mut scores = vec![0.0; r.edge.fft_len()];
    let fast = r
        .edge
        .search(&mut scene, &hint, &reflectors, &mut scores)
        .unwrap();
    let geo = r.edge.geometry();
    for c in &reflectors {
        c.subtract_from(&mut r.samples, &geo, &r.window, r.exponent);
    }
    let bins = r.edge.bins(&hint);
    let reference = brute_force(&r.samples, &geo, &r.edge.contour(&hint), bins).unwrap();
    let step = 1.0 / FINE_STEPS_PER_BIN as f32;
    assert!(
        (fast.search.depth_bins - reference.depth_bins).abs() <= step + 1e-4,
        "{fast:?} vs {reference:?}"
    );
    assert!(
        (fast.search.depth_m as f64 - depth).abs() < 0.05,
        "depth {} m vs {depth} m",
        fast.search.depth_m
    );
    assert!(fast.detected(), "{fast:?}");
    assert!(
        fast.search.macs * 5 < reference.macs,
        "{} vs {} MACs",
        fast.search.macs,
        reference.macs
    );
}

#[test]
fn beam_domain_cancellation_equals_time_domain_subtraction() {
    let points = [(3.37, 0.41, 3000.0), (5.0, -0.1, 100.0)];
    let mut r = run(&points);
    let hint = ObjectHint {
        id: 1,
        class: 0,
        span: (-0.15, -0.05),
        prior_m: 0.0,
        window_m: (0.0, 0.0),
        contour: Contour::new([(-0.1f32, 0.0f32)]),
    };
    let scene = metamoran_dsp::pipeline::FrameScene::resume(
        &r.edge,
        &mut r.arena,
        r.exponent,
        r.peaks.clone(),
    )
    .unwrap();
    let reflectors = r.edge.cancel(&scene, &hint);
    assert!(!reflectors.is_empty());
    let geo = r.edge.geometry();
    let mut cleaned = r.samples.clone();
    for c in &reflectors {
        c.subtract_from(&mut cleaned, &geo, &r.window, r.exponent);
    }
    // f64 DFT + beamforming of the cleaned time-domain sums vs the residual beams.
    let scale = 2f64.powi(r.exponent);
    let s = 0.41f32;
    let residual = Residual::new(&scene.spectra, &geo, &reflectors, s);
    let (mut before, mut after, mut worst) = (0.0f64, 0.0f64, 0.0f64);
    for k in 28..40 {
        let (mut re, mut im) = (0.0f64, 0.0f64);
        let (mut re0, mut im0) = (0.0f64, 0.0f64);
        for (e, &p) in geo.positions.iter().enumerate() {
            for n in 0..N {
                let a = -2.0 * PI * (k * n) as f64 / N as f64 - PI * p as f64 * s as f64;
                let (c, sn) = (a.cos(), a.sin());
                let x = cleaned[e * N + n];
                re += x.re as f64 * c - x.im as f64 * sn;
                im += x.re as f64 * sn + x.im as f64 * c;
                let x0 = r.samples[e * N + n];
                re0 += x0.re as f64 * c - x0.im as f64 * sn;
                im0 += x0.re as f64 * sn + x0.im as f64 * c;
            }
        }
        let z = residual.at(k);
        let (dr, di) = (z.re as f64 * scale - re, z.im as f64 * scale - im);
        worst = worst.max((dr * dr + di * di).sqrt());
        before = before.max((re0 * re0 + im0 * im0).sqrt());
        after = after.max((re * re + im * im).sqrt());
    }
    // The reflector is gone (≥ 30 dB) and both domains agree to Q15 precision of the peak.
    assert!(after < 0.03 * before, "{after} of {before}");
    assert!(worst < 2e-3 * before, "worst {worst} of {before}");
    // Filling a run gives the single-bin beams, clipped to the spectrum.
    let m = scene.spectra.bins();
    for first in [0usize, 20, m - 5] {
        let mut run = vec![C32::new(f32::NAN, 0.0); 40];
        residual.fill(first, &mut run);
        for (k, z) in (first..).zip(&run) {
            if k < m {
                assert_eq!(*z, residual.at(k), "bin {k}");
            } else {
                assert!(z.re.is_nan(), "bin {k} beyond the spectrum was written");
            }
        }
    }
    // A residual valid only near some bins gives the same beams there.
    for (lo, hi) in [(28usize, 30usize), (33, 33), (36, 39)] {
        let near = Residual::near(&scene.spectra, &geo, &reflectors, s, lo..=hi);
        for k in lo..=hi {
            assert_eq!(near.at(k), residual.at(k), "bin {k}");
        }
    }
}

#[test]
fn bad_buffers_and_ranges_are_errors() {
    let cfg = config();
    let edge = Edge::new(&cfg).unwrap();
    let mut small = vec![0u32; edge.arena_words() - 1];
    assert!(edge.start(&mut small).is_err());
    let mut arena = vec![0u32; edge.arena_words()];
    let mut frame = edge.start(&mut arena).unwrap();
    assert!(edge.push(&mut frame, 0, 4, &[CQ15::default(); N]).is_err());
    assert!(
        edge.push(&mut frame, 0, 0, &[CQ15::default(); N - 1])
            .is_err()
    );
    let geo = edge.geometry();
    let c = Contour::new([(0.0f32, 1.0f32)]);
    assert!(brute_force(&[C32::new(0.0, 0.0); 31], &geo, &c, (1.0, 5.0)).is_err());
    assert!(
        brute_force(
            &vec![C32::new(0.0, 0.0); 8 * N],
            &geo,
            &Contour::default(),
            (1.0, 5.0)
        )
        .is_err()
    );
    assert!(brute_force(&vec![C32::new(0.0, 0.0); 8 * N], &geo, &c, (5.0, 1.0)).is_err());
}

/// The hint of the [`SHAPE`] object across sin-azimuths ±0.06, without priors.
fn car_hint() -> ObjectHint {
    ObjectHint {
        id: 7,
        class: 1,
        span: (-0.06, 0.06),
        prior_m: 0.0,
        window_m: (0.0, 0.0),
        contour: Contour::new(SHAPE.iter().map(|&(s, rr)| (s as f32, rr as f32))),
    }
}

/// The object's shape twice in the same direction: a stronger copy at 2.0 m (an in-span
/// reflector the camera's window rules out) and the object at 4.23 m.
fn twin_scene() -> (Run, ObjectHint) {
    let mut points: Vec<(f64, f64, f64)> =
        SHAPE.iter().map(|&(s, r)| (4.23 + r, s, 150.0)).collect();
    points.extend(SHAPE.iter().map(|&(s, r)| (2.0 + r, s, 400.0)));
    let hint = car_hint();
    (run(&points), hint)
}

fn search(r: &mut Run, hint: &ObjectHint) -> metamoran_dsp::pipeline::ObjectReport {
    let mut scene = metamoran_dsp::pipeline::FrameScene::resume(
        &r.edge,
        &mut r.arena,
        r.exponent,
        r.peaks.clone(),
    )
    .unwrap();
    let mut scores = vec![0.0; r.edge.fft_len()];
    r.edge.search(&mut scene, hint, &[], &mut scores).unwrap()
}

#[test]
fn the_runner_up_explanation_is_reported_refined_and_distinct() {
    let (mut r, hint) = twin_scene();
    let found = search(&mut r, &hint);
    let s = found.search;
    assert!((s.depth_m - 2.0).abs() < 0.05, "{s:?}");
    let other = s.others[0];
    assert!((other.depth_m - 4.23).abs() < 0.05, "{s:?}");
    assert!(other.peak > 0.0 && other.peak < s.peak && s.others[1].peak <= other.peak);
    // Every alternative lies beyond the contour's extent + 2 bins from d* (6 + 2 bins here).
    for o in s.others.iter().filter(|o| o.peak > 0.0) {
        assert!((o.depth_bins - s.depth_bins).abs() > 8.0, "{s:?}");
    }
    // Its score is P at its depth: the brute-force reference over ±1 bin around it agrees.
    let geo = r.edge.geometry();
    let around = (other.depth_bins - 1.0, other.depth_bins + 1.25);
    let reference = brute_force(&r.samples, &geo, &r.edge.contour(&hint), around).unwrap();
    let step = 1.0 / FINE_STEPS_PER_BIN as f32;
    assert!((reference.depth_bins - other.depth_bins).abs() <= step + 1e-4);
    // The wire carries both, each with its height over the floor; both twins lie inside the
    // span, so both survive.
    let wire = found.to_wire();
    let (depth, score) = wire.alternatives().next().unwrap();
    assert!(
        (depth - f64::from(other.depth_m)).abs() < 0.006,
        "{depth} vs {other:?}"
    );
    let db = score.over_floor_db();
    assert!(wire.score.over_floor_db() > db && db > 0.0);
    assert!(wire.score.survives() && score.survives(), "{wire:?}");
}

#[test]
fn the_camera_window_bounds_the_search() {
    let (mut r, mut hint) = twin_scene();
    hint.window_m = (3.5, 5.5);
    assert_eq!(r.edge.bins(&hint), (35.0, 55.0));
    let s = search(&mut r, &hint).search;
    assert!((s.depth_m - 4.23).abs() < 0.05, "{s:?}");
    // A window narrower than MIN_WINDOW_BINS is ignored.
    hint.window_m = (4.0, 4.5);
    assert_eq!(r.edge.bins(&hint).0, 1.0);
}

/// Issue #17's failure case: a strong reflector outside the span that SIC did not cancel (the
/// search runs with no reflectors cancelled) puts its side lobe inside the span at its range and
/// outscores the object. The survival test finds that the side lobe's energy comes from outside
/// and vanishes once that direction is cancelled, so the module reports the object's depth and
/// flags the side lobe.
#[test]
fn a_side_lobe_outscoring_the_object_is_reported_after_it() {
    let mut points: Vec<(f64, f64, f64)> =
        SHAPE.iter().map(|&(s, r)| (4.23 + r, s, 150.0)).collect();
    // 20× an object point, 17° away, 1.7 m nearer.
    points.push((2.5, 0.3, 3000.0));
    let mut r = run(&points);
    let hint = car_hint();
    let report = search(&mut r, &hint);
    // The search alone is fooled: its best score is the side lobe (some contour point on the
    // reflector's 2.5 m, so the closest point up to the contour's 0.6 m depth nearer).
    let fooled = |d: f64| (1.85..=2.55).contains(&d);
    assert!(fooled(f64::from(report.search.depth_m)), "{report:?}");
    let side_lobe = report.survival[0];
    assert!(
        !side_lobe.survives() && (side_lobe.sin_az - 0.3).abs() < 0.03,
        "{report:?}"
    );
    // The object's candidate survives and goes first on the wire, the side lobe after it.
    let wire = report.to_wire();
    assert!((wire.depth_m() - 4.23).abs() < 0.05, "{wire:?}");
    assert!(wire.score.survives(), "{wire:?}");
    let (depth, score) = wire
        .alternatives()
        .find(|&(d, _)| fooled(d))
        .expect("the side lobe is still reported");
    assert!(
        !score.survives() && score.over_floor_db() > wire.score.over_floor_db(),
        "{depth}"
    );
}
