//! The MMWCAS-RF-EVM's captures as mmWave Studio records them through the TDA2 board: four
//! data files, one per AWR2243 (`master_NNNN_data.bin`, `slave1_…`, `slave2_…`, `slave3_…`),
//! each with an index file (`…_idx.bin`). TI's reader (`read_ADC_bin_TDA2_separateFiles`,
//! `readBinFile`) lays a device's frame out as
//!
//! ```text
//! for loop, for chirp of the loop, for sample, for RX 0..4:  I (int16 LE), Q (int16 LE)
//! ```
//!
//! and stacks the devices' receivers master first. This module turns those bytes into our frame
//! (`[chirp][rx][sample]`, 16 RX device by device) and back, and reads and writes the index
//! files' header (`struct Info { tag, version, flags, numIdx, dataFileSize }`).

use crate::error::InputError;
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::fixed::CQ15;
use std::path::{Path, PathBuf};

/// The devices, in the order their receivers are stacked.
pub const DEVICES: [&str; 4] = ["master", "slave1", "slave2", "slave3"];
/// Receivers per device.
pub const RX_PER_DEVICE: usize = 4;
/// Bytes of an index file's header.
pub const INDEX_HEADER: usize = 24;
/// Bytes of one frame's entry in an index file.
pub const INDEX_ENTRY: usize = 48;

/// The four data files of the capture whose master file is `master` (`master_NNNN_data.bin`).
///
/// # Errors
/// [`InputError`] if `master` is not named like a master data file.
pub fn data_files(master: &Path) -> Result<[PathBuf; 4], InputError> {
    let name = master.file_name().and_then(|n| n.to_str()).unwrap_or("");
    let rest = name
        .strip_prefix("master_")
        .filter(|r| r.ends_with("_data.bin"))
        .ok_or_else(|| {
            InputError::file(
                master,
                "is not an MMWCAS master data file: name it master_NNNN_data.bin, with the \
                 slave1/2/3 files beside it",
            )
        })?;
    let dir = master.parent().unwrap_or(Path::new(""));
    Ok(DEVICES.map(|d| dir.join(format!("{d}_{rest}"))))
}

/// The index file of data file `data` (`…_data.bin` → `…_idx.bin`).
pub fn index_file(data: &Path) -> PathBuf {
    let name = data.file_name().and_then(|n| n.to_str()).unwrap_or("");
    data.with_file_name(name.replace("_data.bin", "_idx.bin"))
}

/// What an index file's header says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Index {
    /// Frames recorded.
    pub frames: u32,
    /// Bytes of data written for them.
    pub data_bytes: u64,
}

/// Reads the header of index file `path`.
///
/// # Errors
/// [`InputError`] naming the file if it is unreadable or shorter than its header.
pub fn read_index(path: &Path) -> Result<Index, InputError> {
    let bytes = crate::error::read(path, crate::limits::MAX_TRUTH_BYTES)?;
    let header = bytes.get(..INDEX_HEADER).ok_or_else(|| {
        InputError::file(
            path,
            format!(
                "{} bytes: an index file starts with a 24-byte header",
                bytes.len()
            ),
        )
    })?;
    let u32_at =
        |i: usize| u32::from_le_bytes([header[i], header[i + 1], header[i + 2], header[i + 3]]);
    let mut size = [0u8; 8];
    size.copy_from_slice(&header[16..24]);
    Ok(Index {
        frames: u32_at(12),
        data_bytes: u64::from_le_bytes(size),
    })
}

/// The bytes of an index file for `frames` frames of `frame_bytes` each: the header and one
/// entry per frame (its size and offset; tag, version and timestamps 0).
pub fn index_bytes(frames: u32, frame_bytes: u64) -> Vec<u8> {
    let mut out = Vec::with_capacity(INDEX_HEADER + frames as usize * INDEX_ENTRY);
    for w in [0u32, 0, 0, frames] {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out.extend_from_slice(&(u64::from(frames) * frame_bytes).to_le_bytes());
    for f in 0..u64::from(frames) {
        let mut entry = [0u8; INDEX_ENTRY];
        entry[28..32].copy_from_slice(&(frame_bytes as u32).to_le_bytes());
        entry[40..48].copy_from_slice(&(f * frame_bytes).to_le_bytes());
        out.extend_from_slice(&entry);
    }
    out
}

/// Bytes of one device's frame for `config` (its 4 receivers).
pub fn device_frame_bytes(config: &RadarConfig) -> u64 {
    config.chirps_per_frame() as u64 * RX_PER_DEVICE as u64 * u64::from(config.adc_samples) * 4
}

/// Whether `config` is a whole cascade: 16 receivers, 4 per device.
///
/// # Errors
/// [`InputError`] naming `path` (the config's file) otherwise.
pub fn check(path: &Path, config: &RadarConfig) -> Result<(), InputError> {
    if config.rx_count() == DEVICES.len() * RX_PER_DEVICE {
        Ok(())
    } else {
        Err(InputError::field(
            path,
            "radar.rx_positions",
            format!(
                "has {} receivers; an MMWCAS capture holds 16 (4 per device, master first)",
                config.rx_count()
            ),
        ))
    }
}

/// Sample `(chirp, rx of the device, n)` of a device frame: its byte index.
fn at(config: &RadarConfig, chirp: usize, rx: usize, n: usize) -> usize {
    ((chirp * usize::from(config.adc_samples) + n) * RX_PER_DEVICE + rx) * 4
}

/// Our frame (`[chirp][rx][sample]`, 16 RX) from the four devices' frames. O(frame).
pub fn to_frame(config: &RadarConfig, devices: &[Vec<u8>; 4], out: &mut Vec<CQ15>) {
    let (n, rx) = (usize::from(config.adc_samples), config.rx_count());
    out.clear();
    out.resize(config.chirps_per_frame() * rx * n, CQ15::default());
    for chirp in 0..config.chirps_per_frame() {
        for r in 0..rx {
            let (d, local) = (r / RX_PER_DEVICE, r % RX_PER_DEVICE);
            for s in 0..n {
                let i = at(config, chirp, local, s);
                let b = &devices[d][i..i + 4];
                out[(chirp * rx + r) * n + s] = CQ15::from_raw(
                    i16::from_le_bytes([b[0], b[1]]),
                    i16::from_le_bytes([b[2], b[3]]),
                );
            }
        }
    }
}

/// The four devices' frames of our frame `frame` (`[chirp][rx][sample]`, 16 RX). O(frame).
pub fn to_devices(config: &RadarConfig, frame: &[CQ15]) -> [Vec<u8>; 4] {
    let (n, rx) = (usize::from(config.adc_samples), config.rx_count());
    let mut out: [Vec<u8>; 4] = Default::default();
    for o in &mut out {
        o.resize(device_frame_bytes(config) as usize, 0);
    }
    for chirp in 0..config.chirps_per_frame() {
        for r in 0..rx.min(16) {
            let (d, local) = (r / RX_PER_DEVICE, r % RX_PER_DEVICE);
            for s in 0..n {
                let z = frame[(chirp * rx + r) * n + s];
                let i = at(config, chirp, local, s);
                out[d][i..i + 2].copy_from_slice(&z.re.0.to_le_bytes());
                out[d][i + 2..i + 4].copy_from_slice(&z.im.0.to_le_bytes());
            }
        }
    }
    out
}
