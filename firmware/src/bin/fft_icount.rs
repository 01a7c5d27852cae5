//! Instruction counts of FFTs on the Cortex-M7 under `qemu-system-arm -icount shift=0`.
//!
//! Prints `ICOUNT impl=… n=… instructions=…` per FFT: timer-0 ticks × 40, minus the cost of an
//! empty measurement, for our Q15 and Q31 FFTs and microfft's f32 FFT, all in the same run.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
mod app {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::hprintln;
    use firmware::board::{INSTRUCTIONS_PER_TICK, Timer0};
    use firmware::workload::{noise_q15, noise_q31};
    use metamoran_dsp::fft::{Complex32, cfft_f32, cfft_q15, cfft_q31};
    use metamoran_dsp::fixed::{CQ15, CQ31, Q15};
    use metamoran_dsp::range::calibration::{Calibration, Correction};

    firmware::hard_fault_exits!();

    /// Best of a few runs (they are identical under -icount; the minimum guards against setup).
    fn best(timer: &Timer0, mut f: impl FnMut(&Timer0) -> u32) -> u32 {
        (0..3).map(|_| f(timer)).min().unwrap_or(0)
    }

    #[entry]
    fn main() -> ! {
        let timer = Timer0::start();
        let overhead = best(&timer, |t| t.ticks(|| ()));
        let report = |name: &str, n: usize, ticks: u32| {
            hprintln!(
                "ICOUNT impl={} n={} instructions={}",
                name,
                n,
                ticks.saturating_sub(overhead) * INSTRUCTIONS_PER_TICK
            );
        };
        let mut q15 = [CQ15::default(); 1024];
        let mut q31 = [CQ31::default(); 1024];
        let mut f32b = [Complex32::new(0.0, 0.0); 1024];
        for n in [256usize, 1024] {
            let ticks = best(&timer, |t| {
                noise_q15(1, Q15(8192), &mut q15[..n]);
                t.ticks(|| {
                    let _ = cfft_q15(core::hint::black_box(&mut q15[..n]));
                })
            });
            report("q15", n, ticks);
            let ticks = best(&timer, |t| {
                noise_q31(1, Q15(8192), &mut q31[..n]);
                t.ticks(|| {
                    let _ = cfft_q31(core::hint::black_box(&mut q31[..n]));
                })
            });
            report("q31", n, ticks);
            let ticks = best(&timer, |t| {
                noise_q15(1, Q15(8192), &mut q15[..n]);
                for (o, z) in f32b.iter_mut().zip(&q15[..n]) {
                    *o = Complex32::new(z.re.to_f32(), z.im.to_f32());
                }
                t.ticks(|| {
                    let _ = cfft_f32(core::hint::black_box(&mut f32b[..n]));
                })
            });
            report("microfft_f32", n, ticks);
        }
        // The range stage's channel calibration (issue #19): one 512-sample chirp of one
        // channel with a gain and a frequency correction, the per-row cost a calibrated frame
        // would add.
        let Ok(mut cal) = Calibration::identity(12, 16) else {
            firmware::board::exit(false)
        };
        let _ = cal.set(3, 5, Correction::from_f64((0.8, -0.6), 0.37, 512));
        let applied = cal.normalized();
        let mut out = [CQ15::default(); 512];
        let ticks = best(&timer, |t| {
            noise_q15(1, Q15(8192), &mut q15[..512]);
            t.ticks(|| {
                let _ = applied.apply(3, 5, core::hint::black_box(&q15[..512]), &mut out);
            })
        });
        report("calibration_q15", 512, ticks);
        hprintln!("ICOUNT done");
        firmware::board::exit(true)
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("fft-icount runs on thumbv7em-none-eabihf under QEMU: metamoran bench fft-m7");
    std::process::exit(2);
}
