//! FFT accuracy against an independent f64 reference (rustfft in double precision) on the same
//! quantized input: complex uniform noise, each component uniform in ±10^(dBFS/20) of full scale.

use metamoran_dsp::fft::{
    Complex32, bit_reversed, cfft_f32, cfft_q15, cfft_q15_bit_reversed, cfft_q31,
};
use metamoran_dsp::fixed::{CQ15, CQ31, Complex};
use rustfft::{FftPlanner, num_complex::Complex64};

/// Deterministic uniform noise in [-1, 1) (xorshift64*).
struct Noise(u64);
impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545F4914F6CDD1D);
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

fn reference(x: &[Complex64]) -> Vec<Complex64> {
    let mut y = x.to_vec();
    FftPlanner::<f64>::new()
        .plan_fft_forward(y.len())
        .process(&mut y);
    y
}

fn sqnr_db(reference: &[Complex64], ours: impl Iterator<Item = Complex64>) -> f64 {
    let (mut s, mut e) = (0.0, 0.0);
    for (r, o) in reference.iter().zip(ours) {
        s += r.norm_sqr();
        e += (r - o).norm_sqr();
    }
    10.0 * (s / e).log10()
}

fn q15_sqnr(n: usize, dbfs: f64, seed: u64) -> f64 {
    let amp = 10f64.powf(dbfs / 20.0);
    let mut noise = Noise(seed);
    let mut buf: Vec<CQ15> = (0..n)
        .map(|_| CQ15::from_f32((amp * noise.next()) as f32, (amp * noise.next()) as f32))
        .collect();
    let input: Vec<Complex64> = buf
        .iter()
        .map(|z| Complex64::new(z.re.to_f32() as f64, z.im.to_f32() as f64))
        .collect();
    let exp = cfft_q15(&mut buf).unwrap();
    let scale = exp.scale_f64();
    sqnr_db(
        &reference(&input),
        buf.iter()
            .map(|z| Complex64::new(z.re.to_f32() as f64 * scale, z.im.to_f32() as f64 * scale)),
    )
}

fn q31_sqnr(n: usize, dbfs: f64, seed: u64) -> f64 {
    let amp = 10f64.powf(dbfs / 20.0);
    let mut noise = Noise(seed);
    let mut buf: Vec<CQ31> = (0..n)
        .map(|_| {
            Complex::new(
                metamoran_dsp::fixed::Q31::from_f64(amp * noise.next()),
                metamoran_dsp::fixed::Q31::from_f64(amp * noise.next()),
            )
        })
        .collect();
    let input: Vec<Complex64> = buf
        .iter()
        .map(|z| Complex64::new(z.re.to_f64(), z.im.to_f64()))
        .collect();
    let exp = cfft_q31(&mut buf).unwrap();
    let scale = exp.scale_f64();
    sqnr_db(
        &reference(&input),
        buf.iter()
            .map(|z| Complex64::new(z.re.to_f64() * scale, z.im.to_f64() * scale)),
    )
}

const SIZES: [usize; 8] = [16, 32, 64, 128, 256, 512, 1024, 2048];

/// Median over a few seeds, so one unlucky draw does not decide.
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[test]
fn q15_meets_cmsis_m7_at_minus_12_dbfs() {
    // arm_cfft_q15 on a Cortex-M7 (issue figures): 59.9 dB (64), 54.8 dB (256), 48.2 dB (1024).
    for (n, cmsis) in [(64, 59.9), (256, 54.8), (1024, 48.2)] {
        let got = median((1..=5).map(|s| q15_sqnr(n, -12.0, s)).collect());
        println!("q15 n={n} -12 dBFS: {got:.1} dB (CMSIS M7 {cmsis})");
        assert!(
            got >= cmsis,
            "Q15 SQNR {got:.1} dB < CMSIS {cmsis} dB at n={n}"
        );
    }
}

#[test]
fn q15_keeps_weak_signals_at_minus_40_dbfs() {
    for n in SIZES {
        let got = median((1..=5).map(|s| q15_sqnr(n, -40.0, s)).collect());
        println!("q15 n={n} -40 dBFS: {got:.1} dB");
        assert!(
            got >= 45.0,
            "Q15 SQNR {got:.1} dB < 45 dB at n={n}, -40 dBFS"
        );
    }
}

#[test]
fn q31_exceeds_130_db_at_every_size() {
    for n in SIZES {
        for dbfs in [-12.0, -40.0] {
            let got = median((1..=3).map(|s| q31_sqnr(n, dbfs, s)).collect());
            println!("q31 n={n} {dbfs} dBFS: {got:.1} dB");
            assert!(got >= 130.0, "Q31 SQNR {got:.1} dB < 130 dB at n={n}");
        }
    }
}

#[test]
fn full_scale_input_never_overflows() {
    // Worst cases for growth: a full-scale constant (all energy in one bin) and alternating
    // corners; the output must still match the reference, i.e. nothing wrapped or clipped.
    for n in SIZES {
        for pattern in 0..3 {
            let mut buf: Vec<CQ15> = (0..n)
                .map(|i| match pattern {
                    0 => CQ15::from_raw(i16::MAX, i16::MIN),
                    1 => {
                        if i % 2 == 0 {
                            CQ15::from_raw(i16::MIN, i16::MIN)
                        } else {
                            CQ15::from_raw(i16::MAX, i16::MAX)
                        }
                    }
                    _ => CQ15::from_raw(
                        if i % 3 == 0 { i16::MIN } else { i16::MAX },
                        if i % 5 == 0 { i16::MAX } else { i16::MIN },
                    ),
                })
                .collect();
            let input: Vec<Complex64> = buf
                .iter()
                .map(|z| Complex64::new(z.re.to_f32() as f64, z.im.to_f32() as f64))
                .collect();
            let scale = cfft_q15(&mut buf).unwrap().scale_f64();
            let got = sqnr_db(
                &reference(&input),
                buf.iter().map(|z| {
                    Complex64::new(z.re.to_f32() as f64 * scale, z.im.to_f32() as f64 * scale)
                }),
            );
            assert!(
                got > 50.0,
                "pattern {pattern} n={n}: {got:.1} dB (overflow?)"
            );
        }
    }
}

#[test]
fn f32_path_matches_reference() {
    for n in SIZES {
        let mut noise = Noise(9);
        let input: Vec<Complex64> = (0..n)
            .map(|_| Complex64::new(noise.next() as f32 as f64, noise.next() as f32 as f64))
            .collect();
        let mut buf: Vec<Complex32> = input
            .iter()
            .map(|z| Complex32::new(z.re as f32, z.im as f32))
            .collect();
        cfft_f32(&mut buf).unwrap();
        let got = sqnr_db(
            &reference(&input),
            buf.iter().map(|z| Complex64::new(z.re as f64, z.im as f64)),
        );
        assert!(got > 110.0, "microfft n={n}: {got:.1} dB");
    }
}

#[test]
fn unsupported_lengths_are_errors() {
    for n in [0, 1, 8, 24, 100, 4096] {
        let mut q = vec![CQ15::default(); n];
        assert!(cfft_q15(&mut q).is_err(), "n={n}");
        let mut f = vec![Complex32::new(0.0, 0.0); n];
        assert!(cfft_f32(&mut f).is_err(), "n={n}");
    }
}

#[test]
fn bit_reversed_output_is_the_natural_spectrum_reindexed() {
    // Index reversal against its definition on the binary digits, then the transform.
    for bits in 4..=11u32 {
        let n = 1usize << bits;
        for k in 0..n {
            let digits: usize = (0..bits).map(|b| ((k >> b) & 1) << (bits - 1 - b)).sum();
            assert_eq!(bit_reversed(k, n), digits, "n={n} k={k}");
        }
        let mut noise = Noise(n as u64);
        let natural: Vec<CQ15> = (0..n)
            .map(|_| CQ15::from_f32(0.9 * noise.next() as f32, 0.9 * noise.next() as f32))
            .collect();
        let (mut a, mut b) = (natural.clone(), natural);
        let ea = cfft_q15(&mut a).unwrap();
        let eb = cfft_q15_bit_reversed(&mut b).unwrap();
        assert_eq!(ea, eb, "n={n}");
        for k in 0..n {
            assert_eq!(a[k], b[bit_reversed(k, n)], "n={n} k={k}");
        }
    }
    assert!(cfft_q15_bit_reversed(&mut [CQ15::default(); 24]).is_err());
}
