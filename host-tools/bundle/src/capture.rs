//! Bare DCA1000 captures: a `.bin` without camera data, described by a radar config TOML.
//!
//! The config file holds a `[radar]` table with the fields of `scene.toml`'s (see
//! `shared/spec/bundle.md`); `frames`, `adc_file` and `adc_layout` may be left out, and the frame
//! count is then taken from the file size.

use crate::error::{InputError, read_text};
use crate::fields::{Fields, parse_toml};
use crate::{FramesField, RadarFile, parse_radar};
use dsp::capture::IqOrder;
use dsp::config::RadarConfig;
use std::path::Path;

/// Parses the `[radar]` table of a radar config TOML (the text of `path`).
///
/// # Errors
/// [`InputError`] naming the first bad field.
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
    parse_radar_config(path, &read_text(path)?)
}

/// Opens a bare capture `bin` with the radar config in `config`.
///
/// # Errors
/// [`InputError`] if either file is unreadable or they do not match.
pub fn open_bare(bin: &Path, config: &Path, order: IqOrder) -> Result<RadarFile, InputError> {
    RadarFile::open(bin, read_radar_config(config)?, order)
}
