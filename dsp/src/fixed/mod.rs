//! Fixed-point number formats used on the radar module.
//!
//! The ADC delivers signed 16-bit samples, which the pipeline reads directly as [`Q15`]
//! fractions (value / 2¹⁵). Wider intermediate results use [`Q31`]. Both saturate instead of
//! wrapping, so an overload clips like the ADC does rather than folding into a false target.
//! [`Complex`] pairs two of them with the memory layout of the DCA1000 and CMSIS (`re`, `im`).

// `words`/`words_mut` view `CQ15` buffers as packed `u32` words (same size and alignment).
#![allow(unsafe_code)]

mod complex;
mod q15;
mod q31;

/// Saturating `+`, `−` and negation for a fixed-point newtype over a signed integer.
macro_rules! saturating_ops {
    ($t:ident) => {
        impl $t {
            /// Saturating addition.
            pub const fn saturating_add(self, rhs: Self) -> Self {
                Self(self.0.saturating_add(rhs.0))
            }

            /// Saturating subtraction.
            pub const fn saturating_sub(self, rhs: Self) -> Self {
                Self(self.0.saturating_sub(rhs.0))
            }
        }

        impl core::ops::Add for $t {
            type Output = Self;
            /// Saturating.
            fn add(self, rhs: Self) -> Self {
                self.saturating_add(rhs)
            }
        }

        impl core::ops::Sub for $t {
            type Output = Self;
            /// Saturating.
            fn sub(self, rhs: Self) -> Self {
                self.saturating_sub(rhs)
            }
        }

        impl core::ops::Neg for $t {
            type Output = Self;
            /// Saturating (−MIN gives MAX).
            fn neg(self) -> Self {
                Self(self.0.saturating_neg())
            }
        }
    };
}
use saturating_ops;

pub use complex::Complex;
pub use q15::Q15;
pub use q31::Q31;

/// A complex Q15 sample: the native format of radar I/Q data on the module (4 bytes).
pub type CQ15 = Complex<Q15>;
/// A complex Q31 sample (8 bytes).
pub type CQ31 = Complex<Q31>;

/// Complex Q15 values as packed words, real part in the low half (the layout of
/// [`crate::range::frame_sum::pack`]): one 32-bit load per value for the M7's SIMD. O(1).
pub fn words(buf: &[CQ15]) -> &[u32] {
    // SAFETY: `CQ15` is `repr(C, align(4))` of two `i16`: 4 bytes, 4-aligned, and every bit
    // pattern is valid both ways, so the memory is a valid `[u32]` of the same length.
    unsafe { core::slice::from_raw_parts(buf.as_ptr().cast::<u32>(), buf.len()) }
}

/// [`words`], mutable.
pub fn words_mut(buf: &mut [CQ15]) -> &mut [u32] {
    // SAFETY: as in `words`.
    unsafe { core::slice::from_raw_parts_mut(buf.as_mut_ptr().cast::<u32>(), buf.len()) }
}

/// Packed words viewed as complex Q15 values (the inverse of [`words_mut`]), e.g. an arena's
/// free words lent as an FFT buffer. O(1).
pub fn from_words_mut(words: &mut [u32]) -> &mut [CQ15] {
    // SAFETY: `u32` is 4 bytes and 4-aligned, as `CQ15` (`repr(C, align(4))` of two `i16`), and
    // every bit pattern is valid both ways.
    unsafe { core::slice::from_raw_parts_mut(words.as_mut_ptr().cast::<CQ15>(), words.len()) }
}
