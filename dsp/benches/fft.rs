//! Host FFT speed: our Q15/Q31 block-floating-point FFTs against microfft (f32) and rustfft
//! (f32) on the same input. `cargo bench -p metamoran-dsp`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use metamoran_dsp::fft::{Complex32, cfft_f32, cfft_q15, cfft_q31};
use metamoran_dsp::fixed::{CQ15, CQ31};
use rustfft::FftPlanner;
use std::hint::black_box;

fn input(n: usize) -> Vec<CQ15> {
    let mut s = 0x2545_f491_4f6c_dd1du64;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            CQ15::from_raw((s as i16) >> 2, ((s >> 16) as i16) >> 2)
        })
        .collect()
}

fn ffts(c: &mut Criterion) {
    let mut g = c.benchmark_group("cfft");
    for n in [32usize, 256, 1024] {
        let x = input(n);
        let x31: Vec<CQ31> = x
            .iter()
            .map(|z| CQ31::new(z.re.into(), z.im.into()))
            .collect();
        let xf: Vec<Complex32> = x
            .iter()
            .map(|z| Complex32::new(z.re.to_f32(), z.im.to_f32()))
            .collect();
        let xr: Vec<Complex32> = xf.iter().map(|z| Complex32::new(z.re, z.im)).collect();
        let plan = FftPlanner::<f32>::new().plan_fft_forward(n);
        g.bench_with_input(BenchmarkId::new("q15", n), &x, |b, x| {
            let mut buf = x.clone();
            b.iter(|| {
                buf.copy_from_slice(x);
                black_box(cfft_q15(black_box(&mut buf)).ok())
            });
        });
        g.bench_with_input(BenchmarkId::new("q31", n), &x31, |b, x| {
            let mut buf = x.clone();
            b.iter(|| {
                buf.copy_from_slice(x);
                black_box(cfft_q31(black_box(&mut buf)).ok())
            });
        });
        g.bench_with_input(BenchmarkId::new("microfft_f32", n), &xf, |b, x| {
            let mut buf = x.clone();
            b.iter(|| {
                buf.copy_from_slice(x);
                black_box(cfft_f32(black_box(&mut buf)).ok())
            });
        });
        g.bench_with_input(BenchmarkId::new("rustfft_f32", n), &xr, |b, x| {
            let mut buf = x.clone();
            b.iter(|| {
                buf.copy_from_slice(x);
                plan.process(black_box(&mut buf));
            });
        });
    }
    g.finish();
}

criterion_group!(benches, ffts);
criterion_main!(benches);
