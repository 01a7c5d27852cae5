//! Reading frames of DCA1000 samples from `radar.bin` or a bare capture.

use crate::error::InputError;
use metamoran_dsp::capture::{IqOrder, deinterleave_bytes};
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::fixed::CQ15;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// A capture file whose size has been checked against its configuration.
#[derive(Debug)]
pub struct RadarFile {
    path: PathBuf,
    config: RadarConfig,
    order: IqOrder,
    file: File,
    /// (loops held, loops configured) when the capture is shorter than one frame.
    loops_of_frame: Option<(u16, u16)>,
}

impl RadarFile {
    /// Opens `path` for `config`. With `config.frames == 0` the frame count is derived from the
    /// size, which must then be a whole number of frames; a capture shorter than one frame that
    /// holds whole loops (all TX slots of each) is read as one frame of those loops (see
    /// [`Self::loops_of_frame`]).
    ///
    /// # Errors
    /// [`InputError`] if the file cannot be read or its size does not match the configuration.
    pub fn open(path: &Path, mut config: RadarConfig, order: IqOrder) -> Result<Self, InputError> {
        let (file, size) = crate::limits::open_regular(path, u64::MAX)?;
        let frame_bytes = (config.samples_per_frame() * 4) as u64;
        let describe = |c: &RadarConfig| {
            format!(
                "chirps_per_tx {} × len(tx_order) {} × len(rx_positions) {} × adc_samples {} × 4 bytes",
                c.chirps_per_tx,
                c.slots(),
                c.rx_count(),
                c.adc_samples
            )
        };
        let loop_bytes = frame_bytes / u64::from(config.chirps_per_tx.max(1));
        let mut loops_of_frame = None;
        if config.frames == 0 && size > 0 && size < frame_bytes && size % loop_bytes == 0 {
            // A capture cut short of its first frame (a pcap of the first packets): the loops
            // it holds are one frame.
            loops_of_frame = Some(((size / loop_bytes) as u16, config.chirps_per_tx));
            config.chirps_per_tx = (size / loop_bytes) as u16;
            config.frames = 1;
        } else if config.frames == 0 {
            if size == 0 || size % frame_bytes != 0 {
                return Err(InputError::file(
                    path,
                    format!(
                        "{size} bytes is not a whole number of {frame_bytes}-byte frames ({}); \
                         the capture is truncated or the config does not match it",
                        describe(&config)
                    ),
                ));
            }
            config.frames = (size / frame_bytes) as u32;
        } else if size != frame_bytes * config.frames as u64 {
            return Err(InputError::file(
                path,
                format!(
                    "{size} bytes, but frames {} × {} = {} bytes are expected; the capture is \
                     truncated or scene.toml's [radar] table does not match it",
                    config.frames,
                    describe(&config),
                    frame_bytes * config.frames as u64
                ),
            ));
        }
        Ok(Self {
            path: path.to_owned(),
            config,
            order,
            file,
            loops_of_frame,
        })
    }

    /// `(loops held, loops per frame configured)` when the capture was cut short of one frame
    /// and is read as one frame of the loops it holds.
    pub fn loops_of_frame(&self) -> Option<(u16, u16)> {
        self.loops_of_frame
    }

    /// The configuration (with `frames` filled in).
    pub fn config(&self) -> &RadarConfig {
        &self.config
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Reads frame `frame` into `out` (resized to one frame): `[chirp][rx][sample]`, chirps in
    /// loop-major TDM order.
    ///
    /// # Errors
    /// [`InputError`] if the frame does not exist or the file cannot be read.
    pub fn read_frame(&mut self, frame: u32, out: &mut Vec<CQ15>) -> Result<(), InputError> {
        if frame >= self.config.frames {
            return Err(InputError::file(
                &self.path,
                format!(
                    "frame {frame} requested; the capture has {}",
                    self.config.frames
                ),
            ));
        }
        let n = self.config.samples_per_frame();
        let mut bytes = vec![0u8; n * 4];
        self.file
            .seek(SeekFrom::Start(frame as u64 * bytes.len() as u64))
            .and_then(|_| self.file.read_exact(&mut bytes))
            .map_err(|e| InputError::io(&self.path, e))?;
        out.resize(n, CQ15::default());
        deinterleave_bytes(&bytes, self.order, out)
            .map_err(|e| InputError::file(&self.path, e.to_string()))
    }
}
