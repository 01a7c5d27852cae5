//! The range FFT of one chirp of one receiver.

use crate::fft::{self, Exponent, FftError};
use crate::fixed::{CQ15, Q15};
use crate::window;
use core::fmt;

/// Why range processing could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RangeError {
    /// The FFT length is unsupported.
    Fft(FftError),
    /// More samples than FFT points, or a window of another length than the samples.
    Samples {
        /// Samples per chirp the processor was built for.
        expected: usize,
        /// Samples given.
        got: usize,
    },
    /// A buffer has the wrong length (names it).
    Buffer {
        /// Which buffer.
        what: &'static str,
        /// Length needed.
        expected: usize,
        /// Length given.
        got: usize,
    },
    /// A cube index is out of range (names the axis).
    Index {
        /// Which axis.
        what: &'static str,
        /// Index given.
        index: usize,
        /// Size of the axis.
        len: usize,
    },
}

impl From<FftError> for RangeError {
    fn from(e: FftError) -> Self {
        Self::Fft(e)
    }
}

impl core::error::Error for RangeError {}

impl fmt::Display for RangeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Fft(e) => e.fmt(f),
            Self::Samples { expected, got } => {
                write!(
                    f,
                    "{got} samples given to a range stage built for {expected}: check `adc_samples`"
                )
            }
            Self::Buffer {
                what,
                expected,
                got,
            } => {
                write!(
                    f,
                    "{what} holds {got} entries but {expected} are needed: size it from the radar config"
                )
            }
            Self::Index { what, index, len } => {
                write!(f, "{what} {index} is out of range (0..{len})")
            }
        }
    }
}

/// Windowed range FFT for chirps of a fixed sample count.
#[derive(Clone, Copy, Debug)]
pub struct RangeProcessor<'w> {
    window: Option<&'w [Q15]>,
    samples: usize,
    fft_len: usize,
}

impl<'w> RangeProcessor<'w> {
    /// A processor for chirps of `samples` samples, zero-padded to `fft_len` points, with an
    /// optional window of `samples` coefficients (`None`: rectangular).
    ///
    /// # Errors
    /// [`RangeError`] if `fft_len` is unsupported, smaller than `samples`, or the window length
    /// differs from `samples`.
    pub fn new(
        samples: usize,
        fft_len: usize,
        window: Option<&'w [Q15]>,
    ) -> Result<Self, RangeError> {
        if !fft::is_supported_len(fft_len) {
            return Err(FftError::UnsupportedLength(fft_len).into());
        }
        if samples > fft_len || samples == 0 {
            return Err(RangeError::Samples {
                expected: fft_len,
                got: samples,
            });
        }
        if let Some(w) = window {
            if w.len() != samples {
                return Err(RangeError::Buffer {
                    what: "window",
                    expected: samples,
                    got: w.len(),
                });
            }
        }
        Ok(Self {
            window,
            samples,
            fft_len,
        })
    }

    /// FFT points per chirp.
    pub fn fft_len(&self) -> usize {
        self.fft_len
    }

    /// Samples per chirp.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// Windows `samples`, zero-pads and transforms them into `out`. O(N log N).
    ///
    /// # Errors
    /// [`RangeError`] if `samples` or `out` has the wrong length.
    pub fn process(&self, samples: &[CQ15], out: &mut [CQ15]) -> Result<Exponent, RangeError> {
        if samples.len() != self.samples {
            return Err(RangeError::Samples {
                expected: self.samples,
                got: samples.len(),
            });
        }
        if out.len() != self.fft_len {
            return Err(RangeError::Buffer {
                what: "range output",
                expected: self.fft_len,
                got: out.len(),
            });
        }
        let (head, tail) = out.split_at_mut(self.samples);
        head.copy_from_slice(samples);
        tail.fill(CQ15::default());
        if let Some(w) = self.window {
            window::apply(w, head);
        }
        Ok(fft::cfft_q15(out)?)
    }
}
