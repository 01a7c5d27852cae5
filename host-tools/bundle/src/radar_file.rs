//! Reading frames of samples from `radar.bin` or a bare capture (the DCA1000's one file), or
//! from an MMWCAS cascade's four device files ([`crate::mmwcas`]).

use crate::error::InputError;
use metamoran_dsp::capture::{IqOrder, deinterleave_bytes};
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::range::calibration::{AppliedCalibration, Calibration};
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
    /// The slaves' data files of an MMWCAS capture (`file` is the master's).
    slaves: Option<[File; 3]>,
    /// (loops held, loops configured) when the capture is shorter than one frame.
    loops_of_frame: Option<(u16, u16)>,
    /// The channel calibration [`Self::read_frame`] applies.
    calibration: Option<AppliedCalibration>,
    /// Frames a live stream did not deliver whole, sorted.
    incomplete: Vec<u32>,
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
            slaves: None,
            loops_of_frame,
            calibration: None,
            incomplete: Vec::new(),
        })
    }

    /// Opens the MMWCAS capture whose master data file is `master` (the slaves' files and all
    /// four index files beside it) for `config` (16 RX). Every index file must give the same
    /// frame count, every data file hold that many frames, and `config.frames` (when not 0)
    /// agree with it.
    ///
    /// # Errors
    /// [`InputError`] naming the file that is missing, short or disagrees.
    pub fn open_mmwcas(master: &Path, mut config: RadarConfig) -> Result<Self, InputError> {
        crate::mmwcas::check(master, &config)?;
        let paths = crate::mmwcas::data_files(master)?;
        let frame_bytes = crate::mmwcas::device_frame_bytes(&config);
        let mut frames = None;
        let mut files = Vec::with_capacity(4);
        for p in &paths {
            let idx_path = crate::mmwcas::index_file(p);
            let idx = crate::mmwcas::read_index(&idx_path)?;
            if *frames.get_or_insert(idx.frames) != idx.frames {
                return Err(InputError::field(
                    &idx_path,
                    "numIdx",
                    format!(
                        "{} frames, but the master's index says {}",
                        idx.frames,
                        frames.unwrap_or(0)
                    ),
                ));
            }
            let (file, size) = crate::limits::open_regular(p, u64::MAX)?;
            let need = u64::from(idx.frames) * frame_bytes;
            if size < need {
                return Err(InputError::file(
                    p,
                    format!(
                        "{size} bytes, but {} frames of {frame_bytes} bytes ({} loops × {} chirps × 4 RX × {} samples × 4 bytes) are indexed",
                        idx.frames,
                        config.chirps_per_tx,
                        config.slots(),
                        config.adc_samples
                    ),
                ));
            }
            files.push(file);
        }
        let frames = frames.unwrap_or(0);
        if config.frames != 0 && config.frames != frames {
            return Err(InputError::file(
                master,
                format!(
                    "the index files record {frames} frames, the config says {}",
                    config.frames
                ),
            ));
        }
        config.frames = frames;
        let mut files = files.into_iter();
        let (Some(master_file), Some(a), Some(b), Some(c)) =
            (files.next(), files.next(), files.next(), files.next())
        else {
            return Err(InputError::file(master, "four device files are needed"));
        };
        Ok(Self {
            path: master.to_owned(),
            config,
            order: IqOrder::Iiqq,
            file: master_file,
            slaves: Some([a, b, c]),
            loops_of_frame: None,
            calibration: None,
            incomplete: Vec::new(),
        })
    }

    /// Opens the capture of `layout` at `path`: [`Self::open`] or [`Self::open_mmwcas`].
    ///
    /// # Errors
    /// As those.
    pub fn open_layout(
        path: &Path,
        config: RadarConfig,
        order: IqOrder,
        layout: crate::AdcLayout,
    ) -> Result<Self, InputError> {
        match layout {
            crate::AdcLayout::Dca1000 => Self::open(path, config, order),
            crate::AdcLayout::Mmwcas => Self::open_mmwcas(path, config),
        }
    }

    /// Writes every frame in the DCA1000 layout (`radar.bin`'s): what a reader of one file, such
    /// as the module under QEMU, takes. O(capture).
    ///
    /// # Errors
    /// [`InputError`] if a frame cannot be read or `out` fails.
    pub fn write_dca1000(&mut self, out: &mut impl std::io::Write) -> Result<(), InputError> {
        let mut frame = Vec::new();
        for f in 0..self.config.frames {
            self.read_raw_frame(f, &mut frame)?;
            let mut bytes = Vec::with_capacity(frame.len() * 4);
            for pair in frame.chunks(2) {
                let (a, b) = (pair[0], pair.get(1).copied().unwrap_or_default());
                for v in [a.re.0, b.re.0, a.im.0, b.im.0] {
                    bytes.extend_from_slice(&v.to_le_bytes());
                }
            }
            out.write_all(&bytes)
                .map_err(|e| InputError::write(&self.path, e))?;
        }
        Ok(())
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

    /// Applies `calibration` (for this capture's board) in every later [`Self::read_frame`].
    pub fn calibrate(&mut self, calibration: &Calibration) {
        self.calibration = Some(calibration.normalized());
    }

    /// Marks `frames` as not delivered whole (a live stream lost bytes of them or ended before
    /// them): [`Self::read_frame`] then refuses them.
    pub fn mark_incomplete(&mut self, frames: &[u32]) {
        self.incomplete.extend_from_slice(frames);
        self.incomplete.sort_unstable();
        self.incomplete.dedup();
    }

    /// Whether frames are read calibrated.
    pub fn is_calibrated(&self) -> bool {
        self.calibration.is_some()
    }

    /// The calibration [`Self::read_frame`] applies, in Q15 form (what the module is sent).
    pub fn calibration(&self) -> Option<&AppliedCalibration> {
        self.calibration.as_ref()
    }

    /// Reads frame `frame` into `out` (resized to one frame): `[chirp][rx][sample]`, chirps in
    /// loop-major TDM order, calibrated if [`Self::calibrate`] was called (the range stage's
    /// first step, [`metamoran_dsp::range::calibration`]).
    ///
    /// # Errors
    /// [`InputError`] if the frame does not exist or the file cannot be read.
    pub fn read_frame(&mut self, frame: u32, out: &mut Vec<CQ15>) -> Result<(), InputError> {
        self.read_raw_frame(frame, out)?;
        let Some(cal) = &self.calibration else {
            return Ok(());
        };
        let (n, rx) = (self.config.adc_samples as usize, self.config.rx_count());
        let mut row = vec![CQ15::default(); n];
        for (i, chirp) in out.chunks_exact_mut(n).enumerate() {
            let (c, r) = (i / rx, i % rx);
            let tx = self.config.tx_order[c % self.config.slots()] as usize;
            cal.apply(tx, r, chirp, &mut row)
                .map_err(|e| InputError::file(&self.path, e.to_string()))?;
            chirp.copy_from_slice(&row);
        }
        Ok(())
    }

    /// [`Self::read_frame`] without the calibration: the samples as recorded.
    ///
    /// # Errors
    /// As [`Self::read_frame`].
    pub fn read_raw_frame(&mut self, frame: u32, out: &mut Vec<CQ15>) -> Result<(), InputError> {
        if frame >= self.config.frames {
            return Err(InputError::file(
                &self.path,
                format!(
                    "frame {frame} requested; the capture has {}",
                    self.config.frames
                ),
            ));
        }
        if self.incomplete.binary_search(&frame).is_ok() {
            return Err(InputError::file(
                &self.path,
                format!(
                    "frame {frame} did not arrive whole from the DCA1000 (packets lost or the \
                     stream ended first); it is skipped, never processed as if whole"
                ),
            ));
        }
        if let Some(slaves) = self.slaves.as_mut() {
            let bytes = crate::mmwcas::device_frame_bytes(&self.config);
            let mut devices: [Vec<u8>; 4] = Default::default();
            let files = std::iter::once(&mut self.file).chain(slaves.iter_mut());
            for (buf, file) in devices.iter_mut().zip(files) {
                buf.resize(bytes as usize, 0);
                file.seek(SeekFrom::Start(u64::from(frame) * bytes))
                    .and_then(|_| file.read_exact(buf))
                    .map_err(|e| InputError::io(&self.path, e))?;
            }
            crate::mmwcas::to_frame(&self.config, &devices, out);
            return Ok(());
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
