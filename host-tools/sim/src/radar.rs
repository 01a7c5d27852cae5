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
    let (samples, tx, rx): (u16, &[i16], &[i16]) = match kind {
        RadarKind::Xwr18xx => (256, &[0, 4], &[0, 1, 2, 3]),
        RadarKind::Cascade => (512, &CASCADE_TX, &CASCADE_RX),
        RadarKind::Mmwcas => (512, &tx_mmwcas, &rx_mmwcas),
    };
    let ramp = samples as f64 / SAMPLE_RATE;
    RadarConfig {
        start_frequency_hz: 77.0e9,
        slope_hz_per_s: SAMPLE_RATE * SPEED_OF_LIGHT / (2.0 * max_range),
        sample_rate_hz: SAMPLE_RATE,
        adc_samples: samples,
        chirp_period_s: ramp + 8.0e-6,
        chirps_per_tx: loops,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: HVec::from_slice(tx).unwrap_or_default(),
        rx_positions: HVec::from_slice(rx).unwrap_or_default(),
        tx_order: (0..tx.len() as u8).collect(),
    }
}

/// The drive preset's board: xWR1843-like, TX at azimuth 0, 4 and 2 half-wavelengths with the
/// third half a wavelength up, 4 RX; 256 samples, 32 loops, 59 m. Returns the configuration
/// and the TX elevations (half-wavelengths).
pub fn drive_config() -> (RadarConfig, Vec<i16>) {
    let mut c = config(RadarKind::Xwr18xx, 59.4, 32);
    c.tx_positions = HVec::from_slice(&[0, 4, 2]).unwrap_or_default();
    c.tx_order = (0..3).collect();
    (c, vec![0, 0, 1])
}

#[cfg(test)]
mod tests {
    use super::*;

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
