//! Scene bundles (`shared/spec/bundle.md`, version 1): reading and checking every field.
//!
//! [`Bundle::open`] checks `scene.toml`, the size of `radar.bin`, every frame's camera files
//! (PNG headers, instance lists) and `truth.json` when present, so a bad bundle fails before any
//! processing with an error naming the file and the field. Pixels and samples are then read per
//! frame.
//!
//! This crate is the bottom of the host's data flow: bundle → process → (map, operator) → the
//! `metamoran` binary. It also holds what every later stage shares about a bundle: the camera
//! geometry ([`geometry`]), the bare-capture reader ([`capture`]), the ego pose ([`pose`]) and
//! the lidar truth files ([`lidar`]), and the typed input errors ([`error`]).

pub mod calibration;
pub mod capture;
pub mod error;
pub mod fields;
pub mod geometry;
pub mod lidar;
pub mod limits;
pub mod mmwcas;
pub mod pose;
pub mod ti;

mod camera;
pub mod camera_models;
mod radar_file;
mod scene;
mod truth;

pub use camera::{
    CLUTTER_CLASSES, CameraFrame, CameraPaths, Instance, OBJECTS_OF_INTEREST, parse_instances,
    parse_png16, read_instances, read_png16,
};
pub use camera_models::{CameraModels, ImageProducts};
pub use radar_file::RadarFile;
pub use scene::{ADC_LAYOUT, AdcLayout, CameraConfig, FORMAT, FramesField, Scene, parse_radar};
pub use truth::{Ego, Truth, TruthFrame, TruthObject};

use crate::error::InputError;
use metamoran_dsp::capture::IqOrder;
use metamoran_dsp::fixed::CQ15;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// How to read a bundle.
#[derive(Clone, Debug, Default)]
pub struct OpenOptions {
    /// I/Q order of `radar.bin` (the format says IIQQ; QQII reads devices with sample swap set).
    pub iq_order: IqOrder,
    /// Models that compute the mask and instances, or the depth, from `camera/F_image.png`
    /// instead of reading them from the bundle.
    pub camera_models: Option<Arc<CameraModels>>,
    /// Radar samples from elsewhere than `adc_file`: a live stream recorded for this bundle.
    pub capture: Option<LiveCapture>,
}

/// A capture that stands in for a bundle's `adc_file`: a live DCA1000 stream recorded in
/// `radar.bin`'s layout for the bundle's `[radar]` table and frame count, with the frames that
/// did not arrive whole. The camera products still come from the bundle.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LiveCapture {
    /// The recorded samples (DCA1000 layout; missing bytes zero).
    pub file: PathBuf,
    /// Frames that did not arrive whole: reading one is an error, so it is skipped, never
    /// processed as if whole.
    pub incomplete: Vec<u32>,
}

impl OpenOptions {
    /// Options with I/Q order `iq_order` and the camera products read from the bundle.
    pub fn iq(iq_order: IqOrder) -> Self {
        Self {
            iq_order,
            ..Self::default()
        }
    }
}

/// An opened, checked scene bundle.
#[derive(Debug)]
pub struct Bundle {
    /// The canonical bundle folder, which holds every file read.
    root: PathBuf,
    dir: PathBuf,
    /// The parsed `scene.toml`.
    pub scene: Scene,
    /// Ground truth, if the bundle has it.
    pub truth: Option<Truth>,
    instances: Vec<Vec<Instance>>,
    radar: RadarFile,
    models: Option<Arc<CameraModels>>,
}

impl Bundle {
    /// Opens the bundle in folder `dir` and checks it.
    ///
    /// # Errors
    /// [`InputError`] naming the first file and field that break the format.
    ///
    /// # Example
    /// A simulated parking lot (xWR18xx-like radar): its frames, their camera products and
    /// their radar samples.
    /// ```
    /// use metamoran_bundle::{Bundle, OpenOptions};
    /// use metamoran_sim::{layout::Preset, radar::RadarKind, simulate};
    ///
    /// let dir = tempfile::tempdir()?;
    /// let written = simulate(Preset::ParkingLot, RadarKind::Xwr18xx, 7, 1, dir.path(), &|| ())?;
    /// let mut bundle = Bundle::open(&written[0], OpenOptions::default())?;
    /// assert!(bundle.frames() >= 1);
    /// let camera = bundle.camera_frame(0)?;
    /// assert!(!camera.instances.is_empty(), "the scene has objects of interest");
    /// let mut samples = Vec::new();
    /// bundle.read_radar_frame(0, &mut samples)?;
    /// assert_eq!(samples.len(), bundle.scene.radar.samples_per_frame());
    ///
    /// std::fs::write(written[0].join("radar.bin"), b"too short")?;
    /// let err = Bundle::open(&written[0], OpenOptions::default()).unwrap_err();
    /// assert!(err.to_string().contains("radar.bin"), "{err}");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn open(dir: &Path, options: OpenOptions) -> Result<Self, InputError> {
        if !dir.is_dir() {
            return Err(InputError::file(
                dir,
                "is not a folder; give the bundle folder that holds scene.toml",
            ));
        }
        let root = dir.canonicalize().map_err(|e| InputError::io(dir, e))?;
        let scene_file = dir.join("scene.toml");
        limits::confined(&root, &scene_file)?;
        let mut scene = Scene::read(&scene_file)?;
        let mut radar = match &options.capture {
            None => {
                limits::confined(&root, &scene.adc_file)?;
                RadarFile::open_layout(
                    &scene.adc_file,
                    scene.radar.clone(),
                    options.iq_order,
                    scene.layout,
                )?
            }
            Some(live) => {
                if scene.layout != AdcLayout::Dca1000 {
                    return Err(InputError::file(
                        &scene_file,
                        "[radar] adc_layout is an MMWCAS cascade's four device files; a DCA1000 \
                         streams one device: process the cascade's recorded files instead",
                    ));
                }
                let mut file = RadarFile::open(&live.file, scene.radar.clone(), options.iq_order)?;
                file.mark_incomplete(&live.incomplete);
                // Every later reader of the samples (the module under QEMU) takes this file.
                scene.adc_file.clone_from(&live.file);
                file
            }
        };
        if let Some(path) = &scene.calibration_file {
            limits::confined(&root, path)?;
            let file = calibration::CalibrationFile::read(path)?;
            radar.calibrate(&file.for_config(path, &scene.radar)?);
        }
        let (w, h) = (scene.camera.width, scene.camera.height);
        let models = options.camera_models.as_deref();
        let segments = models.is_some_and(CameraModels::segments);
        let estimates_depth = models.is_some_and(CameraModels::estimates_depth);
        let mut instances = Vec::new();
        for f in 0..scene.radar.frames {
            let p = CameraPaths::new(dir, f);
            p.confined(&root, segments, estimates_depth)?;
            if (segments || estimates_depth) && !p.image.is_file() {
                return Err(InputError::file(
                    &p.image,
                    "is missing; the camera models compute the products from it (or drop \
                     --segmenter/--depth-model to read the bundle's own)",
                ));
            }
            if segments {
                instances.push(Vec::new());
            } else {
                camera::check_png16_header(&p.mask, w, h)?;
                instances.push(read_instances(&p.instances)?);
            }
            if !estimates_depth {
                camera::check_png16_header(&p.depth, w, h)?;
            }
        }
        let truth_path = dir.join("truth.json");
        let truth = if truth_path.exists() {
            limits::confined(&root, &truth_path)?;
            Some(Truth::read(&truth_path, scene.radar.frames)?)
        } else {
            None
        };
        Ok(Self {
            root,
            dir: dir.to_owned(),
            scene,
            truth,
            instances,
            radar,
            models: options.camera_models,
        })
    }

    /// The bundle folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Frames in the capture.
    pub fn frames(&self) -> u32 {
        self.scene.radar.frames
    }

    /// The instances of frame `frame` as `F_instances.json` lists them (empty past the last
    /// frame, and where a segmenter makes them: see [`Bundle::camera_frame`]).
    pub fn instances(&self, frame: u32) -> &[Instance] {
        self.instances
            .get(frame as usize)
            .map_or(&[], Vec::as_slice)
    }

    /// The bundle's radar capture (calibrated if the bundle names a calibration), for readers
    /// that need nothing else.
    pub fn into_radar(self) -> RadarFile {
        self.radar
    }

    /// Reads the radar samples of frame `frame`; see [`RadarFile::read_frame`].
    ///
    /// # Errors
    /// [`InputError`] if the frame cannot be read.
    pub fn read_radar_frame(&mut self, frame: u32, out: &mut Vec<CQ15>) -> Result<(), InputError> {
        self.radar.read_frame(frame, out)
    }

    /// Reads frame `frame`'s samples as recorded (the calibration not applied); see
    /// [`RadarFile::read_raw_frame`].
    ///
    /// # Errors
    /// [`InputError`] if the frame cannot be read.
    pub fn read_raw_radar_frame(
        &mut self,
        frame: u32,
        out: &mut Vec<CQ15>,
    ) -> Result<(), InputError> {
        self.radar.read_raw_frame(frame, out)
    }

    /// The channel calibration the radar frames are read with, if the bundle names one.
    pub fn calibration(&self) -> Option<&metamoran_dsp::range::calibration::AppliedCalibration> {
        self.radar.calibration()
    }

    /// Decodes the camera products of frame `frame`, checking that every mask id is listed;
    /// products the camera models make come from `F_image.png` instead.
    ///
    /// # Errors
    /// [`InputError`] naming the file (or the model that failed on it).
    pub fn camera_frame(&self, frame: u32) -> Result<CameraFrame, InputError> {
        let p = CameraPaths::new(&self.dir, frame);
        let models = self.models.as_deref();
        p.confined(
            &self.root,
            models.is_some_and(CameraModels::segments),
            models.is_some_and(CameraModels::estimates_depth),
        )?;
        let (w, h) = (self.scene.camera.width, self.scene.camera.height);
        let computed = match &self.models {
            Some(m) => m.run(&p.image, w, h)?,
            None => ImageProducts::default(),
        };
        let (mask, instances) = match computed.segmentation {
            Some(s) => s,
            None => (read_png16(&p.mask, w, h)?, self.instances(frame).to_vec()),
        };
        let depth = match computed.depth {
            Some(d) => d,
            None => read_png16(&p.depth, w, h)?,
        };
        if let Some(id) = mask
            .iter()
            .find(|&&id| id != 0 && !instances.iter().any(|i| i.id == id))
        {
            return Err(InputError::file(
                &p.mask,
                format!(
                    "holds instance id {id}, which {} does not list",
                    p.instances.display()
                ),
            ));
        }
        Ok(CameraFrame {
            width: w,
            height: h,
            mask,
            depth,
            instances,
        })
    }
}
