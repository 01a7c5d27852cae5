//! The range cube: range spectra of every (virtual channel, loop) of one frame.

use super::{RangeError, RangeProcessor};
use crate::fft::Exponent;
use crate::fixed::CQ15;

/// Range spectra of one frame in caller-owned storage, laid out `[channel][loop][bin]` so that
/// each arriving chirp writes one contiguous row; each row keeps its own block exponent.
///
/// Channel `slot · rx_count + rx` holds the chirps sent in TDM slot `slot` (see
/// [`crate::config::RadarConfig::channels`]).
pub struct RangeCube<'a> {
    data: &'a mut [CQ15],
    exponents: &'a mut [Exponent],
    slots: usize,
    rx: usize,
    loops: usize,
    bins: usize,
}

impl<'a> RangeCube<'a> {
    /// Wraps storage for `slots · rx` channels × `loops` × `bins`.
    ///
    /// # Errors
    /// [`RangeError::Buffer`] if `data` or `exponents` has the wrong length.
    pub fn new(
        data: &'a mut [CQ15],
        exponents: &'a mut [Exponent],
        slots: usize,
        rx: usize,
        loops: usize,
        bins: usize,
    ) -> Result<Self, RangeError> {
        let rows = slots * rx * loops;
        if data.len() != rows * bins {
            return Err(RangeError::Buffer { what: "cube data", expected: rows * bins, got: data.len() });
        }
        if exponents.len() != rows {
            return Err(RangeError::Buffer { what: "cube exponents", expected: rows, got: exponents.len() });
        }
        Ok(Self { data, exponents, slots, rx, loops, bins })
    }

    /// Virtual channels.
    pub fn channels(&self) -> usize {
        self.slots * self.rx
    }

    /// Loops (chirps per channel).
    pub fn loops(&self) -> usize {
        self.loops
    }

    /// Range bins per row.
    pub fn bins(&self) -> usize {
        self.bins
    }

    fn row_index(&self, channel: usize, lp: usize) -> Result<usize, RangeError> {
        if channel >= self.channels() {
            return Err(RangeError::Index { what: "channel", index: channel, len: self.channels() });
        }
        if lp >= self.loops {
            return Err(RangeError::Index { what: "loop", index: lp, len: self.loops });
        }
        Ok(channel * self.loops + lp)
    }

    /// The spectrum and exponent of `channel` in loop `lp`.
    ///
    /// # Errors
    /// [`RangeError::Index`] if either index is out of range.
    pub fn row(&self, channel: usize, lp: usize) -> Result<(&[CQ15], Exponent), RangeError> {
        let r = self.row_index(channel, lp)?;
        Ok((&self.data[r * self.bins..(r + 1) * self.bins], self.exponents[r]))
    }

    /// Range-processes the samples of chirp `chirp` (frame order, loop-major) of receiver `rx`
    /// into its row. O(N log N).
    ///
    /// # Errors
    /// [`RangeError`] for an index out of range or a size mismatch.
    pub fn push_chirp(
        &mut self,
        processor: &RangeProcessor<'_>,
        chirp: usize,
        rx: usize,
        samples: &[CQ15],
    ) -> Result<(), RangeError> {
        if rx >= self.rx {
            return Err(RangeError::Index { what: "rx", index: rx, len: self.rx });
        }
        let (lp, slot) = (chirp / self.slots, chirp % self.slots);
        let r = self.row_index(slot * self.rx + rx, lp)?;
        let out = &mut self.data[r * self.bins..(r + 1) * self.bins];
        self.exponents[r] = processor.process(samples, out)?;
        Ok(())
    }

    /// Copies the values of range bin `bin` of `channel` over all loops into `out[..loops]`,
    /// aligned to their largest exponent (rounded shifts); returns that exponent.
    ///
    /// # Errors
    /// [`RangeError`] if an index is out of range or `out` is shorter than the loops.
    pub fn gather_column(&self, channel: usize, bin: usize, out: &mut [CQ15]) -> Result<Exponent, RangeError> {
        if bin >= self.bins {
            return Err(RangeError::Index { what: "range bin", index: bin, len: self.bins });
        }
        if out.len() < self.loops {
            return Err(RangeError::Buffer { what: "column", expected: self.loops, got: out.len() });
        }
        let first = self.row_index(channel, 0)?;
        let exps = &self.exponents[first..first + self.loops];
        let top = exps.iter().copied().max().unwrap_or_default();
        for (lp, (o, e)) in out.iter_mut().zip(exps).enumerate() {
            let z = self.data[(first + lp) * self.bins + bin];
            *o = shift_right(z, top.0 - e.0);
        }
        Ok(top)
    }
}

/// `z / 2^s`, rounded half up per part.
pub(crate) fn shift_right(z: CQ15, s: u32) -> CQ15 {
    if s == 0 {
        return z;
    }
    if s >= 16 {
        return CQ15::default();
    }
    let f = |x: i16| (((x as i32) + (1 << (s - 1))) >> s) as i16;
    CQ15::from_raw(f(z.re.0), f(z.im.0))
}
