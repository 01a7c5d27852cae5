//! The Q31 FFT: the same radix-2² DIF algorithm and block-floating-point rule as the Q15 one
//! ([`super::q15`]), in scalar 64-bit arithmetic.
//!
//! Before each pass every component is below `2^b` (the OR of the magnitudes written by the
//! previous pass); a radix-4 pass shifts by `b + 3 − 31` when positive (growth below
//! 4·√2 < 2³), the closing radix-2 pass by `b + 1 − 31`. Outputs are rounded half up.

use super::reorder::bit_reverse;
use crate::fixed::{CQ31, Complex, Q31};
use crate::trig::twiddle::{TABLE_LEN, TWIDDLE_Q31};

type Wide = Complex<i64>;

#[inline(always)]
fn widen(z: CQ31) -> Wide {
    Complex::new(z.re.0 as i64, z.im.0 as i64)
}

/// `(re, im) / 2^shift`, rounded half up; the caller guarantees the result fits.
#[inline(always)]
fn narrow(re: i64, im: i64, shift: u32) -> CQ31 {
    let f = |v: i64| {
        if shift == 0 {
            v as i32
        } else {
            ((v + (1 << (shift - 1))) >> shift) as i32
        }
    };
    Complex::new(Q31(f(re)), Q31(f(im)))
}

/// `a · w` rounded to nearest; `|a| < 2³¹` keeps the sums of products inside `i64`.
#[inline(always)]
fn rotate(a: CQ31, w: CQ31) -> CQ31 {
    let (ar, ai, wr, wi) = (a.re.0 as i64, a.im.0 as i64, w.re.0 as i64, w.im.0 as i64);
    Complex::new(
        Q31(((ar * wr - ai * wi + (1 << 30)) >> 31) as i32),
        Q31(((ar * wi + ai * wr + (1 << 30)) >> 31) as i32),
    )
}

#[inline(always)]
fn bits(z: CQ31) -> u32 {
    ((z.re.0 ^ (z.re.0 >> 31)) | (z.im.0 ^ (z.im.0 >> 31))) as u32
}

/// Shift that keeps a pass with growth below `2^growth_bits` inside Q31.
fn needed_shift(or_bits: u32, growth_bits: u32) -> u32 {
    (32 - or_bits.leading_zeros()).saturating_sub(31 - growth_bits)
}

/// Forward FFT in place; `buf.len()` is a power of two in `16..=2048` (checked by the caller).
/// Returns the block exponent.
pub fn fft_in_place(buf: &mut [CQ31]) -> u32 {
    let n = buf.len();
    let mut acc = buf.iter().fold(0, |a, &z| a | bits(z));
    let mut exponent = 0;
    let mut span = n;
    while span >= 4 {
        let shift = needed_shift(acc, 3);
        exponent += shift;
        acc = radix4_pass(buf, span, shift);
        span /= 4;
    }
    if span == 2 {
        let shift = needed_shift(acc, 1);
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

/// One radix-2² DIF pass over groups of `span`; returns the OR of the output magnitudes.
fn radix4_pass(buf: &mut [CQ31], span: usize, shift: u32) -> u32 {
    let q = span / 4;
    let stride = TABLE_LEN / span;
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
                y1 = rotate(y1, TWIDDLE_Q31[2 * k]);
                y2 = rotate(y2, TWIDDLE_Q31[k]);
                y3 = rotate(y3, TWIDDLE_Q31[3 * k]);
            }
            acc |= bits(y0) | bits(y1) | bits(y2) | bits(y3);
            (a[j], b[j], c[j], d[j]) = (y0, y1, y2, y3);
        }
    }
    acc
}
