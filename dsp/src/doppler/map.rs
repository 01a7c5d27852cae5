//! The range–Doppler map: |Doppler spectrum| summed over virtual channels.

use super::column::{DopplerError, DopplerOptions, doppler_column};
use crate::fft::Exponent;
use crate::fixed::CQ15;
use crate::range::RangeCube;

/// `|z| · 2^exponent` as `f32` (exact square root of the exact power, rounded once).
pub fn magnitude(z: CQ15, exponent: Exponent) -> f32 {
    libm::sqrtf(z.norm_sqr_raw() as f32) * (1.0 / 32768.0) * exponent.scale_f32()
}

/// Fills `out` (`bins × doppler_len`, row-major by range bin, Doppler in natural FFT order) with
/// the magnitude of each cell's Doppler spectrum summed over all channels. `scratch.len()` is the
/// Doppler FFT length. O(channels · bins · L log L).
///
/// # Errors
/// [`DopplerError`] on size mismatches.
pub fn range_doppler_map(
    cube: &RangeCube<impl AsRef<[CQ15]>, impl AsRef<[Exponent]>>,
    options: &DopplerOptions<'_>,
    scratch: &mut [CQ15],
    out: &mut [f32],
) -> Result<(), DopplerError> {
    let nd = scratch.len();
    let expected = cube.bins() * nd;
    if out.len() != expected {
        return Err(DopplerError::Map {
            expected,
            got: out.len(),
        });
    }
    out.fill(0.0);
    for bin in 0..cube.bins() {
        let row = &mut out[bin * nd..(bin + 1) * nd];
        for ch in 0..cube.channels() {
            let exp = doppler_column(cube, ch, bin, options, scratch)?;
            for (o, &z) in row.iter_mut().zip(scratch.iter()) {
                *o += magnitude(z, exp);
            }
        }
    }
    Ok(())
}
