//! TI's own radar configurations, read into ours: the mmWave SDK CLI `.cfg` the TI demos and
//! visualizers write ([`cfg`](mod@cfg)) and mmWave Studio's `.mmwave.json` export ([`studio`]), with the
//! antenna layout of a named evaluation board ([`board`]). Where the flow starts: a user's TI
//! capture and its config become a [`CaptureConfig`] that the capture reader
//! ([`crate::RadarFile`]) and every stage after it take like a bundle's `[radar]` table.

pub mod board;
pub mod cfg;
pub mod mat;
pub mod studio;

pub use board::{Antenna, Board, UnknownBoard};

use crate::error::InputError;
use metamoran_dsp::capture::IqOrder;
use metamoran_dsp::config::{MAX_RX, MAX_SLOTS, MAX_TX, RadarConfig};
use std::path::Path;

/// A capture's radar configuration as a TI config describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct CaptureConfig {
    /// The configuration (`frames` 0 when the config leaves the count open).
    pub radar: RadarConfig,
    /// How the device stores I and Q (`adcbufCfg` sample swap, Studio's `iqSwapSel`).
    pub iq_order: IqOrder,
    /// Elevation of each TX of `radar.tx_positions`, half-wavelengths.
    pub tx_elevation: Vec<i16>,
    /// Elevation of each RX, half-wavelengths.
    pub rx_elevation: Vec<i16>,
    /// The board whose layout placed the antennas.
    pub board: Board,
}

/// The profile, chirp and frame timing both formats describe, in their own units (GHz, µs,
/// MHz/µs, ksps, ms).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Timing {
    start_ghz: f64,
    idle_us: f64,
    adc_start_us: f64,
    ramp_end_us: f64,
    slope_mhz_per_us: f64,
    samples: u32,
    rate_ksps: f64,
    loops: u32,
    frames: u32,
    period_ms: f64,
}

/// Where each enabled antenna sits and which TX sends each chirp of a loop, in the order the
/// capture stores channels (device by device, each device's RX in channel order).
#[derive(Clone, Debug, Default, PartialEq)]
struct Antennas {
    tx: Vec<Antenna>,
    rx: Vec<Antenna>,
    /// Per chirp of a loop, an index into `tx`.
    order: Vec<u8>,
}

impl Antennas {
    /// The index of (device, channel)'s TX in `tx`, added once.
    fn tx_index(&mut self, antenna: Antenna) -> u8 {
        match self.tx.iter().position(|&a| a == antenna) {
            Some(i) => i as u8,
            None => {
                self.tx.push(antenna);
                (self.tx.len() - 1) as u8
            }
        }
    }
}

/// The [`CaptureConfig`] of `timing` and `antennas`, checked; `at` names the config's part
/// an error is about (the `.cfg` line, the JSON path).
fn capture_config(
    path: &Path,
    at: &dyn Fn(&str) -> String,
    timing: Timing,
    antennas: Antennas,
    iq_order: IqOrder,
    board: Board,
) -> Result<CaptureConfig, InputError> {
    let err = |what: &str, problem: String| InputError::field(path, at(what), problem);
    if antennas.tx.len() > MAX_TX || antennas.rx.len() > MAX_RX || antennas.order.len() > MAX_SLOTS
    {
        return Err(err(
            "chirps",
            format!(
                "{} TX, {} RX and {} chirps per loop exceed the {MAX_TX}, {MAX_RX} and {MAX_SLOTS} supported",
                antennas.tx.len(),
                antennas.rx.len(),
                antennas.order.len()
            ),
        ));
    }
    if antennas.rx.is_empty() || antennas.order.is_empty() {
        return Err(err("channels", "no receiver or no chirp is enabled".into()));
    }
    if !timing.samples.is_multiple_of(2) || timing.samples < 2 || timing.samples > 2048 {
        return Err(err(
            "numAdcSamples",
            format!(
                "{} samples per chirp: give an even count from 2 to 2048",
                timing.samples
            ),
        ));
    }
    // The ADC must sample inside the ramp.
    let window_us = f64::from(timing.samples) / (timing.rate_ksps * 1e-3);
    if window_us + timing.adc_start_us > timing.ramp_end_us + 1e-9 {
        return Err(err(
            "rampEndTime",
            format!(
                "the ADC samples {window_us:.2} µs from {} µs, past the ramp's end at {} µs",
                timing.adc_start_us, timing.ramp_end_us
            ),
        ));
    }
    let radar = RadarConfig {
        start_frequency_hz: timing.start_ghz * 1e9,
        slope_hz_per_s: timing.slope_mhz_per_us * 1e12,
        sample_rate_hz: timing.rate_ksps * 1e3,
        adc_samples: timing.samples as u16,
        chirp_period_s: (timing.idle_us + timing.ramp_end_us) * 1e-6,
        chirps_per_tx: timing.loops.min(u32::from(u16::MAX)) as u16,
        frames: timing.frames,
        frame_period_s: timing.period_ms * 1e-3,
        tx_positions: antennas.tx.iter().map(|a| a.azimuth).collect(),
        rx_positions: antennas.rx.iter().map(|a| a.azimuth).collect(),
        tx_order: antennas.order.iter().copied().collect(),
    };
    radar.validate().map_err(|e| {
        err(
            "profile",
            format!("the configuration it gives is unusable: {e}"),
        )
    })?;
    Ok(CaptureConfig {
        radar,
        iq_order,
        tx_elevation: antennas.tx.iter().map(|a| a.elevation).collect(),
        rx_elevation: antennas.rx.iter().map(|a| a.elevation).collect(),
        board,
    })
}
