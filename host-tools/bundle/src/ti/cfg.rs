//! The mmWave SDK CLI configuration (`.cfg`), as TI's demos, mmWave Demo Visualizer and the
//! DCA1000 capture tools write it: one command per line, `%` comments.
//!
//! Read: `channelCfg`, `adcCfg`, `adcbufCfg` (its sample swap gives the I/Q order),
//! `profileCfg`, `chirpCfg`, `frameCfg`, `lowPower`, `dfeDataOutputMode 1`. The demo's
//! processing commands (`cfarCfg`, `guiMonitor`, `clutterRemoval`, …) do not change the ADC data
//! and are skipped. Commands that change it in ways a uniform TDM frame cannot describe
//! (`advFrameCfg`, `subFrameCfg`, an enabled `bpmCfg`, per-chirp variations, chirps of several
//! profiles) are refused by name, as is any command this reader does not know.

use super::{Antennas, Board, CaptureConfig, Timing, capture_config};
use crate::error::InputError;
use metamoran_dsp::capture::IqOrder;
use std::collections::BTreeMap;
use std::path::Path;

/// Commands of the SDK demos that configure their processing chain, not the ADC data.
pub const PROCESSING_ONLY: [&str; 24] = [
    "sensorStop",
    "sensorStart",
    "flushCfg",
    "guiMonitor",
    "cfarCfg",
    "multiObjBeamForming",
    "clutterRemoval",
    "calibDcRangeSig",
    "extendedMaxVelocity",
    "lvdsStreamCfg",
    "compRangeBiasAndRxChanPhase",
    "measureRangeBiasAndRxChanPhase",
    "CQRxSatMonitor",
    "CQSigImgMonitor",
    "analogMonitor",
    "aoaFovCfg",
    "cfarFovCfg",
    "calibData",
    "antGeometry0",
    "antGeometry1",
    "antPhaseRot",
    "fovCfg",
    "staticBoundaryBox",
    "idlePowerCycle",
];

/// Commands that change the ADC data in ways this reader does not model.
pub const UNSUPPORTED: [&str; 4] = ["advFrameCfg", "subFrameCfg", "advChirpCfg", "dataFmtCfg"];

/// One command line: its number (from 1), name and arguments.
struct Line<'a> {
    number: usize,
    name: &'a str,
    args: Vec<&'a str>,
}

impl Line<'_> {
    fn at(&self, arg: &str) -> String {
        format!("line {}: {} {arg}", self.number, self.name)
    }

    /// Argument `i` (named `arg` in errors) as a number.
    fn number(&self, path: &Path, i: usize, arg: &str) -> Result<f64, InputError> {
        let text = self.args.get(i).ok_or_else(|| {
            InputError::field(path, self.at(arg), format!("missing (argument {})", i + 1))
        })?;
        text.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                InputError::field(path, self.at(arg), format!("`{text}` is not a number"))
            })
    }

    /// Argument `i` as a whole number in `0..=max`.
    fn whole(&self, path: &Path, i: usize, arg: &str, max: u32) -> Result<u32, InputError> {
        let v = self.number(path, i, arg)?;
        if v.fract() != 0.0 || !(0.0..=f64::from(max)).contains(&v) {
            return Err(InputError::field(
                path,
                self.at(arg),
                format!("{v} must be a whole number from 0 to {max}"),
            ));
        }
        Ok(v as u32)
    }

    /// Argument `i` as an integer that may be -1 (a subframe index: -1 means all).
    fn subframe(&self, path: &Path, i: usize) -> Result<(), InputError> {
        let v = self.number(path, i, "subFrameIdx")?;
        if v == -1.0 || v == 0.0 {
            Ok(())
        } else {
            Err(InputError::field(
                path,
                self.at("subFrameIdx"),
                format!("{v}: subframes are for advFrameCfg, which is not supported"),
            ))
        }
    }
}

/// The chirp definitions of `chirpCfg` lines: per chirp index, its profile and TX mask.
type Chirps = BTreeMap<u32, (u32, u32, usize)>;

/// Parses a `.cfg` (the text of `path`) for `board`.
///
/// # Errors
/// [`InputError`] naming the line and argument: a missing or malformed required command, a
/// value out of range, a command this reader refuses (with why), or a TX the board lacks.
///
/// # Example
/// ```
/// use metamoran_bundle::ti::{Board, cfg};
/// use metamoran_dsp::capture::IqOrder;
/// use std::path::Path;
///
/// let text = "channelCfg 15 5 0\nadcCfg 2 1\nadcbufCfg -1 0 1 1 1\n\
///             profileCfg 0 77 429 7 57.14 0 0 70 1 256 5209 0 0 30\n\
///             chirpCfg 0 0 0 0 0 0 0 1\nchirpCfg 1 1 0 0 0 0 0 4\nframeCfg 0 1 16 0 100 1 0\n";
/// let c = cfg::parse(Path::new("x.cfg"), text, Board::Xwr18xxBoost)?;
/// assert_eq!(c.radar.tx_positions.as_slice(), &[0, 4]); // TX0 and TX2
/// assert_eq!((c.radar.chirps_per_tx, c.iq_order), (16, IqOrder::Qqii));
/// # Ok::<(), metamoran_bundle::error::InputError>(())
/// ```
pub fn parse(path: &Path, text: &str, board: Board) -> Result<CaptureConfig, InputError> {
    if board.devices() != 1 {
        return Err(InputError::file(
            path,
            format!(
                "an SDK .cfg configures one device; {board} has {}: give its mmWave Studio .mmwave.json",
                board.devices()
            ),
        ));
    }
    let mut seen: BTreeMap<&str, Line<'_>> = BTreeMap::new();
    let mut profiles: BTreeMap<u32, Line<'_>> = BTreeMap::new();
    let mut chirps = Chirps::new();
    for (i, raw) in text.lines().enumerate() {
        let content = raw.split('%').next().unwrap_or("").trim();
        let mut words = content.split_whitespace();
        let Some(name) = words.next() else { continue };
        let line = Line {
            number: i + 1,
            name,
            args: words.collect(),
        };
        match name {
            _ if PROCESSING_ONLY.contains(&name) => {}
            _ if UNSUPPORTED.contains(&name) => {
                return Err(InputError::field(
                    path,
                    line.at(""),
                    "changes the ADC data in a way a uniform TDM frame cannot describe \
                     (advanced frames, subframes, per-chirp data formats); not supported",
                ));
            }
            "bpmCfg" => {
                if line.number(path, 1, "enabled")? != 0.0 {
                    return Err(InputError::field(
                        path,
                        line.at("enabled"),
                        "BPM-MIMO (binary phase-coded TX) is not supported: use TDM chirps",
                    ));
                }
            }
            "profileCfg" => {
                let id = line.whole(path, 0, "profileId", 255)?;
                profiles.insert(id, line);
            }
            "chirpCfg" => add_chirps(path, &line, &mut chirps)?,
            "dfeDataOutputMode" | "channelCfg" | "adcCfg" | "adcbufCfg" | "frameCfg"
            | "lowPower" => {
                seen.insert(name, line);
            }
            _ => {
                return Err(InputError::field(
                    path,
                    line.at(""),
                    "unknown command: this reader knows the SDK's channelCfg, adcCfg, adcbufCfg, \
                     profileCfg, chirpCfg, frameCfg, lowPower and dfeDataOutputMode, and skips \
                     the demo's processing commands",
                ));
            }
        }
    }
    let need = |name: &str| {
        seen.get(name).ok_or_else(|| {
            InputError::field(path, name.to_owned(), "missing: the .cfg must configure it")
        })
    };
    if let Some(mode) = seen.get("dfeDataOutputMode") {
        if mode.number(path, 0, "modeType")? != 1.0 {
            return Err(InputError::field(
                path,
                mode.at("modeType"),
                "only 1 (frame-based chirps) is supported; 3 is the advanced frame",
            ));
        }
    }
    let channel = need("channelCfg")?;
    let (rx_mask, tx_mask) = (
        channel.whole(path, 0, "rxChannelEn", 15)?,
        channel.whole(path, 1, "txChannelEn", 7)?,
    );
    if channel.args.len() > 2 && channel.number(path, 2, "cascading")? != 0.0 {
        return Err(InputError::field(
            path,
            channel.at("cascading"),
            "a cascaded device: read the board's mmWave Studio .mmwave.json instead",
        ));
    }
    let adc = need("adcCfg")?;
    if adc.number(path, 0, "numADCBits")? != 2.0 {
        return Err(InputError::field(
            path,
            adc.at("numADCBits"),
            "only 2 (16-bit samples) is supported",
        ));
    }
    if !matches!(adc.whole(path, 1, "adcOutputFmt", 2)?, 1 | 2) {
        return Err(InputError::field(
            path,
            adc.at("adcOutputFmt"),
            "real ADC output (0) is not supported: configure complex 1x (1) or 2x (2)",
        ));
    }
    let buf = need("adcbufCfg")?;
    buf.subframe(path, 0)?;
    if buf.number(path, 1, "adcOutputFmt")? != 0.0 {
        return Err(InputError::field(
            path,
            buf.at("adcOutputFmt"),
            "only 0 (complex) is supported",
        ));
    }
    let iq_order = match buf.whole(path, 2, "SampleSwap", 1)? {
        1 => IqOrder::Qqii,
        _ => IqOrder::Iiqq,
    };
    if buf.whole(path, 3, "ChanInterleave", 1)? != 1 {
        return Err(InputError::field(
            path,
            buf.at("ChanInterleave"),
            "only 1 (non-interleaved: chirp, RX, sample, as the DCA1000 records) is supported",
        ));
    }
    let frame = need("frameCfg")?;
    let (first, last) = (
        frame.whole(path, 0, "chirpStartIdx", 511)?,
        frame.whole(path, 1, "chirpEndIdx", 511)?,
    );
    if last < first {
        return Err(InputError::field(
            path,
            frame.at("chirpEndIdx"),
            format!("{last} is before chirpStartIdx {first}"),
        ));
    }
    let mut antennas = Antennas::default();
    for r in (0..4).filter(|r| rx_mask >> r & 1 == 1) {
        // Every board here has RX0–3.
        antennas.rx.extend(board.rx(0, r));
    }
    let mut profile_id = None;
    for c in first..=last {
        let Some(&(p, tx, number)) = chirps.get(&c) else {
            return Err(InputError::field(
                path,
                frame.at("chirpStartIdx"),
                format!("chirp {c} of the frame is not defined by any chirpCfg"),
            ));
        };
        let chirp_at = format!("line {number}: chirpCfg txEnable");
        if *profile_id.get_or_insert(p) != p {
            return Err(InputError::field(
                path,
                format!("line {number}: chirpCfg profileId"),
                "the frame's chirps use several profiles: not supported",
            ));
        }
        if tx.count_ones() != 1 || tx & !tx_mask != 0 {
            return Err(InputError::field(
                path,
                chirp_at,
                format!(
                    "{tx:#05b}: each chirp must enable exactly one TX that channelCfg enables \
                     ({tx_mask:#05b}); simultaneous TX is not TDM"
                ),
            ));
        }
        let antenna = board.tx(0, tx.trailing_zeros() as usize).ok_or_else(|| {
            InputError::field(
                path,
                format!("line {number}: chirpCfg txEnable"),
                format!("TX{} does not exist on {board}", tx.trailing_zeros()),
            )
        })?;
        let index = antennas.tx_index(antenna);
        antennas.order.push(index);
    }
    let profile = profiles.get(&profile_id.unwrap_or(0)).ok_or_else(|| {
        InputError::field(
            path,
            "profileCfg",
            format!(
                "profile {} is used but not defined",
                profile_id.unwrap_or(0)
            ),
        )
    })?;
    let timing = Timing {
        start_ghz: profile.number(path, 1, "startFreq")?,
        idle_us: profile.number(path, 2, "idleTime")?,
        adc_start_us: profile.number(path, 3, "adcStartTime")?,
        ramp_end_us: profile.number(path, 4, "rampEndTime")?,
        slope_mhz_per_us: profile.number(path, 7, "freqSlopeConst")?,
        samples: profile.whole(path, 9, "numAdcSamples", 65535)?,
        rate_ksps: profile.number(path, 10, "digOutSampleRate")?,
        loops: frame.whole(path, 2, "numLoops", 255)?,
        frames: frame.whole(path, 3, "numFrames", 65535)?,
        period_ms: frame.number(path, 4, "framePeriodicity")?,
    };
    let at = |what: &str| format!("{} ({what})", profile.at(""));
    capture_config(path, &at, timing, antennas, iq_order, board)
}

/// Records the chirps of one `chirpCfg` line, refusing per-chirp variations.
fn add_chirps(path: &Path, line: &Line<'_>, chirps: &mut Chirps) -> Result<(), InputError> {
    let (start, end) = (
        line.whole(path, 0, "startIdx", 511)?,
        line.whole(path, 1, "endIdx", 511)?,
    );
    let profile = line.whole(path, 2, "profileId", 255)?;
    for (i, arg) in [
        (3, "startFreqVar"),
        (4, "freqSlopeVar"),
        (5, "idleTimeVar"),
        (6, "adcStartTimeVar"),
    ] {
        if line.number(path, i, arg)? != 0.0 {
            return Err(InputError::field(
                path,
                line.at(arg),
                "per-chirp variations are not supported: the chirps of a frame must be alike",
            ));
        }
    }
    let tx = line.whole(path, 7, "txEnable", 7)?;
    for c in start..=end.max(start) {
        chirps.insert(c, (profile, tx, line.number));
    }
    Ok(())
}

/// The board a `.cfg`'s Visualizer header names (`% Platform:xWR18xx`), where one board goes
/// with that platform: the xWR18xx and xWR16xx BOOST boards (an xWR68xx may be an ISK, AOP or
/// ODS module, whose antennas differ).
pub fn platform(text: &str) -> Option<Board> {
    let name = text
        .lines()
        .filter_map(|l| l.trim().strip_prefix('%'))
        .find_map(|l| l.trim().strip_prefix("Platform:"))?
        .trim();
    match name {
        "xWR18xx" => Some(Board::Xwr18xxBoost),
        "xWR16xx" => Some(Board::Xwr16xxBoost),
        _ => None,
    }
}
