//! The Doppler spectrum of one (channel, range bin).

use crate::clutter::remove_mean;
use crate::fft::{self, Exponent, FftError};
use crate::fixed::{CQ15, Q15};
use crate::range::{RangeCube, RangeError};
use crate::window;
use core::fmt;

/// How to form a Doppler spectrum.
#[derive(Clone, Copy, Debug, Default)]
pub struct DopplerOptions<'w> {
    /// Subtract the mean over loops first (static clutter removal).
    pub remove_static: bool,
    /// Window over the loops (`None`: rectangular); its length must equal the loops.
    pub window: Option<&'w [Q15]>,
}

/// Why Doppler processing could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum DopplerError {
    /// The cube could not be read.
    Range(RangeError),
    /// The scratch length is not a supported FFT length of at least the loops.
    Scratch {
        /// Loops in the cube.
        loops: usize,
        /// Scratch length given.
        got: usize,
    },
    /// The window length differs from the loops.
    Window {
        /// Loops in the cube.
        loops: usize,
        /// Window length given.
        got: usize,
    },
    /// The output map has the wrong size.
    Map {
        /// Entries needed.
        expected: usize,
        /// Entries given.
        got: usize,
    },
}

impl From<RangeError> for DopplerError {
    fn from(e: RangeError) -> Self {
        Self::Range(e)
    }
}

impl From<FftError> for DopplerError {
    fn from(e: FftError) -> Self {
        Self::Range(RangeError::Fft(e))
    }
}

impl core::error::Error for DopplerError {}

impl fmt::Display for DopplerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Range(e) => e.fmt(f),
            Self::Scratch { loops, got } => write!(
                f,
                "Doppler scratch of {got} points for {loops} loops: use a power of two ≥ loops (and ≥ 16)"
            ),
            Self::Window { loops, got } => write!(
                f,
                "Doppler window of {got} for {loops} loops: use one coefficient per loop"
            ),
            Self::Map { expected, got } => write!(
                f,
                "range–Doppler map holds {got} cells but {expected} are needed"
            ),
        }
    }
}

/// Doppler spectrum of range bin `bin` of `channel` into `scratch` (its length is the Doppler
/// FFT length, ≥ loops): columns are aligned to a common exponent, optionally mean-removed and
/// windowed, zero-padded and transformed. Returns the exponent of the spectrum (natural FFT
/// order: index k > len/2 are negative Doppler). O(L log L).
///
/// # Errors
/// [`DopplerError`] on index or size mismatches.
pub fn doppler_column(
    cube: &RangeCube<impl AsRef<[CQ15]>, impl AsRef<[Exponent]>>,
    channel: usize,
    bin: usize,
    options: &DopplerOptions<'_>,
    scratch: &mut [CQ15],
) -> Result<Exponent, DopplerError> {
    let loops = cube.loops();
    if !fft::is_supported_len(scratch.len()) || scratch.len() < loops {
        return Err(DopplerError::Scratch {
            loops,
            got: scratch.len(),
        });
    }
    if let Some(w) = options.window {
        if w.len() != loops {
            return Err(DopplerError::Window {
                loops,
                got: w.len(),
            });
        }
    }
    let Exponent(mut exp) = cube.gather_column(channel, bin, scratch)?;
    let (column, pad) = scratch.split_at_mut(loops);
    pad.fill(CQ15::default());
    if options.remove_static {
        exp += remove_mean(column);
    }
    if let Some(w) = options.window {
        window::apply(w, column);
    }
    Ok(Exponent(exp + fft::cfft_q15(scratch)?.0))
}
