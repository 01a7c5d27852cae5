//! Azimuth FFT over the zero-padded virtual array.

use crate::array::{ArrayError, VirtualArray};
use crate::fft::{self, Exponent};
use crate::fixed::CQ15;

/// Angle spectrum of one range(-Doppler) cell: channel values (one per virtual channel, aligned
/// to one exponent) are placed at their positions in `out`, zero-padded to `out.len()` and
/// transformed. Signed bin k is the direction sin θ = 2k / out.len(). O(M log M).
///
/// # Errors
/// [`ArrayError`] on size mismatches, including an unsupported FFT length.
pub fn azimuth_spectrum(
    array: &VirtualArray,
    channel_values: &[CQ15],
    out: &mut [CQ15],
) -> Result<Exponent, ArrayError> {
    if !fft::is_supported_len(out.len()) {
        return Err(ArrayError::Buffer {
            what: "azimuth FFT (power of two, 16..=2048)",
            expected: array.span().max(fft::MIN_LEN),
            got: out.len(),
        });
    }
    array.gather(channel_values, out)?;
    fft::cfft_q15(out).map_err(|_| ArrayError::Span(out.len()))
}
