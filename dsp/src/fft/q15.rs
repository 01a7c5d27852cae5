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

/// Twiddle word `k` (`k < TABLE_LEN`).
#[cfg(target_arch = "x86_64")]
fn table_word(k: usize) -> u32 {
    twiddle_words()[k]
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
///
/// On x86-64 the radix-4 passes over spans of 16 or more run four butterflies at once with
/// SSE2 ([`super::sse2`]), bit for bit the scalar passes the M7 runs.
pub fn fft_bit_reversed(buf: &mut [CQ15]) -> u32 {
    passes::<true>(buf)
}

/// [`fft_bit_reversed`] with only the scalar passes (the reference of the SSE2 ones).
#[cfg(test)]
pub fn fft_bit_reversed_scalar(buf: &mut [CQ15]) -> u32 {
    passes::<false>(buf)
}

/// The passes of [`fft_bit_reversed`], with SSE2 where `VECTOR` and the target has it.
fn passes<const VECTOR: bool>(buf: &mut [CQ15]) -> u32 {
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
            (0, true) => radix4_pass::<VECTOR, false, false, false, true>(words, span),
            (1, true) => radix4_pass::<VECTOR, false, true, false, true>(words, span),
            (2, true) => radix4_pass::<VECTOR, false, true, true, true>(words, span),
            (_, true) => radix4_pass::<VECTOR, true, true, true, true>(words, span),
            (0, false) => radix4_pass::<VECTOR, false, false, false, false>(words, span),
            (1, false) => radix4_pass::<VECTOR, false, true, false, false>(words, span),
            (2, false) => radix4_pass::<VECTOR, false, true, true, false>(words, span),
            (_, false) => radix4_pass::<VECTOR, true, true, true, false>(words, span),
        };
        span /= 4;
    }
    if span == 2 {
        let halve = bound_bits(acc) > 14;
        exponent += u32::from(halve);
        match (VECTOR, halve) {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: SSE2 is part of every x86-64 target's baseline (as in `radix4_pass`).
            (true, true) => unsafe { super::sse2::radix2_pass::<true>(words) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as above.
            (true, false) => unsafe { super::sse2::radix2_pass::<false>(words) },
            (_, true) => radix2_pass::<true>(words),
            (_, false) => radix2_pass::<false>(words),
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
/// bound accumulator of what it wrote (else 0). `VECTOR` lets x86-64 take spans of 16 or more
/// four butterflies at a time.
#[inline(always)]
fn radix4_pass<
    const VECTOR: bool,
    const PRE: bool,
    const T: bool,
    const Y: bool,
    const TRACK: bool,
>(
    words: &mut [u32],
    span: usize,
) -> u32 {
    let n = words.len();
    let q = span / 4;
    let stride = TABLE_LEN / span;
    #[cfg(target_arch = "x86_64")]
    if VECTOR && span == 8 {
        let twiddles = (
            table_word(2 * stride),
            table_word(stride),
            table_word(3 * stride),
        );
        // SAFETY: as below.
        return unsafe { super::sse2::radix4_pass_8::<PRE, T, Y, TRACK>(words, twiddles) };
    }
    #[cfg(target_arch = "x86_64")]
    if VECTOR && span >= 16 {
        // SAFETY: SSE2 is part of every x86-64 target's baseline, so the pass's
        // `target_feature(enable = "sse2")` holds wherever this code is built.
        return unsafe {
            super::sse2::radix4_pass::<PRE, T, Y, TRACK>(words, span, twiddle_words(), stride)
        };
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::from_words_mut;
    use std::{vec, vec::Vec};

    /// Deterministic packed words (xorshift64), each lane shifted down to `bits` (16 = full
    /// scale).
    fn random_words(n: usize, seed: u64, bits: u32) -> Vec<u32> {
        let mut s = seed | 1;
        let lane = |x: u64| ((x as u16 as i16) >> (16 - bits)) as u16 as u32;
        (0..n)
            .map(|_| {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                lane(s) | (lane(s >> 16) << 16)
            })
            .collect()
    }

    /// The SSE2 passes (x86-64) and the scalar passes give the same words and exponent for
    /// every length, at every scale (each shift pattern of the block floating point), and on
    /// the extremes (−32768 in every lane, alternating full-scale signs, one extreme impulse,
    /// opposite extremes where the first pass needs index 0 left unrotated).
    #[test]
    fn vector_passes_equal_the_scalar_ones_bit_for_bit() {
        for log2 in 4..=11 {
            let n = 1usize << log2;
            let mut inputs = vec![
                vec![0x8000_8000; n],
                (0..n)
                    .map(|i| if i % 2 == 0 { 0x7FFF_8000 } else { 0x8000_7FFF })
                    .collect(),
                (0..n)
                    .map(|i| if i == 1 { 0x8000_7FFF } else { 0 })
                    .collect(),
            ];
            for (seed, bits) in (1..=40u64).zip([16, 15, 13, 11, 8, 4, 2, 1].iter().cycle()) {
                inputs.push(random_words(n, seed * 7919 + n as u64, *bits));
            }
            // Random full scale but for opposite extremes at the first pass's index 0 (words
            // 0, 2q and q, 3q): its y1 is −16384 in both lanes, the one value the table's
            // 32767 does not leave alone, so index 0 must not be rotated.
            for seed in 1..=8u64 {
                let mut w = random_words(n, seed * 104_729 + n as u64, 16);
                for (m, extreme) in [0x8000_8000, 0x7FFF_7FFF, 0x8000_8000, 0x7FFF_7FFF]
                    .into_iter()
                    .enumerate()
                {
                    w[m * n / 4] = extreme;
                }
                inputs.push(w);
            }
            for input in inputs {
                let (mut v, mut s) = (input.clone(), input);
                let ev = fft_bit_reversed(from_words_mut(&mut v));
                let es = fft_bit_reversed_scalar(from_words_mut(&mut s));
                assert_eq!(ev, es, "exponent, n = {n}");
                assert!(v == s, "words, n = {n}");
            }
        }
    }
}
