//! The block-floating-point radix-2² DIF FFT, written once for Q15 and Q31.
//!
//! Each pass fuses two radix-2 stages into one radix-4 butterfly (three twiddle products per four
//! points); an odd power of two ends with one radix-2 pass. Before a pass we know an upper bound
//! `2^b` on every |re| and |im| (the OR of the magnitudes written by the previous pass), and we
//! scale the pass's outputs down only by what the worst case needs:
//!
//! * a radix-4 pass can grow a complex magnitude ×4 and the rotation maps it onto one component,
//!   so components stay below `4·√2·2^b < 2^(b+3)`: shift `b + 3 − FRAC` when positive;
//! * the closing radix-2 pass (no rotation) grows components at most ×2: shift `b + 1 − FRAC`.
//!
//! Weak inputs are therefore not scaled at all until their spectrum needs the room, which is why a
//! −40 dBFS radar return keeps ≈ 20 dB more SQNR than fixed 1/N scaling. The bounds also prove that
//! no intermediate result overflows its wide type, so the arithmetic never saturates or wraps.

use super::twiddle::TABLE_LEN;
use crate::fixed::{Complex, Q15, Q31};
use core::ops::{Add, Sub};

/// What the FFT needs of a fixed-point format.
pub trait Format: Copy + 'static {
    /// A type wide enough to hold the sum of four values.
    type Wide: Copy + Add<Output = Self::Wide> + Sub<Output = Self::Wide>;
    /// Fractional bits of the format.
    const FRAC: u32;
    /// The full-circle twiddle table in this format.
    fn table() -> &'static [Complex<Self>; TABLE_LEN];
    /// Exact widening.
    fn widen(self) -> Self::Wide;
    /// `w / 2^shift`, rounded half up; the caller guarantees that the result fits.
    fn narrow(w: Self::Wide, shift: u32) -> Self;
    /// `a · w` rounded to nearest; the caller guarantees `|a| < 2^FRAC`.
    fn rotate(a: Complex<Self>, w: Complex<Self>) -> Complex<Self>;
    /// A bit pattern whose bit length bounds `|self|` from above.
    fn magnitude_bits(self) -> u32;
}

impl Format for Q15 {
    type Wide = i32;
    const FRAC: u32 = 15;
    fn table() -> &'static [Complex<Self>; TABLE_LEN] {
        &super::twiddle::TWIDDLE_Q15
    }
    #[inline(always)]
    fn widen(self) -> i32 {
        self.0 as i32
    }
    #[inline(always)]
    fn narrow(w: i32, shift: u32) -> Self {
        if shift == 0 {
            Q15(w as i16)
        } else {
            Q15(((w + (1 << (shift - 1))) >> shift) as i16)
        }
    }
    #[inline(always)]
    fn rotate(a: Complex<Self>, w: Complex<Self>) -> Complex<Self> {
        let (ar, ai, wr, wi) = (a.re.0 as i32, a.im.0 as i32, w.re.0 as i32, w.im.0 as i32);
        Complex::new(
            Q15(((ar * wr - ai * wi + (1 << 14)) >> 15) as i16),
            Q15(((ar * wi + ai * wr + (1 << 14)) >> 15) as i16),
        )
    }
    #[inline(always)]
    fn magnitude_bits(self) -> u32 {
        (self.0 ^ (self.0 >> 15)) as u16 as u32
    }
}

impl Format for Q31 {
    type Wide = i64;
    const FRAC: u32 = 31;
    fn table() -> &'static [Complex<Self>; TABLE_LEN] {
        &super::twiddle::TWIDDLE_Q31
    }
    #[inline(always)]
    fn widen(self) -> i64 {
        self.0 as i64
    }
    #[inline(always)]
    fn narrow(w: i64, shift: u32) -> Self {
        if shift == 0 {
            Q31(w as i32)
        } else {
            Q31(((w + (1 << (shift - 1))) >> shift) as i32)
        }
    }
    #[inline(always)]
    fn rotate(a: Complex<Self>, w: Complex<Self>) -> Complex<Self> {
        let (ar, ai, wr, wi) = (a.re.0 as i64, a.im.0 as i64, w.re.0 as i64, w.im.0 as i64);
        Complex::new(
            Q31(((ar * wr - ai * wi + (1 << 30)) >> 31) as i32),
            Q31(((ar * wi + ai * wr + (1 << 30)) >> 31) as i32),
        )
    }
    #[inline(always)]
    fn magnitude_bits(self) -> u32 {
        (self.0 ^ (self.0 >> 31)) as u32
    }
}

#[inline(always)]
fn bits_of<F: Format>(z: Complex<F>) -> u32 {
    z.re.magnitude_bits() | z.im.magnitude_bits()
}

#[inline(always)]
fn widen<F: Format>(z: Complex<F>) -> Complex<F::Wide> {
    Complex::new(z.re.widen(), z.im.widen())
}

#[inline(always)]
fn narrow<F: Format>(re: F::Wide, im: F::Wide, shift: u32) -> Complex<F> {
    Complex::new(F::narrow(re, shift), F::narrow(im, shift))
}

/// Shift that keeps a pass with growth below `2^growth_bits` inside the format, given that every
/// input component is below `2^(bit length of or_bits)`.
#[inline(always)]
fn needed_shift<F: Format>(or_bits: u32, growth_bits: u32) -> u32 {
    (32 - or_bits.leading_zeros()).saturating_sub(F::FRAC - growth_bits)
}

/// Forward FFT in place; `buf.len()` must be a power of two in `4..=TABLE_LEN` (checked by the
/// callers). Returns the block exponent: the true DFT is `output · 2^exponent`.
///
/// Cost: `N/4·log₄N` radix-4 butterflies (3 complex products each), one scan of the input, and
/// the bit-reversal permutation.
pub fn fft_in_place<F: Format>(buf: &mut [Complex<F>]) -> u32 {
    let n = buf.len();
    let table = F::table();
    let mut bits = buf.iter().fold(0, |acc, &z| acc | bits_of(z));
    let mut exponent = 0;
    let mut span = n;
    while span >= 4 {
        let shift = needed_shift::<F>(bits, 3);
        exponent += shift;
        bits = radix4_pass(buf, span, TABLE_LEN / span, shift, table);
        span /= 4;
    }
    if span == 2 {
        let shift = needed_shift::<F>(bits, 1);
        exponent += shift;
        for pair in buf.chunks_exact_mut(2) {
            let (a, b) = (widen(pair[0]), widen(pair[1]));
            pair[0] = narrow(a.re + b.re, a.im + b.im, shift);
            pair[1] = narrow(a.re - b.re, a.im - b.im, shift);
        }
    }
    bit_reverse(buf);
    exponent
}

/// One radix-2² DIF pass over groups of `span` points; returns the OR of the output magnitudes.
#[inline(always)]
fn radix4_pass<F: Format>(
    buf: &mut [Complex<F>],
    span: usize,
    stride: usize,
    shift: u32,
    table: &[Complex<F>; TABLE_LEN],
) -> u32 {
    let q = span / 4;
    let mut acc = 0;
    for group in buf.chunks_exact_mut(span) {
        let (a, rest) = group.split_at_mut(q);
        let (b, rest) = rest.split_at_mut(q);
        let (c, d) = rest.split_at_mut(q);
        for j in 0..q {
            let (x0, x1, x2, x3) = (widen(a[j]), widen(b[j]), widen(c[j]), widen(d[j]));
            let (t0, t1, t2, t3) = (x0 + x2, x0 - x2, x1 + x3, x1 - x3);
            let y0 = narrow(t0.re + t2.re, t0.im + t2.im, shift);
            let mut y1 = narrow(t0.re - t2.re, t0.im - t2.im, shift);
            let mut y2 = narrow(t1.re + t3.im, t1.im - t3.re, shift);
            let mut y3 = narrow(t1.re - t3.im, t1.im + t3.re, shift);
            if j != 0 {
                let k = j * stride;
                y1 = F::rotate(y1, table[2 * k]);
                y2 = F::rotate(y2, table[k]);
                y3 = F::rotate(y3, table[3 * k]);
            }
            acc |= bits_of(y0) | bits_of(y1) | bits_of(y2) | bits_of(y3);
            a[j] = y0;
            b[j] = y1;
            c[j] = y2;
            d[j] = y3;
        }
    }
    acc
}

/// Reorders a bit-reversed spectrum into natural order (`len` a power of two ≥ 2).
fn bit_reverse<T>(buf: &mut [T]) {
    let shift = usize::BITS - buf.len().trailing_zeros();
    for i in 0..buf.len() {
        let r = i.reverse_bits() >> shift;
        if i < r {
            buf.swap(i, r);
        }
    }
}
