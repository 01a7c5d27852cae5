//! Complex values of any scalar format.

use super::{Q15, Q31};
use core::ops::{Add, Sub};

/// A complex value laid out as `re` then `im` (the order of CMSIS-DSP buffers).
///
/// Aligned to at least 4 bytes, so a complex Q15 sample is one 32-bit word (`re` in the low
/// half) that the DSP extension's SIMD instructions load and store whole.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(C, align(4))]
pub struct Complex<T> {
    /// Real part (I).
    pub re: T,
    /// Imaginary part (Q).
    pub im: T,
}

impl<T> Complex<T> {
    /// Builds a complex value from its parts.
    pub const fn new(re: T, im: T) -> Self {
        Self { re, im }
    }
}

impl<T: Add<Output = T>> Add for Complex<T> {
    type Output = Self;
    /// Component-wise (saturating for the fixed-point formats).
    fn add(self, rhs: Self) -> Self {
        Self::new(self.re + rhs.re, self.im + rhs.im)
    }
}

impl<T: Sub<Output = T>> Sub for Complex<T> {
    type Output = Self;
    /// Component-wise (saturating for the fixed-point formats).
    fn sub(self, rhs: Self) -> Self {
        Self::new(self.re - rhs.re, self.im - rhs.im)
    }
}

impl Complex<Q15> {
    /// Builds a sample from raw I and Q integers.
    pub const fn from_raw(re: i16, im: i16) -> Self {
        Self::new(Q15(re), Q15(im))
    }

    /// Converts from an `f32` pair, rounding and saturating each part.
    pub fn from_f32(re: f32, im: f32) -> Self {
        Self::new(Q15::from_f32(re), Q15::from_f32(im))
    }

    /// Squared magnitude in Q30 units (`re² + im²` of the raw integers); exact.
    pub const fn norm_sqr_raw(self) -> u32 {
        let (r, i) = (self.re.0 as i32, self.im.0 as i32);
        (r * r) as u32 + (i * i) as u32
    }

    /// The value as an `f32` pair.
    pub fn to_f32(self) -> (f32, f32) {
        (self.re.to_f32(), self.im.to_f32())
    }

    /// `self / 2^shift`, each part rounded half up; used to align block exponents.
    pub fn scale_down(self, shift: u32) -> Self {
        if shift == 0 {
            return self;
        }
        if shift >= 16 {
            return Self::from_raw(0, 0);
        }
        let f = |x: i16| (((x as i32) + (1 << (shift - 1))) >> shift) as i16;
        Self::from_raw(f(self.re.0), f(self.im.0))
    }
}

impl Complex<Q31> {
    /// Builds a sample from raw I and Q integers.
    pub const fn from_raw(re: i32, im: i32) -> Self {
        Self::new(Q31(re), Q31(im))
    }

    /// Squared magnitude in Q62 units; exact.
    pub const fn norm_sqr_raw(self) -> u64 {
        let (r, i) = (self.re.0 as i64, self.im.0 as i64);
        (r * r) as u64 + (i * i) as u64
    }

    /// The value as an `f64` pair.
    pub fn to_f64(self) -> (f64, f64) {
        (self.re.to_f64(), self.im.to_f64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_matches_interleaved_buffers() {
        assert_eq!(size_of::<Complex<Q15>>(), 4);
        assert_eq!(size_of::<Complex<Q31>>(), 8);
    }

    #[test]
    fn add_sub_saturate_per_part() {
        let a = Complex::<Q15>::from_raw(32000, -32000);
        let b = Complex::<Q15>::from_raw(1000, 1000);
        assert_eq!(a + b, Complex::<Q15>::from_raw(32767, -31000));
        assert_eq!(a - b, Complex::<Q15>::from_raw(31000, -32768));
        assert_eq!(
            Complex::<Q15>::from_raw(-32768, -32768).norm_sqr_raw(),
            1 << 31
        );
    }
}
