//! Host cost of the module pipeline's stages on a synthetic 2 TX × 4 RX, 256-sample static
//! frame: the frame stage (sums, range spectra, peak scan), SIC, and the depth search
//! (coarse-to-fine vs the brute-force reference; the brute force on a cascade frame takes
//! seconds per run, `metamoran bench search` measures that once).
//! `cargo bench -p metamoran-dsp --bench search`.

use criterion::{Criterion, criterion_group, criterion_main};
use metamoran_dsp::config::{RadarConfig, SPEED_OF_LIGHT};
use metamoran_dsp::fft::C32;
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::pipeline::{Edge, FrameScene, ObjectHint};
use metamoran_dsp::range::StaticSum;
use metamoran_dsp::search::Contour;
use metamoran_dsp::search::depth::brute_force;
use metamoran_dsp::window::coefficient_f64;
use std::f64::consts::PI;
use std::hint::black_box;

const N: usize = 256;
const BIN_M: f64 = 0.1;

fn config() -> RadarConfig {
    RadarConfig {
        start_frequency_hz: 77.0e9,
        slope_hz_per_s: SPEED_OF_LIGHT * 10.0e6 / (2.0 * BIN_M * N as f64),
        sample_rate_hz: 10.0e6,
        adc_samples: N as u16,
        chirp_period_s: 30.0e-6,
        chirps_per_tx: 2,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: heapless::Vec::from_slice(&[0, 4]).unwrap(),
        rx_positions: heapless::Vec::from_slice(&[0, 1, 2, 3]).unwrap(),
        tx_order: heapless::Vec::from_slice(&[0, 1]).unwrap(),
    }
}

/// `[chirp][rx][sample]`: a car-like contour at 12.3 m plus clutter 30× stronger at 6 m.
fn frame(cfg: &RadarConfig) -> Vec<Vec<CQ15>> {
    let pts: Vec<(f64, f64, f64)> = (0..8)
        .map(|i| (12.3 + 0.08 * i as f64, -0.05 + 0.012 * i as f64, 200.0))
        .chain([(6.0, 0.6, 6000.0)])
        .collect();
    (0..cfg.chirps_per_frame() * 4)
        .map(|row| {
            let p = cfg.channel_position((row / 4 % 2) * 4 + row % 4).unwrap() as f64;
            (0..N)
                .map(|n| {
                    let (mut re, mut im) = (0.0, 0.0);
                    for (i, &(r, s, a)) in pts.iter().enumerate() {
                        let ph =
                            2.0 * PI * (r / BIN_M) * n as f64 / N as f64 + PI * p * s + i as f64;
                        re += a * ph.cos();
                        im += a * ph.sin();
                    }
                    CQ15::from_raw(re as i16, im as i16)
                })
                .collect()
        })
        .collect()
}

fn benches(c: &mut Criterion) {
    let cfg = config();
    let edge = Edge::new(&cfg).unwrap();
    let chirps = frame(&cfg);
    let mut arena = vec![0u32; edge.arena_words()];
    let (mut row, mut az, mut pw) = (
        vec![CQ15::default(); edge.fft_len()],
        vec![CQ15::default(); edge.azimuth_len()],
        vec![0u64; 3 * edge.azimuth_len()],
    );
    let mut run_frame = |arena: &mut [u32]| {
        let mut f = edge.start(arena).unwrap();
        for (i, ch) in chirps.iter().enumerate() {
            edge.push(&mut f, i / 4, i % 4, ch).unwrap();
        }
        let s = edge.finish(f, &mut row, &mut az, &mut pw).unwrap();
        (s.spectra.exponent(), s.peaks.clone())
    };
    let (exponent, peaks) = run_frame(&mut arena);
    let hint = ObjectHint {
        id: 1,
        class: 0,
        span: (-0.06, 0.06),
        prior_m: 30.0,
        window_m: (0.0, 0.0),
        contour: Contour::new((0..8).map(|i| (-0.05 + 0.012 * i as f32, 30.0 + 0.08 * i as f32))),
    };
    let mut g = c.benchmark_group("pipeline_8ch_256");
    g.sample_size(10);
    g.bench_function("frame_stage", |b| {
        let mut a = vec![0u32; edge.arena_words()];
        b.iter(|| black_box(run_frame(&mut a)));
    });
    let scene = FrameScene::resume(&edge, &mut arena, exponent, peaks.clone()).unwrap();
    g.bench_function("sic", |b| b.iter(|| black_box(edge.cancel(&scene, &hint))));
    let reflectors = edge.cancel(&scene, &hint);
    drop(scene);
    g.bench_function("coarse_to_fine", |b| {
        let mut scores = vec![0.0; edge.fft_len()];
        b.iter(|| {
            let mut s = FrameScene::resume(&edge, &mut arena, exponent, peaks.clone()).unwrap();
            black_box(edge.search(&mut s, &hint, &reflectors, &mut scores).ok())
        });
    });
    // The reference on the f32 sums with the same reflectors subtracted.
    let mut samples = vec![C32::new(0.0, 0.0); edge.array().elements() * N];
    let mut sum = StaticSum::new(&mut samples, N).unwrap();
    for (i, ch) in chirps.iter().enumerate() {
        let e = edge.array().element_of((i / 4 % 2) * 4 + i % 4).unwrap();
        sum.push(e, ch).unwrap();
    }
    let window: Vec<f32> = (0..N)
        .map(|i| coefficient_f64(Edge::WINDOW, i, N) as f32)
        .collect();
    let samples = sum.finish(&window).unwrap();
    let geo = edge.geometry();
    for r in &reflectors {
        r.subtract_from(samples, &geo, &window, exponent);
    }
    let bins = edge.bins(&hint);
    g.bench_function("brute_force", |b| {
        b.iter(|| black_box(brute_force(samples, &geo, &edge.contour(&hint), bins).ok()));
    });
    g.finish();
}

criterion_group!(search, benches);
criterion_main!(search);
