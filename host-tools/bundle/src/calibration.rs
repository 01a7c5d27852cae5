//! Channel calibration files: what `metamoran calibrate` writes and a bundle's optional
//! `[radar] calibration_file` names (README, "Channel calibration"), checked against the board
//! they are applied to and turned into the range stage's [`Calibration`].
//!
//! The calibrated sample `n` of channel `(t, r)` is `(re + j·im) · exp(j·2π·f·n/N) · x[n]`,
//! `t` indexing `tx_positions`, `r` indexing `rx_positions`, `N` = `adc_samples` of the
//! calibration capture. `f` is a range-delay correction, so on a chirp of another slope, sample
//! rate or length it scales with the beat frequency a delay makes: `f · (S/S₀) · (fs₀/fs) ·
//! (N/N₀)`.

use crate::error::{InputError, read_text};
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::range::calibration::{Calibration, Correction};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The `format` string of a calibration file.
pub const FORMAT: &str = "metamoran-calibration/1";

/// Largest calibration file read, bytes (256 channels take about 30 KB).
pub const MAX_BYTES: u64 = 1 << 20;

/// One (TX, RX) pair's correction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChannelCalibration {
    /// Index into `tx_positions`.
    pub tx: usize,
    /// Index into `rx_positions`.
    pub rx: usize,
    /// Complex gain `[re, im]` relative to the reference channel.
    pub gain: [f64; 2],
    /// Frequency correction, range bins of an `adc_samples`-point transform.
    pub frequency_bins: f64,
}

/// A (TX, RX) pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChannelId {
    /// Index into `tx_positions`.
    pub tx: usize,
    /// Index into `rx_positions`.
    pub rx: usize,
}

/// `metamoran calibrate --json`: exactly `{"reference", "target_range_m", "channels"}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrationReport {
    /// The channel every gain is relative to.
    pub reference: ChannelId,
    /// Range of the reflector the calibration was measured on, m.
    pub target_range_m: f64,
    /// One entry per (TX, RX) pair.
    pub channels: Vec<ChannelCalibration>,
}

/// A calibration file: the report plus the chirp it was measured with.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrationFile {
    /// [`FORMAT`].
    pub format: String,
    /// Chirp slope of the calibration capture, Hz/s.
    pub slope_hz_per_s: f64,
    /// Complex sample rate of the calibration capture, Hz.
    pub sample_rate_hz: f64,
    /// Samples per chirp of the calibration capture (`N` of `frequency_bins`).
    pub adc_samples: u16,
    /// The channel every gain is relative to.
    pub reference: ChannelId,
    /// Range of the reflector the calibration was measured on, m.
    pub target_range_m: f64,
    /// One entry per (TX, RX) pair.
    pub channels: Vec<ChannelCalibration>,
}

impl CalibrationFile {
    /// The file for `report`, measured with `config`'s chirp.
    pub fn new(report: CalibrationReport, config: &RadarConfig) -> Self {
        Self {
            format: FORMAT.to_owned(),
            slope_hz_per_s: config.slope_hz_per_s,
            sample_rate_hz: config.sample_rate_hz,
            adc_samples: config.adc_samples,
            reference: report.reference,
            target_range_m: report.target_range_m,
            channels: report.channels,
        }
    }

    /// The `--json` view.
    pub fn report(&self) -> CalibrationReport {
        CalibrationReport {
            reference: self.reference,
            target_range_m: self.target_range_m,
            channels: self.channels.clone(),
        }
    }

    /// Reads and checks `path` (format, finite values; not yet against a board).
    ///
    /// # Errors
    /// [`InputError`] naming the file and the first bad field.
    pub fn read(path: &Path) -> Result<Self, InputError> {
        Self::parse(path, &read_text(path, MAX_BYTES)?)
    }

    /// [`Self::read`] on text already read from `path`.
    ///
    /// # Errors
    /// As [`Self::read`].
    pub fn parse(path: &Path, text: &str) -> Result<Self, InputError> {
        let de = toml::Deserializer::parse(text).map_err(|e| InputError::Syntax {
            path: path.to_owned(),
            format: "TOML",
            message: e.to_string(),
        })?;
        let file: Self = serde_path_to_error::deserialize(de)
            .map_err(|e| InputError::field(path, e.path().to_string(), e.inner().to_string()))?;
        let field = |name: String, problem: String| Err(InputError::field(path, name, problem));
        if file.format != FORMAT {
            return field(
                "format".into(),
                format!("is \"{}\"; this reader reads \"{FORMAT}\"", file.format),
            );
        }
        for (key, v) in [
            ("slope_hz_per_s", file.slope_hz_per_s),
            ("sample_rate_hz", file.sample_rate_hz),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return field(key.into(), format!("{v} must be a positive finite number"));
            }
        }
        if file.adc_samples < 2 {
            return field("adc_samples".into(), "must be at least 2".into());
        }
        if !(file.target_range_m.is_finite() && file.target_range_m >= 0.0) {
            return field(
                "target_range_m".into(),
                format!("{} must be a finite range", file.target_range_m),
            );
        }
        let half = f64::from(file.adc_samples) / 2.0;
        for (i, c) in file.channels.iter().enumerate() {
            let magnitude = c.gain[0].hypot(c.gain[1]);
            if !(magnitude.is_finite() && magnitude > 1e-6 && magnitude < 1e6) {
                return field(
                    format!("channels[{i}].gain"),
                    format!(
                        "{:?} must be a finite, non-zero complex gain (a dead channel cannot be calibrated; recalibrate)",
                        c.gain
                    ),
                );
            }
            if !(c.frequency_bins.is_finite() && c.frequency_bins.abs() <= half) {
                return field(
                    format!("channels[{i}].frequency_bins"),
                    format!(
                        "{} must be finite and within ±{half} bins (N/2)",
                        c.frequency_bins
                    ),
                );
            }
        }
        Ok(file)
    }

    /// The TOML text of the file.
    pub fn to_toml(&self) -> String {
        // A derived struct of numbers, strings and arrays always serializes.
        toml::to_string(self).unwrap_or_default()
    }

    /// The range stage's form for a capture of `config`: every (TX, RX) pair present exactly
    /// once, frequency corrections rescaled to `config`'s chirp.
    ///
    /// # Errors
    /// [`InputError`] naming `path` (the calibration file) and the channel that does not fit.
    pub fn for_config(&self, path: &Path, config: &RadarConfig) -> Result<Calibration, InputError> {
        let (tx, rx) = (config.tx_positions.len(), config.rx_count());
        let mut cal =
            Calibration::identity(tx, rx).map_err(|e| InputError::file(path, e.to_string()))?;
        let mut seen = vec![false; tx * rx];
        let scale = (config.slope_hz_per_s / self.slope_hz_per_s)
            * (self.sample_rate_hz / config.sample_rate_hz)
            * (f64::from(config.adc_samples) / f64::from(self.adc_samples));
        let ref_ok = self.reference.tx < tx && self.reference.rx < rx;
        if !ref_ok {
            return Err(InputError::field(
                path,
                "reference",
                format!(
                    "(tx {}, rx {}) is not on this board ({tx} TX × {rx} RX)",
                    self.reference.tx, self.reference.rx
                ),
            ));
        }
        for (i, c) in self.channels.iter().enumerate() {
            if c.tx >= tx || c.rx >= rx {
                return Err(InputError::field(
                    path,
                    format!("channels[{i}]"),
                    format!(
                        "(tx {}, rx {}) is not on this board ({tx} TX × {rx} RX): the calibration is for another radar",
                        c.tx, c.rx
                    ),
                ));
            }
            let slot = &mut seen[c.tx * rx + c.rx];
            if std::mem::replace(slot, true) {
                return Err(InputError::field(
                    path,
                    format!("channels[{i}]"),
                    format!("(tx {}, rx {}) appears twice", c.tx, c.rx),
                ));
            }
            let correction = Correction::from_f64(
                (c.gain[0], c.gain[1]),
                c.frequency_bins * scale,
                config.adc_samples,
            );
            cal.set(c.tx, c.rx, correction)
                .map_err(|e| InputError::file(path, e.to_string()))?;
        }
        if let Some(missing) = seen.iter().position(|s| !s) {
            return Err(InputError::field(
                path,
                "channels",
                format!(
                    "has no entry for (tx {}, rx {}); a calibration lists every (TX, RX) pair ({})",
                    missing / rx,
                    missing % rx,
                    tx * rx
                ),
            ));
        }
        Ok(cal)
    }
}

/// What TI's cascade calibration file (`calibrateResults*.mat`) holds for one board, read
/// as TI's `calibration_cascade.m` applies it.
#[derive(Clone, Debug, PartialEq)]
pub struct TiCalibration {
    /// `calibResult.RangeMat`: the reflector's peak per (TX ID, RX in device order), bins of
    /// an `N · interp`-point transform (MATLAB's 1-based index), row-major here.
    pub range_bins: Vec<Vec<f64>>,
    /// `calibResult.PeakValMat`: the complex peak value per (TX ID, RX).
    pub peaks: Vec<Vec<(f64, f64)>>,
    /// `params.Slope_MHzperus` in Hz/s.
    pub slope_hz_per_s: f64,
    /// `params.Sampling_Rate_sps`.
    pub sample_rate_hz: f64,
}

impl TiCalibration {
    /// Reads `calibResult.RangeMat`, `calibResult.PeakValMat`, `params.Slope_MHzperus` and
    /// `params.Sampling_Rate_sps` from the MAT file at `path`.
    ///
    /// # Errors
    /// [`InputError`] naming the file and the missing or malformed variable.
    pub fn read(path: &Path) -> Result<Self, InputError> {
        Self::parse(
            path,
            &crate::limits::read_bounded(path, crate::ti::mat::MAX_FILE_BYTES)?,
        )
    }

    /// [`Self::read`] on the bytes of `path` already read.
    ///
    /// # Errors
    /// As [`Self::read`].
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Self, InputError> {
        use crate::ti::mat::{self, MatValue};
        let vars = mat::parse(path, bytes)?;
        let var = |name: &str| {
            vars.iter()
                .find(|(n, _)| n == name)
                .map(|(_, v)| v)
                .ok_or_else(|| {
                    InputError::field(
                        path,
                        name,
                        "missing: a TI calibration file holds the structs calibResult and params (calibration_cascade.m)",
                    )
                })
        };
        let (result, params) = (var("calibResult")?, var("params")?);
        let matrix = |s: &MatValue, key: &str, complex: bool| -> Result<_, InputError> {
            let owner = if complex || key == "RangeMat" {
                "calibResult"
            } else {
                "params"
            };
            let name = format!("{owner}.{key}");
            match s.field(key) {
                // A real PeakValMat (all phases 0) is still a gain table.
                Some(MatValue::Numeric { dims, re, im }) if dims.len() == 2 => {
                    let (rows, cols) = (dims[0], dims[1]);
                    let get = |i: usize, j: usize| {
                        let k = i + j * rows;
                        (re[k], im.as_ref().map_or(0.0, |v| v[k]))
                    };
                    Ok((
                        rows,
                        cols,
                        (0..rows)
                            .map(|i| (0..cols).map(|j| get(i, j)).collect::<Vec<_>>())
                            .collect::<Vec<_>>(),
                    ))
                }
                Some(_) => Err(InputError::field(path, name, "is not a numeric matrix")),
                None => Err(InputError::field(path, name, "missing")),
            }
        };
        let (rows, cols, range) = matrix(result, "RangeMat", false)?;
        let (prows, pcols, peaks) = matrix(result, "PeakValMat", true)?;
        if (rows, cols) != (prows, pcols) {
            return Err(InputError::field(
                path,
                "calibResult.PeakValMat",
                format!("is {prows}×{pcols}; RangeMat is {rows}×{cols}"),
            ));
        }
        let scalar = |key: &str| -> Result<f64, InputError> {
            let (_, _, m) = matrix(params, key, false)?;
            m.first()
                .and_then(|r| r.first())
                .map(|v| v.0)
                .filter(|v| v.is_finite() && *v > 0.0)
                .ok_or_else(|| {
                    InputError::field(path, format!("params.{key}"), "must be a positive number")
                })
        };
        Ok(Self {
            range_bins: range
                .into_iter()
                .map(|r| r.into_iter().map(|v| v.0).collect())
                .collect(),
            peaks,
            slope_hz_per_s: scalar("Slope_MHzperus")? * 1e12,
            sample_rate_hz: scalar("Sampling_Rate_sps")?,
        })
    }

    /// The calibration file for `config` on `board`. TI's matrices are indexed by TX ID
    /// (`3·device + channel + 1`, RangeMat's row) and RX in device order (its column); each
    /// TX and RX of `config` is matched to its ID by its position on the board. As TI applies
    /// it: the reference is the first TX of `tx_order` with the first RX, the frequency
    /// correction is `(RangeMat(ref) − RangeMat(t, r)) / interp` bins, the gain
    /// `PeakValMat(ref) / PeakValMat(t, r)`, and (as TI assumes) the calibration capture had
    /// `config`'s number of samples. `path` names the file in errors.
    ///
    /// # Errors
    /// [`InputError`] when an antenna is not on the board, the matrices do not cover it, or a
    /// peak is zero.
    pub fn to_file(
        &self,
        path: &Path,
        config: &RadarConfig,
        board: crate::ti::Board,
        interp: f64,
    ) -> Result<CalibrationFile, InputError> {
        let (tx, rx) = (config.tx_positions.len(), config.rx_count());
        if !(interp.is_finite() && interp > 0.0) {
            return Err(InputError::file(
                path,
                format!("interpolation factor {interp} must be positive"),
            ));
        }
        let devices = board.devices();
        let tx_id = |p: i16| {
            (0..devices * 3).find(|&id| board.tx(id / 3, id % 3).is_some_and(|a| a.azimuth == p))
        };
        let rx_col = |p: i16| {
            (0..devices * 4).find(|&c| board.rx(c / 4, c % 4).is_some_and(|a| a.azimuth == p))
        };
        let unplaced = |what: &str, i: usize, p: i16| {
            InputError::file(
                path,
                format!(
                    "{what} {i} of the config sits at {p}, which is no {what} of {board}: give the board the calibration was made on (--board)"
                ),
            )
        };
        let rows: Vec<usize> = config
            .tx_positions
            .iter()
            .enumerate()
            .map(|(i, &p)| tx_id(p).ok_or_else(|| unplaced("TX", i, p)))
            .collect::<Result<_, _>>()?;
        let cols: Vec<usize> = config
            .rx_positions
            .iter()
            .enumerate()
            .map(|(i, &p)| rx_col(p).ok_or_else(|| unplaced("RX", i, p)))
            .collect::<Result<_, _>>()?;
        // TI's (row, column) of a TX ID and an RX column: RangeMat's bin and PeakValMat's value.
        let covered = |row: usize, col: usize| {
            let bins = self.range_bins.get(row).and_then(|v| v.get(col)).copied();
            let peak = self.peaks.get(row).and_then(|v| v.get(col)).copied();
            bins.zip(peak).ok_or_else(|| {
                InputError::field(
                    path,
                    "calibResult.RangeMat",
                    format!(
                        "has no entry for TX ID {}, RX {}: it covers {}×{}",
                        row + 1,
                        col + 1,
                        self.range_bins.len(),
                        self.range_bins.first().map_or(0, Vec::len)
                    ),
                )
            })
        };
        let t_ref = usize::from(config.tx_order.first().copied().unwrap_or(0));
        let row_ref = rows.get(t_ref).copied().unwrap_or(0);
        let (r_ref, p_ref) = covered(row_ref, cols.first().copied().unwrap_or(0))?;
        let mut channels = Vec::with_capacity(tx * rx);
        for (t, &row) in rows.iter().enumerate() {
            for (r, &col) in cols.iter().enumerate() {
                let (bins, p) = covered(row, col)?;
                let d = p.0 * p.0 + p.1 * p.1;
                if !(d.is_finite() && d > 0.0) {
                    return Err(InputError::field(
                        path,
                        format!("calibResult.PeakValMat({}, {})", row + 1, col + 1),
                        "is zero: that channel saw no reflector",
                    ));
                }
                let g = (
                    (p_ref.0 * p.0 + p_ref.1 * p.1) / d,
                    (p_ref.1 * p.0 - p_ref.0 * p.1) / d,
                );
                channels.push(ChannelCalibration {
                    tx: t,
                    rx: r,
                    gain: [g.0, g.1],
                    frequency_bins: (r_ref - bins) / interp,
                });
            }
        }
        let n = f64::from(config.adc_samples);
        let bin_m = metamoran_dsp::config::SPEED_OF_LIGHT * self.sample_rate_hz
            / (2.0 * self.slope_hz_per_s * n * interp);
        let file = CalibrationFile {
            format: FORMAT.to_owned(),
            slope_hz_per_s: self.slope_hz_per_s,
            sample_rate_hz: self.sample_rate_hz,
            adc_samples: config.adc_samples,
            reference: ChannelId { tx: t_ref, rx: 0 },
            target_range_m: (r_ref - 1.0).max(0.0) * bin_m,
            channels,
        };
        // The same checks as a file read from disk.
        Self::recheck(path, &file)?;
        Ok(file)
    }

    fn recheck(path: &Path, file: &CalibrationFile) -> Result<(), InputError> {
        CalibrationFile::parse(path, &file.to_toml()).map(|_| ())
    }
}
