//! Signed Q1.31 fractions.

use super::q15::round_saturate;

/// A signed Q1.31 fraction: the value is `self.0 / 2³¹`, in `[-1, 1 - 2⁻³¹]`.
///
/// Arithmetic saturates at the ends of the range.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Q31(pub i32);

impl Q31 {
    /// Number of fractional bits.
    pub const FRAC_BITS: u32 = 31;
    /// The largest value, 1 − 2⁻³¹.
    pub const MAX: Self = Self(i32::MAX);
    /// The smallest value, −1.
    pub const MIN: Self = Self(i32::MIN);
    /// Zero.
    pub const ZERO: Self = Self(0);

    /// Converts from `f64`, rounding to nearest and saturating; NaN maps to zero.
    pub const fn from_f64(x: f64) -> Self {
        Self(round_saturate(x * 2147483648.0, i32::MIN as f64, i32::MAX as f64) as i32)
    }

    /// Converts from `f32`, rounding to nearest and saturating; NaN maps to zero.
    pub fn from_f32(x: f32) -> Self {
        Self::from_f64(x as f64)
    }

    /// The value as `f64` (exact).
    pub fn to_f64(self) -> f64 {
        self.0 as f64 * (1.0 / 2147483648.0)
    }

    /// The value as `f32` (rounded).
    pub fn to_f32(self) -> f32 {
        self.to_f64() as f32
    }

    /// Saturating multiplication, rounded to nearest (−1 × −1 gives [`Q31::MAX`]).
    pub const fn saturating_mul(self, rhs: Self) -> Self {
        let p = (self.0 as i64 * rhs.0 as i64 + (1 << 30)) >> 31;
        Self(if p > i32::MAX as i64 {
            i32::MAX
        } else {
            p as i32
        })
    }
}

impl From<super::Q15> for Q31 {
    /// Exact widening: the Q15 value shifted into the upper half.
    fn from(x: super::Q15) -> Self {
        Self((x.0 as i32) << 16)
    }
}

super::saturating_ops!(Q31);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::Q15;

    #[test]
    fn conversions() {
        assert_eq!(Q31::from_f64(0.25).0, 1 << 29);
        assert_eq!(Q31::from_f64(2.0), Q31::MAX);
        assert_eq!(Q31::from_f64(f64::NAN), Q31::ZERO);
        assert_eq!(Q31::from(Q15(-16384)).to_f64(), -0.5);
    }

    #[test]
    fn arithmetic_saturates() {
        assert_eq!(Q31::MAX + Q31(1), Q31::MAX);
        assert_eq!(Q31::MIN.saturating_mul(Q31::MIN), Q31::MAX);
        assert_eq!(Q31(1 << 30).saturating_mul(Q31(1 << 30)).0, 1 << 29);
    }
}
