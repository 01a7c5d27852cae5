//! Azimuth: angle spectra over the virtual array, by zero-padded FFT (all angles at once) or by
//! steering-vector beamforming (any angle, e.g. the edges of a camera mask).

mod beamform;
mod spectrum;

pub use beamform::beamform;
pub use spectrum::azimuth_spectrum;
