//! `scene.toml`: the format tag, the `[radar]` table and the `[camera]` table.

use crate::error::{InputError, read_text};
use crate::fields::{Fields, parse_toml};
use crate::limits::{MAX_FRAME_BYTES, MAX_FRAMES, MAX_PIXELS};
use metamoran_dsp::config::{ConfigError, MAX_RX, MAX_SLOTS, MAX_TX, RadarConfig};
use std::path::{Path, PathBuf};

/// The exact format tag of a version-1 bundle.
pub const FORMAT: &str = "metamoran-bundle/1";
/// The `adc_layout` of bundle.md's version 1.
pub const ADC_LAYOUT: &str = "dca1000-xwr18xx";

/// How the radar samples are stored: bundle.md's DCA1000 layout, or (README's extension) the
/// MMWCAS-RF-EVM's four device files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AdcLayout {
    /// One file, `radar.bin`'s layout (`dca1000-xwr18xx`).
    #[default]
    Dca1000,
    /// `mmwcas-rf-evm`: `adc_file` names the master's data file (`master_NNNN_data.bin`); the
    /// slaves' and the index files lie beside it ([`crate::mmwcas`]).
    Mmwcas,
}

impl AdcLayout {
    /// Its `adc_layout` name.
    pub fn name(self) -> &'static str {
        match self {
            AdcLayout::Dca1000 => ADC_LAYOUT,
            AdcLayout::Mmwcas => "mmwcas-rf-evm",
        }
    }
}

/// Camera intrinsics and its pose in the radar frame.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraConfig {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Focal length along x, pixels.
    pub fx: f64,
    /// Focal length along y, pixels.
    pub fy: f64,
    /// Principal point x, pixels.
    pub cx: f64,
    /// Principal point y, pixels.
    pub cy: f64,
    /// Camera centre in the radar frame, m.
    pub translation_m: [f64; 3],
    /// Yaw, degrees (applied first).
    pub yaw_deg: f64,
    /// Pitch, degrees.
    pub pitch_deg: f64,
    /// Roll, degrees (applied last).
    pub roll_deg: f64,
}

/// A parsed `scene.toml`.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Free-text name.
    pub name: String,
    /// The radar configuration.
    pub radar: RadarConfig,
    /// The ADC file, resolved against the bundle directory (the master's for an MMWCAS capture).
    pub adc_file: PathBuf,
    /// How its samples are stored.
    pub layout: AdcLayout,
    /// The camera.
    pub camera: CameraConfig,
    /// Elevation of each TX, half-wavelengths (README's extension of bundle.md; empty = all 0).
    pub tx_elevation: Vec<i16>,
    /// Elevation of each RX, half-wavelengths (empty = all 0).
    pub rx_elevation: Vec<i16>,
    /// The channel calibration file, resolved against the bundle directory (README's
    /// `calibration_file` extension; `None`: the channels are used as recorded).
    pub calibration_file: Option<PathBuf>,
}

/// The optional elevation list `key` of a `[radar]` table: one entry per antenna of `count`.
fn elevation(f: &Fields<'_>, key: &str, count: usize) -> Result<Vec<i16>, InputError> {
    if !f.has(key) {
        return Ok(Vec::new());
    }
    let v = f.int_list(key, i16::MIN as i64, i16::MAX as i64)?;
    if v.len() != count {
        return Err(f.error(
            key,
            format!(
                "has {} entries; give one elevation (half-wavelengths) per antenna ({count})",
                v.len()
            ),
        ));
    }
    Ok(v.into_iter().map(|e| e as i16).collect())
}

impl Scene {
    /// Reads and checks `scene.toml` at `path`; `adc_file` is resolved against `path`'s folder.
    ///
    /// # Errors
    /// [`InputError`] naming the first bad field.
    pub fn read(path: &Path) -> Result<Self, InputError> {
        Self::parse(path, &read_text(path, crate::limits::MAX_TOML_BYTES)?)
    }

    /// [`Scene::read`] on the text of `path` already read (`adc_file` is resolved against
    /// `path`'s folder, which is not touched).
    ///
    /// # Errors
    /// [`InputError`] naming the first bad field.
    pub fn parse(path: &Path, text: &str) -> Result<Self, InputError> {
        let table = parse_toml(path, text)?;
        let root = Fields::root(path, &table);
        root.only(&["format", "name", "radar", "camera"])?;
        let format = root.string("format")?;
        if format != FORMAT {
            return Err(root.error(
                "format",
                format!("is \"{format}\"; this reader reads \"{FORMAT}\""),
            ));
        }
        let name = root.string("name")?.to_owned();
        let radar_fields = root.table("radar")?;
        let radar = parse_radar(&radar_fields, FramesField::Required)?;
        let adc_file = inside_name(&radar_fields, "adc_file")?;
        let calibration_file = if radar_fields.has("calibration_file") {
            Some(inside_name(&radar_fields, "calibration_file")?)
        } else {
            None
        };
        let layout_name = radar_fields.string("adc_layout")?;
        let Some(layout) = [AdcLayout::Dca1000, AdcLayout::Mmwcas]
            .into_iter()
            .find(|l| l.name() == layout_name)
        else {
            return Err(radar_fields.error(
                "adc_layout",
                format!(
                    "is \"{layout_name}\"; bundle.md's version 1 has \"{ADC_LAYOUT}\" (and this \
                     reader \"mmwcas-rf-evm\", the cascade's four device files)"
                ),
            ));
        };
        if layout == AdcLayout::Mmwcas {
            crate::mmwcas::check(path, &radar)?;
        }
        let camera = parse_camera(&root.table("camera")?)?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let tx_elevation = elevation(&radar_fields, "tx_elevation", radar.tx_positions.len())?;
        let rx_elevation = elevation(&radar_fields, "rx_elevation", radar.rx_count())?;
        Ok(Self {
            name,
            radar,
            adc_file: dir.join(adc_file),
            layout,
            camera,
            tx_elevation,
            rx_elevation,
            calibration_file: calibration_file.map(|c| dir.join(c)),
        })
    }
}

/// The file name `key`, which must name a file inside the bundle folder.
fn inside_name<'a>(f: &Fields<'a>, key: &str) -> Result<&'a str, InputError> {
    let name = f.string(key)?;
    let inside = Path::new(name)
        .components()
        .all(|c| matches!(c, std::path::Component::Normal(_)));
    if name.is_empty() || !inside {
        return Err(f.error(
            key,
            format!(
                "\"{name}\" must be a file name inside the bundle folder (no `..`, no absolute path)"
            ),
        ));
    }
    Ok(name)
}

/// Every key of a `[radar]` table: bundle.md's, and the README's elevation and calibration
/// extensions.
pub const RADAR_KEYS: [&str; 16] = [
    "start_frequency_hz",
    "slope_hz_per_s",
    "sample_rate_hz",
    "adc_samples",
    "chirp_period_s",
    "chirps_per_tx",
    "frames",
    "frame_period_s",
    "tx_positions",
    "rx_positions",
    "tx_order",
    "adc_file",
    "adc_layout",
    "tx_elevation",
    "rx_elevation",
    "calibration_file",
];

/// Whether `frames` must be given (bundles) or may be derived from the file size (bare captures).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FramesField {
    /// `frames` must be present.
    Required,
    /// `frames` may be absent (then 0: derive it from the capture size).
    Optional,
}

/// Parses a `[radar]` table (as in `scene.toml`) into a checked [`RadarConfig`].
///
/// # Errors
/// [`InputError`] naming the first bad field.
pub fn parse_radar(f: &Fields<'_>, frames: FramesField) -> Result<RadarConfig, InputError> {
    f.only(&RADAR_KEYS)?;
    let list_error = |key: &str, max: usize| f.error(key, format!("has more than {max} entries"));
    let positions = |key: &str| -> Result<Vec<i16>, InputError> {
        let v = f.int_list(key, i16::MIN as i64, i16::MAX as i64)?;
        if v.is_empty() {
            return Err(f.error(key, "must list at least one position"));
        }
        Ok(v.into_iter().map(|p| p as i16).collect())
    };
    let tx_positions = bounded::<_, MAX_TX>(positions("tx_positions")?)
        .ok_or_else(|| list_error("tx_positions", MAX_TX))?;
    let rx_positions = bounded::<_, MAX_RX>(positions("rx_positions")?)
        .ok_or_else(|| list_error("rx_positions", MAX_RX))?;
    let order = f.int_list("tx_order", 0, tx_positions.len() as i64 - 1)?;
    if order.is_empty() {
        return Err(f.error("tx_order", "must list at least one transmitter"));
    }
    let tx_order = bounded::<_, MAX_SLOTS>(order.into_iter().map(|t| t as u8).collect())
        .ok_or_else(|| list_error("tx_order", MAX_SLOTS))?;
    let frames = match frames {
        FramesField::Optional if !f.has("frames") => 0,
        _ => f.integer("frames", 1, MAX_FRAMES as i64)? as u32,
    };
    let max_fft = metamoran_dsp::fft::MAX_LEN as i64;
    let adc_samples = f.integer("adc_samples", 2, max_fft)?;
    if adc_samples % 2 != 0 {
        return Err(f.error(
            "adc_samples",
            format!("{adc_samples} must be even (DCA1000 groups hold two samples)"),
        ));
    }
    let config = RadarConfig {
        start_frequency_hz: f.positive("start_frequency_hz")?,
        slope_hz_per_s: f.positive("slope_hz_per_s")?,
        sample_rate_hz: f.positive("sample_rate_hz")?,
        adc_samples: adc_samples as u16,
        chirp_period_s: f.positive("chirp_period_s")?,
        chirps_per_tx: f.integer("chirps_per_tx", 1, max_fft)? as u16,
        frames,
        frame_period_s: f.positive("frame_period_s")?,
        tx_positions,
        rx_positions,
        tx_order,
    };
    let frame_bytes = config.samples_per_frame() as u64 * 4;
    if frame_bytes > MAX_FRAME_BYTES {
        return Err(f.error(
            "adc_samples",
            format!(
                "a frame of adc_samples × chirps_per_tx × len(tx_order) × len(rx_positions) × 4 \
                 = {frame_bytes} bytes is over the limit of {MAX_FRAME_BYTES} bytes per frame"
            ),
        ));
    }
    config.validate().map_err(|e| match e {
        ConfigError::NotPositive(field) => f.error(field, "must be a positive, finite number"),
        ConfigError::AdcSamples(_) => f.error("adc_samples", e.to_string()),
        ConfigError::ChirpsPerTx(_) => f.error("chirps_per_tx", e.to_string()),
        ConfigError::Empty(field) => f.error(field, e.to_string()),
        ConfigError::TxOrder { slot, .. } => f.error(&format!("tx_order[{slot}]"), e.to_string()),
        ConfigError::Implausible { quantity, .. } => f.error(quantity.field(), e.to_string()),
        _ => f.error("radar", e.to_string()),
    })?;
    Ok(config)
}

/// Moves `v` into a fixed-capacity vector, or `None` if it is too long.
fn bounded<T, const N: usize>(v: Vec<T>) -> Option<heapless::Vec<T, N>> {
    let mut out = heapless::Vec::new();
    for x in v {
        out.push(x).ok()?;
    }
    Some(out)
}

fn parse_camera(f: &Fields<'_>) -> Result<CameraConfig, InputError> {
    f.only(&[
        "width",
        "height",
        "fx",
        "fy",
        "cx",
        "cy",
        "translation_m",
        "yaw_deg",
        "pitch_deg",
        "roll_deg",
    ])?;
    let translation = f.f64_list("translation_m")?;
    let translation_m: [f64; 3] = translation.try_into().map_err(|v: Vec<f64>| {
        f.error(
            "translation_m",
            format!("has {} entries; give [x, y, z] in metres", v.len()),
        )
    })?;
    let width = f.integer("width", 1, 65535)? as u32;
    let height = f.integer("height", 1, 65535)? as u32;
    if width as u64 * height as u64 > MAX_PIXELS {
        return Err(f.error(
            "width",
            format!(
                "{width} × {height} = {} pixels is over the limit of {MAX_PIXELS} pixels",
                width as u64 * height as u64
            ),
        ));
    }
    Ok(CameraConfig {
        width,
        height,
        fx: f.positive("fx")?,
        fy: f.positive("fy")?,
        cx: f.f64("cx")?,
        cy: f.f64("cy")?,
        translation_m,
        yaw_deg: f.f64("yaw_deg")?,
        pitch_deg: f.f64("pitch_deg")?,
        roll_deg: f.f64("roll_deg")?,
    })
}
