//! Signed Q1.15 fractions.

/// A signed Q1.15 fraction: the value is `self.0 / 32768`, in `[-1, 1 - 2⁻¹⁵]`.
///
/// Arithmetic saturates at the ends of the range.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Q15(pub i16);

impl Q15 {
    /// Number of fractional bits.
    pub const FRAC_BITS: u32 = 15;
    /// The largest value, 1 − 2⁻¹⁵.
    pub const MAX: Self = Self(i16::MAX);
    /// The smallest value, −1.
    pub const MIN: Self = Self(i16::MIN);
    /// Zero.
    pub const ZERO: Self = Self(0);

    /// Converts from `f32`, rounding to nearest and saturating; NaN maps to zero.
    pub fn from_f32(x: f32) -> Self {
        Self(round_saturate(x as f64 * 32768.0, i16::MIN as f64, i16::MAX as f64) as i16)
    }

    /// Converts from `f64` at compile time or run time, rounding to nearest and saturating;
    /// NaN maps to zero.
    pub const fn from_f64(x: f64) -> Self {
        Self(round_saturate(x * 32768.0, i16::MIN as f64, i16::MAX as f64) as i16)
    }

    /// The value as `f32` (exact).
    pub fn to_f32(self) -> f32 {
        self.0 as f32 * (1.0 / 32768.0)
    }

    /// Saturating multiplication, rounded to nearest (−1 × −1 gives [`Q15::MAX`]).
    pub const fn saturating_mul(self, rhs: Self) -> Self {
        let p = (self.0 as i32 * rhs.0 as i32 + (1 << 14)) >> 15;
        Self(if p > i16::MAX as i32 {
            i16::MAX
        } else {
            p as i16
        })
    }
}

/// Rounds `y` half away from zero and clamps it to `[lo, hi]`; NaN gives 0.
pub(crate) const fn round_saturate(y: f64, lo: f64, hi: f64) -> i64 {
    if y.is_nan() {
        return 0;
    }
    let r = if y >= 0.0 { y + 0.5 } else { y - 0.5 };
    let c = if r > hi {
        hi
    } else if r < lo {
        lo
    } else {
        r
    };
    c as i64
}

super::saturating_ops!(Q15);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_round_and_saturate() {
        assert_eq!(Q15::from_f32(0.5).0, 16384);
        assert_eq!(Q15::from_f32(-1.0).0, -32768);
        assert_eq!(Q15::from_f32(1.0).0, 32767);
        assert_eq!(Q15::from_f32(-7.0).0, -32768);
        assert_eq!(Q15::from_f32(f32::NAN).0, 0);
        assert_eq!(Q15::from_f64(1.5 / 32768.0).0, 2);
        assert_eq!(Q15::from_f64(-1.5 / 32768.0).0, -2);
        assert_eq!(Q15(-16384).to_f32(), -0.5);
    }

    #[test]
    fn arithmetic_saturates() {
        assert_eq!(Q15::MAX + Q15(1), Q15::MAX);
        assert_eq!(Q15::MIN - Q15(1), Q15::MIN);
        assert_eq!(-Q15::MIN, Q15::MAX);
        assert_eq!(Q15::MIN.saturating_mul(Q15::MIN), Q15::MAX);
        assert_eq!(Q15(16384).saturating_mul(Q15(16384)).0, 8192);
        assert_eq!(Q15(3).saturating_mul(Q15(16384)).0, 2); // 1.5 rounds away from zero
    }
}
