//! Channel calibration from a corner-reflector capture (TI's procedure; Metamoran §V,
//! "calibrated using a corner reflector placed at 5 m"), and the array coherence that says
//! whether a calibration works. Host-side, in `f64`: it runs once per board, not per frame.
//!
//! Per (TX, RX) pair the chirps of every frame are averaged; the reflector is the strongest
//! range bin of the power summed over channels. Each channel's peak is found on its windowed
//! DTFT (a quarter-bin grid over ±3 bins, then a golden-section search), which gives the frequency correction
//! `f = k_ref − k_c`; its value there, `Y_c = X_c(k_c)`, gives the gain `Y_ref / Y_c`. Both make
//! the calibrated channel `g · exp(j·2π·f·n/N) · x[n]` equal the reference at the reflector.

use crate::ProcessError;
use metamoran_bundle::RadarFile;
use metamoran_bundle::calibration::{
    CalibrationFile, CalibrationReport, ChannelCalibration, ChannelId,
};
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::window::{WindowKind, coefficient_f64};
use std::f64::consts::PI;
use std::fmt;

/// Nearest range the reflector may be searched at, m (DC and the TX–RX leakage sit below).
pub const MIN_TARGET_M: f64 = 1.0;

/// Why a capture gives no calibration.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CalibrateError {
    /// A TX that never transmits.
    #[error(
        "TX {tx} never transmits in tx_order, so its channels cannot be calibrated; record the calibration capture with every TX enabled"
    )]
    Silent {
        /// The TX.
        tx: usize,
    },
    /// The search window holds no range bin.
    #[error(
        "no range bin between {near_m:.2} and {far_m:.2} m (R_max {max_m:.1} m): give --target-m where the reflector stands"
    )]
    Window {
        /// Near end, m.
        near_m: f64,
        /// Far end, m.
        far_m: f64,
        /// The radar's R_max, m.
        max_m: f64,
    },
    /// A reference channel off the board.
    #[error(
        "reference channel (tx {tx}, rx {rx}) is not on the board ({txs} TX × {rxs} RX): pick another with --reference"
    )]
    Reference {
        /// TX asked for.
        tx: usize,
        /// RX asked for.
        rx: usize,
        /// TX on the board.
        txs: usize,
        /// RX on the board.
        rxs: usize,
    },
    /// A channel with nothing at the reflector.
    #[error(
        "channel (tx {tx}, rx {rx}) has no signal at the reflector: check the board and that the reflector is in view"
    )]
    Dead {
        /// TX.
        tx: usize,
        /// RX.
        rx: usize,
    },
}

/// A complex value in `f64`.
type C64 = (f64, f64);

fn mul(a: C64, b: C64) -> C64 {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

fn div(a: C64, b: C64) -> C64 {
    let d = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
}

fn abs(a: C64) -> f64 {
    a.0.hypot(a.1)
}

/// What to calibrate on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CalibrateOptions {
    /// The channel gains are relative to.
    pub reference: ChannelId,
    /// Where the reflector stands, m: the search keeps within ±1 m of it (`None`: the strongest
    /// reflector beyond [`MIN_TARGET_M`]).
    pub target_m: Option<f64>,
}

impl Default for CalibrateOptions {
    fn default() -> Self {
        Self {
            reference: ChannelId { tx: 0, rx: 0 },
            target_m: None,
        }
    }
}

/// Each (TX, RX) pair's chirps averaged over a capture: `N` samples per pair, TX-major.
#[derive(Clone, Debug)]
pub struct ChannelMeans {
    config: RadarConfig,
    means: Vec<Vec<C64>>,
}

impl ChannelMeans {
    /// Averages every chirp of `file` per (TX, RX) pair; `raw` skips the file's calibration.
    /// O(capture).
    ///
    /// # Errors
    /// [`ProcessError`] if a frame cannot be read or a TX never transmits.
    pub fn read(file: &mut RadarFile, raw: bool) -> Result<Self, ProcessError> {
        let config = file.config().clone();
        let (n, rx, tx) = (
            config.adc_samples as usize,
            config.rx_count(),
            config.tx_positions.len(),
        );
        let mut means = vec![vec![(0.0, 0.0); n]; tx * rx];
        let mut counts = vec![0u64; tx * rx];
        let mut frame = Vec::new();
        for f in 0..config.frames {
            if raw {
                file.read_raw_frame(f, &mut frame)?;
            } else {
                file.read_frame(f, &mut frame)?;
            }
            for (i, chirp) in frame.chunks_exact(n).enumerate() {
                let (slot, r) = ((i / rx) % config.slots(), i % rx);
                let ch = usize::from(config.tx_order[slot]) * rx + r;
                counts[ch] += 1;
                for (m, s) in means[ch].iter_mut().zip(chirp) {
                    m.0 += f64::from(s.re.0);
                    m.1 += f64::from(s.im.0);
                }
            }
        }
        if let Some(ch) = counts.iter().position(|&c| c == 0) {
            return Err(CalibrateError::Silent { tx: ch / rx }.into());
        }
        for (m, &c) in means.iter_mut().zip(&counts) {
            for v in m.iter_mut() {
                *v = (v.0 / c as f64, v.1 / c as f64);
            }
        }
        Ok(Self { config, means })
    }

    fn n(&self) -> usize {
        self.config.adc_samples as usize
    }

    /// Windowed DTFT of channel `ch` at fractional bin `k` (of an `N`-point transform). O(N).
    fn spectrum(&self, ch: usize, k: f64, window: &[f64]) -> C64 {
        let n = self.n();
        let w = -2.0 * PI * k / n as f64;
        let mut acc = (0.0, 0.0);
        for (i, (&x, &g)) in self.means[ch].iter().zip(window).enumerate() {
            let (s, c) = (w * i as f64).sin_cos();
            let v = mul((x.0 * g, x.1 * g), (c, s));
            acc = (acc.0 + v.0, acc.1 + v.1);
        }
        acc
    }

    fn window(&self) -> Vec<f64> {
        let n = self.n();
        (0..n)
            .map(|i| coefficient_f64(WindowKind::Hann, i, n))
            .collect()
    }

    /// The array coherence at the reflector at bin `peak` after `calibration` (`None`: as
    /// recorded): `|Σ_c Y_c| / Σ_c |Y_c|` over every channel, averaged over the bins
    /// `round(peak) − 1 ..= round(peak) + 1`, with `Y_c` channel c's calibrated spectrum
    /// (`g · X_c(b − f)`, `f` taken in this capture's bins: the file's own chirp). 1 for a
    /// coherent array; about `1/√C` for random phases.
    pub fn coherence(&self, peak: f64, calibration: Option<&CalibrationFile>) -> f64 {
        let window = self.window();
        let centre = peak.round();
        let rx = self.config.rx_count();
        let mut total = 0.0;
        for b in [centre - 1.0, centre, centre + 1.0] {
            let (mut sum, mut norms) = ((0.0, 0.0), 0.0);
            for ch in 0..self.means.len() {
                let (g, f) = calibration
                    .and_then(|c| {
                        c.channels
                            .iter()
                            .find(|e| e.tx == ch / rx && e.rx == ch % rx)
                    })
                    .map_or(((1.0, 0.0), 0.0), |e| {
                        ((e.gain[0], e.gain[1]), e.frequency_bins)
                    });
                let y = mul(g, self.spectrum(ch, b - f, &window));
                sum = (sum.0 + y.0, sum.1 + y.1);
                norms += abs(y);
            }
            total += if norms > 0.0 { abs(sum) / norms } else { 0.0 };
        }
        total / 3.0
    }

    /// The reflector's bin: the strongest of the power summed over channels, within ±1 m of
    /// `target_m` or beyond [`MIN_TARGET_M`] up to 0.9·R_max. O(C · N²).
    ///
    /// # Errors
    /// [`CalibrateError::Window`] when the search window holds no bin.
    pub fn reflector_bin(&self, target_m: Option<f64>) -> Result<usize, CalibrateError> {
        let n = self.n();
        let bin_m = f64::from(self.config.range_bin_size(n));
        let (near, far) = match target_m {
            Some(r) => (r - 1.0, r + 1.0),
            None => (MIN_TARGET_M, 0.9 * self.config.max_range_m()),
        };
        let lo = (near.max(MIN_TARGET_M) / bin_m).ceil() as usize;
        let hi = ((far.min(0.9 * self.config.max_range_m()) / bin_m).floor() as usize).min(n - 1);
        if lo > hi {
            return Err(CalibrateError::Window {
                near_m: near,
                far_m: far,
                max_m: self.config.max_range_m(),
            });
        }
        let window = self.window();
        let power = |k: usize| -> f64 {
            (0..self.means.len())
                .map(|ch| {
                    let v = self.spectrum(ch, k as f64, &window);
                    v.0 * v.0 + v.1 * v.1
                })
                .sum()
        };
        let mut best = (lo, f64::MIN);
        for k in lo..=hi {
            let p = power(k);
            if p > best.1 {
                best = (k, p);
            }
        }
        Ok(best.0)
    }

    /// Channel `ch`'s peak near `bin`: the best of a quarter-bin grid over `bin ± 3` (a
    /// channel's delay may put its peak bins away from the array's: the Hann main lobe is ±2
    /// bins wide), then a golden-section search of `|X_c(k)|` within a quarter bin of it.
    fn refine(&self, ch: usize, bin: usize, window: &[f64]) -> f64 {
        let f = |k: f64| abs(self.spectrum(ch, k, window));
        let start = (-12..=12)
            .map(|q| bin as f64 + f64::from(q) / 4.0)
            .map(|k| (k, f(k)))
            .fold(
                (bin as f64, f64::MIN),
                |best, x| if x.1 > best.1 { x } else { best },
            )
            .0;
        let gr = (5f64.sqrt() - 1.0) / 2.0;
        let (mut a, mut b) = (start - 0.25, start + 0.25);
        let (mut c, mut d) = (b - gr * (b - a), a + gr * (b - a));
        let (mut fc, mut fd) = (f(c), f(d));
        for _ in 0..48 {
            if fc > fd {
                b = d;
                d = c;
                fd = fc;
                c = b - gr * (b - a);
                fc = f(c);
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + gr * (b - a);
                fd = f(d);
            }
        }
        (a + b) / 2.0
    }
}

/// A calibration measured on a capture, with its quality.
#[derive(Clone, Debug)]
pub struct Measured {
    /// The calibration file.
    pub file: CalibrationFile,
    /// The reflector's range bin (fractional, reference channel).
    pub peak_bin: f64,
    /// Array coherence at the reflector as recorded.
    pub coherence_before: f64,
    /// Array coherence at the reflector after the calibration.
    pub coherence_after: f64,
}

/// Measures the calibration of `means` (see the module text). O(C · N²).
///
/// # Errors
/// [`CalibrateError`] for a reference channel off the board, no reflector or a channel that saw
/// nothing.
pub fn calibrate(
    means: &ChannelMeans,
    options: CalibrateOptions,
) -> Result<Measured, CalibrateError> {
    let config = &means.config;
    let (rx, tx) = (config.rx_count(), config.tx_positions.len());
    let r = options.reference;
    if r.tx >= tx || r.rx >= rx {
        return Err(CalibrateError::Reference {
            tx: r.tx,
            rx: r.rx,
            txs: tx,
            rxs: rx,
        });
    }
    let bin = means.reflector_bin(options.target_m)?;
    let window = means.window();
    let peaks: Vec<f64> = (0..tx * rx)
        .map(|ch| means.refine(ch, bin, &window))
        .collect();
    let values: Vec<C64> = peaks
        .iter()
        .enumerate()
        .map(|(ch, &k)| means.spectrum(ch, k, &window))
        .collect();
    let reference = r.tx * rx + r.rx;
    let (k_ref, y_ref) = (peaks[reference], values[reference]);
    let mut channels = Vec::with_capacity(tx * rx);
    for (ch, (&k, &y)) in peaks.iter().zip(&values).enumerate() {
        if abs(y) == 0.0 || !abs(y).is_finite() {
            return Err(CalibrateError::Dead {
                tx: ch / rx,
                rx: ch % rx,
            });
        }
        let g = div(y_ref, y);
        channels.push(ChannelCalibration {
            tx: ch / rx,
            rx: ch % rx,
            gain: [g.0, g.1],
            frequency_bins: k_ref - k,
        });
    }
    let n = config.adc_samples as usize;
    let report = CalibrationReport {
        reference: r,
        target_range_m: f64::from(config.bin_to_range(k_ref as f32, n)),
        channels,
    };
    let file = CalibrationFile::new(report, config);
    Ok(Measured {
        coherence_before: means.coherence(k_ref, None),
        coherence_after: means.coherence(k_ref, Some(&file)),
        peak_bin: k_ref,
        file,
    })
}

impl fmt::Display for Measured {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.file.channels;
        let phase: Vec<f64> = c
            .iter()
            .map(|e| e.gain[1].atan2(e.gain[0]).to_degrees())
            .collect();
        let db: Vec<f64> = c
            .iter()
            .map(|e| 20.0 * e.gain[0].hypot(e.gain[1]).log10())
            .collect();
        let bins: Vec<f64> = c.iter().map(|e| e.frequency_bins).collect();
        let span = |v: &[f64]| {
            v.iter()
                .fold((f64::MAX, f64::MIN), |(lo, hi), &x| (lo.min(x), hi.max(x)))
        };
        let (pl, ph) = span(&phase);
        let (gl, gh) = span(&db);
        let (fl, fh) = span(&bins);
        writeln!(
            f,
            "reflector    {:.3} m (bin {:.2}), reference tx {} rx {}",
            self.file.target_range_m, self.peak_bin, self.file.reference.tx, self.file.reference.rx
        )?;
        writeln!(f, "channels     {}", c.len())?;
        writeln!(f, "phase        {pl:+.1}° … {ph:+.1}°")?;
        writeln!(f, "gain         {gl:+.2} … {gh:+.2} dB")?;
        writeln!(f, "frequency    {fl:+.3} … {fh:+.3} bins")?;
        writeln!(
            f,
            "coherence    {:.3} as recorded → {:.3} calibrated (|Σ Y| / Σ |Y| at the reflector, ±1 bin)",
            self.coherence_before, self.coherence_after
        )
    }
}
