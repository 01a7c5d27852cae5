//! Fixed-point number formats used on the radar module.
//!
//! The ADC delivers signed 16-bit samples, which the pipeline reads directly as [`Q15`]
//! fractions (value / 2¹⁵). Wider intermediate results use [`Q31`]. Both saturate instead of
//! wrapping, so an overload clips like the ADC does rather than folding into a false target.
//! [`Complex`] pairs two of them with the memory layout of the DCA1000 and CMSIS (`re`, `im`).

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
