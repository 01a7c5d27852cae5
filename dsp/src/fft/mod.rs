//! Complex FFTs for range, Doppler and azimuth processing.
//!
//! [`cfft_q15`] and [`cfft_q31`] transform in place with block floating point and return the
//! block [`Exponent`]; [`Cfft`] is the same with the length fixed at compile time. [`cfft_f32`]
//! runs microfft for comparison. Every power of two from 16 to 2048 points is supported.

mod float;
mod q15;
mod q31;
mod reorder;
pub(crate) mod simd;
#[cfg(target_arch = "x86_64")]
mod sse2;
pub use simd::complex_mac;

/// Short name of the f32 complex type used for f32 spectra.
pub use float::Complex32 as C32;
pub use float::{Complex32, cfft_f32};

use crate::fixed::{CQ15, CQ31};
use core::fmt;

/// Smallest supported FFT length.
pub const MIN_LEN: usize = 16;
/// Largest supported FFT length.
pub const MAX_LEN: usize = crate::trig::twiddle::TABLE_LEN;

/// Block exponent of a fixed-point spectrum: the true DFT equals the output times `2^exponent`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Exponent(pub u32);

impl Exponent {
    /// `2^exponent` as `f32`.
    pub fn scale_f32(self) -> f32 {
        libm::ldexpf(1.0, self.0 as i32)
    }

    /// `2^exponent` as `f64`.
    pub fn scale_f64(self) -> f64 {
        libm::ldexp(1.0, self.0 as i32)
    }
}

/// Why an FFT could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum FftError {
    /// The buffer length is not a power of two in `16..=2048`.
    UnsupportedLength(usize),
}

impl core::error::Error for FftError {}

impl fmt::Display for FftError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnsupportedLength(n) => write!(
                f,
                "FFT length {n} is not supported: use a power of two from {MIN_LEN} to {MAX_LEN} \
                 (zero-pad the input)"
            ),
        }
    }
}

/// Whether `n` is a supported FFT length.
pub const fn is_supported_len(n: usize) -> bool {
    n.is_power_of_two() && n >= MIN_LEN && n <= MAX_LEN
}

/// The smallest supported FFT length that holds `n` samples, if any.
pub const fn padded_len(n: usize) -> Option<usize> {
    let p = if n <= MIN_LEN {
        MIN_LEN
    } else {
        n.next_power_of_two()
    };
    if p <= MAX_LEN { Some(p) } else { None }
}

fn check(n: usize) -> Result<(), FftError> {
    if is_supported_len(n) {
        Ok(())
    } else {
        Err(FftError::UnsupportedLength(n))
    }
}

/// Forward complex FFT of Q15 samples in place, natural order in and out.
///
/// The output is scaled down only as far as overflow could require; the true DFT of the input
/// (as fractions) is `output · 2^exponent`. O(N log N), no allocation, deterministic.
///
/// # Errors
/// [`FftError::UnsupportedLength`] unless `buf.len()` is a power of two in `16..=2048`.
///
/// # Example
/// A half-scale tone at bin 3 of a 16-point FFT:
/// ```
/// use metamoran_dsp::fft::cfft_q15;
/// use metamoran_dsp::fixed::{CQ15, Q15};
/// use metamoran_dsp::trig::{Phase, expj_neg};
///
/// let mut x = [CQ15::default(); 16];
/// for (n, z) in x.iter_mut().enumerate() {
///     let t = expj_neg(Phase::from_turns(-3.0 * n as f64 / 16.0)); // exp(+j2π·3n/16)
///     *z = CQ15::new(Q15(t.re.0 / 2), Q15(t.im.0 / 2));
/// }
/// let exponent = cfft_q15(&mut x)?;
/// let power = |z: &CQ15| i32::from(z.re.0).pow(2) + i32::from(z.im.0).pow(2);
/// let peak = (0..16).max_by_key(|&k| power(&x[k])).unwrap();
/// assert_eq!(peak, 3);
/// // The true DFT is the output · 2^exponent: 16 samples of amplitude ½ sum to 8.
/// let amplitude = x[3].re.to_f32() * 2f32.powi(exponent.0 as i32);
/// assert!((amplitude - 8.0).abs() < 0.05, "{amplitude}");
/// # Ok::<(), metamoran_dsp::fft::FftError>(())
/// ```
pub fn cfft_q15(buf: &mut [CQ15]) -> Result<Exponent, FftError> {
    check(buf.len())?;
    Ok(Exponent(q15::fft_in_place(buf)))
}

/// [`cfft_q15`] without the closing bit-reversal: bin `k` is left at index
/// [`bit_reversed(k, len)`](bit_reversed). For a consumer that reads every bin once anyway
/// (a copy, a power map), reading through that index costs two instructions per bin on the M7
/// (`RBIT`, `LSR`) where the reorder costs about six per bin.
///
/// # Errors
/// [`FftError::UnsupportedLength`] unless `buf.len()` is a power of two in `16..=2048`.
pub fn cfft_q15_bit_reversed(buf: &mut [CQ15]) -> Result<Exponent, FftError> {
    check(buf.len())?;
    Ok(Exponent(q15::fft_bit_reversed(buf)))
}

/// Where [`cfft_q15_bit_reversed`] leaves bin `k` of an `n`-point transform (`n` a power of
/// two, `k < n`): `k` with its `log₂ n` bits reversed. O(1).
#[inline(always)]
pub const fn bit_reversed(k: usize, n: usize) -> usize {
    let bits = n.trailing_zeros();
    if bits == 0 {
        0
    } else {
        ((k as u32).reverse_bits() >> (32 - bits)) as usize
    }
}

/// Forward complex FFT of Q31 samples in place; see [`cfft_q15`].
///
/// # Errors
/// [`FftError::UnsupportedLength`] unless `buf.len()` is a power of two in `16..=2048`.
pub fn cfft_q31(buf: &mut [CQ31]) -> Result<Exponent, FftError> {
    check(buf.len())?;
    Ok(Exponent(q31::fft_in_place(buf)))
}

/// An FFT whose length is checked at compile time.
///
/// ```
/// use metamoran_dsp::fft::Cfft;
/// use metamoran_dsp::fixed::CQ15;
/// let mut x = [CQ15::default(); 256];
/// let _exp = Cfft::<256>::q15(&mut x);
/// ```
pub struct Cfft<const N: usize>;

impl<const N: usize> Cfft<N> {
    const LEN_OK: () = assert!(
        is_supported_len(N),
        "FFT length must be a power of two in 16..=2048"
    );

    /// Forward Q15 FFT; see [`cfft_q15`].
    pub fn q15(buf: &mut [CQ15; N]) -> Exponent {
        let () = Self::LEN_OK;
        Exponent(q15::fft_in_place(buf))
    }

    /// Forward Q31 FFT; see [`cfft_q31`].
    pub fn q31(buf: &mut [CQ31; N]) -> Exponent {
        let () = Self::LEN_OK;
        Exponent(q31::fft_in_place(buf))
    }
}
