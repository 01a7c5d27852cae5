//! The Q15 FFT on packed words with the DSP extension's SIMD (see [`super::simd`]).
//!
//! Radix-2² DIF passes (radix-4 butterflies, three twiddle products per four points) and a
//! closing radix-2 pass for odd powers of two, as the M7 likes them: each complex sample is one
//! 32-bit word, a butterfly's additions are eight SIMD instructions with the block scaling folded
//! into halving additions, a twiddle product is four, and loops run twiddle-outer, group-inner so
//! each twiddle is loaded once per pass.
//!
//! Scaling (block floating point): a pass ORs `w ^ (w << 1)` of every word it writes; the highest
//! set bit `p` of either lane bounds every component, which then lies in `[−2^p, 2^p)`. A radix-4
//! pass grows components at most 4·√2×, so it halves `p − 12` times (0..=3); the closing radix-2
//! pass grows them at most 2× and halves `p − 14` times (0..=1). With those shifts every lane
//! provably fits in `i16` and every product in `i32`, so nothing saturates or wraps, and a weak
//! input is not scaled until its spectrum needs the room.

// Packed-word loads and stores of the SIMD passes (each `unsafe` block says why it is sound).
#![allow(unsafe_code)]

use super::reorder::bit_reverse;
use super::simd::{add, add_j, rotate, shadd16, sub, sub_j};
use crate::fixed::{CQ15, words_mut};
use crate::trig::twiddle::{TABLE_LEN, TWIDDLE_Q15};

/// The twiddle table as packed words.
fn twiddle_words() -> &'static [u32; TABLE_LEN] {
    // SAFETY: as in `crate::fixed::words`; the table is `[CQ15; TABLE_LEN]`.
    unsafe { &*TWIDDLE_Q15.as_ptr().cast::<[u32; TABLE_LEN]>() }
}

/// Bound accumulator term of one written word.
#[inline(always)]
fn bound(w: u32) -> u32 {
    w ^ (w << 1)
}

/// `p` such that every lane seen by `acc` lies in `[−2^p, 2^p)`.
fn bound_bits(acc: u32) -> u32 {
    let top = |x: u32| 31u32.saturating_sub(x.leading_zeros());
    top(acc & 0xFFFF).max(top(acc >> 16))
}

/// Forward FFT in place; `buf.len()` is a power of two in `16..=2048` (checked by the caller).
/// Returns the block exponent.
pub fn fft_in_place(buf: &mut [CQ15]) -> u32 {
    let exponent = fft_bit_reversed(buf);
    bit_reverse(buf);
    exponent
}

/// [`fft_in_place`] without the closing reorder: bin `k` is left at index `rev(k)`.
pub fn fft_bit_reversed(buf: &mut [CQ15]) -> u32 {
    let words = words_mut(buf);
    let n = words.len();
    let mut acc = words.iter().fold(0, |a, &w| a | bound(w));
    let mut exponent = 0;
    let mut span = n;
    while span >= 4 {
        let shift = bound_bits(acc).saturating_sub(12);
        exponent += shift;
        // The bound is needed only if another pass follows.
        acc = match (shift, span > 4) {
            (0, true) => radix4_pass::<false, false, false, true>(words, span),
            (1, true) => radix4_pass::<false, true, false, true>(words, span),
            (2, true) => radix4_pass::<false, true, true, true>(words, span),
            (_, true) => radix4_pass::<true, true, true, true>(words, span),
            (0, false) => radix4_pass::<false, false, false, false>(words, span),
            (1, false) => radix4_pass::<false, true, false, false>(words, span),
            (2, false) => radix4_pass::<false, true, true, false>(words, span),
            (_, false) => radix4_pass::<true, true, true, false>(words, span),
        };
        span /= 4;
    }
    if span == 2 {
        let halve = bound_bits(acc) > 14;
        exponent += u32::from(halve);
        if halve {
            radix2_pass::<true>(words);
        } else {
            radix2_pass::<false>(words);
        }
    }
    exponent
}

/// The closing radix-2 pass over adjacent pairs (no twiddles).
fn radix2_pass<const HALVE: bool>(words: &mut [u32]) {
    for pair in words.chunks_exact_mut(2) {
        let (a, b) = (pair[0], pair[1]);
        pair[0] = add::<HALVE>(a, b);
        pair[1] = sub::<HALVE>(a, b);
    }
}

/// One radix-2² DIF pass over groups of `span` (a power of two ≥ 4 dividing `words.len()`).
/// `PRE` halves the inputs, `T` the first and `Y` the second radix-2 level; `TRACK` returns the
/// bound accumulator of what it wrote (else 0).
#[inline(always)]
fn radix4_pass<const PRE: bool, const T: bool, const Y: bool, const TRACK: bool>(
    words: &mut [u32],
    span: usize,
) -> u32 {
    let n = words.len();
    let q = span / 4;
    let stride = TABLE_LEN / span;
    let table = twiddle_words().as_ptr();
    let base = words.as_mut_ptr();
    let end = base.wrapping_add(n);
    let mut acc = 0;
    // Twiddle-free butterflies (j = 0) of every group.
    let mut p = base;
    while p < end {
        // SAFETY: `p` is a group start below `end`; `n` is a multiple of `span`, so the group's
        // words `p .. p + 4q` are inside `words`.
        acc |= unsafe { butterfly::<PRE, T, Y, TRACK>(p, q, None) };
        p = p.wrapping_add(span);
    }
    let mut k = stride;
    for j in 1..q {
        // SAFETY: `k = j · stride` with `j < q`, so `3k < 3/4 · TABLE_LEN`.
        let twiddles = unsafe {
            (
                table.add(2 * k).read(),
                table.add(k).read(),
                table.add(3 * k).read(),
            )
        };
        let mut p = base.wrapping_add(j);
        while p < end {
            // SAFETY: `p` is a group start plus `j < q`, below `end`; its words `p + {0,1,2,3}q`
            // stay inside the group and so inside `words`.
            acc |= unsafe { butterfly::<PRE, T, Y, TRACK>(p, q, Some(twiddles)) };
            p = p.wrapping_add(span);
        }
        k += stride;
    }
    acc
}

/// The radix-4 butterfly on words `p`, `p + q`, `p + 2q`, `p + 3q`.
///
/// # Safety
/// All four words must be valid for reads and writes.
#[inline(always)]
unsafe fn butterfly<const PRE: bool, const T: bool, const Y: bool, const TRACK: bool>(
    p: *mut u32,
    q: usize,
    twiddles: Option<(u32, u32, u32)>,
) -> u32 {
    // SAFETY: the caller guarantees the four words.
    let (p0, p1, p2, p3) = unsafe { (p, p.add(q), p.add(2 * q), p.add(3 * q)) };
    let (mut x0, mut x1, mut x2, mut x3) = unsafe { (p0.read(), p1.read(), p2.read(), p3.read()) };
    if PRE {
        (x0, x1, x2, x3) = (
            shadd16(x0, 0),
            shadd16(x1, 0),
            shadd16(x2, 0),
            shadd16(x3, 0),
        );
    }
    let (t0, t1, t2, t3) = (
        add::<T>(x0, x2),
        sub::<T>(x0, x2),
        add::<T>(x1, x3),
        sub::<T>(x1, x3),
    );
    let y0 = add::<Y>(t0, t2);
    let mut y1 = sub::<Y>(t0, t2);
    let mut y2 = sub_j::<Y>(t1, t3);
    let mut y3 = add_j::<Y>(t1, t3);
    if let Some((w1, w2, w3)) = twiddles {
        y1 = rotate(y1, w1);
        y2 = rotate(y2, w2);
        y3 = rotate(y3, w3);
    }
    // SAFETY: as above.
    unsafe {
        p0.write(y0);
        p1.write(y1);
        p2.write(y2);
        p3.write(y3);
    }
    if TRACK {
        bound(y0) | bound(y1) | bound(y2) | bound(y3)
    } else {
        0
    }
}
