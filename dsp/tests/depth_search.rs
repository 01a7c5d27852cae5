//! The depth search on signals synthesized from the bundle signal model: a contour object next
//! to a much stronger clutter point. The production search must pick the reference's depth to a
//! fine step, find the true depth, and spend far fewer multiply-accumulates.

use dsp::search::depth::{C32, FINE_STEPS_PER_BIN, Geometry, brute_force, coarse_to_fine};
use dsp::search::{Contour, ContourPoint};
use std::f64::consts::PI;

/// (range m, sin az, amplitude) point reflectors → windowed static samples `[ch][n]` and their
/// zero-padded FFT `[ch][k]`.
fn synth(
    points: &[(f64, f64, f64)],
    positions: &[f32],
    n: usize,
    m: usize,
    bin_m: f64,
) -> (Vec<C32>, Vec<C32>) {
    let mut samples = Vec::new();
    for &p in positions {
        for k in 0..n {
            let w = 0.5 - 0.5 * (2.0 * PI * k as f64 / (n - 1) as f64).cos();
            let (mut re, mut im) = (0.0, 0.0);
            for (i, &(r, s, a)) in points.iter().enumerate() {
                // Beat frequency in bins of the M-point FFT is r / bin_m; phase per point arbitrary.
                let ph = 2.0 * PI * (r / bin_m) * k as f64 / m as f64
                    + PI * p as f64 * s
                    + 1.7 * i as f64;
                re += a * ph.cos();
                im += a * ph.sin();
            }
            samples.push(C32::new((w * re) as f32, (w * im) as f32));
        }
    }
    let mut spectra = Vec::new();
    for row in samples.chunks_exact(n) {
        for b in 0..m {
            let (mut re, mut im) = (0.0f64, 0.0f64);
            for (k, x) in row.iter().enumerate() {
                let a = -2.0 * PI * (b * k) as f64 / m as f64;
                re += x.re as f64 * a.cos() - x.im as f64 * a.sin();
                im += x.re as f64 * a.sin() + x.im as f64 * a.cos();
            }
            spectra.push(C32::new(re as f32, im as f32));
        }
    }
    (samples, spectra)
}

#[test]
fn coarse_to_fine_matches_brute_force_and_finds_the_object() {
    let positions: Vec<f32> = (0..8).map(|p| p as f32).collect();
    let (n, m, bin_m) = (64usize, 128usize, 0.1f64);
    // A car-like contour: 5 points across 6°, 0..0.6 m deep, true closest point at 4.23 m.
    let shape = [
        (-0.05, 0.3),
        (-0.03, 0.1),
        (0.0, 0.0),
        (0.02, 0.15),
        (0.05, 0.6),
    ];
    let depth = 4.23;
    let mut points: Vec<(f64, f64, f64)> =
        shape.iter().map(|&(s, r)| (depth + r, s, 1.0)).collect();
    // Clutter 15× stronger, 30° away and 2 m nearer.
    points.push((2.2, 0.5, 15.0));
    let (samples, spectra) = synth(&points, &positions, n, m, bin_m);
    // The camera's contour: right shape, monocular ranges 7 m off (relative ranges survive).
    let contour = Contour::new(shape.iter().map(|&(s, r)| (s as f32, (r + 7.0) as f32)));
    let geo = Geometry {
        positions: &positions,
        samples: n,
        fft_len: m,
        bin_m: bin_m as f32,
    };
    let range = (2.0, 100.0);
    let reference = brute_force(&samples, &geo, &contour, range).unwrap();
    let mut profiles = vec![C32::new(0.0, 0.0); contour.points().len() * m];
    let mut scores = vec![0.0; m];
    let fast = coarse_to_fine(&spectra, &geo, &contour, range, &mut profiles, &mut scores).unwrap();
    let step = 1.0 / FINE_STEPS_PER_BIN as f32;
    assert!(
        (fast.depth_bins - reference.depth_bins).abs() <= step + 1e-4,
        "{fast:?} vs {reference:?}"
    );
    assert!(
        (fast.depth_m as f64 - depth).abs() < 0.05,
        "depth {} m vs {depth} m",
        fast.depth_m
    );
    assert!(fast.peak > 10.0 * fast.floor);
    assert!(
        fast.macs * 20 < reference.macs,
        "{} vs {} MACs",
        fast.macs,
        reference.macs
    );
}

#[test]
fn empty_and_bad_inputs_are_errors() {
    let positions = [0.0f32; 4];
    let geo = Geometry {
        positions: &positions,
        samples: 8,
        fft_len: 16,
        bin_m: 0.1,
    };
    let c = Contour::new([(0.0f32, 1.0f32)]);
    assert!(brute_force(&[C32::new(0.0, 0.0); 31], &geo, &c, (1.0, 5.0)).is_err());
    assert!(
        brute_force(
            &[C32::new(0.0, 0.0); 32],
            &geo,
            &Contour::default(),
            (1.0, 5.0)
        )
        .is_err()
    );
    let mut p = vec![C32::new(0.0, 0.0); 16];
    let mut s = vec![0.0; 16];
    assert!(
        coarse_to_fine(
            &[C32::new(0.0, 0.0); 64],
            &geo,
            &c,
            (5.0, 1.0),
            &mut p,
            &mut s
        )
        .is_err()
    );
    assert!(
        coarse_to_fine(
            &[C32::new(0.0, 0.0); 64],
            &geo,
            &c,
            (1.0, 5.0),
            &mut p[..8],
            &mut s
        )
        .is_err()
    );
    let _ = ContourPoint {
        sin_az: 0.0,
        rel_range_m: 0.0,
    };
}

#[test]
fn streaming_cancellation_equals_frame_cancellation() {
    use dsp::clutter::sic::{SicScratch, cancel};
    use dsp::fixed::CQ15;
    use dsp::range::StaticSum;
    let (n, m, loops) = (64usize, 64usize, 4usize);
    let positions: Vec<f32> = (0..8).map(|p| p as f32).collect();
    let window: Vec<f32> = (0..n)
        .map(|k| (0.5 - 0.5 * (2.0 * PI * k as f64 / (n - 1) as f64).cos()) as f32)
        .collect();
    // One loop's chirp per channel: an object at broadside and a strong reflector at sin θ = 0.6.
    let chirp = |p: f32| -> Vec<CQ15> {
        (0..n)
            .map(|k| {
                let a = 2.0 * PI * 20.3 * k as f64 / m as f64;
                let b = 2.0 * PI * 9.6 * k as f64 / m as f64 + PI * p as f64 * 0.6;
                CQ15::from_f32(
                    (0.01 * a.cos() + 0.3 * b.cos()) as f32,
                    (0.01 * a.sin() + 0.3 * b.sin()) as f32,
                )
            })
            .collect()
    };
    let geo = Geometry {
        positions: &positions,
        samples: n,
        fft_len: m,
        bin_m: 0.1,
    };
    // Frame level: sum, then cancel.
    let mut samples = vec![C32::new(0.0, 0.0); 8 * n];
    let mut sum = StaticSum::new(&mut samples, n).unwrap();
    for (ch, &p) in positions.iter().enumerate() {
        for _ in 0..loops {
            sum.push(ch, &chirp(p)).unwrap();
        }
    }
    let mut spectra = vec![C32::new(0.0, 0.0); 8 * m];
    sum.finish(&window, &mut spectra).unwrap();
    let (mut el, mut tone) = (vec![C32::new(0.0, 0.0); 32], vec![C32::new(0.0, 0.0); m]);
    let found = cancel(
        &mut spectra,
        &mut samples,
        &geo,
        &window,
        &[(-0.2, 0.2)],
        m - 4,
        0.05,
        SicScratch {
            elements: &mut el,
            tone: &mut tone,
        },
    );
    assert!(
        !found.is_empty()
            && (found[0].sin_az - 0.6).abs() < 0.03
            && (found[0].range_bins - 9.6).abs() < 0.2,
        "{found:?}"
    );
    // Streaming: the same reflectors removed chirp by chirp.
    let mut streamed = vec![C32::new(0.0, 0.0); 8 * n];
    let mut sum = StaticSum::new(&mut streamed, n).unwrap();
    for (ch, &p) in positions.iter().enumerate() {
        for _ in 0..loops {
            sum.push_cancelled(ch, &chirp(p), p, &found, loops, m)
                .unwrap();
        }
    }
    let mut streamed_spectra = vec![C32::new(0.0, 0.0); 8 * m];
    sum.finish(&window, &mut streamed_spectra).unwrap();
    let scale = samples.iter().map(|z| z.norm()).fold(0.0f32, f32::max);
    for (a, b) in samples.iter().zip(&streamed) {
        assert!((a - b).norm() < 1e-4 * scale.max(1.0), "{a} vs {b}");
    }
}
