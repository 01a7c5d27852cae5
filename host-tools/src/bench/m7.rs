//! `metamoran bench fft-m7`: FFT instruction counts on the Cortex-M7 under QEMU.
//!
//! Method: the `fft-icount` firmware runs under `qemu-system-arm -icount shift=0`, where each
//! guest instruction advances virtual time by exactly 1 ns; CMSDK timer 0 counts down at 25 MHz,
//! i.e. one tick per 40 instructions. The firmware reads the timer around each FFT call and
//! subtracts an empty measurement. Counts are deterministic (±40 instructions of quantization).
//! The same run counts the channel calibration of one 512-sample chirp (`calibration_q15`).

use metamoran_edge::qemu;
use serde::Serialize;
use std::time::Duration;

/// CMSIS-DSP instruction counts measured the same way (given with the issue), for ratios.
pub const CMSIS_ANCHORS: [(&str, usize, u64); 4] = [
    ("cmsis_q15", 256, 12_640),
    ("cmsis_q15", 1024, 60_520),
    ("cmsis_f32", 256, 17_080),
    ("cmsis_f32", 1024, 77_200),
];

/// One measured FFT.
#[derive(Clone, Debug, Serialize)]
pub struct M7Row {
    /// Implementation (`q15`, `q31`, `microfft_f32`; `calibration_q15` is the range stage's
    /// channel calibration of one chirp, not an FFT).
    #[serde(rename = "impl")]
    pub implementation: String,
    /// FFT length.
    pub n: usize,
    /// Guest instructions per FFT.
    pub instructions: u64,
    /// Ratio to CMSIS `arm_cfft_q15` (fixed point) or `arm_cfft_f32` (float) at this length.
    pub vs_cmsis: Option<f64>,
}

/// The report.
#[derive(Clone, Debug, Serialize)]
pub struct M7Report {
    /// How the numbers were made.
    pub method: &'static str,
    /// Measured rows.
    pub fft: Vec<M7Row>,
}

/// Builds and runs the benchmark firmware.
///
/// # Errors
/// A message if the build or QEMU fails or the output cannot be parsed.
pub fn run(firmware: &std::path::Path) -> Result<M7Report, crate::Error> {
    let elf = qemu::build(firmware, "fft-icount", None)?;
    let out = qemu::run(&elf, true, Duration::from_secs(120))?;
    let mut fft = Vec::new();
    for line in out.lines().filter(|l| l.starts_with("ICOUNT impl=")) {
        let field = |k: &str| {
            line.split_whitespace()
                .find_map(|w| w.strip_prefix(k))
                .ok_or(format!("bad line: {line}"))
        };
        let implementation = field("impl=")?.to_owned();
        let n: usize = field("n=")?
            .parse()
            .map_err(|_| format!("bad line: {line}"))?;
        let instructions: u64 = field("instructions=")?
            .parse()
            .map_err(|_| format!("bad line: {line}"))?;
        let anchor = if implementation.ends_with("f32") {
            "cmsis_f32"
        } else {
            "cmsis_q15"
        };
        let vs_cmsis = CMSIS_ANCHORS
            .iter()
            .find(|a| a.0 == anchor && a.1 == n)
            .map(|a| instructions as f64 / a.2 as f64);
        fft.push(M7Row {
            implementation,
            n,
            instructions,
            vs_cmsis,
        });
    }
    if fft.is_empty() {
        return Err(format!("the benchmark printed no counts:\n{out}").into());
    }
    Ok(M7Report {
        method: "qemu-system-arm -machine mps2-an500 -icount shift=0; CMSDK timer 0 ticks x 40",
        fft,
    })
}

impl std::fmt::Display for M7Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "Cortex-M7 instruction counts ({})", self.method)?;
        writeln!(
            f,
            "{:<14} {:>5} {:>13} {:>10}",
            "impl", "n", "instructions", "vs CMSIS"
        )?;
        for r in &self.fft {
            let ratio = r.vs_cmsis.map_or("—".into(), |x| format!("{x:.2}×"));
            writeln!(
                f,
                "{:<14} {:>5} {:>13} {:>10}",
                r.implementation, r.n, r.instructions, ratio
            )?;
        }
        writeln!(
            f,
            "CMSIS anchors (same method): arm_cfft_q15 12,640 (256) / 60,520 (1024); arm_cfft_f32 17,080 / 77,200"
        )
    }
}
