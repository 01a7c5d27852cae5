//! Positions of the virtual channels in azimuth and elevation (half-wavelengths).
//!
//! Channel `slot · rx_count + rx` sits at azimuth `tx_positions[tx] + rx_positions[rx]` and
//! elevation `tx_elevation[tx] + rx_elevation[rx]` (`tx = tx_order[slot]`). Channels at
//! elevation 0 form the base row for the azimuth FFT. With one other elevation, its channels
//! give the elevation by their phase against the base channels at the same azimuth positions;
//! with two or more, the rows at the azimuth positions they all share form an elevation
//! aperture that is beamformed ([`ArrayGeometry::rows`]).

use crate::array::MAX_CHANNELS;
use crate::config::RadarConfig;
use core::fmt;

/// Longest azimuth aperture (half-wavelengths) the point cloud handles, and its shortest
/// azimuth FFT.
pub const AZIMUTH_FFT: usize = 64;

/// Longest azimuth FFT: four times the longest aperture, so the peak interpolation of a full
/// 64-element row is not biased by a coarse grid.
pub const MAX_AZIMUTH_FFT: usize = 4 * AZIMUTH_FFT;

/// Most distinct elevations (rows, the base row included) an array may have.
pub const MAX_ROWS: usize = 16;

/// Why an array cannot give a point cloud.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum GeometryError {
    /// More channels than [`MAX_CHANNELS`].
    TooManyChannels(usize),
    /// An elevation list does not have one entry per TX (or RX).
    ElevationLength {
        /// Entries needed.
        expected: usize,
        /// Entries given.
        got: usize,
    },
    /// The base row's azimuth positions span [`AZIMUTH_FFT`] or more.
    Aperture(i32),
    /// No channel at elevation 0.
    NoBaseRow,
    /// More distinct elevations than [`MAX_ROWS`].
    TooManyRows(usize),
    /// Three or more rows with no azimuth position in common: no elevation aperture.
    NoCommonColumn,
}

impl core::error::Error for GeometryError {}

impl fmt::Display for GeometryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GeometryError::TooManyChannels(n) => {
                write!(f, "{n} virtual channels; at most {MAX_CHANNELS}")
            }
            GeometryError::ElevationLength { expected, got } => write!(
                f,
                "an elevation list has {got} entries; give one per antenna ({expected})"
            ),
            GeometryError::Aperture(span) => write!(
                f,
                "the azimuth aperture spans {span} half-wavelengths; at most {}",
                AZIMUTH_FFT - 1
            ),
            GeometryError::NoBaseRow => write!(
                f,
                "no virtual channel at elevation 0; the azimuth row must be at elevation 0"
            ),
            GeometryError::TooManyRows(n) => write!(
                f,
                "{n} distinct elevations; at most {MAX_ROWS} rows (base row included)"
            ),
            GeometryError::NoCommonColumn => write!(
                f,
                "the elevation rows share no azimuth position; give every row the same azimuths"
            ),
        }
    }
}

/// Azimuth and elevation of every virtual channel, relative to the base row's first position.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrayGeometry {
    azimuth: [u8; MAX_CHANNELS],
    elevation: [i16; MAX_CHANNELS],
    channels: usize,
    rows: heapless::Vec<i16, MAX_ROWS>,
    /// Azimuth positions every row has a channel at.
    shared: [bool; AZIMUTH_FFT],
}

impl ArrayGeometry {
    /// The geometry of `config` with per-antenna elevations (empty slices: all at 0).
    ///
    /// # Errors
    /// [`GeometryError`] if the lists do not fit the array or the aperture is too wide.
    pub fn new(
        config: &RadarConfig,
        tx_elevation: &[i16],
        rx_elevation: &[i16],
    ) -> Result<Self, GeometryError> {
        let channels = config.channels();
        if channels > MAX_CHANNELS {
            return Err(GeometryError::TooManyChannels(channels));
        }
        for (list, n) in [
            (tx_elevation, config.tx_positions.len()),
            (rx_elevation, config.rx_count()),
        ] {
            if !list.is_empty() && list.len() != n {
                return Err(GeometryError::ElevationLength {
                    expected: n,
                    got: list.len(),
                });
            }
        }
        let rx = config.rx_count();
        let at = |list: &[i16], i: usize| list.get(i).copied().unwrap_or(0);
        let mut azimuth = [0i32; MAX_CHANNELS];
        let mut elevation = [0i16; MAX_CHANNELS];
        for ch in 0..channels {
            let tx = config.tx_order[ch / rx] as usize;
            azimuth[ch] = config.channel_position(ch).unwrap_or(0);
            elevation[ch] = at(tx_elevation, tx).saturating_add(at(rx_elevation, ch % rx));
        }
        let base = || {
            (0..channels)
                .filter(|&c| elevation[c] == 0)
                .map(|c| azimuth[c])
        };
        let lo = base().min().ok_or(GeometryError::NoBaseRow)?;
        let span = base().max().unwrap_or(lo) - lo;
        // Elevated channels are compared with base channels at their own azimuth, so they
        // must lie inside the base row's aperture too.
        let all_hi = (0..channels).map(|c| azimuth[c]).max().unwrap_or(lo);
        let all_lo = (0..channels).map(|c| azimuth[c]).min().unwrap_or(lo);
        if span >= AZIMUTH_FFT as i32 || all_hi - lo >= AZIMUTH_FFT as i32 || all_lo < lo {
            return Err(GeometryError::Aperture((all_hi - all_lo).max(span)));
        }
        let mut out = Self {
            azimuth: [0; MAX_CHANNELS],
            elevation,
            channels,
            rows: heapless::Vec::new(),
            shared: [false; AZIMUTH_FFT],
        };
        for (dst, &a) in out.azimuth.iter_mut().zip(&azimuth[..channels]) {
            *dst = (a - lo) as u8;
        }
        let mut rows: heapless::Vec<i16, MAX_CHANNELS> = heapless::Vec::new();
        for &e in &elevation[..channels] {
            if !rows.contains(&e) {
                let _ = rows.push(e);
            }
        }
        rows.sort_unstable();
        if rows.len() > MAX_ROWS {
            return Err(GeometryError::TooManyRows(rows.len()));
        }
        out.rows = rows.iter().copied().collect();
        for p in 0..AZIMUTH_FFT {
            out.shared[p] = out
                .rows
                .iter()
                .all(|&e| (0..channels).any(|c| elevation[c] == e && out.azimuth(c) == p));
        }
        if out.rows.len() > 2 && !out.shared.contains(&true) {
            return Err(GeometryError::NoCommonColumn);
        }
        Ok(out)
    }

    /// The distinct elevations, ascending, half-wavelengths (the base row's 0 among them).
    pub fn rows(&self) -> &[i16] {
        &self.rows
    }

    /// Whether every row has a channel at azimuth position `p`: the columns of the elevation
    /// aperture.
    pub fn shared(&self, p: usize) -> bool {
        self.shared.get(p).copied().unwrap_or(false)
    }

    /// The elevation rows' common spacing, half-wavelengths (the greatest common divisor of
    /// their elevations; 0 with one row): the beamformer's unambiguous range is
    /// `|sin φ| < 1 / spacing`.
    pub fn row_spacing(&self) -> i16 {
        fn gcd(a: i16, b: i16) -> i16 {
            if b == 0 { a.abs() } else { gcd(b, a % b) }
        }
        self.rows.iter().fold(0, |g, &e| gcd(g, e))
    }

    /// Virtual channels.
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// Azimuth position of channel `ch` from the base row's first, half-wavelengths.
    pub fn azimuth(&self, ch: usize) -> usize {
        usize::from(self.azimuth[ch])
    }

    /// Elevation of channel `ch`, half-wavelengths.
    pub fn elevation(&self, ch: usize) -> i16 {
        self.elevation[ch]
    }

    /// Azimuth FFT length for this array: the base row's aperture zero-padded four times, at
    /// least [`AZIMUTH_FFT`] (an 8-element row: 64 points; a 64-element row: 256).
    pub fn azimuth_fft_len(&self) -> usize {
        let span = (0..self.channels)
            .filter(|&c| self.elevation[c] == 0)
            .map(|c| usize::from(self.azimuth[c]))
            .max()
            .unwrap_or(0);
        (4 * (span + 1))
            .next_power_of_two()
            .clamp(AZIMUTH_FFT, MAX_AZIMUTH_FFT)
    }

    /// Whether any channel is off the base row (the array can measure elevation).
    pub fn has_elevation(&self) -> bool {
        self.elevation[..self.channels].iter().any(|&e| e != 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::tests::example;

    #[test]
    fn an_elevated_tx_puts_its_channels_off_the_base_row() {
        // xWR1843-like: TX at azimuth 0, 4, 2 with the third one half a wavelength up.
        let mut c = example();
        c.tx_positions = heapless::Vec::from_slice(&[0, 4, 2]).unwrap();
        c.rx_positions = heapless::Vec::from_slice(&[0, 1, 2, 3]).unwrap();
        c.tx_order = heapless::Vec::from_slice(&[0, 1, 2]).unwrap();
        let g = ArrayGeometry::new(&c, &[0, 0, 1], &[]).unwrap();
        assert_eq!(g.channels(), 12);
        let az: std::vec::Vec<usize> = (0..12).map(|c| g.azimuth(c)).collect();
        assert_eq!(az, [0, 1, 2, 3, 4, 5, 6, 7, 2, 3, 4, 5]);
        assert!((0..8).all(|c| g.elevation(c) == 0) && (8..12).all(|c| g.elevation(c) == 1));
        assert!(g.has_elevation());
        assert_eq!(
            ArrayGeometry::new(&c, &[0, 1], &[]),
            Err(GeometryError::ElevationLength {
                expected: 3,
                got: 2
            })
        );
        assert_eq!(
            ArrayGeometry::new(&c, &[1, 1, 1], &[]),
            Err(GeometryError::NoBaseRow)
        );
    }
}
