//! Channel calibration, the first step of the range stage: each (TX, RX) channel's samples are
//! multiplied by its complex gain and de-rotated by its beat-frequency (range-delay) offset
//! before any channels are summed, so that elements built from several channels and the
//! azimuth beams see one coherent array.
//!
//! The calibrated sample `n` of channel `(t, r)` is `g · exp(j·2π·f·n/N) · x[n]` (`N` =
//! `adc_samples`, `f` in range bins of an `N`-point transform), the meaning of `metamoran
//! calibrate`'s output. Gains are stored in Q15 after dividing all of them by the largest
//! magnitude, so no product can grow past the input's range; a common scale changes no ratio
//! the search reads.
//!
//! ```
//! use metamoran_dsp::fixed::CQ15;
//! use metamoran_dsp::range::calibration::{Calibration, Correction};
//! // Two RX on one TX: the second lags by 90° and is half as strong.
//! let mut cal = Calibration::identity(1, 2).unwrap();
//! cal.set(0, 1, Correction::from_f64((0.0, 2.0), 0.0, 4)).unwrap();
//! let cal = cal.normalized();
//! let x = [CQ15::from_raw(0, -4000); 4];
//! let mut y = [CQ15::default(); 4];
//! cal.apply(0, 1, &x, &mut y).unwrap();
//! // 2·(−j·4000) · j = 8000, then halved by the normalization: 4000.
//! assert!((y[0].re.0 - 4000).abs() <= 1 && y[0].im.0.abs() <= 1);
//! ```

use crate::config::{MAX_RX, MAX_TX};
use crate::fixed::{CQ15, Q15};
use crate::trig::{Phase, expj_neg};

/// One channel's correction: a complex gain and a frequency offset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Correction {
    /// Complex gain (re, im), any scale.
    pub gain: (f64, f64),
    /// Frequency offset per sample, turns (`f / N`).
    pub step: Phase,
}

impl Correction {
    /// The correction `gain · exp(j·2π·bins·n/samples)`.
    pub fn from_f64(gain: (f64, f64), bins: f64, samples: u16) -> Self {
        Self {
            gain,
            step: Phase::from_turns(bins / f64::from(samples.max(1))),
        }
    }

    /// The identity: gain 1, no frequency offset.
    pub const IDENTITY: Self = Self {
        gain: (1.0, 0.0),
        step: Phase(0),
    };
}

/// A correction per (TX, RX) pair of a board, in the form the range stage applies.
#[derive(Clone, Debug, PartialEq)]
pub struct Calibration {
    tx: usize,
    rx: usize,
    corrections: [[Correction; MAX_RX]; MAX_TX],
}

/// [`Calibration::normalized`]: Q15 gains and per-sample phase steps.
#[derive(Clone, Debug, PartialEq)]
pub struct AppliedCalibration {
    tx: usize,
    rx: usize,
    gains: [[CQ15; MAX_RX]; MAX_TX],
    steps: [[Phase; MAX_RX]; MAX_TX],
}

/// Why a calibration cannot be built or applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CalibrationError {
    /// More TX or RX than the board may have.
    Size {
        /// TX given.
        tx: usize,
        /// RX given.
        rx: usize,
    },
    /// A (TX, RX) pair outside the board.
    Channel {
        /// TX index.
        tx: usize,
        /// RX index.
        rx: usize,
    },
    /// Input and output rows differ in length.
    Length,
    /// More chirps per virtual element in a frame than the module's calibrated sums hold.
    Chirps {
        /// Chirps an element takes per frame.
        per_element: usize,
        /// The most the module takes calibrated.
        max: usize,
    },
}

impl core::error::Error for CalibrationError {}

impl core::fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Self::Size { tx, rx } => write!(
                f,
                "a calibration for {tx} TX × {rx} RX: at most {MAX_TX} × {MAX_RX} are supported"
            ),
            Self::Channel { tx, rx } => write!(
                f,
                "channel (tx {tx}, rx {rx}) is not on the board: check the calibration against tx_positions and rx_positions"
            ),
            Self::Length => f.write_str("calibration input and output rows differ in length"),
            Self::Chirps { per_element, max } => write!(
                f,
                "a frame sums {per_element} chirps into one virtual element; the module applies a calibration to at most {max}: use fewer loops per frame, or calibrate on the host"
            ),
        }
    }
}

impl Calibration {
    /// No correction on any of `tx × rx` channels.
    ///
    /// # Errors
    /// [`CalibrationError::Size`] beyond [`MAX_TX`] × [`MAX_RX`].
    pub fn identity(tx: usize, rx: usize) -> Result<Self, CalibrationError> {
        if tx == 0 || rx == 0 || tx > MAX_TX || rx > MAX_RX {
            return Err(CalibrationError::Size { tx, rx });
        }
        Ok(Self {
            tx,
            rx,
            corrections: [[Correction::IDENTITY; MAX_RX]; MAX_TX],
        })
    }

    /// Sets channel `(tx, rx)`'s correction.
    ///
    /// # Errors
    /// [`CalibrationError::Channel`] for a pair outside the board.
    pub fn set(&mut self, tx: usize, rx: usize, c: Correction) -> Result<(), CalibrationError> {
        match self.corrections.get_mut(tx).and_then(|row| row.get_mut(rx)) {
            Some(slot) if tx < self.tx && rx < self.rx => {
                *slot = c;
                Ok(())
            }
            _ => Err(CalibrationError::Channel { tx, rx }),
        }
    }

    /// Channel `(tx, rx)`'s correction, if on the board.
    pub fn get(&self, tx: usize, rx: usize) -> Option<Correction> {
        let c = self.corrections.get(tx).and_then(|row| row.get(rx));
        c.copied().filter(|_| tx < self.tx && rx < self.rx)
    }

    /// TX and RX counts.
    pub fn size(&self) -> (usize, usize) {
        (self.tx, self.rx)
    }

    /// Q15 form: every gain divided by the largest magnitude (a calibration of zero gains, or a
    /// non-finite one, gives zero gains). O(TX · RX).
    pub fn normalized(&self) -> AppliedCalibration {
        let mut peak = 0.0f64;
        for row in self.corrections.iter().take(self.tx) {
            for c in row.iter().take(self.rx) {
                peak = peak.max(libm::hypot(c.gain.0, c.gain.1));
            }
        }
        let scale = if peak.is_finite() && peak > 0.0 {
            // Just under one, so that the largest gain stays inside Q15.
            32_767.0 / peak
        } else {
            0.0
        };
        let q = |v: f64| {
            let r = libm::round(v * scale);
            if r.is_finite() {
                r.clamp(-32_768.0, 32_767.0) as i16
            } else {
                0
            }
        };
        let mut gains = [[CQ15::default(); MAX_RX]; MAX_TX];
        let mut steps = [[Phase(0); MAX_RX]; MAX_TX];
        let rows = gains.iter_mut().zip(&mut steps).zip(&self.corrections);
        for ((g, p), c) in rows.take(self.tx) {
            for ((g, p), c) in g.iter_mut().zip(p.iter_mut()).zip(c).take(self.rx) {
                *g = CQ15::from_raw(q(c.gain.0), q(c.gain.1));
                *p = c.step;
            }
        }
        AppliedCalibration {
            tx: self.tx,
            rx: self.rx,
            gains,
            steps,
        }
    }
}

/// `a · b` of Q15 values, rounded, saturating (`−1 · −1`).
#[inline(always)]
fn mul_q15(a: CQ15, b: CQ15) -> CQ15 {
    let (ar, ai, br, bi) = (
        i64::from(a.re.0),
        i64::from(a.im.0),
        i64::from(b.re.0),
        i64::from(b.im.0),
    );
    let part = |v: i64| Q15(((v + (1 << 14)) >> 15).clamp(-32_768, 32_767) as i16);
    CQ15::new(part(ar * br - ai * bi), part(ar * bi + ai * br))
}

impl AppliedCalibration {
    /// Calibrates one chirp of channel `(tx, rx)`: `out[n] = g · exp(j·2π·step·n) · x[n]`,
    /// rounded and saturated to Q15. O(N), about two complex products per sample; bit-identical
    /// everywhere (integer arithmetic and the twiddle table).
    ///
    /// # Errors
    /// [`CalibrationError`] for a pair outside the board or rows of different lengths.
    pub fn apply(
        &self,
        tx: usize,
        rx: usize,
        x: &[CQ15],
        out: &mut [CQ15],
    ) -> Result<(), CalibrationError> {
        let Some((g, Phase(step))) = self.get(tx, rx) else {
            return Err(CalibrationError::Channel { tx, rx });
        };
        if x.len() != out.len() {
            return Err(CalibrationError::Length);
        }
        if step == 0 {
            for (o, &v) in out.iter_mut().zip(x) {
                *o = mul_q15(g, v);
            }
            return Ok(());
        }
        let mut phase = 0u32;
        for (o, &v) in out.iter_mut().zip(x) {
            // exp(+j·2π·phase) = exp(−j·2π·(−phase)).
            let rot = expj_neg(Phase(phase.wrapping_neg()));
            *o = mul_q15(mul_q15(g, rot), v);
            phase = phase.wrapping_add(step);
        }
        Ok(())
    }

    /// TX and RX counts.
    pub fn size(&self) -> (usize, usize) {
        (self.tx, self.rx)
    }

    /// An identity calibration of `tx × rx` channels in Q15 form, to fill with
    /// [`Self::set`] (the module builds one from the messages of the link).
    ///
    /// # Errors
    /// [`CalibrationError::Size`] beyond [`MAX_TX`] × [`MAX_RX`].
    pub fn identity(tx: usize, rx: usize) -> Result<Self, CalibrationError> {
        Ok(Calibration::identity(tx, rx)?.normalized())
    }

    /// Channel `(tx, rx)`'s Q15 gain and per-sample phase step, if on the board.
    pub fn get(&self, tx: usize, rx: usize) -> Option<(CQ15, Phase)> {
        let g = self.gains.get(tx).and_then(|row| row.get(rx));
        let p = self.steps.get(tx).and_then(|row| row.get(rx));
        g.copied()
            .zip(p.copied())
            .filter(|_| tx < self.tx && rx < self.rx)
    }

    /// Sets channel `(tx, rx)`'s Q15 gain and per-sample phase step (as [`Self::get`] gives
    /// them; the gains of one calibration share one scale).
    ///
    /// # Errors
    /// [`CalibrationError::Channel`] for a pair outside the board.
    pub fn set(
        &mut self,
        tx: usize,
        rx: usize,
        gain: CQ15,
        step: Phase,
    ) -> Result<(), CalibrationError> {
        let g = self.gains.get_mut(tx).and_then(|row| row.get_mut(rx));
        let p = self.steps.get_mut(tx).and_then(|row| row.get_mut(rx));
        match (g, p) {
            (Some(g), Some(p)) if tx < self.tx && rx < self.rx => {
                (*g, *p) = (gain, step);
                Ok(())
            }
            _ => Err(CalibrationError::Channel { tx, rx }),
        }
    }

    /// Channel `(tx, rx)`'s correction of an `n`-sample chirp as one coefficient per block of
    /// [`BLOCK_LEN`] samples (the last block may be shorter), for the module's range
    /// stage, which multiplies and sums in one pass (`FrameSum::add_calibrated`): block `b`'s
    /// coefficient is `g · exp(j·2π·step·c_b)` at the block's centre `c_b`, rounded to
    /// Q(15 − `headroom`) so that sums of up to `2^headroom − 1` products stay inside `i32`.
    /// Writes [`blocks`]`(n)` packed words to `out`. The phase within a block is off by at most
    /// `π · f · L / N` (f the offset in bins, L = 16: 5.6° for one bin at N = 512, 11° at 256).
    /// O(blocks).
    ///
    /// # Errors
    /// [`CalibrationError`] for a pair outside the board or `out` shorter than the blocks.
    pub fn block_coefficients(
        &self,
        tx: usize,
        rx: usize,
        n: usize,
        headroom: u32,
        out: &mut [u32],
    ) -> Result<(), CalibrationError> {
        let Some((g, step)) = self.get(tx, rx) else {
            return Err(CalibrationError::Channel { tx, rx });
        };
        let (len, count) = (BLOCK_LEN, blocks(n));
        let Some(out) = out.get_mut(..count) else {
            return Err(CalibrationError::Length);
        };
        let down = headroom.min(15);
        let part = |v: i16| {
            if down == 0 {
                v
            } else {
                ((i32::from(v) + (1 << (down - 1))) >> down) as i16
            }
        };
        for (b, o) in out.iter_mut().enumerate() {
            let start = b * len;
            let here = len.min(n.saturating_sub(start));
            // Twice the centre, so that a half sample stays exact: phase = step · (2s + l − 1) / 2,
            // the step signed (a wrapped negative step halved unsigned would be half a turn off).
            let twice = (2 * start + here).saturating_sub(1) as i64;
            let phase = ((i64::from(step.0 as i32) * twice) >> 1) as u32;
            // exp(+j·2π·phase) = exp(−j·2π·(−phase)), as `apply` turns.
            let c = mul_q15(g, expj_neg(Phase(phase.wrapping_neg())));
            *o = crate::range::frame_sum::pack(CQ15::from_raw(part(c.re.0), part(c.im.0)));
        }
        Ok(())
    }
}

/// Samples per block of [`AppliedCalibration::block_coefficients`]: the M7's unrolled
/// multiply-accumulate loop's unit (`fft::simd::mac_add_blocks`).
pub const BLOCK_LEN: usize = 16;

/// Blocks of [`BLOCK_LEN`] in an `n`-sample chirp (the last may be short).
pub const fn blocks(n: usize) -> usize {
    n.div_ceil(BLOCK_LEN)
}

/// Blocks of the longest chirp the module's calibration table is sized for (512 samples: 32
/// blocks, 24 KiB for a 192-channel cascade).
pub const BLOCKS: usize = 32;

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec;
    use std::vec::Vec;

    /// The f64 definition, scaled as `normalized` scales.
    fn reference(
        gain: (f64, f64),
        bins: f64,
        n_len: u16,
        scale: f64,
        x: &[CQ15],
    ) -> Vec<(f64, f64)> {
        x.iter()
            .enumerate()
            .map(|(n, v)| {
                let th = 2.0 * core::f64::consts::PI * bins * n as f64 / f64::from(n_len);
                let (s, c) = th.sin_cos();
                let (gr, gi) = (gain.0 * scale, gain.1 * scale);
                let (cr, ci) = (gr * c - gi * s, gr * s + gi * c);
                let (xr, xi) = (f64::from(v.re.0), f64::from(v.im.0));
                (cr * xr - ci * xi, cr * xi + ci * xr)
            })
            .collect()
    }

    #[test]
    fn apply_matches_the_f64_definition() {
        let n = 256u16;
        let mut cal = Calibration::identity(3, 4).unwrap();
        let cases = [
            (0, 0, (1.0, 0.0), 0.0),
            (1, 2, (0.3, -1.7), 0.37),
            (2, 3, (-0.9, 0.2), -0.49),
            (2, 0, (0.0, 1.1), 17.25),
        ];
        for &(t, r, g, f) in &cases {
            cal.set(t, r, Correction::from_f64(g, f, n)).unwrap();
        }
        let applied = cal.normalized();
        let peak = cases.iter().map(|c| c.2.0.hypot(c.2.1)).fold(0.0, f64::max);
        let x: Vec<CQ15> = (0..n as i32)
            .map(|i| {
                CQ15::from_raw(
                    ((i * 977) % 20_001 - 10_000) as i16,
                    ((i * 331) % 16_001 - 8_000) as i16,
                )
            })
            .collect();
        let mut y = vec![CQ15::default(); x.len()];
        for &(t, r, g, f) in &cases {
            applied.apply(t, r, &x, &mut y).unwrap();
            let want = reference(g, f, n, 32_767.0 / 32_768.0 / peak, &x);
            for (k, (o, w)) in y.iter().zip(&want).enumerate() {
                let err = (f64::from(o.re.0) - w.0)
                    .abs()
                    .max((f64::from(o.im.0) - w.1).abs());
                // Gain quantization (½ LSB of 2¹⁵ relative), the twiddle interpolation (2 LSB
                // relative) and two roundings, on inputs up to 1.4·10⁴.
                assert!(err < 4.0, "channel ({t},{r}) sample {k}: {o:?} vs {w:?}");
            }
        }
    }

    #[test]
    fn identity_passes_samples_through_scaled_by_one_lsb() {
        let applied = Calibration::identity(1, 1).unwrap().normalized();
        let x = [CQ15::from_raw(12_345, -32_768), CQ15::from_raw(-1, 7)];
        let mut y = [CQ15::default(); 2];
        applied.apply(0, 0, &x, &mut y).unwrap();
        assert_eq!(y, [CQ15::from_raw(12_345, -32_767), CQ15::from_raw(-1, 7)]);
    }

    #[test]
    fn channels_off_the_board_and_bad_rows_are_refused() {
        let mut cal = Calibration::identity(2, 4).unwrap();
        assert_eq!(
            cal.set(2, 0, Correction::IDENTITY),
            Err(CalibrationError::Channel { tx: 2, rx: 0 })
        );
        assert!(Calibration::identity(17, 1).is_err());
        assert!(Calibration::identity(1, 0).is_err());
        let a = cal.normalized();
        let mut out = [CQ15::default(); 3];
        assert_eq!(
            a.apply(0, 4, &[CQ15::default(); 3], &mut out),
            Err(CalibrationError::Channel { tx: 0, rx: 4 })
        );
        assert_eq!(
            a.apply(0, 0, &[CQ15::default(); 2], &mut out),
            Err(CalibrationError::Length)
        );
    }

    #[test]
    fn non_finite_gains_give_silence_not_garbage() {
        let mut cal = Calibration::identity(1, 2).unwrap();
        cal.set(0, 1, Correction::from_f64((f64::NAN, 0.0), 0.0, 8))
            .unwrap();
        let a = cal.normalized();
        let mut y = [CQ15::from_raw(1, 1); 2];
        a.apply(0, 1, &[CQ15::from_raw(100, 100); 2], &mut y)
            .unwrap();
        assert_eq!(y, [CQ15::default(); 2]);
        a.apply(0, 0, &[CQ15::from_raw(100, 100); 2], &mut y)
            .unwrap();
        assert_eq!(y, [CQ15::from_raw(100, 100); 2]);
    }

    /// Block coefficients are the f64 correction at each block's centre, in Q(15 − headroom),
    /// for chirp lengths that fill the blocks and that do not.
    #[test]
    fn block_coefficients_match_the_f64_correction_at_block_centres() {
        let mut cal = Calibration::identity(2, 2).unwrap();
        let cases = [
            (0, 0, (1.0, 0.0), 0.0),
            (1, 1, (-0.4, 0.9), 1.37),
            (0, 1, (0.2, -0.3), -0.6),
        ];
        for &(t, r, g, f) in &cases {
            cal.set(t, r, Correction::from_f64(g, f, 512)).unwrap();
        }
        let peak = cases.iter().map(|c| c.2.0.hypot(c.2.1)).fold(0.0, f64::max);
        let applied = cal.normalized();
        for (n, headroom) in [(512usize, 4u32), (100, 0), (256, 8)] {
            let len = BLOCK_LEN;
            assert!(blocks(n) <= BLOCKS && blocks(n) * len >= n && (blocks(n) - 1) * len < n);
            let mut out = vec![0u32; blocks(n)];
            for &(t, r, g, f) in &cases {
                applied
                    .block_coefficients(t, r, n, headroom, &mut out)
                    .unwrap();
                // The step was set for 512 samples: f / 512 turns per sample at any n.
                for (b, &w) in out.iter().enumerate() {
                    let (start, end) = (b * len, ((b + 1) * len).min(n));
                    let centre = (start + end - 1) as f64 / 2.0;
                    let th = 2.0 * core::f64::consts::PI * f * centre / 512.0;
                    let scale = 32_767.0 / peak / f64::from(1u32 << headroom);
                    let (gr, gi) = (g.0 * scale, g.1 * scale);
                    let want = (gr * th.cos() - gi * th.sin(), gr * th.sin() + gi * th.cos());
                    let c = crate::range::frame_sum::unpack(w);
                    let err = (f64::from(c.re.0) - want.0)
                        .abs()
                        .max((f64::from(c.im.0) - want.1).abs());
                    // Two Q15 roundings and the twiddle interpolation, then one more rounding.
                    assert!(
                        err < 1.0 + 3.0 / f64::from(1u32 << headroom),
                        "n {n} ({t},{r}) block {b}: {c:?} vs {want:?}"
                    );
                }
            }
        }
        assert_eq!(
            applied.block_coefficients(2, 0, 512, 4, &mut [0; 32]),
            Err(CalibrationError::Channel { tx: 2, rx: 0 })
        );
        assert_eq!(
            applied.block_coefficients(0, 0, 512, 4, &mut [0; 31]),
            Err(CalibrationError::Length)
        );
    }
}
