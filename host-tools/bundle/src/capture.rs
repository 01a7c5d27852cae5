//! Bare DCA1000 captures: a `.bin` without camera data, described by a radar config TOML.
//!
//! The config file holds a `[radar]` table with the fields of `scene.toml`'s (see
//! `shared/spec/bundle.md`); `frames`, `adc_file` and `adc_layout` may be left out, and the frame
//! count is then taken from the file size.

use crate::error::{InputError, read_text};
use crate::fields::{Fields, parse_toml};
use crate::{FramesField, RadarFile, parse_radar};
use metamoran_dsp::capture::IqOrder;
use metamoran_dsp::config::RadarConfig;
use std::path::Path;

/// Parses the `[radar]` table of a radar config TOML (the text of `path`).
///
/// # Errors
/// [`InputError`] naming the first bad field.
///
/// # Example
/// ```
/// use metamoran_bundle::capture::parse_radar_config;
/// use std::path::Path;
///
/// let text = r#"
/// [radar]
/// start_frequency_hz = 77e9
/// slope_hz_per_s     = 29.982e12
/// sample_rate_hz     = 10e6
/// adc_samples        = 256
/// chirp_period_s     = 60e-6
/// chirps_per_tx      = 128
/// frame_period_s     = 0.1
/// tx_positions       = [0, 4]
/// rx_positions       = [0, 1, 2, 3]
/// tx_order           = [0, 1]
/// "#;
/// let config = parse_radar_config(Path::new("radar.toml"), text)?;
/// assert_eq!((config.adc_samples, config.channels()), (256, 8));
///
/// let bad = text.replace("chirps_per_tx      = 128", "chirps_per_tx = -4");
/// let err = parse_radar_config(Path::new("radar.toml"), &bad).unwrap_err();
/// assert!(err.to_string().contains("radar.toml: field `radar.chirps_per_tx`"), "{err}");
/// # Ok::<(), metamoran_bundle::error::InputError>(())
/// ```
pub fn parse_radar_config(path: &Path, text: &str) -> Result<RadarConfig, InputError> {
    let table = parse_toml(path, text)?;
    parse_radar(
        &Fields::root(path, &table).table("radar")?,
        FramesField::Optional,
    )
}

/// Reads a radar config TOML file.
///
/// # Errors
/// [`InputError`] naming the file and field.
pub fn read_radar_config(path: &Path) -> Result<RadarConfig, InputError> {
    parse_radar_config(path, &read_text(path, crate::limits::MAX_TOML_BYTES)?)
}

/// Opens a bare capture `bin` with the radar config in `config`.
///
/// # Errors
/// [`InputError`] if either file is unreadable or they do not match.
pub fn open_bare(bin: &Path, config: &Path, order: IqOrder) -> Result<RadarFile, InputError> {
    RadarFile::open(bin, read_radar_config(config)?, order)
}
