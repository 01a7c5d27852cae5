//! The TDM-MIMO virtual array: which virtual channel sits where along the azimuth axis.
//!
//! Channel `slot · rx_count + rx` sits at `tx_positions[tx_order[slot]] + rx_positions[rx]`
//! half-wavelengths. Positions may repeat (a cascade board overlaps elements; repeats are
//! averaged) and need not be contiguous (gaps stay zero). Positions are shifted so the first
//! element is at 0; the azimuth FFT then runs over `span()` elements, zero-padded.

use crate::config::{MAX_RX, MAX_SLOTS, RadarConfig};
use crate::fixed::{CQ15, Complex, Q15};
use core::fmt;
use heapless::Vec;

/// Most virtual channels.
pub const MAX_CHANNELS: usize = MAX_SLOTS * MAX_RX;

/// Why a virtual array could not be built or used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ArrayError {
    /// The configuration has no channels or an invalid `tx_order`.
    Config,
    /// The array spans more positions than an FFT can hold.
    Span(usize),
    /// A buffer has the wrong length (names it).
    Buffer {
        /// Which buffer.
        what: &'static str,
        /// Length needed.
        expected: usize,
        /// Length given.
        got: usize,
    },
}

impl core::error::Error for ArrayError {}

impl fmt::Display for ArrayError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Config => write!(
                f,
                "the radar config has no virtual channels: check tx_order and the positions"
            ),
            Self::Span(s) => write!(
                f,
                "the virtual array spans {s} half-wavelengths, more than the largest FFT ({})",
                crate::fft::MAX_LEN
            ),
            Self::Buffer {
                what,
                expected,
                got,
            } => {
                write!(f, "{what} holds {got} entries but {expected} are needed")
            }
        }
    }
}

/// Virtual element positions of a configuration.
#[derive(Clone, Debug)]
pub struct VirtualArray {
    /// Position (from 0) of each channel, in half-wavelengths.
    position_of_channel: Vec<u16, MAX_CHANNELS>,
    /// How many channels share each position (0 for gaps); length `span`.
    count_at: Vec<u8, { crate::fft::MAX_LEN }>,
    /// Distinct positions.
    elements: usize,
    /// Dense index (0..elements, by position) of each channel's element.
    element_of_channel: Vec<u16, MAX_CHANNELS>,
    /// Position of each element; ascending.
    element_position: Vec<u16, MAX_CHANNELS>,
    /// Channels summed into each element.
    element_count: Vec<u8, MAX_CHANNELS>,
}

impl VirtualArray {
    /// Builds the array of `config`. O(channels).
    ///
    /// # Errors
    /// [`ArrayError`] if the config has no channels or spans more than 2048 half-wavelengths.
    pub fn new(config: &RadarConfig) -> Result<Self, ArrayError> {
        let channels = config.channels();
        if channels == 0 || channels > MAX_CHANNELS {
            return Err(ArrayError::Config);
        }
        let mut raw: Vec<i32, MAX_CHANNELS> = Vec::new();
        for ch in 0..channels {
            let p = config.channel_position(ch).ok_or(ArrayError::Config)?;
            raw.push(p).map_err(|_| ArrayError::Config)?;
        }
        let min = raw.iter().copied().min().unwrap_or(0);
        let max = raw.iter().copied().max().unwrap_or(0);
        let span = (max - min + 1) as usize;
        if span > crate::fft::MAX_LEN {
            return Err(ArrayError::Span(span));
        }
        let mut count_at: Vec<u8, { crate::fft::MAX_LEN }> = Vec::new();
        count_at
            .resize(span, 0)
            .map_err(|_| ArrayError::Span(span))?;
        let mut position_of_channel = Vec::new();
        for p in raw {
            let rel = (p - min) as usize;
            if let Some(c) = count_at.get_mut(rel) {
                *c = c.saturating_add(1);
            }
            position_of_channel
                .push(rel as u16)
                .map_err(|_| ArrayError::Config)?;
        }
        let mut element_position: Vec<u16, MAX_CHANNELS> = Vec::new();
        let mut element_count: Vec<u8, MAX_CHANNELS> = Vec::new();
        for (p, &c) in count_at.iter().enumerate().filter(|(_, c)| **c > 0) {
            element_position
                .push(p as u16)
                .map_err(|_| ArrayError::Config)?;
            element_count.push(c).map_err(|_| ArrayError::Config)?;
        }
        let mut element_of_channel = Vec::new();
        for p in &position_of_channel {
            let e = element_position.partition_point(|q| q < p) as u16;
            element_of_channel.push(e).map_err(|_| ArrayError::Config)?;
        }
        Ok(Self {
            position_of_channel,
            count_at,
            elements: element_position.len(),
            element_of_channel,
            element_position,
            element_count,
        })
    }

    /// Positions from the first to the last element, gaps included.
    pub fn span(&self) -> usize {
        self.count_at.len()
    }

    /// Distinct occupied positions.
    pub fn elements(&self) -> usize {
        self.elements
    }

    /// Virtual channels.
    pub fn channels(&self) -> usize {
        self.position_of_channel.len()
    }

    /// Position of `channel` (from 0) in half-wavelengths.
    pub fn position(&self, channel: usize) -> Option<u16> {
        self.position_of_channel.get(channel).copied()
    }

    /// The element (dense index over distinct positions, ascending) that `channel` feeds.
    pub fn element_of(&self, channel: usize) -> Option<usize> {
        self.element_of_channel.get(channel).map(|&e| e as usize)
    }

    /// Position of each element (half-wavelengths from the first), ascending.
    pub fn element_positions(&self) -> &[u16] {
        &self.element_position
    }

    /// How many channels each element sums (its weight in the array factor).
    pub fn element_counts(&self) -> &[u8] {
        &self.element_count
    }

    /// Whether position `p` holds an element.
    pub fn occupied(&self, p: usize) -> bool {
        self.count_at.get(p).is_some_and(|&c| c > 0)
    }

    /// Writes the element values into `out` (index = position): repeated positions averaged
    /// (rounded), gaps and the padding beyond `span()` zero. O(channels + out.len()).
    ///
    /// # Errors
    /// [`ArrayError::Buffer`] if `channel_values` does not hold one value per channel or `out` is
    /// shorter than `span()`.
    pub fn gather(&self, channel_values: &[CQ15], out: &mut [CQ15]) -> Result<(), ArrayError> {
        if channel_values.len() != self.channels() {
            return Err(ArrayError::Buffer {
                what: "channel values",
                expected: self.channels(),
                got: channel_values.len(),
            });
        }
        if out.len() < self.span() {
            return Err(ArrayError::Buffer {
                what: "element buffer",
                expected: self.span(),
                got: out.len(),
            });
        }
        let mut sums: Vec<Complex<i32>, { crate::fft::MAX_LEN }> = Vec::new();
        let _ = sums.resize(self.span(), Complex::new(0, 0));
        for (z, &p) in channel_values.iter().zip(&self.position_of_channel) {
            let s = &mut sums[p as usize];
            s.re += z.re.0 as i32;
            s.im += z.im.0 as i32;
        }
        for (p, o) in out.iter_mut().enumerate() {
            *o = match (sums.get(p), self.count_at.get(p)) {
                (Some(s), Some(&c)) if c > 0 => {
                    let avg = |v: i32| Q15(libm::round(v as f64 / c as f64) as i16);
                    Complex::new(avg(s.re), avg(s.im))
                }
                _ => CQ15::default(),
            };
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::tests::example;

    #[test]
    fn overlapping_and_gapped_positions() {
        let mut c = example();
        c.tx_positions = Vec::from_slice(&[0, 2, 8]).unwrap();
        c.rx_positions = Vec::from_slice(&[0, 1, 2, 3]).unwrap();
        c.tx_order = Vec::from_slice(&[0, 1, 2]).unwrap();
        // TX0: 0..3, TX1: 2..5 (2 and 3 repeat), TX2: 8..11 (6, 7 are gaps)
        let a = VirtualArray::new(&c).unwrap();
        assert_eq!(a.span(), 12);
        assert_eq!(a.elements(), 10);
        assert!(!a.occupied(6) && a.occupied(8));
        assert_eq!(a.element_positions(), &[0, 1, 2, 3, 4, 5, 8, 9, 10, 11]);
        assert_eq!(a.element_counts(), &[1, 1, 2, 2, 1, 1, 1, 1, 1, 1]);
        // channel 4 (TX1 RX0) sits at 2: element 2; channel 8 (TX2 RX0) at 8: element 6
        assert_eq!((a.element_of(4), a.element_of(8)), (Some(2), Some(6)));
        let vals: std::vec::Vec<CQ15> = (0..12)
            .map(|ch| CQ15::from_raw(100 * ch as i16, -(ch as i16)))
            .collect();
        let mut out = [CQ15::default(); 16];
        a.gather(&vals, &mut out).unwrap();
        assert_eq!(out[0], vals[0]);
        // position 2: channel 2 (TX0 RX2) and channel 4 (TX1 RX0): mean of 200 and 400
        assert_eq!(out[2].re.0, 300);
        assert_eq!(out[6], CQ15::default());
        assert_eq!(out[11], vals[11]);
        assert_eq!(out[15], CQ15::default());
    }
}
