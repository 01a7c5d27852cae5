//! The antenna layouts of TI's evaluation boards: where each physical TX and RX sits, in
//! half-wavelengths of the board's design frequency, azimuth along +x and elevation up. A TI
//! configuration names channels by number (`channelCfg 15 5 0`, `txEnable 0x1`); the board turns
//! those numbers into the positions a [`RadarConfig`](metamoran_dsp::config::RadarConfig) lists.

use metamoran_dsp::config::boards::{CASCADE_RX, CASCADE_TX};
use std::fmt;
use std::str::FromStr;

/// A TI board whose antenna layout is known.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Board {
    /// xWR1843BOOST (also AWR1843/IWR1843): TX0, TX1, TX2 at azimuth 0, 2, 4 with TX1 half a
    /// wavelength up; RX0–3 at 0–3 (TI's `xwr18xx` out-of-box demo geometry).
    Xwr18xxBoost,
    /// xWR1642BOOST: TX0 and TX1 at azimuth 0 and 4 (two wavelengths apart); RX0–3 at 0–3.
    Xwr16xxBoost,
    /// IWR6843ISK: the xWR18xx layout (TX1 half a wavelength up).
    Iwr6843Isk,
    /// MMWCAS-RF-EVM: four AWR2243 (master, slave 1–3), 12 TX and 16 RX, positions of TI's
    /// cascade MATLAB reference (`TI_Cascade_TX_position_azi`/`_ele`, `TI_Cascade_RX_position_azi`).
    MmwcasRfEvm,
}

/// Where one antenna sits, half-wavelengths.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Antenna {
    /// Azimuth position (+x).
    pub azimuth: i16,
    /// Elevation position (up).
    pub elevation: i16,
}

const fn at(azimuth: i16, elevation: i16) -> Antenna {
    Antenna { azimuth, elevation }
}

/// TX1–TX12 of the cascade (three per device, master first): azimuth from
/// [`CASCADE_TX`], elevation 6, 4, 1 for the master's three.
const CASCADE_TX_ELEVATION: [i16; 12] = [6, 4, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0];

impl Board {
    /// Every board, in the order of [`Board::NAMES`].
    pub const ALL: [Board; 4] = [
        Board::Xwr18xxBoost,
        Board::Xwr16xxBoost,
        Board::Iwr6843Isk,
        Board::MmwcasRfEvm,
    ];
    /// The names `--board` takes.
    pub const NAMES: [&'static str; 4] = [
        "xwr18xx-boost",
        "xwr16xx-boost",
        "iwr6843isk",
        "mmwcas-rf-evm",
    ];

    /// Its name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// Radar devices on the board (a cascade has four, each with its own TX and RX).
    pub fn devices(self) -> usize {
        match self {
            Board::MmwcasRfEvm => 4,
            _ => 1,
        }
    }

    /// TX `channel` of device `device` (channel numbers as the device's own masks count them).
    pub fn tx(self, device: usize, channel: usize) -> Option<Antenna> {
        match self {
            Board::Xwr18xxBoost | Board::Iwr6843Isk => [at(0, 0), at(2, 1), at(4, 0)]
                .get(channel)
                .copied()
                .filter(|_| device == 0),
            Board::Xwr16xxBoost => [at(0, 0), at(4, 0)]
                .get(channel)
                .copied()
                .filter(|_| device == 0),
            Board::MmwcasRfEvm => {
                // TX ID 3·device + channel + 1 of TI's tables.
                let id = (channel < 3).then_some(3 * device + channel)?;
                Some(at(*CASCADE_TX.get(id)?, *CASCADE_TX_ELEVATION.get(id)?))
            }
        }
    }

    /// RX `channel` of device `device`.
    pub fn rx(self, device: usize, channel: usize) -> Option<Antenna> {
        if channel >= 4 || device >= self.devices() {
            return None;
        }
        match self {
            // TI's CASCADE_RX lists the positions in its processing order (RX IDs 13–16, 1–4,
            // 9–12, 5–8); in device order the master's RX0–3 sit at 50–53, slave 1's at 0–3,
            // slave 2's at 46–49 and slave 3's at 11–14.
            Board::MmwcasRfEvm => {
                let block = [4, 12, 8, 0][device];
                Some(at(CASCADE_RX[block + channel], 0))
            }
            _ => Some(at(channel as i16, 0)),
        }
    }
}

impl fmt::Display for Board {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A board name that is not one of [`Board::NAMES`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown board `{0}`: use one of xwr18xx-boost, xwr16xx-boost, iwr6843isk, mmwcas-rf-evm")]
pub struct UnknownBoard(pub String);

impl FromStr for Board {
    type Err = UnknownBoard;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|b| b.name() == s)
            .ok_or_else(|| UnknownBoard(s.to_owned()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cascade_has_86_azimuth_positions_in_device_order() {
        let b = Board::MmwcasRfEvm;
        let mut virtual_az = std::collections::BTreeSet::new();
        for (d, c) in (0..4).flat_map(|d| (0..3).map(move |c| (d, c))) {
            let t = b.tx(d, c).unwrap();
            for (e, r) in (0..4).flat_map(|e| (0..4).map(move |r| (e, r))) {
                let rx = b.rx(e, r).unwrap();
                if t.elevation == 0 {
                    virtual_az.insert(t.azimuth + rx.azimuth);
                }
            }
        }
        assert_eq!(virtual_az.len(), 86);
        // TI's processing order (RX IDs 13–16, 1–4, 9–12, 5–8) gives back CASCADE_RX.
        let ti_order: Vec<i16> = [(3, 0..4), (0, 0..4), (2, 0..4), (1, 0..4)]
            .into_iter()
            .flat_map(|(d, rs)| rs.map(move |r| b.rx(d, r).unwrap().azimuth))
            .collect();
        assert_eq!(ti_order, CASCADE_RX);
        assert_eq!(b.tx(0, 0), Some(at(11, 6)));
        assert_eq!(b.tx(3, 2), Some(at(0, 0)));
        assert_eq!((b.tx(0, 3), b.rx(4, 0)), (None, None));
    }

    #[test]
    fn names_round_trip() {
        for b in Board::ALL {
            assert_eq!(b.name().parse::<Board>(), Ok(b));
        }
        assert!(
            "xwr1843"
                .parse::<Board>()
                .unwrap_err()
                .to_string()
                .contains("xwr18xx-boost")
        );
        assert_eq!(Board::Xwr16xxBoost.tx(0, 1), Some(at(4, 0)));
        assert_eq!(Board::Xwr18xxBoost.tx(0, 1), Some(at(2, 1)));
    }
}
