//! `metamoran bench fft`: speed and accuracy of our FFTs against microfft, rustfft and CMSIS-DSP.
//!
//! Accuracy is SQNR against a double-precision rustfft of the same quantized input (complex
//! uniform noise, each part uniform in ±10^(dBFS/20) of full scale), at −12 and −40 dBFS.

use super::cmsis::{CmsisFormat, CmsisRequest, cmsis_fft};
use metamoran_dsp::fft::{Complex32, cfft_f32, cfft_q15, cfft_q31};
use metamoran_dsp::fixed::{CQ15, CQ31, Complex, Q31};
use rustfft::FftPlanner;
use rustfft::num_complex::{Complex32 as RComplex32, Complex64};
use serde::Serialize;
use std::time::Instant;

/// One implementation at one size.
#[derive(Clone, Debug, Serialize)]
pub struct FftRow {
    /// FFT length.
    pub n: usize,
    /// `q15`, `q31`, `microfft_f32`, `rustfft_f32`, `cmsis_q15` or `cmsis_q31`.
    #[serde(rename = "impl")]
    pub implementation: String,
    /// Host time per transform, ns (minimum over batches); `None` where not timed (CMSIS runs in Python).
    pub ns_per_fft: Option<f64>,
    /// SQNR at −12 dBFS, dB.
    pub sqnr_db_m12: f64,
    /// SQNR at −40 dBFS, dB.
    pub sqnr_db_m40: f64,
}

/// The whole report.
#[derive(Clone, Debug, Serialize)]
pub struct FftReport {
    /// The machine the times were measured on.
    pub machine: String,
    /// One row per implementation and size.
    pub fft: Vec<FftRow>,
    /// Why the CMSIS rows are missing, if they are.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cmsis_missing: Option<String>,
}

/// Deterministic uniform noise in [-1, 1) (xorshift64*).
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64) / (1u64 << 52) as f64 - 1.0
    }
}

/// Test inputs of one size and level, quantized once for each format.
struct Input {
    q15: Vec<CQ15>,
    q31: Vec<CQ31>,
}

impl Input {
    fn new(n: usize, dbfs: f64, seed: u64) -> Self {
        let amp = 10f64.powf(dbfs / 20.0);
        let mut noise = Noise(seed);
        let v: Vec<(f64, f64)> = (0..n)
            .map(|_| (amp * noise.next(), amp * noise.next()))
            .collect();
        Self {
            q15: v
                .iter()
                .map(|&(r, i)| CQ15::from_f32(r as f32, i as f32))
                .collect(),
            q31: v
                .iter()
                .map(|&(r, i)| Complex::new(Q31::from_f64(r), Q31::from_f64(i)))
                .collect(),
        }
    }

    fn q15_f64(&self) -> Vec<Complex64> {
        self.q15
            .iter()
            .map(|z| Complex64::new(z.re.to_f32() as f64, z.im.to_f32() as f64))
            .collect()
    }

    /// Interleaved raw integers of the input quantized for `format`.
    fn raw(&self, format: CmsisFormat) -> Vec<i64> {
        match format {
            CmsisFormat::Q15 => self
                .q15
                .iter()
                .flat_map(|z| [z.re.0 as i64, z.im.0 as i64])
                .collect(),
            CmsisFormat::Q31 => self
                .q31
                .iter()
                .flat_map(|z| [z.re.0 as i64, z.im.0 as i64])
                .collect(),
        }
    }

    /// The exact values of the input quantized for `format`.
    fn exact(&self, format: CmsisFormat) -> Vec<Complex64> {
        match format {
            CmsisFormat::Q15 => self.q15_f64(),
            CmsisFormat::Q31 => self.q31_f64(),
        }
    }

    fn q31_f64(&self) -> Vec<Complex64> {
        self.q31
            .iter()
            .map(|z| Complex64::new(z.re.to_f64(), z.im.to_f64()))
            .collect()
    }
}

fn reference(x: &[Complex64]) -> Vec<Complex64> {
    let mut y = x.to_vec();
    FftPlanner::<f64>::new()
        .plan_fft_forward(y.len())
        .process(&mut y);
    y
}

/// SQNR of `ours` against `reference`, dB.
pub fn sqnr_db(reference: &[Complex64], ours: &[Complex64]) -> f64 {
    let s: f64 = reference
        .iter()
        .map(rustfft::num_complex::Complex::norm_sqr)
        .sum();
    let e: f64 = reference
        .iter()
        .zip(ours)
        .map(|(r, o)| (r - o).norm_sqr())
        .sum();
    10.0 * (s / e).log10()
}

/// The implementations we run in-process.
const IMPLS: [&str; 4] = ["q15", "q31", "microfft_f32", "rustfft_f32"];

/// Runs `implementation` on `input` once; returns the spectrum as f64 (true DFT scale).
fn transform(implementation: &str, input: &Input) -> Vec<Complex64> {
    match implementation {
        "q15" => {
            let mut b = input.q15.clone();
            let s = cfft_q15(&mut b)
                .map(metamoran_dsp::fft::Exponent::scale_f64)
                .unwrap_or(f64::NAN);
            b.iter()
                .map(|z| Complex64::new(z.re.to_f32() as f64 * s, z.im.to_f32() as f64 * s))
                .collect()
        }
        "q31" => {
            let mut b = input.q31.clone();
            let s = cfft_q31(&mut b)
                .map(metamoran_dsp::fft::Exponent::scale_f64)
                .unwrap_or(f64::NAN);
            b.iter()
                .map(|z| Complex64::new(z.re.to_f64() * s, z.im.to_f64() * s))
                .collect()
        }
        "microfft_f32" => {
            let mut b: Vec<Complex32> = input
                .q15
                .iter()
                .map(|z| Complex32::new(z.re.to_f32(), z.im.to_f32()))
                .collect();
            if cfft_f32(&mut b).is_err() {
                return vec![Complex64::new(f64::NAN, 0.0); b.len()];
            }
            b.iter()
                .map(|z| Complex64::new(z.re as f64, z.im as f64))
                .collect()
        }
        _ => {
            let mut b: Vec<RComplex32> = input
                .q15
                .iter()
                .map(|z| RComplex32::new(z.re.to_f32(), z.im.to_f32()))
                .collect();
            FftPlanner::<f32>::new()
                .plan_fft_forward(b.len())
                .process(&mut b);
            b.iter()
                .map(|z| Complex64::new(z.re as f64, z.im as f64))
                .collect()
        }
    }
}

/// Median SQNR over `seeds` inputs.
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Seeds per size and level.
const SEEDS: u64 = 5;

fn sqnr_of(implementation: &str, n: usize, dbfs: f64) -> f64 {
    median(
        (1..=SEEDS)
            .map(|seed| {
                let input = Input::new(n, dbfs, seed);
                let reference = if implementation == "q31" {
                    reference(&input.q31_f64())
                } else {
                    reference(&input.q15_f64())
                };
                sqnr_db(&reference, &transform(implementation, &input))
            })
            .collect(),
    )
}

/// Host nanoseconds per transform: the minimum over batches of ≥ 20 ms, input copy included.
fn time_ns(implementation: &str, n: usize) -> f64 {
    let input = Input::new(n, -12.0, 1);
    let mut best = f64::INFINITY;
    let planner = FftPlanner::<f32>::new().plan_fft_forward(n);
    let f32_in: Vec<Complex32> = input
        .q15
        .iter()
        .map(|z| Complex32::new(z.re.to_f32(), z.im.to_f32()))
        .collect();
    let r32_in: Vec<RComplex32> = f32_in.iter().map(|z| RComplex32::new(z.re, z.im)).collect();
    let (mut q15, mut q31, mut f32b, mut r32) = (
        input.q15.clone(),
        input.q31.clone(),
        f32_in.clone(),
        r32_in.clone(),
    );
    let mut scratch = vec![RComplex32::default(); planner.get_inplace_scratch_len()];
    for _ in 0..5 {
        let mut iters = 0u64;
        let start = Instant::now();
        while start.elapsed().as_millis() < 20 {
            for _ in 0..64 {
                match implementation {
                    "q15" => {
                        q15.copy_from_slice(&input.q15);
                        std::hint::black_box(cfft_q15(std::hint::black_box(&mut q15)).ok());
                    }
                    "q31" => {
                        q31.copy_from_slice(&input.q31);
                        std::hint::black_box(cfft_q31(std::hint::black_box(&mut q31)).ok());
                    }
                    "microfft_f32" => {
                        f32b.copy_from_slice(&f32_in);
                        std::hint::black_box(cfft_f32(std::hint::black_box(&mut f32b)).ok());
                    }
                    _ => {
                        r32.copy_from_slice(&r32_in);
                        planner.process_with_scratch(std::hint::black_box(&mut r32), &mut scratch);
                    }
                }
            }
            iters += 64;
        }
        best = best.min(start.elapsed().as_nanos() as f64 / iters as f64);
    }
    best
}

fn cmsis_rows(sizes: &[usize]) -> Result<Vec<FftRow>, String> {
    let levels = [-12.0, -40.0];
    let mut requests = Vec::new();
    let mut refs = Vec::new();
    for &n in sizes {
        for format in [CmsisFormat::Q15, CmsisFormat::Q31] {
            for dbfs in levels {
                for seed in 1..=SEEDS {
                    let input = Input::new(n, dbfs, seed);
                    let (data, reference) = (input.raw(format), reference(&input.exact(format)));
                    requests.push(CmsisRequest { format, data });
                    refs.push((n, format, dbfs, reference));
                }
            }
        }
    }
    let answers = cmsis_fft(&requests)?;
    let mut rows = Vec::new();
    for &n in sizes {
        for format in [CmsisFormat::Q15, CmsisFormat::Q31] {
            let mut sqnr = [0.0; 2];
            for (li, dbfs) in levels.iter().enumerate() {
                let v = refs
                    .iter()
                    .zip(&answers)
                    .filter(|((rn, rf, rd, _), _)| *rn == n && *rf == format && rd == dbfs)
                    .map(|((_, _, _, reference), raw)| {
                        let frac = if format == CmsisFormat::Q15 { 15 } else { 31 };
                        let s = n as f64 / (1u64 << frac) as f64;
                        let ours: Vec<Complex64> = raw
                            .chunks_exact(2)
                            .map(|p| Complex64::new(p[0] as f64 * s, p[1] as f64 * s))
                            .collect();
                        sqnr_db(reference, &ours)
                    })
                    .collect();
                sqnr[li] = median(v);
            }
            let name = if format == CmsisFormat::Q15 {
                "cmsis_q15"
            } else {
                "cmsis_q31"
            };
            rows.push(FftRow {
                n,
                implementation: name.into(),
                ns_per_fft: None,
                sqnr_db_m12: sqnr[0],
                sqnr_db_m40: sqnr[1],
            });
        }
    }
    Ok(rows)
}

/// The CPU model, from `/proc/cpuinfo` where there is one.
fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, std::num::NonZero::get);
    format!(
        "{cpu}, {cores} cores, {} {}",
        std::env::consts::OS,
        std::env::consts::ARCH
    )
}

/// Measures every implementation at every size in one run; `timing: false` skips the clock
/// (accuracy only, for tests).
pub fn run(sizes: &[usize], timing: bool) -> FftReport {
    let mut fft = Vec::new();
    for &n in sizes {
        for implementation in IMPLS {
            fft.push(FftRow {
                n,
                implementation: implementation.into(),
                ns_per_fft: timing.then(|| time_ns(implementation, n)),
                sqnr_db_m12: sqnr_of(implementation, n, -12.0),
                sqnr_db_m40: sqnr_of(implementation, n, -40.0),
            });
        }
    }
    let cmsis_missing = match cmsis_rows(sizes) {
        Ok(rows) => {
            fft.extend(rows);
            None
        }
        Err(e) => Some(e),
    };
    FftReport {
        machine: machine(),
        fft,
        cmsis_missing,
    }
}

impl std::fmt::Display for FftReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "FFT benchmark on {}", self.machine)?;
        writeln!(
            f,
            "{:>5} {:<13} {:>10} {:>10} {:>12} {:>12}",
            "n", "impl", "ns/fft", "vs rustfft", "SQNR -12dB", "SQNR -40dB"
        )?;
        for r in &self.fft {
            let base = self
                .fft
                .iter()
                .find(|b| b.n == r.n && b.implementation == "rustfft_f32")
                .and_then(|b| b.ns_per_fft);
            let (ns, ratio) = match (r.ns_per_fft, base) {
                (Some(ns), Some(b)) => (format!("{ns:.0}"), format!("{:.2}×", ns / b)),
                (Some(ns), None) => (format!("{ns:.0}"), "—".into()),
                _ => ("—".into(), "—".into()),
            };
            writeln!(
                f,
                "{:>5} {:<13} {:>10} {:>10} {:>12.1} {:>12.1}",
                r.n, r.implementation, ns, ratio, r.sqnr_db_m12, r.sqnr_db_m40
            )?;
        }
        if let Some(why) = &self.cmsis_missing {
            writeln!(f, "CMSIS rows missing: {why}")?;
        }
        Ok(())
    }
}
