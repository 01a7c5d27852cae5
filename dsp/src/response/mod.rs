//! The response model that clutter cancellation and the depth search share: what the radar
//! records from a point reflector. [`Geometry`] describes the array and the range FFT; a
//! reflector at fractional range bin `r` and direction sine `s` appears in range bin `k` of the
//! beam steered to `s'` as `α·T(k − r)·AF(s − s')`, with `T` the windowed range kernel
//! ([`kernel`], built on the periodic sinc [`dirichlet()`]) and `AF` the array factor; [`beam`]
//! steers the fixed-point range spectra.
//!
//! It sits under both users: `clutter::sic` subtracts modelled responses, `search::depth`
//! correlates contours with what is left. Neither imports the other.

pub mod beam;
mod dirichlet;
pub mod kernel;

pub use dirichlet::dirichlet;

use crate::window::WindowKind;

/// What the search needs to know about the radar.
#[derive(Clone, Copy, Debug)]
pub struct Geometry<'a> {
    /// Position of each virtual element, half-wavelengths from the first (ascending).
    pub positions: &'a [u16],
    /// Channels summed into each element.
    pub counts: &'a [u8],
    /// ADC samples per chirp (N).
    pub samples: usize,
    /// Range FFT length (M ≥ N).
    pub fft_len: usize,
    /// Range window.
    pub window: WindowKind,
    /// Metres per range bin of the M-point FFT.
    pub bin_m: f32,
}
