//! Simulated radar configurations: an 8-element xWR18xx-like board and an 86-element
//! cascade-like board (TI MMWCAS), with the range resolution chosen from the scene's depth as
//! in the Metamoran paper (4.2 cm to 20 m, 11.6 cm to 60 m, 21 cm to 90 m, coarser beyond).

use heapless::Vec as HVec;
use metamoran_dsp::config::{RadarConfig, SPEED_OF_LIGHT};

/// Which board to simulate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadarKind {
    /// xWR18xx-like: 2 TX × 4 RX, 8 virtual elements, 256 samples.
    Xwr18xx,
    /// Cascade-like (MMWCAS): 12 TX × 16 RX, 86 distinct virtual elements, 512 samples.
    Cascade,
    /// The MMWCAS-RF-EVM as TI lays it out and records it: the [`Cascade`](Self::Cascade)'s
    /// array with TI's chirp order (TX12 … TX1), the master's three TX raised 6, 4 and 1
    /// half-wavelengths, the 16 RX device by device, written as the board's four device files.
    Mmwcas,
    /// A 4D imaging board for the drive preset (issue #21): 12 TX × 16 RX laid out as a T, a
    /// 64-element azimuth row and nine elevation rows ([`IMAGING_TX`]).
    Imaging,
}

/// The imaging board's TX (azimuth, elevation) in half-wavelengths, in chirp order. With the 16
/// RX at azimuth 0..15:
/// - TX 0–3 at azimuth 0, 16, 32, 48 fill one row of 64 elements at elevation 0: a 1.8° beam
///   at boresight (the paper's radar class resolves 2°);
/// - TX 4–11 at azimuth 24, raised 3, 6, …, 24, put 16 elements (azimuth 24..39) on each of
///   eight more rows; with the base row's elements at the same azimuths that is a 9-row
///   elevation aperture of 24 half-wavelengths: a 4.2° beam (the paper's 3–4°),
///   unambiguous over ±19.5° (the depth image spans ±20°).
///
/// Not the MMWCAS-RF-EVM: its raised TX are at 1, 4 and 6 half-wavelengths, a 16° elevation beam.
pub const IMAGING_TX: [(i16, i16); 12] = [
    (0, 0),
    (16, 0),
    (32, 0),
    (48, 0),
    (24, 3),
    (24, 6),
    (24, 9),
    (24, 12),
    (24, 15),
    (24, 18),
    (24, 21),
    (24, 24),
];

/// The imaging board's complex sample rate, Hz: 256 samples in a 12.8 µs ramp keep the loop of
/// twelve chirps at 190 µs (unambiguous radial velocity ±5.1 m/s, so a street's returns fold and
/// the cloud unfolds them) with the small board's 0.23 m range bins at 59 m.
pub const IMAGING_SAMPLE_RATE: f64 = 20.0e6;

/// TX elevations of `kind` in its chirp order, half-wavelengths (empty: all at 0).
pub fn tx_elevation(kind: RadarKind) -> Vec<i16> {
    match kind {
        RadarKind::Mmwcas => mmwcas_layout().1,
        RadarKind::Imaging => IMAGING_TX.iter().map(|t| t.1).collect(),
        RadarKind::Xwr18xx | RadarKind::Cascade => Vec::new(),
    }
}

/// The MMWCAS-RF-EVM's layout from its board table: TX azimuths in TI's MIMO chirp order
/// (TX12 … TX1), their elevations, and the RX azimuths master first.
pub fn mmwcas_layout() -> (Vec<i16>, Vec<i16>, Vec<i16>) {
    let b = metamoran_bundle::ti::Board::MmwcasRfEvm;
    let tx: Vec<_> = (0..4)
        .rev()
        .flat_map(|d| (0..3).rev().map(move |c| (d, c)))
        .filter_map(|(d, c)| b.tx(d, c))
        .collect();
    let rx = (0..4)
        .flat_map(|d| (0..4).map(move |r| (d, r)))
        .filter_map(|(d, r)| b.rx(d, r))
        .map(|a| a.azimuth)
        .collect();
    (
        tx.iter().map(|a| a.azimuth).collect(),
        tx.iter().map(|a| a.elevation).collect(),
        rx,
    )
}

use metamoran_dsp::config::boards::{CASCADE_RX, CASCADE_TX};

/// Complex ADC sample rate of both boards, Hz.
const SAMPLE_RATE: f64 = 10.0e6;

/// The unambiguous range to configure for a scene whose objects of interest reach `depth` m.
pub fn max_range_for(depth: f64) -> f64 {
    match depth {
        d if d < 17.0 => 21.5,
        d if d < 50.0 => 59.4,
        d if d < 90.0 => 107.5,
        _ => 330.0,
    }
}

/// A configuration for `kind` with unambiguous range `max_range` and `loops` chirps per TX.
pub fn config(kind: RadarKind, max_range: f64, loops: u16) -> RadarConfig {
    let (tx_mmwcas, _, rx_mmwcas) = mmwcas_layout();
    let imaging_tx: Vec<i16> = IMAGING_TX.iter().map(|t| t.0).collect();
    let imaging_rx: Vec<i16> = (0..16).collect();
    let (samples, tx, rx): (u16, &[i16], &[i16]) = match kind {
        RadarKind::Xwr18xx => (256, &[0, 4], &[0, 1, 2, 3]),
        RadarKind::Cascade => (512, &CASCADE_TX, &CASCADE_RX),
        RadarKind::Mmwcas => (512, &tx_mmwcas, &rx_mmwcas),
        RadarKind::Imaging => (256, &imaging_tx, &imaging_rx),
    };
    let (rate, idle) = match kind {
        RadarKind::Imaging => (IMAGING_SAMPLE_RATE, 3.0e-6),
        _ => (SAMPLE_RATE, 8.0e-6),
    };
    let ramp = samples as f64 / rate;
    RadarConfig {
        start_frequency_hz: 77.0e9,
        slope_hz_per_s: rate * SPEED_OF_LIGHT / (2.0 * max_range),
        sample_rate_hz: rate,
        adc_samples: samples,
        chirp_period_s: ramp + idle,
        chirps_per_tx: loops,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: HVec::from_slice(tx).unwrap_or_default(),
        rx_positions: HVec::from_slice(rx).unwrap_or_default(),
        tx_order: (0..tx.len() as u8).collect(),
    }
}

/// The drive preset's board: with [`RadarKind::Imaging`] the 4D imaging board, otherwise
/// xWR1843-like (TX at azimuth 0, 4 and 2 half-wavelengths with the third half a wavelength up,
/// 4 RX); 256 samples, 32 loops, 59 m. Returns the configuration and the TX elevations
/// (half-wavelengths).
pub fn drive_config(kind: RadarKind) -> (RadarConfig, Vec<i16>) {
    if kind == RadarKind::Imaging {
        return (config(kind, 59.4, 32), tx_elevation(kind));
    }
    let mut c = config(RadarKind::Xwr18xx, 59.4, 32);
    c.tx_positions = HVec::from_slice(&[0, 4, 2]).unwrap_or_default();
    c.tx_order = (0..3).collect();
    (c, vec![0, 0, 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_imaging_board_has_the_papers_resolutions_and_folds_at_five_metres_per_second() {
        let (c, elevation) = drive_config(RadarKind::Imaging);
        c.validate().unwrap();
        assert_eq!(c.channels(), 192);
        let g = metamoran_dsp::points::ArrayGeometry::new(&c, &elevation, &[]).unwrap();
        // 64 azimuth positions at elevation 0: Rayleigh 2/64 in sin θ at boresight, 1.8°.
        let row: std::collections::BTreeSet<usize> = (0..192)
            .filter(|&ch| g.elevation(ch) == 0)
            .map(|ch| g.azimuth(ch))
            .collect();
        assert_eq!(row, (0..64).collect());
        assert!((2.0f64 / 64.0).asin().to_degrees() < 2.0);
        // Nine rows 3 apart: 2/27 in sin φ, 4.2°, unambiguous while |sin φ| < 1/3 (19.5°).
        assert_eq!(g.rows().len(), 9);
        assert!(((2.0f64 / 27.0).asin().to_degrees() - 4.25).abs() < 0.05);
        // λ / (4 · 12 · (12.8 + 3) µs) at 77 GHz; 0.23 m range bins to 59.4 m; 646 MHz sweep.
        let v_max = SPEED_OF_LIGHT / 77.0e9 / (4.0 * 12.0 * 15.8e-6);
        assert!(
            (f64::from(c.max_velocity()) - v_max).abs() < 1e-3,
            "{}",
            c.max_velocity()
        );
        assert!((f64::from(c.range_bin_size(256)) - 59.4 / 256.0).abs() < 1e-3);
        assert!(c.slope_hz_per_s * 12.8e-6 < 0.7e9);
    }

    #[test]
    fn cascade_has_86_elements_and_the_papers_resolutions() {
        let c = config(RadarKind::Cascade, max_range_for(10.0), 2);
        c.validate().unwrap();
        assert_eq!(
            metamoran_dsp::array::VirtualArray::new(&c)
                .unwrap()
                .elements(),
            86
        );
        assert!((c.range_bin_size(512) - 0.042).abs() < 0.001);
        assert!(
            (config(RadarKind::Cascade, max_range_for(30.0), 2).range_bin_size(512) - 0.116).abs()
                < 0.001
        );
        assert!(
            (config(RadarKind::Cascade, max_range_for(70.0), 2).range_bin_size(512) - 0.21).abs()
                < 0.001
        );
        let x = config(RadarKind::Xwr18xx, 59.4, 16);
        assert_eq!(
            metamoran_dsp::array::VirtualArray::new(&x)
                .unwrap()
                .elements(),
            8
        );
        // Chirp bandwidth stays within the 77–81 GHz band.
        assert!(c.slope_hz_per_s * 512.0 / SAMPLE_RATE < 4.0e9);
    }
}
