//! The static scene of a frame in `f32`: chirps summed over loops per row (channel or element),
//! then windowed, in ADC LSB units (as [`super::FrameSum`]'s sums). The host's reference matched filter (`search::depth::brute_force`) runs on
//! these; the module works on [`super::FrameSum`]. Memory: `rows × N` complex values,
//! caller-owned.

use super::RangeError;
use crate::fft::C32;
use crate::fixed::CQ15;

/// Accumulates chirps per channel over the loops of a frame.
pub struct StaticSum<'a> {
    samples: &'a mut [C32],
    n: usize,
}

impl<'a> StaticSum<'a> {
    /// Accumulator over `samples` (`channels × n`), cleared.
    ///
    /// # Errors
    /// [`RangeError::Buffer`] if `samples` is not a whole number of `n`-sample rows.
    pub fn new(samples: &'a mut [C32], n: usize) -> Result<Self, RangeError> {
        if n == 0 || !samples.len().is_multiple_of(n) {
            return Err(RangeError::Buffer {
                what: "static samples",
                expected: n,
                got: samples.len(),
            });
        }
        samples.fill(C32::new(0.0, 0.0));
        Ok(Self { samples, n })
    }

    /// Adds one chirp of one channel (as the chirp streams in). O(N).
    ///
    /// # Errors
    /// [`RangeError`] for a channel out of range or a wrong sample count.
    pub fn push(&mut self, channel: usize, chirp: &[CQ15]) -> Result<(), RangeError> {
        let rows = self.samples.len() / self.n;
        let row = self
            .samples
            .chunks_exact_mut(self.n)
            .nth(channel)
            .ok_or(RangeError::Index {
                what: "channel",
                index: channel,
                len: rows,
            })?;
        if chirp.len() != self.n {
            return Err(RangeError::Samples {
                expected: self.n,
                got: chirp.len(),
            });
        }
        for (o, z) in row.iter_mut().zip(chirp) {
            o.re += z.re.0 as f32;
            o.im += z.im.0 as f32;
        }
        Ok(())
    }

    /// Windows the sums in place (`window.len() == N`) and returns them (`rows × N`). O(C·N).
    ///
    /// # Errors
    /// [`RangeError::Buffer`] for a window of the wrong length.
    pub fn finish(self, window: &[f32]) -> Result<&'a mut [C32], RangeError> {
        if window.len() != self.n {
            return Err(RangeError::Buffer {
                what: "window",
                expected: self.n,
                got: window.len(),
            });
        }
        for row in self.samples.chunks_exact_mut(self.n) {
            for (x, &w) in row.iter_mut().zip(window) {
                *x *= w;
            }
        }
        Ok(self.samples)
    }
}
