//! The static scene of a frame on the module: chirps summed over loops per virtual *element* as
//! they stream in (exact `i32` sums; channels at the same position add into one element), then
//! windowed and range-transformed in place into Q15 spectra with one block exponent.
//!
//! **Memory.** One caller-owned word arena of [`FrameSum::words_needed`] `u32`s holds both
//! stages: element `e`'s sums occupy words `e·S .. e·S + 2N` (`S = max(2N, M)`, re and im as
//! `i32`); its spectrum is written to words `e·M .. (e+1)·M` (one packed `CQ15` per word) after
//! the sums of rows `≤ e` are consumed, so the transform never overwrites unread sums. The rows
//! are then copied to the upper half and interleaved back **bin-major** (word `k·E + e` holds
//! element e's bin k): every consumer reads a whole bin across the array (beamforming, the
//! azimuth FFT), and a contiguous column lets the M7 stream it with post-incremented loads
//! instead of a 2 KiB stride. The words after the spectra are free for the per-object search
//! ([`FrameSum::finish`] hands them back). For the 86-element, 512-sample cascade board this is
//! 352 KiB in all (`2·E·M` words), of which the spectra take 176 KiB.

use super::RangeError;
use crate::array::MAX_CHANNELS;
use crate::fft::{self, Exponent};
use crate::fixed::{CQ15, Q15};
use heapless::Vec;

/// Packs a complex Q15 value into one word (real part in the low half).
#[inline(always)]
pub const fn pack(z: CQ15) -> u32 {
    (z.re.0 as u16 as u32) | ((z.im.0 as u16 as u32) << 16)
}

/// Unpacks a word written by [`pack`].
#[inline(always)]
pub const fn unpack(w: u32) -> CQ15 {
    CQ15::from_raw(w as u16 as i16, (w >> 16) as u16 as i16)
}

/// Accumulates a frame's chirps per element.
pub struct FrameSum<'a> {
    words: &'a mut [u32],
    elements: usize,
    n: usize,
    m: usize,
    /// Chirps added so far (saturates).
    rows: u32,
    /// Calibrated sums ([`FrameSum::new_calibrated`]): the coefficients' headroom bits and the
    /// rows each element took so far.
    calibrated: Option<(u32, Vec<u16, MAX_CHANNELS>)>,
}

/// Chirps a frame may add before its sums need saturating additions: no element can then hold
/// more than this many, and `65_535 · 2¹⁵ < 2³¹`, so the plain `i32` sums are exact.
const EXACT_ROWS: u32 = 65_535;

/// A frame's range spectra: `elements × M` Q15 values, all scaled by `2^exponent` (input LSB
/// units, windowed).
#[derive(Clone, Copy)]
pub struct Spectra<'a> {
    words: &'a [u32],
    elements: usize,
    m: usize,
    exponent: i32,
}

impl<'a> FrameSum<'a> {
    /// Arena words needed for `elements` elements of `n` samples and an `m`-point range FFT:
    /// the sums, or the spectra and their copy while they are interleaved, whichever is more.
    pub const fn words_needed(elements: usize, n: usize, m: usize) -> usize {
        let stride = Self::sum_stride(n, m);
        if stride > 2 * m {
            elements * stride
        } else {
            elements * 2 * m
        }
    }

    /// Words between two elements' sums.
    const fn sum_stride(n: usize, m: usize) -> usize {
        if 2 * n > m { 2 * n } else { m }
    }

    fn stride(&self) -> usize {
        Self::sum_stride(self.n, self.m)
    }

    /// An empty frame over `words`.
    ///
    /// # Errors
    /// [`RangeError`] if `m` is not a supported FFT length at least `n`, there are more than
    /// [`MAX_CHANNELS`] elements, or `words` is too small.
    pub fn new(
        words: &'a mut [u32],
        elements: usize,
        n: usize,
        m: usize,
    ) -> Result<Self, RangeError> {
        if !fft::is_supported_len(m) || n == 0 || n > m {
            return Err(RangeError::Samples {
                expected: m,
                got: n,
            });
        }
        if elements == 0 || elements > MAX_CHANNELS {
            return Err(RangeError::Index {
                what: "element count",
                index: elements,
                len: MAX_CHANNELS + 1,
            });
        }
        let need = Self::words_needed(elements, n, m);
        if words.len() < need {
            return Err(RangeError::Buffer {
                what: "frame arena (u32 words)",
                expected: need,
                got: words.len(),
            });
        }
        words[..need].fill(0);
        Ok(Self {
            words,
            elements,
            n,
            m,
            rows: 0,
            calibrated: None,
        })
    }

    /// An empty frame whose chirps come calibrated ([`Self::add_calibrated`] only): each is
    /// multiplied by coefficients of Q(15 − `headroom`) as it is summed, so an element may take
    /// at most `2^headroom − 1` chirps and the spectra's exponent is lowered by 15 − `headroom`
    /// (they stay in input LSB units).
    ///
    /// # Errors
    /// As [`Self::new`], or a headroom above 15.
    pub fn new_calibrated(
        words: &'a mut [u32],
        elements: usize,
        n: usize,
        m: usize,
        headroom: u32,
    ) -> Result<Self, RangeError> {
        if headroom > 15 {
            return Err(RangeError::Index {
                what: "calibration headroom (bits)",
                index: headroom as usize,
                len: 16,
            });
        }
        let mut frame = Self::new(words, elements, n, m)?;
        let mut counts = Vec::new();
        let _ = counts.resize(elements, 0);
        frame.calibrated = Some((headroom, counts));
        Ok(frame)
    }

    /// Adds one chirp of one channel multiplied by its block coefficients (`coefficients[b]`,
    /// packed, for samples `16·b ..`, as `calibration::AppliedCalibration::block_coefficients`
    /// makes them) into its element's sums, products exact. O(N): on the M7 3.7 instructions
    /// per sample (`fft::simd::mac_add_blocks`), fewer than an uncalibrated chirp.
    ///
    /// # Errors
    /// [`RangeError`] for an element out of range, a wrong sample count, too few coefficients,
    /// a frame not made by [`Self::new_calibrated`], or an element past its chirps.
    pub fn add_calibrated(
        &mut self,
        element: usize,
        chirp: &[CQ15],
        coefficients: &[u32],
    ) -> Result<(), RangeError> {
        let (n, start) = (self.n, element.saturating_mul(self.stride()));
        let Some((headroom, counts)) = self.calibrated.as_mut() else {
            return Err(RangeError::Buffer {
                what: "calibrated frame (FrameSum::new_calibrated)",
                expected: 1,
                got: 0,
            });
        };
        let Some(count) = counts.get_mut(element) else {
            return Err(RangeError::Index {
                what: "element",
                index: element,
                len: self.elements,
            });
        };
        if u32::from(*count) + 1 >= 1 << *headroom {
            return Err(RangeError::Index {
                what: "calibrated chirps of an element",
                index: usize::from(*count) + 1,
                len: (1usize << *headroom) - 1,
            });
        }
        if chirp.len() != n {
            return Err(RangeError::Samples {
                expected: n,
                got: chirp.len(),
            });
        }
        let blocks = super::calibration::blocks(n);
        if coefficients.len() < blocks {
            return Err(RangeError::Buffer {
                what: "calibration coefficients",
                expected: blocks,
                got: coefficients.len(),
            });
        }
        *count += 1;
        let Some(row) = self.words.get_mut(start..start + 2 * n) else {
            return Err(RangeError::Buffer {
                what: "frame arena (u32 words)",
                expected: start + 2 * n,
                got: self.words.len(),
            });
        };
        fft::simd::mac_add_blocks(row, crate::fixed::words(chirp), coefficients);
        self.rows = self.rows.saturating_add(1);
        Ok(())
    }

    /// The arena turned out smaller than [`Self::words_needed`] (checked in [`Self::new`], so
    /// only reachable through a logic error; reported, never a panic).
    fn arena_error(&self) -> RangeError {
        RangeError::Buffer {
            what: "frame arena (u32 words)",
            expected: Self::words_needed(self.elements, self.n, self.m),
            got: self.words.len(),
        }
    }

    /// Adds one chirp of one channel into its element's sums (saturating). O(N): on the M7 the
    /// first `EXACT_ROWS` chirps of a frame take five instructions per sample
    /// (`fft::simd::widen_add`), since no sum can overflow yet; later ones saturate.
    ///
    /// # Errors
    /// [`RangeError`] for an element out of range or a wrong sample count.
    pub fn add(&mut self, element: usize, chirp: &[CQ15]) -> Result<(), RangeError> {
        if element >= self.elements {
            return Err(RangeError::Index {
                what: "element",
                index: element,
                len: self.elements,
            });
        }
        if self.calibrated.is_some() {
            return Err(RangeError::Buffer {
                what: "uncalibrated frame (FrameSum::new)",
                expected: 1,
                got: 0,
            });
        }
        if chirp.len() != self.n {
            return Err(RangeError::Samples {
                expected: self.n,
                got: chirp.len(),
            });
        }
        let start = element * self.stride();
        let Some(row) = self.words.get_mut(start..start + 2 * self.n) else {
            return Err(self.arena_error());
        };
        if self.rows < EXACT_ROWS {
            fft::simd::widen_add(row, crate::fixed::words(chirp));
        } else {
            for (acc, z) in row.chunks_exact_mut(2).zip(chirp) {
                acc[0] = (acc[0] as i32).saturating_add(z.re.0 as i32) as u32;
                acc[1] = (acc[1] as i32).saturating_add(z.im.0 as i32) as u32;
            }
        }
        self.rows = self.rows.saturating_add(1);
        Ok(())
    }

    /// Windows each element's sums (`window.len() == N`), transforms them in place, and aligns
    /// every row to the largest block exponent. `scratch` holds `M` values. Returns the spectra
    /// and the arena's free words. O(E·M log M).
    ///
    /// # Errors
    /// [`RangeError`] for a wrong window or scratch length.
    pub fn finish(
        self,
        window: &[Q15],
        scratch: &mut [CQ15],
    ) -> Result<(Spectra<'a>, &'a mut [u32]), RangeError> {
        let (n, m, stride) = (self.n, self.m, self.stride());
        if window.len() != n {
            return Err(RangeError::Samples {
                expected: n,
                got: window.len(),
            });
        }
        let Some(row) = scratch.get_mut(..m) else {
            return Err(RangeError::Buffer {
                what: "range scratch",
                expected: m,
                got: scratch.len(),
            });
        };
        let mut exps: Vec<i32, MAX_CHANNELS> = Vec::new();
        for e in 0..self.elements {
            let Some(sums) = self.words.get(e * stride..e * stride + 2 * n) else {
                return Err(self.arena_error());
            };
            let shift = normalizing_shift(sums);
            normalize(row, sums, window, shift);
            row.iter_mut().skip(n).for_each(|z| *z = CQ15::default());
            // Reordered on the copy out, not in place.
            let Exponent(fe) = fft::cfft_q15_bit_reversed(row)?;
            let _ = exps.push(shift + fe as i32);
            let Some(out) = self.words.get_mut(e * m..(e + 1) * m) else {
                return Err(self.arena_error());
            };
            let row = crate::fixed::words(row);
            for (k, w) in out.iter_mut().enumerate() {
                *w = row.get(fft::bit_reversed(k, m)).copied().unwrap_or(0);
            }
        }
        let exponent = exps.iter().copied().max().unwrap_or(0);
        // Calibrated sums carry the coefficients' 15 − headroom fraction bits.
        let scale = self.calibrated.as_ref().map_or(0, |(h, _)| 15 - *h as i32);
        // Interleave bin-major through a copy of the rows in the upper half, aligning each row
        // to the common exponent on the way: O(E·M), a few per cent of the transforms.
        let size = self.elements * m;
        let error = self.arena_error();
        let Some((spec, rest)) = self.words.split_at_mut_checked(size) else {
            return Err(error);
        };
        let Some(rows) = rest.get_mut(..size) else {
            return Err(error);
        };
        for (r, &s) in rows.iter_mut().zip(spec.iter()) {
            *r = s;
        }
        // Row by row, each with its own constant shift, written strided into the bin-major
        // layout: word k·E + e.
        for (e, (row, &x)) in rows.chunks_exact(m.max(1)).zip(&exps).enumerate() {
            let column = spec
                .get_mut(e..)
                .unwrap_or_default()
                .iter_mut()
                .step_by(self.elements.max(1));
            align_row(column, row, (exponent - x) as u32);
        }
        Ok((
            Spectra {
                words: spec,
                elements: self.elements,
                m,
                exponent: exponent - scale,
            },
            rest,
        ))
    }
}

impl<'a> Spectra<'a> {
    /// Spectra over packed words already laid out bin-major (word [`Self::word_index`]`(e, k,
    /// elements)` holds element e's bin k; e.g. built on the host).
    ///
    /// # Errors
    /// [`RangeError::Buffer`] if `words.len() != elements · m`.
    pub fn from_words(
        words: &'a [u32],
        elements: usize,
        m: usize,
        exponent: i32,
    ) -> Result<Self, RangeError> {
        if words.len() != elements * m || m == 0 {
            return Err(RangeError::Buffer {
                what: "spectra words",
                expected: elements * m,
                got: words.len(),
            });
        }
        Ok(Self {
            words,
            elements,
            m,
            exponent,
        })
    }

    /// Elements (rows).
    pub fn elements(&self) -> usize {
        self.elements
    }

    /// Range bins per row (M).
    pub fn bins(&self) -> usize {
        self.m
    }

    /// Every stored value is the true value (input LSB, windowed) divided by `2^exponent`.
    pub fn exponent(&self) -> i32 {
        self.exponent
    }

    /// The word that holds element `e`'s bin `k` in spectra of `elements` elements.
    #[inline(always)]
    pub const fn word_index(e: usize, k: usize, elements: usize) -> usize {
        k * elements + e
    }

    /// Bin `k` of element `e` (zero out of range).
    #[inline(always)]
    pub fn get(&self, e: usize, k: usize) -> CQ15 {
        if e < self.elements {
            self.words
                .get(Self::word_index(e, k, self.elements))
                .map_or(CQ15::default(), |&w| unpack(w))
        } else {
            CQ15::default()
        }
    }

    /// Bin `k` of every element, as packed words (empty beyond the spectrum). Contiguous.
    #[inline]
    pub fn column(&self, k: usize) -> &[u32] {
        self.columns(k..k + 1)
    }

    /// Bins `bins` (clipped to the spectrum) of every element, bin after bin: one contiguous
    /// block of `elements` words per bin.
    #[inline]
    pub fn columns(&self, bins: core::ops::Range<usize>) -> &[u32] {
        let (e, end) = (self.elements, bins.end.min(self.m));
        self.words.get(bins.start * e..end * e).unwrap_or(&[])
    }
}

/// `row` scaled down by `2^down` with rounding into `out` (as [`CQ15::scale_down`], with the
/// shift's constants hoisted out of the loop). O(len).
fn align_row<'w>(out: impl Iterator<Item = &'w mut u32>, row: &[u32], down: u32) {
    match down {
        0 => out.zip(row).for_each(|(o, &w)| *o = w),
        16.. => out.for_each(|o| *o = 0),
        d => {
            let half = 1i32 << (d - 1);
            let part = |x: i32| ((x + half) >> d) as u16 as u32;
            out.zip(row)
                .for_each(|(o, &w)| *o = part(w as i16 as i32) | part((w as i32) >> 16) << 16);
        }
    }
}

/// The smallest `shift ≥ −15` with every sum in `[−2^(15 + shift), 2^(15 + shift))`.
///
/// `v ^ (v << 1)` has its top bit at `t` for `v` in `[−2^t, 2^t)` (where the sign bit's run
/// ends), so the OR over the sums bounds them all: two instructions a word.
fn normalizing_shift(sums: &[u32]) -> i32 {
    let bound = sums.iter().fold(0u32, |a, &w| a | (w ^ (w << 1)));
    (16 - bound.leading_zeros() as i32).max(-15) // t − 15 = (31 − clz) − 15
}

/// Windowed Q15 samples from one element's sums (`[re, im]` word pairs): each part scaled by
/// `2^−shift` with rounding (every part is below `2^(15 + shift)`), then multiplied by the window
/// with rounding. Only a rounded-up maximum can reach 2^15, so one clamp (`SSAT`) keeps it in
/// `i16`. All
/// `i32` (no `i64` on the M7's hot path): `((v >> (s−1)) + 1) >> 1` is `(v + 2^(s−1)) >> s`
/// without its overflow. O(N).
fn normalize(row: &mut [CQ15], sums: &[u32], window: &[Q15], shift: i32) {
    let windowed = |s: i32, w: Q15| ((s * w.0 as i32 + (1 << 14)) >> 15) as i16;
    let pairs = row.iter_mut().zip(sums.chunks_exact(2)).zip(window);
    if shift > 0 {
        let down = (shift - 1) as u32;
        let q = |v: u32| ((((v as i32) >> down) + 1) >> 1).clamp(i16::MIN as i32, i16::MAX as i32);
        for ((o, acc), &w) in pairs {
            *o = CQ15::from_raw(windowed(q(acc[0]), w), windowed(q(acc[1]), w));
        }
    } else {
        let up = (-shift) as u32;
        for ((o, acc), &w) in pairs {
            let q = |v: u32| (v as i32) << up;
            *o = CQ15::from_raw(windowed(q(acc[0]), w), windowed(q(acc[1]), w));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::window::{WindowKind, coefficient, coefficient_f64};
    use std::vec;

    #[test]
    fn align_row_is_scale_down() {
        let row: vec::Vec<u32> = [(-32768i16, 32767i16), (-1, 1), (12345, -23456), (0, -3)]
            .iter()
            .map(|&(r, i)| pack(CQ15::from_raw(r, i)))
            .collect();
        for down in 0..20u32 {
            let mut out = vec![7u32; 2 * row.len()];
            align_row(out.iter_mut().step_by(2), &row, down);
            for (i, &w) in row.iter().enumerate() {
                assert_eq!(
                    out[2 * i],
                    pack(unpack(w).scale_down(down)),
                    "down {down} word {i}"
                );
                assert_eq!(out[2 * i + 1], 7, "down {down} gap {i}");
            }
        }
    }

    #[test]
    fn normalizing_shift_is_the_tightest() {
        let fits = |v: &[u32], s: i32| {
            let b = 1i64 << (15 + s);
            v.iter().all(|&w| (-b..b).contains(&(w as i32 as i64)))
        };
        let mut x = 3u64;
        for len in [0usize, 1, 2, 7] {
            for _ in 0..2000 {
                let v: vec::Vec<u32> = (0..len)
                    .map(|_| {
                        x = x
                            .wrapping_mul(6364136223846793005)
                            .wrapping_add(1442695040888963407);
                        // Random magnitudes, powers of two and their negatives included.
                        let m = (x >> 59) as u32;
                        match (x >> 56) & 3 {
                            0 => 1u32 << m.min(30),
                            1 => (1u32 << m.min(30)).wrapping_neg(),
                            _ => ((x >> 20) as i32 >> m) as u32,
                        }
                    })
                    .collect();
                let s = normalizing_shift(&v);
                assert!(fits(&v, s), "{v:?} shift {s}");
                assert!(s == -15 || !fits(&v, s - 1), "{v:?} shift {s} not tight");
            }
        }
    }

    /// `normalize` is `round(round(v / 2^shift) · w / 2^15)` (halves up), computed here in
    /// `i64` with floor division, for every shift a frame can need.
    #[test]
    fn normalize_rounds_like_i64() {
        let mut x = 7u64;
        for shift in -15i32..=16 {
            let bound = 1i64 << (15 + shift);
            let sums: vec::Vec<u32> = (0..64)
                .map(|i| {
                    x = x
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    let v = match i {
                        0 => bound - 1,
                        1 => -bound,
                        _ => (x >> 20) as i64 % bound,
                    };
                    v as i32 as u32
                })
                .collect();
            let window: vec::Vec<Q15> = (0..32).map(|i| Q15(32767 - 1000 * i)).collect();
            let mut row = vec![CQ15::default(); 32];
            normalize(&mut row, &sums, &window, shift);
            for (i, z) in row.iter().enumerate() {
                let q = |v: u32| {
                    let v = v as i32 as i64;
                    let s = if shift > 0 {
                        (v + (1 << (shift - 1))).div_euclid(1 << shift)
                    } else {
                        v << -shift
                    }
                    .min(i16::MAX as i64);
                    ((s * window[i].0 as i64 + (1 << 14)).div_euclid(1 << 15)) as i16
                };
                assert_eq!(
                    (z.re.0, z.im.0),
                    (q(sums[2 * i]), q(sums[2 * i + 1])),
                    "{shift} {i}"
                );
            }
        }
    }

    /// The spectra equal the f64 DFT of the windowed sums, to Q15 precision of the peak.
    #[test]
    fn in_place_spectra_match_f64() {
        let (el, n, m) = (3usize, 24usize, 32usize);
        let mut words = vec![0u32; FrameSum::words_needed(el, n, m)];
        let mut sum = FrameSum::new(&mut words, el, n, m).unwrap();
        let mut truth = vec![(0.0f64, 0.0f64); el * n];
        for lp in 0..3 {
            for e in 0..el {
                let chirp: vec::Vec<CQ15> = (0..n)
                    .map(|i| {
                        let ph = 0.7 * i as f64 + e as f64 + lp as f64 * 0.1;
                        let a = 3000.0 * (e + 1) as f64;
                        CQ15::from_raw((a * ph.cos()) as i16, (a * ph.sin()) as i16)
                    })
                    .collect();
                for (t, z) in truth[e * n..].iter_mut().zip(&chirp) {
                    t.0 += z.re.0 as f64;
                    t.1 += z.im.0 as f64;
                }
                sum.add(e, &chirp).unwrap();
            }
        }
        let window: vec::Vec<Q15> = (0..n)
            .map(|i| coefficient(WindowKind::Hann, i, n))
            .collect();
        let mut scratch = vec![CQ15::default(); m];
        let (spec, rest) = sum.finish(&window, &mut scratch).unwrap();
        assert_eq!(rest.len(), FrameSum::words_needed(el, n, m) - el * m);
        let scale = libm::pow(2.0, spec.exponent() as f64);
        let mut worst = 0.0f64;
        let mut peak = 0.0f64;
        for e in 0..el {
            for k in 0..m {
                let (mut re, mut im) = (0.0, 0.0);
                for i in 0..n {
                    let w = coefficient_f64(WindowKind::Hann, i, n);
                    let a = -2.0 * core::f64::consts::PI * (k * i) as f64 / m as f64;
                    let (x, y) = truth[e * n + i];
                    re += w * (x * a.cos() - y * a.sin());
                    im += w * (x * a.sin() + y * a.cos());
                }
                let z = spec.get(e, k);
                let (dr, di) = (z.re.0 as f64 * scale - re, z.im.0 as f64 * scale - im);
                worst = worst.max((dr * dr + di * di).sqrt());
                peak = peak.max((re * re + im * im).sqrt());
            }
        }
        assert!(worst < 2e-3 * peak, "worst {worst} of peak {peak}");
    }

    #[test]
    fn rejects_small_arenas_and_bad_rows() {
        let mut words = vec![0u32; 10];
        assert!(matches!(
            FrameSum::new(&mut words, 2, 8, 16),
            Err(RangeError::Buffer { .. })
        ));
        let mut words = vec![0u32; 64];
        let mut s = FrameSum::new(&mut words, 2, 8, 16).unwrap();
        assert!(s.add(2, &[CQ15::default(); 8]).is_err());
        assert!(s.add(0, &[CQ15::default(); 7]).is_err());
    }

    #[test]
    fn sums_are_exact_then_saturate() {
        // Extreme samples into one element: the i64 sums until they leave i32, then the bounds.
        let (n, m) = (4usize, 16usize);
        let mut words = vec![0u32; FrameSum::words_needed(2, n, m)];
        let mut s = FrameSum::new(&mut words, 2, n, m).unwrap();
        let chirp = [
            CQ15::from_raw(i16::MAX, i16::MIN),
            CQ15::from_raw(i16::MIN, 1),
            CQ15::from_raw(-1, i16::MAX),
            CQ15::from_raw(0, 0),
        ];
        let rows = 2 * EXACT_ROWS as i64 + 3;
        for r in 0..rows {
            s.add(0, &chirp).unwrap();
            if r == EXACT_ROWS as i64 - 1 || r == rows - 1 {
                for (i, z) in chirp.iter().enumerate() {
                    let want =
                        |x: i16| (x as i64 * (r + 1)).clamp(i32::MIN as i64, i32::MAX as i64);
                    assert_eq!(s.words[2 * i] as i32 as i64, want(z.re.0), "row {r} re {i}");
                    assert_eq!(
                        s.words[2 * i + 1] as i32 as i64,
                        want(z.im.0),
                        "row {r} im {i}"
                    );
                }
            }
        }
        assert!(
            2 * EXACT_ROWS as i64 * 32768 > i32::MAX as i64,
            "the test reaches saturation"
        );
    }

    /// Calibrated sums are the exact integer sums of every chirp times its block's coefficient,
    /// at the largest headroom allowed, extreme samples and coefficients included; one chirp
    /// more than the headroom allows is refused.
    #[test]
    fn calibrated_sums_are_exact_up_to_their_headroom() {
        let (n, m, len) = (37usize, 64usize, 16usize);
        let headroom = 3u32; // up to 7 chirps per element
        let mut words = vec![0u32; FrameSum::words_needed(2, n, m)];
        let mut s = FrameSum::new_calibrated(&mut words, 2, n, m, headroom).unwrap();
        let big = 1i16 << (15 - headroom);
        let coefficients = [
            pack(CQ15::from_raw(-big, -big)),
            pack(CQ15::from_raw(big, -big)),
            pack(CQ15::from_raw(-1234, 777)),
            pack(CQ15::from_raw(big, big)),
        ];
        let chirp: vec::Vec<CQ15> = (0..n)
            .map(|i| match i % 3 {
                0 => CQ15::from_raw(i16::MIN, i16::MAX),
                1 => CQ15::from_raw(i16::MIN, i16::MIN),
                _ => CQ15::from_raw((i as i16) * 701 - 9000, 31_000 - (i as i16) * 800),
            })
            .collect();
        let mut want = vec![(0i64, 0i64); n];
        for _ in 0..7 {
            s.add_calibrated(1, &chirp, &coefficients).unwrap();
            for (i, (z, w)) in chirp.iter().zip(&mut want).enumerate() {
                let c = unpack(coefficients[i / len]);
                let (cr, ci, xr, xi) = (
                    i64::from(c.re.0),
                    i64::from(c.im.0),
                    i64::from(z.re.0),
                    i64::from(z.im.0),
                );
                w.0 += cr * xr - ci * xi;
                w.1 += cr * xi + ci * xr;
            }
        }
        assert!(matches!(
            s.add_calibrated(1, &chirp, &coefficients),
            Err(RangeError::Index { .. })
        ));
        assert!(
            s.add(0, &chirp).is_err(),
            "a calibrated frame takes only calibrated chirps"
        );
        assert!(s.add_calibrated(0, &chirp, &coefficients[..2]).is_err());
        let stride = FrameSum::sum_stride(n, m);
        for (i, w) in want.iter().enumerate() {
            assert!(w.0.abs() < 1 << 31 && w.1.abs() < 1 << 31);
            assert_eq!(s.words[stride + 2 * i] as i32 as i64, w.0, "re {i}");
            assert_eq!(s.words[stride + 2 * i + 1] as i32 as i64, w.1, "im {i}");
        }
        let mut words = vec![0u32; FrameSum::words_needed(2, n, m)];
        let mut raw = FrameSum::new(&mut words, 2, n, m).unwrap();
        assert!(raw.add_calibrated(0, &chirp, &coefficients).is_err());
    }

    /// A unit coefficient at headroom h gives the uncalibrated spectra at the same exponent
    /// scale (the exponent is lowered by 15 − h).
    #[test]
    fn calibrated_spectra_keep_input_units() {
        let (n, m) = (16usize, 16usize);
        let chirp: vec::Vec<CQ15> = (0..n)
            .map(|i| CQ15::from_raw((i as i16) * 1500 - 11_000, 9000 - (i as i16) * 700))
            .collect();
        let window = vec![Q15(32767); n];
        let spectra = |headroom: Option<u32>| {
            let mut words = vec![0u32; FrameSum::words_needed(1, n, m)];
            let mut scratch = vec![CQ15::default(); m];
            let values: vec::Vec<(f64, i32)> = {
                let mut s = match headroom {
                    None => FrameSum::new(&mut words, 1, n, m).unwrap(),
                    Some(h) => FrameSum::new_calibrated(&mut words, 1, n, m, h).unwrap(),
                };
                for _ in 0..3 {
                    match headroom {
                        None => s.add(0, &chirp).unwrap(),
                        Some(h) => {
                            let one = pack(CQ15::from_raw(1 << (15 - h), 0));
                            s.add_calibrated(0, &chirp, &[one; 1]).unwrap();
                        }
                    }
                }
                let (spec, _) = s.finish(&window, &mut scratch).unwrap();
                (0..m)
                    .map(|k| (f64::from(spec.get(0, k).re.0), spec.exponent()))
                    .collect()
            };
            values
                .iter()
                .map(|&(v, e)| v * libm::pow(2.0, f64::from(e)))
                .collect::<vec::Vec<f64>>()
        };
        let (raw, cal) = (spectra(None), spectra(Some(2)));
        let peak = raw.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (k, (a, b)) in raw.iter().zip(&cal).enumerate() {
            assert!((a - b).abs() < 1e-3 * peak, "bin {k}: {a} vs {b}");
        }
    }
}
