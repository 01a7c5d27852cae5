//! mmWave Studio's configuration export (`*.mmwave.json`): one `rfConfig` per device, so it
//! describes single-chip boards and the four-device MMWCAS cascade alike. Read: each device's
//! channel masks, ADC format, the profile, chirps and frame; `rawDataCaptureConfig`'s
//! `iqSwapSel` gives the I/Q order. Other keys are Studio's own and are left alone.

use super::{Antennas, Board, CaptureConfig, Timing, capture_config};
use crate::error::{InputError, parse_json};
use metamoran_dsp::capture::IqOrder;
use serde::Deserialize;
use std::path::Path;

/// A channel mask as Studio writes it (`"0xF"`) or as a number.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
enum Mask {
    Number(u32),
    Text(String),
}

// The key names are Studio's.
#[allow(non_snake_case)]
#[derive(Deserialize)]
struct File {
    mmWaveDevices: Devices,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum Devices {
    Many(Vec<Device>),
    One(Box<Device>),
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct Device {
    #[serde(default)]
    mmWaveDeviceId: u32,
    rfConfig: Rf,
    #[serde(default)]
    rawDataCaptureConfig: Option<Raw>,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct Rf {
    rlChanCfg_t: Chan,
    rlAdcOutCfg_t: AdcOut,
    rlProfiles: Vec<ProfileEntry>,
    rlChirps: Vec<ChirpEntry>,
    rlFrameCfg_t: Frame,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct Chan {
    rxChannelEn: Mask,
    txChannelEn: Mask,
}

#[derive(Deserialize)]
struct AdcOut {
    fmt: AdcFmt,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct AdcFmt {
    b2AdcBits: u32,
    b2AdcOutFmt: u32,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct ProfileEntry {
    rlProfileCfg_t: Profile,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct Profile {
    profileId: u32,
    startFreqConst_GHz: f64,
    idleTimeConst_usec: f64,
    adcStartTimeConst_usec: f64,
    rampEndTime_usec: f64,
    freqSlopeConst_MHz_usec: f64,
    numAdcSamples: u32,
    digOutSampleRate: f64,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct ChirpEntry {
    rlChirpCfg_t: Chirp,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct Chirp {
    chirpStartIdx: u32,
    chirpEndIdx: u32,
    profileId: u32,
    txEnable: Mask,
    #[serde(default)]
    startFreqVar_MHz: f64,
    #[serde(default)]
    freqSlopeVar_KHz_usec: f64,
    #[serde(default)]
    idleTimeVar_usec: f64,
    #[serde(default)]
    adcStartTimeVar_usec: f64,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct Frame {
    chirpStartIdx: u32,
    chirpEndIdx: u32,
    numLoops: u32,
    numFrames: u32,
    framePeriodicity_msec: f64,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct Raw {
    #[serde(default)]
    rlDevDataFmtCfg_t: Option<DataFmt>,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
struct DataFmt {
    #[serde(default)]
    iqSwapSel: u32,
    #[serde(default = "non_interleaved")]
    chInterleave: u32,
}

fn non_interleaved() -> u32 {
    1
}

impl Mask {
    fn value(&self, path: &Path, at: &str) -> Result<u32, InputError> {
        match self {
            Mask::Number(n) => Ok(*n),
            Mask::Text(t) => {
                let digits = t.trim().trim_start_matches("0x").trim_start_matches("0X");
                u32::from_str_radix(digits, 16).map_err(|_| {
                    InputError::field(path, at.to_owned(), format!("`{t}` is not a hex mask"))
                })
            }
        }
    }
}

/// Parses a `.mmwave.json` (the bytes of `path`). `board` places the antennas; with `None`, a
/// four-device file is the MMWCAS-RF-EVM and a one-device file is an error asking for it.
///
/// # Errors
/// [`InputError`] naming the JSON path: a missing or malformed key, devices that disagree on
/// the profile or frame, a chirp that enables no TX or several, an unsupported ADC format.
pub fn parse(path: &Path, bytes: &[u8], board: Option<Board>) -> Result<CaptureConfig, InputError> {
    let file: File = parse_json(path, bytes)?;
    let mut devices = match file.mmWaveDevices {
        Devices::Many(v) => v,
        Devices::One(d) => vec![*d],
    };
    devices.sort_by_key(|d| d.mmWaveDeviceId);
    let board = match board {
        Some(b) => b,
        None if devices.len() == 4 => Board::MmwcasRfEvm,
        None => {
            return Err(InputError::file(
                path,
                format!(
                    "{} device(s): name the board with --board ({})",
                    devices.len(),
                    Board::NAMES.join(", ")
                ),
            ));
        }
    };
    if devices.len() != board.devices() {
        return Err(InputError::field(
            path,
            "mmWaveDevices",
            format!(
                "{} devices, but {board} has {}",
                devices.len(),
                board.devices()
            ),
        ));
    }
    let dev_at = |d: usize, k: &str| format!("mmWaveDevices[{d}].rfConfig.{k}");
    let first = &devices[0].rfConfig;
    let frame = &first.rlFrameCfg_t;
    if frame.chirpEndIdx < frame.chirpStartIdx {
        return Err(InputError::field(
            path,
            dev_at(0, "rlFrameCfg_t.chirpEndIdx"),
            "is before chirpStartIdx",
        ));
    }
    let mut antennas = Antennas::default();
    let mut masks = Vec::new();
    for (d, dev) in devices.iter().enumerate() {
        let rf = &dev.rfConfig;
        let fmt = &rf.rlAdcOutCfg_t.fmt;
        if fmt.b2AdcBits != 2 || !matches!(fmt.b2AdcOutFmt, 1 | 2) {
            return Err(InputError::field(
                path,
                dev_at(d, "rlAdcOutCfg_t.fmt"),
                "only 16-bit (b2AdcBits 2) complex (b2AdcOutFmt 1 or 2) samples are supported",
            ));
        }
        let same_frame = rf.rlFrameCfg_t.chirpStartIdx == frame.chirpStartIdx
            && rf.rlFrameCfg_t.chirpEndIdx == frame.chirpEndIdx
            && rf.rlFrameCfg_t.numLoops == frame.numLoops;
        if !same_frame {
            return Err(InputError::field(
                path,
                dev_at(d, "rlFrameCfg_t"),
                "differs from device 0's: the devices of a cascade share one frame",
            ));
        }
        let rx = rf
            .rlChanCfg_t
            .rxChannelEn
            .value(path, &dev_at(d, "rlChanCfg_t.rxChannelEn"))?;
        let tx = rf
            .rlChanCfg_t
            .txChannelEn
            .value(path, &dev_at(d, "rlChanCfg_t.txChannelEn"))?;
        for r in (0..4).filter(|r| rx >> r & 1 == 1) {
            antennas.rx.extend(board.rx(d, r));
        }
        masks.push(tx);
    }
    let mut profile_id = None;
    for c in frame.chirpStartIdx..=frame.chirpEndIdx {
        // The one device and TX that send chirp c.
        let mut sender = None;
        for (d, dev) in devices.iter().enumerate() {
            let Some((k, chirp)) = dev
                .rfConfig
                .rlChirps
                .iter()
                .enumerate()
                .find(|(_, e)| {
                    (e.rlChirpCfg_t.chirpStartIdx..=e.rlChirpCfg_t.chirpEndIdx).contains(&c)
                })
                .map(|(k, e)| (k, &e.rlChirpCfg_t))
            else {
                continue;
            };
            let at = dev_at(d, &format!("rlChirps[{k}].rlChirpCfg_t"));
            if [
                chirp.startFreqVar_MHz,
                chirp.freqSlopeVar_KHz_usec,
                chirp.idleTimeVar_usec,
                chirp.adcStartTimeVar_usec,
            ]
            .iter()
            .any(|&v| v != 0.0)
            {
                return Err(InputError::field(
                    path,
                    at,
                    "per-chirp variations are not supported: the chirps of a frame must be alike",
                ));
            }
            let tx = chirp.txEnable.value(path, &format!("{at}.txEnable"))?;
            if tx == 0 {
                continue;
            }
            if tx.count_ones() != 1 || tx & !masks[d] != 0 || sender.is_some() {
                return Err(InputError::field(
                    path,
                    format!("{at}.txEnable"),
                    format!(
                        "chirp {c}: exactly one enabled TX of one device must send each chirp (TDM)"
                    ),
                ));
            }
            if *profile_id.get_or_insert(chirp.profileId) != chirp.profileId {
                return Err(InputError::field(
                    path,
                    format!("{at}.profileId"),
                    "the frame's chirps use several profiles: not supported",
                ));
            }
            sender = Some((d, tx.trailing_zeros() as usize, at));
        }
        let Some((d, t, at)) = sender else {
            return Err(InputError::field(
                path,
                dev_at(0, "rlFrameCfg_t"),
                format!("chirp {c} of the frame is sent by no TX"),
            ));
        };
        let antenna = board.tx(d, t).ok_or_else(|| {
            InputError::field(
                path,
                format!("{at}.txEnable"),
                format!("TX{t} of device {d} does not exist on {board}"),
            )
        })?;
        let index = antennas.tx_index(antenna);
        antennas.order.push(index);
    }
    let pid = profile_id.unwrap_or(0);
    let profile = first
        .rlProfiles
        .iter()
        .map(|p| &p.rlProfileCfg_t)
        .find(|p| p.profileId == pid)
        .ok_or_else(|| {
            InputError::field(
                path,
                dev_at(0, "rlProfiles"),
                format!("profile {pid} is used but not defined"),
            )
        })?;
    let fmt = devices[0]
        .rawDataCaptureConfig
        .as_ref()
        .and_then(|r| r.rlDevDataFmtCfg_t.as_ref());
    if fmt.is_some_and(|f| f.chInterleave != 1) {
        return Err(InputError::field(
            path,
            "mmWaveDevices[0].rawDataCaptureConfig.rlDevDataFmtCfg_t.chInterleave",
            "only 1 (non-interleaved: chirp, RX, sample, as the DCA1000 records) is supported",
        ));
    }
    let iq_order = if fmt.is_some_and(|f| f.iqSwapSel == 1) {
        IqOrder::Qqii
    } else {
        IqOrder::Iiqq
    };
    let timing = Timing {
        start_ghz: profile.startFreqConst_GHz,
        idle_us: profile.idleTimeConst_usec,
        adc_start_us: profile.adcStartTimeConst_usec,
        ramp_end_us: profile.rampEndTime_usec,
        slope_mhz_per_us: profile.freqSlopeConst_MHz_usec,
        samples: profile.numAdcSamples,
        rate_ksps: profile.digOutSampleRate,
        loops: frame.numLoops,
        frames: frame.numFrames,
        period_ms: frame.framePeriodicity_msec,
    };
    let at = |what: &str| format!("mmWaveDevices[0].rfConfig.rlProfiles ({what})");
    capture_config(path, &at, timing, antennas, iq_order, board)
}
