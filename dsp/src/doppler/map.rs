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
    let expected = cube.bins() * scratch.len();
    if out.len() != expected {
        return Err(DopplerError::Map {
            expected,
            got: out.len(),
        });
    }
    range_doppler_rows(cube, options, scratch, 0, out)
}

/// The rows of [`range_doppler_map`] from range bin `first` on, as many as `out` holds (whole
/// rows of `scratch.len()`): the same values, so disjoint parts can be filled apart (on the
/// host, one per thread).
///
/// # Errors
/// [`DopplerError`] on size mismatches (rows beyond the cube, or a part row).
pub fn range_doppler_rows(
    cube: &RangeCube<impl AsRef<[CQ15]>, impl AsRef<[Exponent]>>,
    options: &DopplerOptions<'_>,
    scratch: &mut [CQ15],
    first: usize,
    out: &mut [f32],
) -> Result<(), DopplerError> {
    range_doppler_rows_keeping(cube, options, scratch, first, out, |_, _, _, _| {})
}

/// [`range_doppler_rows`] that also hands each spectrum it forms to `keep` (range bin, channel,
/// block exponent, spectrum in natural FFT order), for a host that reads them again (the point
/// cloud) rather than transform them twice. The map's values are the same.
///
/// # Errors
/// [`DopplerError`] on size mismatches (rows beyond the cube, or a part row).
pub fn range_doppler_rows_keeping(
    cube: &RangeCube<impl AsRef<[CQ15]>, impl AsRef<[Exponent]>>,
    options: &DopplerOptions<'_>,
    scratch: &mut [CQ15],
    first: usize,
    out: &mut [f32],
    mut keep: impl FnMut(usize, usize, Exponent, &[CQ15]),
) -> Result<(), DopplerError> {
    let nd = scratch.len();
    if out.is_empty() {
        return Ok(());
    }
    let rows = out.len() / nd.max(1);
    if nd == 0 || rows * nd != out.len() || first + rows > cube.bins() {
        return Err(DopplerError::Map {
            expected: cube.bins().saturating_sub(first) * nd,
            got: out.len(),
        });
    }
    out.fill(0.0);
    for (i, row) in out.chunks_exact_mut(nd).enumerate() {
        let bin = first + i;
        for ch in 0..cube.channels() {
            let exp = doppler_column(cube, ch, bin, options, scratch)?;
            for (o, &z) in row.iter_mut().zip(scratch.iter()) {
                *o += magnitude(z, exp);
            }
            keep(bin, ch, exp, scratch);
        }
    }
    Ok(())
}
