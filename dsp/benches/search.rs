//! Host cost of the depth search (coarse-to-fine vs brute force) and of SIC per frame, on a
//! synthetic 8-channel, 256-sample static frame (the brute force on a cascade frame takes
//! seconds per run; `metamoran bench search` measures that once). `cargo bench -p metamoran-dsp --bench search`.

use criterion::{Criterion, criterion_group, criterion_main};
use dsp::clutter::sic::{SicScratch, cancel};
use dsp::fft::{C32, cfft_f32};
use dsp::search::Contour;
use dsp::search::depth::{Geometry, brute_force, coarse_to_fine};
use std::f32::consts::PI;
use std::hint::black_box;

const N: usize = 256;
const M: usize = 256;
const C: usize = 8;

/// Windowed static samples and spectra of a car-like contour at 12.3 m plus strong clutter.
fn frame(positions: &[f32]) -> (Vec<C32>, Vec<C32>, Vec<f32>) {
    let window: Vec<f32> = (0..N)
        .map(|n| 0.5 - 0.5 * (2.0 * PI * n as f32 / (N - 1) as f32).cos())
        .collect();
    let bin_m = 0.1;
    let pts: Vec<(f32, f32, f32)> = (0..8)
        .map(|i| (12.3 + 0.08 * i as f32, -0.05 + 0.012 * i as f32, 1.0))
        .chain([(6.0, 0.6, 30.0)])
        .collect();
    let mut samples = vec![C32::new(0.0, 0.0); C * N];
    for (ch, &p) in positions.iter().enumerate() {
        for n in 0..N {
            let mut z = C32::new(0.0, 0.0);
            for (i, &(r, s, a)) in pts.iter().enumerate() {
                let ph = 2.0 * PI * (r / bin_m) * n as f32 / M as f32 + PI * p * s + i as f32;
                z += C32::new(ph.cos(), ph.sin()) * a;
            }
            samples[ch * N + n] = z * window[n];
        }
    }
    let mut spectra = vec![C32::new(0.0, 0.0); C * M];
    for (row, out) in samples.chunks_exact(N).zip(spectra.chunks_exact_mut(M)) {
        out[..N].copy_from_slice(row);
        cfft_f32(out).unwrap();
    }
    (samples, spectra, window)
}

fn benches(c: &mut Criterion) {
    let positions: Vec<f32> = (0..C).map(|p| p as f32).collect();
    let (samples, spectra, window) = frame(&positions);
    let geo = Geometry {
        positions: &positions,
        samples: N,
        fft_len: M,
        bin_m: 0.1,
    };
    let contour = Contour::new((0..8).map(|i| (-0.05 + 0.012 * i as f32, 30.0 + 0.08 * i as f32)));
    let range = (2.0, 230.0);
    let mut g = c.benchmark_group("depth_search_8ch_256");
    g.sample_size(10);
    g.bench_function("coarse_to_fine", |b| {
        let mut profiles = vec![C32::new(0.0, 0.0); contour.points().len() * M];
        let mut scores = vec![0.0; M];
        b.iter(|| {
            black_box(
                coarse_to_fine(&spectra, &geo, &contour, range, &mut profiles, &mut scores).ok(),
            )
        })
    });
    g.bench_function("brute_force", |b| {
        b.iter(|| black_box(brute_force(&samples, &geo, &contour, range).ok()))
    });
    g.bench_function("sic_frame", |b| {
        let mut elements = vec![C32::new(0.0, 0.0); 64];
        let mut tone = vec![C32::new(0.0, 0.0); M];
        b.iter(|| {
            let (mut s, mut sp) = (samples.clone(), spectra.clone());
            black_box(
                cancel(
                    &mut sp,
                    &mut s,
                    &geo,
                    &window,
                    &[(-0.2, 0.1)],
                    230,
                    0.05,
                    SicScratch {
                        elements: &mut elements,
                        tone: &mut tone,
                    },
                )
                .len(),
            )
        })
    });
    g.finish();
}

criterion_group!(search, benches);
criterion_main!(search);
