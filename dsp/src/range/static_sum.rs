//! The static scene of a frame: chirps summed over loops per virtual channel, as they arrive,
//! then windowed and transformed (`f32`, microfft). This is what the depth search and SIC work on
//! for static objects. Memory: `channels × (N + M)` complex values, caller-owned.

use super::RangeError;
use crate::fft::{C32, cfft_f32};
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
        if n == 0 || samples.len() % n != 0 {
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
            o.re += z.re.to_f32();
            o.im += z.im.to_f32();
        }
        Ok(())
    }

    /// Adds one chirp of one channel at virtual position `position` (half-wavelengths) with the
    /// reflectors already known (e.g. cancelled in the previous frame of a static scene) removed
    /// as it streams in: each contributes `α / loops · exp(jπ·p·sin θ) · exp(j2π·r·n/M)` per
    /// chirp. Windowing the sum later gives exactly the frame-level cancellation. O(R·N); the
    /// state is the reflector list, at most [`crate::clutter::sic::MAX_REFLECTORS`] entries.
    ///
    /// # Errors
    /// [`RangeError`] for a channel out of range or a wrong sample count.
    pub fn push_cancelled(
        &mut self,
        channel: usize,
        chirp: &[CQ15],
        position: f32,
        reflectors: &[crate::clutter::sic::Reflector],
        loops: usize,
        fft_len: usize,
    ) -> Result<(), RangeError> {
        self.push(channel, chirp)?;
        let row = &mut self.samples[channel * self.n..(channel + 1) * self.n];
        for r in reflectors {
            let a = core::f32::consts::PI * position * r.sin_az;
            let gain = C32::new(libm::cosf(a), libm::sinf(a)) * r.amplitude / loops.max(1) as f32;
            let w = 2.0 * core::f32::consts::PI * r.range_bins / fft_len as f32;
            for (k, x) in row.iter_mut().enumerate() {
                let ph = w * k as f32;
                *x -= gain * C32::new(libm::cosf(ph), libm::sinf(ph));
            }
        }
        Ok(())
    }

    /// Windows the sums (`window.len() == N`) in place and writes their `M`-point spectra
    /// into `spectra` (`channels × M`). O(C·M log M).
    ///
    /// # Errors
    /// [`RangeError`] for wrong buffer sizes or an unsupported `M`.
    pub fn finish(self, window: &[f32], spectra: &mut [C32]) -> Result<(), RangeError> {
        let rows = self.samples.len() / self.n;
        if window.len() != self.n {
            return Err(RangeError::Buffer {
                what: "window",
                expected: self.n,
                got: window.len(),
            });
        }
        if spectra.len() % rows.max(1) != 0 || spectra.len() / rows.max(1) < self.n {
            return Err(RangeError::Buffer {
                what: "spectra",
                expected: rows * self.n,
                got: spectra.len(),
            });
        }
        let m = spectra.len() / rows.max(1);
        for (row, out) in self
            .samples
            .chunks_exact_mut(self.n)
            .zip(spectra.chunks_exact_mut(m))
        {
            for (x, &w) in row.iter_mut().zip(window) {
                *x = *x * w;
            }
            out[..self.n].copy_from_slice(row);
            out[self.n..].fill(C32::new(0.0, 0.0));
            cfft_f32(out)?;
        }
        Ok(())
    }
}
