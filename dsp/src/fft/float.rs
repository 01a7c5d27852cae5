//! The `f32` comparison path: microfft's radix-2 FFT behind the same length checks.

use super::FftError;
pub use microfft::Complex32;

/// Forward FFT of `buf` in place with microfft (unscaled, natural order).
///
/// # Errors
/// [`FftError::UnsupportedLength`] unless `buf.len()` is a power of two in `16..=2048`.
pub fn cfft_f32(buf: &mut [Complex32]) -> Result<(), FftError> {
    use microfft::complex::*;
    let n = buf.len();
    macro_rules! dispatch {
        ($($len:literal => $f:ident),*) => {
            match n {
                $($len => { let _ = $f(buf.try_into().map_err(|_| FftError::UnsupportedLength(n))?); })*
                _ => return Err(FftError::UnsupportedLength(n)),
            }
        };
    }
    dispatch!(16 => cfft_16, 32 => cfft_32, 64 => cfft_64, 128 => cfft_128, 256 => cfft_256,
              512 => cfft_512, 1024 => cfft_1024, 2048 => cfft_2048);
    Ok(())
}
