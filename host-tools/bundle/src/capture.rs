//! Bare DCA1000 captures: a `.bin` without camera data, described by a radar config.
//!
//! The config is a TOML file with a `[radar]` table holding the fields of `scene.toml`'s (see
//! `shared/spec/bundle.md`; `frames`, `adc_file` and `adc_layout` may be left out, and the frame
//! count is then taken from the file size), or TI's own: an mmWave SDK `.cfg` or an mmWave
//! Studio `.mmwave.json` ([`crate::ti`]), whose antennas a named board places.

use crate::error::{InputError, read, read_text};
use crate::fields::{Fields, parse_toml};
use crate::ti::{Board, cfg, studio};
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

/// A bare capture's configuration, from whichever kind of file holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct BareConfig {
    /// The radar configuration.
    pub radar: RadarConfig,
    /// The I/Q order the device was set to, where the config says (TI configs).
    pub iq_order: Option<IqOrder>,
    /// The board that placed the antennas (TI configs).
    pub board: Option<Board>,
}

/// Reads a radar config: TOML (`.toml`), an mmWave SDK `.cfg` or an mmWave Studio
/// `.mmwave.json`, by its name. TI configs take their antenna layout from `board`; without one,
/// a `.cfg` whose Visualizer header names an xWR18xx or xWR16xx platform is read for that
/// BOOST board and a four-device `.mmwave.json` for the MMWCAS-RF-EVM.
///
/// # Errors
/// [`InputError`] naming the file and field, or asking for `--board`.
pub fn read_config(path: &Path, board: Option<Board>) -> Result<BareConfig, InputError> {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
    let limit = crate::limits::MAX_TOML_BYTES;
    let ti = |c: crate::ti::CaptureConfig| BareConfig {
        radar: c.radar,
        iq_order: Some(c.iq_order),
        board: Some(c.board),
    };
    if name.ends_with(".cfg") {
        let text = read_text(path, limit)?;
        let board = board.or_else(|| cfg::platform(&text)).ok_or_else(|| {
            InputError::file(
                path,
                format!(
                    "name the board its antennas are on with --board ({})",
                    Board::NAMES.join(", ")
                ),
            )
        })?;
        cfg::parse(path, &text, board).map(ti)
    } else if name.ends_with(".json") {
        studio::parse(path, &read(path, limit)?, board).map(ti)
    } else if name.ends_with(".toml") {
        Ok(BareConfig {
            radar: read_radar_config(path)?,
            iq_order: None,
            board: None,
        })
    } else {
        Err(InputError::file(
            path,
            "is not a radar config: give a TOML [radar] table (.toml), an mmWave SDK .cfg or an \
             mmWave Studio .mmwave.json",
        ))
    }
}

/// Opens a bare capture `bin` with the radar config in `config` ([`read_config`], `board` for
/// TI configs), reading samples in `order` or, without one, the order the config gives (I
/// first where it gives none).
///
/// # Errors
/// [`InputError`] if either file is unreadable or they do not match.
pub fn open_bare(
    bin: &Path,
    config: &Path,
    order: Option<IqOrder>,
    board: Option<Board>,
) -> Result<RadarFile, InputError> {
    let c = read_config(config, board)?;
    RadarFile::open(bin, c.radar, order.or(c.iq_order).unwrap_or_default())
}
