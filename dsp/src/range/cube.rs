//! The range cube: range spectra of every (virtual channel, loop) of one frame.

use super::{RangeError, RangeProcessor};
use crate::fft::Exponent;
use crate::fixed::CQ15;

/// Range spectra of one frame in caller-owned storage, laid out `[channel][loop][bin]` so that
/// each arriving chirp writes one contiguous row; each row keeps its own block exponent.
///
/// Channel `slot · rx_count + rx` holds the chirps sent in TDM slot `slot` (see
/// [`crate::config::RadarConfig::channels`]). Storage is anything that derefs to slices:
/// `&mut [CQ15]` on the module, `Vec<CQ15>` on the host.
pub struct RangeCube<D, E> {
    data: D,
    exponents: E,
    slots: usize,
    rx: usize,
    loops: usize,
    bins: usize,
}

impl<D: AsRef<[CQ15]>, E: AsRef<[Exponent]>> RangeCube<D, E> {
    /// Wraps storage for `slots · rx` channels × `loops` × `bins`.
    ///
    /// # Errors
    /// [`RangeError::Buffer`] if `data` or `exponents` has the wrong length.
    pub fn new(
        data: D,
        exponents: E,
        slots: usize,
        rx: usize,
        loops: usize,
        bins: usize,
    ) -> Result<Self, RangeError> {
        let rows = slots * rx * loops;
        let (n_data, n_exp) = (data.as_ref().len(), exponents.as_ref().len());
        if n_data != rows * bins {
            return Err(RangeError::Buffer {
                what: "cube data",
                expected: rows * bins,
                got: n_data,
            });
        }
        if n_exp != rows {
            return Err(RangeError::Buffer {
                what: "cube exponents",
                expected: rows,
                got: n_exp,
            });
        }
        Ok(Self {
            data,
            exponents,
            slots,
            rx,
            loops,
            bins,
        })
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
            return Err(RangeError::Index {
                what: "channel",
                index: channel,
                len: self.channels(),
            });
        }
        if lp >= self.loops {
            return Err(RangeError::Index {
                what: "loop",
                index: lp,
                len: self.loops,
            });
        }
        Ok(channel * self.loops + lp)
    }

    /// The spectrum and exponent of `channel` in loop `lp`.
    ///
    /// # Errors
    /// [`RangeError::Index`] if either index is out of range.
    pub fn row(&self, channel: usize, lp: usize) -> Result<(&[CQ15], Exponent), RangeError> {
        let r = self.row_index(channel, lp)?;
        Ok((
            &self.data.as_ref()[r * self.bins..(r + 1) * self.bins],
            self.exponents.as_ref()[r],
        ))
    }

    /// Every row with its exponent, in `[channel][loop]` order.
    pub fn rows(&self) -> impl Iterator<Item = (&[CQ15], Exponent)> {
        self.data
            .as_ref()
            .chunks_exact(self.bins.max(1))
            .zip(self.exponents.as_ref().iter().copied())
    }

    /// Copies the values of range bin `bin` of `channel` over all loops into `out[..loops]`,
    /// aligned to their largest exponent (rounded shifts); returns that exponent.
    ///
    /// # Errors
    /// [`RangeError`] if an index is out of range or `out` is shorter than the loops.
    pub fn gather_column(
        &self,
        channel: usize,
        bin: usize,
        out: &mut [CQ15],
    ) -> Result<Exponent, RangeError> {
        if bin >= self.bins {
            return Err(RangeError::Index {
                what: "range bin",
                index: bin,
                len: self.bins,
            });
        }
        if out.len() < self.loops {
            return Err(RangeError::Buffer {
                what: "column",
                expected: self.loops,
                got: out.len(),
            });
        }
        let first = self.row_index(channel, 0)?;
        let exps = &self.exponents.as_ref()[first..first + self.loops];
        let data = self.data.as_ref();
        let top = exps.iter().copied().max().unwrap_or_default();
        for (lp, (o, e)) in out.iter_mut().zip(exps).enumerate() {
            let z = data[(first + lp) * self.bins + bin];
            *o = z.scale_down(top.0 - e.0);
        }
        Ok(top)
    }
}

impl<D: AsRef<[CQ15]> + AsMut<[CQ15]>, E: AsRef<[Exponent]> + AsMut<[Exponent]>> RangeCube<D, E> {
    /// Every row and its exponent to write, in `[channel][loop]` order, each with the chirp
    /// (frame order, loop-major) and the receiver whose samples it holds: the rows
    /// [`Self::push_chirp`] writes, for a caller that fills them in another order or splits
    /// them among threads (disjoint borrows).
    pub fn rows_mut(&mut self) -> impl Iterator<Item = (usize, usize, &mut [CQ15], &mut Exponent)> {
        let (slots, rx, loops) = (self.slots, self.rx.max(1), self.loops.max(1));
        self.data
            .as_mut()
            .chunks_exact_mut(self.bins.max(1))
            .zip(self.exponents.as_mut().iter_mut())
            .enumerate()
            .map(move |(r, (row, exp))| {
                let (channel, lp) = (r / loops, r % loops);
                (lp * slots + channel / rx, channel % rx, row, exp)
            })
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
            return Err(RangeError::Index {
                what: "rx",
                index: rx,
                len: self.rx,
            });
        }
        let (lp, slot) = (chirp / self.slots, chirp % self.slots);
        let r = self.row_index(slot * self.rx + rx, lp)?;
        let out = &mut self.data.as_mut()[r * self.bins..(r + 1) * self.bins];
        self.exponents.as_mut()[r] = processor.process(samples, out)?;
        Ok(())
    }
}
