//! Fixed-point number formats used on the radar module.
//!
//! The ADC delivers signed 16-bit samples, which the pipeline reads directly as [`Q15`]
//! fractions (value / 2¹⁵). Wider intermediate results use [`Q31`]. Both saturate instead of
//! wrapping, so an overload clips like the ADC does rather than folding into a false target.
//! [`Complex`] pairs two of them with the memory layout of the DCA1000 and CMSIS (`re`, `im`).

mod complex;
mod q15;
mod q31;

pub use complex::Complex;
pub use q15::Q15;
pub use q31::Q31;

/// A complex Q15 sample: the native format of radar I/Q data on the module (4 bytes).
pub type CQ15 = Complex<Q15>;
/// A complex Q31 sample (8 bytes).
pub type CQ31 = Complex<Q31>;
