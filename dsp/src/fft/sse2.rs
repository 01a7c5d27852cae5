//! The radix-4 pass of the Q15 FFT ([`super::q15`]) with x86-64's SSE2, four butterflies at
//! once, **bit for bit** the scalar pass: a host running the module's code (the map path, the
//! depth method on recorded frames) spends half its frame in this FFT, and the scalar pass spells
//! out each of the M7's DSP instructions one 16-bit lane at a time.
//!
//! Four consecutive twiddle indices `j .. j + 4` of one group are four adjacent words in each
//! quarter of the group, so one 128-bit load takes them. Each M7 instruction maps to exact
//! integer operations on eight 16-bit lanes:
//! - `SADD16` / `SSUB16`: wrapping 16-bit adds (`paddw`, `psubw`);
//! - `SHADD16`: ⌊(a + b) / 2⌋ = (a ≫ 1) + (b ≫ 1) + (a & b & 1), exact without a 17th bit;
//! - `SHSUB16`: ⌊(a − b) / 2⌋ = (a ≫ 1) − (b ≫ 1) − (¬a & b & 1);
//! - `SASX` / `SSAX` and their halving forms: the other operand's lanes swapped within each
//!   word, then the sum in one lane and the difference in the other;
//! - a twiddle product (`SMLSD`, `SMLADX`, `PKHBT`): `pmaddwd` forms the exact 32-bit sums of
//!   products, rounded and shifted as the M7 does, the real part without negating a lane
//!   (−(−32768) does not fit).
//!
//! Only the x86-64 build has this module; the M7 runs [`super::q15`]'s own pass.

// 128-bit loads and stores of checked slices (each `unsafe` block says why it is sound).
#![allow(unsafe_code)]

use core::arch::x86_64::{
    __m128i, _mm_add_epi16, _mm_add_epi32, _mm_and_si128, _mm_andnot_si128, _mm_cvtsi128_si32,
    _mm_loadu_si128, _mm_madd_epi16, _mm_or_si128, _mm_set_epi32, _mm_set1_epi16, _mm_set1_epi32,
    _mm_setzero_si128, _mm_shuffle_epi32, _mm_shufflehi_epi16, _mm_shufflelo_epi16, _mm_slli_epi32,
    _mm_srai_epi16, _mm_srai_epi32, _mm_srli_si128, _mm_storeu_si128, _mm_sub_epi16, _mm_sub_epi32,
    _mm_xor_si128,
};

/// The low (real) lane of every word set.
#[inline]
#[target_feature(enable = "sse2")]
fn re_lanes() -> __m128i {
    _mm_set1_epi32(0x0000_FFFF)
}

/// ⌊(a + b) / 2⌋ per lane (`SHADD16`).
#[inline]
#[target_feature(enable = "sse2")]
fn hadd(a: __m128i, b: __m128i) -> __m128i {
    let carry = _mm_and_si128(_mm_and_si128(a, b), _mm_set1_epi16(1));
    _mm_add_epi16(
        _mm_add_epi16(_mm_srai_epi16(a, 1), _mm_srai_epi16(b, 1)),
        carry,
    )
}

/// ⌊(a − b) / 2⌋ per lane (`SHSUB16`).
#[inline]
#[target_feature(enable = "sse2")]
fn hsub(a: __m128i, b: __m128i) -> __m128i {
    let borrow = _mm_and_si128(_mm_andnot_si128(a, b), _mm_set1_epi16(1));
    _mm_sub_epi16(
        _mm_sub_epi16(_mm_srai_epi16(a, 1), _mm_srai_epi16(b, 1)),
        borrow,
    )
}

/// `(a + b)` per lane, halved if `HALVE`.
#[inline]
#[target_feature(enable = "sse2")]
fn add<const HALVE: bool>(a: __m128i, b: __m128i) -> __m128i {
    if HALVE {
        hadd(a, b)
    } else {
        _mm_add_epi16(a, b)
    }
}

/// `(a − b)` per lane, halved if `HALVE`.
#[inline]
#[target_feature(enable = "sse2")]
fn sub<const HALVE: bool>(a: __m128i, b: __m128i) -> __m128i {
    if HALVE {
        hsub(a, b)
    } else {
        _mm_sub_epi16(a, b)
    }
}

/// Each word's two lanes swapped.
#[inline]
#[target_feature(enable = "sse2")]
fn swap_lanes(x: __m128i) -> __m128i {
    // 0xB1 picks lanes 1, 0, 3, 2 of each half.
    _mm_shufflehi_epi16::<0xB1>(_mm_shufflelo_epi16::<0xB1>(x))
}

/// The real lanes of `re`, the imaginary lanes of `im`.
#[inline]
#[target_feature(enable = "sse2")]
fn merge(re: __m128i, im: __m128i) -> __m128i {
    let mask = re_lanes();
    _mm_or_si128(_mm_and_si128(mask, re), _mm_andnot_si128(mask, im))
}

/// `a − j·b` (re + b.im, im − b.re), halved if `HALVE` (`SSAX` / `SHSAX`).
#[inline]
#[target_feature(enable = "sse2")]
fn sub_j<const HALVE: bool>(a: __m128i, b: __m128i) -> __m128i {
    let b = swap_lanes(b);
    merge(add::<HALVE>(a, b), sub::<HALVE>(a, b))
}

/// `a + j·b` (re − b.im, im + b.re), halved if `HALVE` (`SASX` / `SHASX`).
#[inline]
#[target_feature(enable = "sse2")]
fn add_j<const HALVE: bool>(a: __m128i, b: __m128i) -> __m128i {
    let b = swap_lanes(b);
    merge(sub::<HALVE>(a, b), add::<HALVE>(a, b))
}

/// Four twiddles in the forms a product needs.
#[derive(Clone, Copy)]
struct Twiddles {
    /// `(w.re, 0)` per word.
    re: __m128i,
    /// `(0, w.im)` per word.
    im: __m128i,
    /// `(w.im, w.re)` per word.
    swapped: __m128i,
}

impl Twiddles {
    /// From four packed twiddle words.
    #[inline]
    #[target_feature(enable = "sse2")]
    fn new(words: [u32; 4]) -> Self {
        let [a, b, c, d] = words.map(|w| w as i32);
        let w = _mm_set_epi32(d, c, b, a);
        let mask = re_lanes();
        Self {
            re: _mm_and_si128(mask, w),
            im: _mm_andnot_si128(mask, w),
            swapped: swap_lanes(w),
        }
    }

    /// `a · w` per word, rounded as [`super::simd::rotate`]: the real part
    /// `(a.re·w.re − a.im·w.im + 2¹⁴) ≫ 15`, the imaginary `(a.re·w.im + a.im·w.re + 2¹⁴) ≫ 15`,
    /// each kept to its low 16 bits.
    #[inline]
    #[target_feature(enable = "sse2")]
    fn rotate(&self, a: __m128i) -> __m128i {
        let half = _mm_set1_epi32(1 << 14);
        let re = _mm_sub_epi32(_mm_madd_epi16(a, self.re), _mm_madd_epi16(a, self.im));
        let im = _mm_madd_epi16(a, self.swapped);
        let re = _mm_srai_epi32::<15>(_mm_add_epi32(re, half));
        let im = _mm_srai_epi32::<15>(_mm_add_epi32(im, half));
        _mm_or_si128(_mm_and_si128(re_lanes(), re), _mm_slli_epi32::<16>(im))
    }
}

/// The words of `keep` where `mask` is set, of `other` elsewhere.
#[inline]
#[target_feature(enable = "sse2")]
fn select(mask: __m128i, keep: __m128i, other: __m128i) -> __m128i {
    _mm_or_si128(_mm_and_si128(mask, keep), _mm_andnot_si128(mask, other))
}

/// `w ^ (w << 1)` per word, the scalar pass's bound term.
#[inline]
#[target_feature(enable = "sse2")]
fn bound(w: __m128i) -> __m128i {
    _mm_xor_si128(w, _mm_slli_epi32::<1>(w))
}

/// The OR of a vector's four words.
#[target_feature(enable = "sse2")]
fn or_words(v: __m128i) -> u32 {
    let v = _mm_or_si128(v, _mm_srli_si128::<8>(v));
    let v = _mm_or_si128(v, _mm_srli_si128::<4>(v));
    _mm_cvtsi128_si32(v) as u32
}

/// Four adjacent words of `s` from `at` (`at + 4 ≤ s.len()`: the pass steps `at` by four
/// inside a quarter of a group whose length is a multiple of four; checked).
#[inline]
#[target_feature(enable = "sse2")]
fn load(s: &[u32], at: usize) -> __m128i {
    let four = &s[at..at + 4];
    // SAFETY: `four` is four initialized `u32`s, 16 bytes; `loadu` has no alignment need.
    unsafe { _mm_loadu_si128(four.as_ptr().cast()) }
}

/// Stores `v` to four adjacent words of `s` from `at` (checked as [`load`]).
#[inline]
#[target_feature(enable = "sse2")]
fn store(s: &mut [u32], at: usize, v: __m128i) {
    let four = &mut s[at..at + 4];
    // SAFETY: `four` is 16 writable bytes; `storeu` has no alignment need.
    unsafe { _mm_storeu_si128(four.as_mut_ptr().cast(), v) }
}

/// The radix-2² DIF pass of [`super::q15`] over groups of `span` (a power of two in
/// `16..=2048` dividing `words.len()`), with the same `PRE`, `T`, `Y`, `TRACK` and result.
/// `table` is the packed twiddle table, `stride` its step per twiddle index (`TABLE_LEN / span`).
///
/// O(`words.len()`), four butterflies per step.
#[inline]
#[target_feature(enable = "sse2")]
pub fn radix4_pass<const PRE: bool, const T: bool, const Y: bool, const TRACK: bool>(
    words: &mut [u32],
    span: usize,
    table: &[u32],
    stride: usize,
) -> u32 {
    let q = span / 4;
    // Twiddle index 0 is not rotated at all (the table's 1 is 32767, not 1).
    let first = _mm_set_epi32(0, 0, 0, -1);
    let mut acc = _mm_setzero_si128();
    for at in (0..q).step_by(4) {
        let twiddle =
            |m: usize| Twiddles::new(core::array::from_fn(|i| table[m * (at + i) * stride]));
        // The scalar pass rotates y1 by w^2j, y2 by w^j and y3 by w^3j.
        let (w1, w2, w3) = (twiddle(2), twiddle(1), twiddle(3));
        for g in (at..words.len()).step_by(span) {
            let (x0, x1, x2, x3) = (
                load(words, g),
                load(words, g + q),
                load(words, g + 2 * q),
                load(words, g + 3 * q),
            );
            let (x0, x1, x2, x3) = if PRE {
                let zero = _mm_setzero_si128();
                (
                    hadd(x0, zero),
                    hadd(x1, zero),
                    hadd(x2, zero),
                    hadd(x3, zero),
                )
            } else {
                (x0, x1, x2, x3)
            };
            let (t0, t1, t2, t3) = (
                add::<T>(x0, x2),
                sub::<T>(x0, x2),
                add::<T>(x1, x3),
                sub::<T>(x1, x3),
            );
            let y0 = add::<Y>(t0, t2);
            let y1 = sub::<Y>(t0, t2);
            let y2 = sub_j::<Y>(t1, t3);
            let y3 = add_j::<Y>(t1, t3);
            let (mut r1, mut r2, mut r3) = (w1.rotate(y1), w2.rotate(y2), w3.rotate(y3));
            if at == 0 {
                let keep = |y, r| _mm_or_si128(_mm_and_si128(first, y), _mm_andnot_si128(first, r));
                (r1, r2, r3) = (keep(y1, r1), keep(y2, r2), keep(y3, r3));
            }
            store(words, g, y0);
            store(words, g + q, r1);
            store(words, g + 2 * q, r2);
            store(words, g + 3 * q, r3);
            if TRACK {
                let written = _mm_or_si128(
                    _mm_or_si128(bound(y0), bound(r1)),
                    _mm_or_si128(bound(r2), bound(r3)),
                );
                acc = _mm_or_si128(acc, written);
            }
        }
    }
    if TRACK { or_words(acc) } else { 0 }
}

/// The radix-4 pass over groups of 8 (`q = 2`), two groups' halves per vector: words
/// `g .. g + 4` hold `x0, x1` of twiddle indices 0 and 1, `g + 4 .. g + 8` hold `x2, x3`, so the
/// first radix-2 level is one add and one subtract of the two vectors and the second pairs each
/// vector with its 64-bit halves swapped. Same `PRE`, `T`, `Y`, `TRACK` and result as
/// [`radix4_pass`]; `w` are the twiddles of index 1 (`w^2`, `w`, `w^3` in the scalar order).
///
/// O(`words.len()`).
#[inline]
#[target_feature(enable = "sse2")]
pub fn radix4_pass_8<const PRE: bool, const T: bool, const Y: bool, const TRACK: bool>(
    words: &mut [u32],
    (w1, w2, w3): (u32, u32, u32),
) -> u32 {
    // Index 0 is not rotated: of y0 y0 y1 y1 only the last word turns, of y2 y2 y3 y3 the odd.
    let (w1, keep1) = (Twiddles::new([0, 0, 0, w1]), _mm_set_epi32(0, -1, -1, -1));
    let (w23, keep23) = (Twiddles::new([0, w2, 0, w3]), _mm_set_epi32(0, -1, 0, -1));
    let low = _mm_set_epi32(0, 0, -1, -1);
    let mut acc = _mm_setzero_si128();
    for g in (0..words.len()).step_by(8) {
        let (a, b) = (load(words, g), load(words, g + 4));
        let (a, b) = if PRE {
            let zero = _mm_setzero_si128();
            (hadd(a, zero), hadd(b, zero))
        } else {
            (a, b)
        };
        // t0 t0 t2 t2 and t1 t1 t3 t3.
        let (p, m) = (add::<T>(a, b), sub::<T>(a, b));
        let (ps, ms) = (_mm_shuffle_epi32::<0x4E>(p), _mm_shuffle_epi32::<0x4E>(m));
        let y01 = select(low, add::<Y>(p, ps), sub::<Y>(ps, p));
        let y23 = select(low, sub_j::<Y>(m, ms), add_j::<Y>(ms, m));
        let r01 = select(keep1, y01, w1.rotate(y01));
        let r23 = select(keep23, y23, w23.rotate(y23));
        store(words, g, r01);
        store(words, g + 4, r23);
        if TRACK {
            acc = _mm_or_si128(acc, _mm_or_si128(bound(r01), bound(r23)));
        }
    }
    if TRACK { or_words(acc) } else { 0 }
}

/// The closing radix-2 pass of [`super::q15`] (adjacent pairs, no twiddles), two pairs per
/// vector: the sum in the even word, the difference in the odd. O(`words.len()`), a multiple
/// of four.
#[inline]
#[target_feature(enable = "sse2")]
pub fn radix2_pass<const HALVE: bool>(words: &mut [u32]) {
    let even = _mm_set_epi32(0, -1, 0, -1);
    for g in (0..words.len()).step_by(4) {
        let v = load(words, g);
        // b0 a0 b1 a1
        let s = _mm_shuffle_epi32::<0xB1>(v);
        store(
            words,
            g,
            select(even, add::<HALVE>(v, s), sub::<HALVE>(s, v)),
        );
    }
}
