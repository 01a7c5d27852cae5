//! Trigonometry for compile-time tables and run-time phase rotation.
//!
//! Twiddle factors, windows and steering vectors all come from here. [`cos_sin_turn`] is a
//! `const fn` (range reduction on exact integers, then a Taylor series on at most π/4), so every
//! table is built by the compiler, identical on x86 and the Cortex-M7. [`expj_neg`] rotates by a
//! binary angle at run time through the twiddle table ([`twiddle`], which the FFTs stride) with
//! linear interpolation.

pub mod twiddle;

use crate::fixed::{CQ15, Complex, Q15};
use twiddle::{TABLE_LEN, TWIDDLE_Q15};

const FRAC_PI_2: f64 = core::f64::consts::FRAC_PI_2;

/// `(cos, sin)` of the angle `2π · num / den`, accurate to about 1e-16.
///
/// `den` must be positive; any `num` is accepted. Usable in constant expressions.
pub const fn cos_sin_turn(num: i64, den: i64) -> (f64, f64) {
    // Exact reduction to a quadrant and an offset inside it.
    let r = num.rem_euclid(den);
    let quadrant = (4 * r) / den; // 0..=3
    let rem = 4 * r - quadrant * den; // 0..den, angle = (π/2)·rem/den
    // Reduce further to [0, π/4] using the complementary angle.
    let (c, s) = if 2 * rem <= den {
        cos_sin_small(FRAC_PI_2 * rem as f64 / den as f64)
    } else {
        let (c, s) = cos_sin_small(FRAC_PI_2 * (den - rem) as f64 / den as f64);
        (s, c)
    };
    match quadrant {
        0 => (c, s),
        1 => (-s, c),
        2 => (-c, -s),
        _ => (s, -c),
    }
}

/// Taylor series of cos and sin for `|x| ≤ π/4` (terms to x²¹; truncation below 1e-19).
const fn cos_sin_small(x: f64) -> (f64, f64) {
    let x2 = x * x;
    let mut cos = 1.0;
    let mut sin = x;
    let mut tc = 1.0;
    let mut ts = x;
    let mut n = 1;
    while n <= 10 {
        let k = (2 * n) as f64;
        tc = -tc * x2 / ((k - 1.0) * k);
        ts = -ts * x2 / (k * (k + 1.0));
        cos += tc;
        sin += ts;
        n += 1;
    }
    (cos, sin)
}

/// `(cos πx, sin πx)` in `f32` for `x` in half-turns (`x = 1` is π radians).
///
/// Exact reduction to `|r| ≤ 1/4` (`x` minus the nearest multiple of ½, which `f32` represents
/// exactly), then Taylor polynomials of `πr` to the 9th/10th power (truncation below 2e-9), so
/// the error is a few `f32` ulp. Only IEEE `+ − ×` on `f32`: the same bits on x86 and on the
/// M7's single-precision FPU, about 30 instructions there, where `libm::sinf` spends ~700 in
/// soft `f64`. NaN and infinities give NaN. O(1), no panics.
pub fn cos_sin_pi(x: f32) -> (f32, f32) {
    /// 1.5·2²³: adding and subtracting it rounds an `f32` below 2²² to the nearest integer.
    const ROUND: f32 = 12_582_912.0;
    if !x.is_finite() {
        return (f32::NAN, f32::NAN);
    }
    // Beyond 2²¹ half-turns every f32 is a multiple of ¼ (beyond 2²⁴, of 2): reduce mod 2
    // exactly in integers first (no `fmodf` call, which LLVM would evaluate speculatively).
    let x = if x.abs() >= 16_777_216.0 {
        0.0
    } else if x.abs() >= 2_097_152.0 {
        ((x * 4.0) as i32 & 7) as f32 * 0.25
    } else {
        x
    };
    let q = (2.0 * x + ROUND) - ROUND; // nearest multiple of ½, doubled
    let r = x - 0.5 * q;
    let y = core::f32::consts::PI * r;
    let y2 = y * y;
    let s = y
        * (1.0
            + y2 * (-1.0 / 6.0
                + y2 * (1.0 / 120.0 + y2 * (-1.0 / 5040.0 + y2 * (1.0 / 362_880.0)))));
    let c = 1.0 + y2 * (-0.5 + y2 * (1.0 / 24.0 + y2 * (-1.0 / 720.0 + y2 * (1.0 / 40_320.0))));
    match (q as i32) & 3 {
        0 => (c, s),
        1 => (-s, c),
        2 => (-c, -s),
        _ => (s, -c),
    }
}

/// A binary angle: `turns / 2³²` of a full turn (so wrapping addition is angle addition).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Phase(pub u32);

impl Phase {
    /// The phase of `x` turns, wrapped into one turn (NaN and infinities give zero).
    pub fn from_turns(x: f64) -> Self {
        if !x.is_finite() {
            return Self(0);
        }
        let frac = x - libm::floor(x);
        Self((frac * 4294967296.0) as u64 as u32)
    }
}

/// `exp(−j·2π·phase)` in Q15, by linear interpolation in the 2048-entry twiddle table.
///
/// Error below 2 LSB of Q15. Constant time; no panics.
pub fn expj_neg(phase: Phase) -> CQ15 {
    const IDX_SHIFT: u32 = 32 - TABLE_LEN.trailing_zeros();
    let idx = (phase.0 >> IDX_SHIFT) as usize;
    let frac = ((phase.0 << (32 - IDX_SHIFT)) >> 17) as i32; // 15-bit fraction
    let a = TWIDDLE_Q15[idx % TABLE_LEN];
    let b = TWIDDLE_Q15[(idx + 1) % TABLE_LEN];
    let lerp = |p: Q15, q: Q15| {
        let (p, q) = (p.0 as i32, q.0 as i32);
        Q15((p + (((q - p) * frac + (1 << 14)) >> 15)) as i16)
    };
    Complex::new(lerp(a.re, b.re), lerp(a.im, b.im))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn const_cos_sin_matches_libm() {
        for den in [3i64, 7, 64, 2048, 1000] {
            for num in -2 * den..2 * den {
                let (c, s) = cos_sin_turn(num, den);
                let x = 2.0 * core::f64::consts::PI * num as f64 / den as f64;
                assert!((c - libm::cos(x)).abs() < 1e-14, "cos {num}/{den}");
                assert!((s - libm::sin(x)).abs() < 1e-14, "sin {num}/{den}");
            }
        }
    }

    #[test]
    fn cos_sin_pi_matches_f64() {
        let mut worst = 0.0f64;
        let mut x = -1000.0f32;
        while x < 1000.0 {
            for dx in [0.0f32, 1e-3, 0.25, 0.5, 0.75] {
                let v = x + dx;
                let (c, s) = cos_sin_pi(v);
                let a = core::f64::consts::PI * v as f64;
                worst = worst
                    .max((c as f64 - libm::cos(a)).abs())
                    .max((s as f64 - libm::sin(a)).abs());
            }
            x += 0.0137;
        }
        assert!(worst < 4e-7, "worst error {worst}");
        // Huge arguments reduce exactly; exact quarter turns are exact.
        assert_eq!(cos_sin_pi(3_000_001.0), (-1.0, 0.0));
        assert_eq!(cos_sin_pi(2_500_000.5), (0.0, 1.0));
        assert_eq!(cos_sin_pi(-0.5), (0.0, -1.0));
        assert!(cos_sin_pi(f32::NAN).0.is_nan() && cos_sin_pi(f32::INFINITY).1.is_nan());
    }

    #[test]
    fn expj_neg_is_accurate_to_two_lsb() {
        let mut p = 0u32;
        for _ in 0..10_000 {
            let z = expj_neg(Phase(p));
            let x = 2.0 * core::f64::consts::PI * (p as f64 / 4294967296.0);
            assert!((z.re.0 as f64 - 32768.0 * libm::cos(x)).abs() <= 2.0);
            assert!((z.im.0 as f64 + 32768.0 * libm::sin(x)).abs() <= 2.0);
            p = p.wrapping_add(429_497); // about 1e-4 turn, not a table multiple
        }
    }
}
