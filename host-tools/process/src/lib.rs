//! Frame processing: per-frame estimates of each object of interest's depth, azimuth and
//! depth-image points, in the JSON shape of `shared/spec/cli.md`.
//!
//! This crate is the host's middle stage (bundle → **process** → map, operator → binary). The
//! radar side runs the module's `dsp` code ([`frame`], and the module itself through
//! `metamoran-edge`); the camera side reads the bundle's mask and monocular depth
//! ([`camera_points`]). The three methods are [`naive`], [`monocular`] and [`metamoran`];
//! [`inspect`] shows what the search saw, [`eval`] scores methods against the truth and
//! [`summary`] describes a bare capture.

pub mod calibrate;
pub mod camera_points;
pub mod contest;
mod error;
pub mod eval;
pub mod frame;
pub mod ground;
pub mod inspect;
pub mod lead;
pub mod metamoran;
pub mod monocular;
pub mod naive;
pub mod summary;
pub mod trust;

pub use error::ProcessError;

use crate::frame::{FrameOptions, FrameProcessor};
use camera_points::{CameraObject, objects_of_interest};
use metamoran_bundle::geometry::{CameraModel, Point};
use metamoran_bundle::{Bundle, OpenOptions};
use metamoran_dsp::pipeline::ObjectHint;
use metamoran_dsp::window::WindowKind;
use metamoran_edge::link::{EdgeLog, QemuEdge};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// A processing method.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Camera-guided shape correlation with clutter cancellation, then depth imaging.
    #[default]
    Metamoran,
    /// Strongest range–azimuth reflector inside the mask's azimuth span.
    Naive,
    /// The closest masked monocular depth point.
    Monocular,
}

impl Mode {
    /// The name used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Metamoran => "metamoran",
            Mode::Naive => "naive",
            Mode::Monocular => "monocular",
        }
    }
}

/// The widest azimuth a forward-looking array sees, degrees: past it the object is behind
/// the radar.
pub const MAX_AZIMUTH_DEG: f64 = 90.0;

/// One object's estimate (cli.md).
#[derive(Clone, Debug, Serialize)]
pub struct ObjectEstimate {
    /// Instance id.
    pub instance: u16,
    /// Class word.
    pub class: String,
    /// Whether the method found something it trusts.
    pub detected: bool,
    /// Range of the object's closest point, m (`null` when not detected).
    pub depth_m: Option<f64>,
    /// Azimuth, degrees (`null` when unknown).
    pub azimuth_deg: Option<f64>,
    /// Radial velocity, m/s (positive away), where the method measured one (a mover the
    /// Doppler path found); not part of cli.md's JSON.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radial_velocity_mps: Option<f64>,
    /// Depth image as points in the radar frame, m.
    pub points: Vec<[f64; 3]>,
    /// The module's confidence (dB of the search peak over its floor) where the method has one;
    /// not part of cli.md's JSON.
    #[serde(skip)]
    pub confidence_db: Option<f64>,
    /// Probability that `depth_m` (or, when not detected, the best candidate) is within 1 m of
    /// the truth, where the method computes one (the trust test of [`trust`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub confidence: Option<f64>,
    /// What the trust test saw and chose, for `eval`; not part of the JSON.
    #[serde(skip)]
    pub evidence: Option<Box<(trust::Evidence, Option<trust::Verdict>)>>,
}

impl ObjectEstimate {
    /// A detection at `depth` (m) and `azimuth` (rad) with its points.
    pub fn found(obj: &CameraObject, depth: f64, azimuth: Option<f64>, points: Vec<Point>) -> Self {
        let mm = |v: f64| (v * 1000.0).round() / 1000.0;
        Self {
            instance: obj.instance,
            class: obj.class.clone(),
            detected: true,
            depth_m: Some(mm(depth)),
            azimuth_deg: azimuth.map(|a| (a.to_degrees() * 100.0).round() / 100.0),
            radial_velocity_mps: None,
            points: points.iter().map(|p| [mm(p.x), mm(p.y), mm(p.z)]).collect(),
            confidence_db: None,
            confidence: None,
            evidence: None,
        }
    }

    /// Withdraws a detection the radar cannot have made: a depth that is not finite or not
    /// below `max_range_m` (a saturated conversion), or an azimuth outside ±90° (behind the
    /// array). It becomes "not detected" with confidence 0, as cli.md's `detected: false`.
    pub fn keep_in_view(&mut self, max_range_m: f64) {
        let depth_ok = self
            .depth_m
            .is_none_or(|d| d.is_finite() && (0.0..max_range_m).contains(&d));
        let azimuth_ok = self
            .azimuth_deg
            .is_none_or(|a| a.is_finite() && a.abs() <= MAX_AZIMUTH_DEG);
        if self.detected && !(depth_ok && azimuth_ok) {
            self.detected = false;
            self.depth_m = None;
            self.azimuth_deg = None;
            self.radial_velocity_mps = None;
            self.points.clear();
            self.confidence = Some(0.0);
        }
    }

    /// Nothing trusted for this object.
    pub fn missed(obj: &CameraObject) -> Self {
        Self::unprocessed(obj.instance, &obj.class)
    }

    /// Nothing known about instance `instance` of class `class` (its frame was not processed).
    pub fn unprocessed(instance: u16, class: &str) -> Self {
        Self {
            instance,
            class: class.to_owned(),
            detected: false,
            depth_m: None,
            azimuth_deg: None,
            radial_velocity_mps: None,
            points: Vec::new(),
            confidence_db: None,
            confidence: None,
            evidence: None,
        }
    }
}

/// One frame's estimates.
#[derive(Clone, Debug, Serialize)]
pub struct FrameResult {
    /// Frame number.
    pub frame: u32,
    /// One entry per object-of-interest instance, in id order.
    pub objects: Vec<ObjectEstimate>,
    /// Why the frame could not be processed (a corrupt file, a bad sample count…): its
    /// objects are then all "not detected". Not part of cli.md's JSON; absent when the frame
    /// was processed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

impl FrameResult {
    /// A frame processed into `objects`.
    pub fn new(frame: u32, objects: Vec<ObjectEstimate>) -> Self {
        Self {
            frame,
            objects,
            error: None,
        }
    }
}

/// The whole output of `process --json`.
#[derive(Clone, Debug, Serialize)]
pub struct ProcessOutput {
    /// The mode that produced it.
    pub mode: Mode,
    /// Per frame.
    pub frames: Vec<FrameResult>,
    /// Why the run stopped before the last frame (the module under QEMU failed, or the
    /// consumer of the frames did); the frames before it are kept. Not part of cli.md's JSON.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped: Option<String>,
}

impl ProcessOutput {
    /// The frames that could not be processed.
    pub fn skipped(&self) -> impl Iterator<Item = &FrameResult> {
        self.frames.iter().filter(|f| f.error.is_some())
    }

    /// What went wrong, for stderr: the skipped frames and why the run stopped; `None` when
    /// every frame was processed.
    pub fn faults(&self) -> Option<String> {
        let mut lines: Vec<String> = self
            .skipped()
            .map(|f| {
                format!(
                    "frame {} skipped: {}",
                    f.frame,
                    f.error.as_deref().unwrap_or("")
                )
            })
            .collect();
        if let Some(why) = &self.stopped {
            lines.push(format!(
                "stopped after {} frame(s): {why}",
                self.frames.len()
            ));
        }
        (!lines.is_empty()).then(|| lines.join("\n"))
    }
}

/// Where the module's share of [`Mode::Metamoran`] runs. Both give the same JSON.
#[derive(Clone, Default)]
pub enum Runner {
    /// The `dsp` pipeline called in this process.
    #[default]
    InProcess,
    /// The firmware under QEMU, over the telemetry link (`metamoran_edge::link`).
    Qemu {
        /// The firmware's Cargo workspace (`firmware/` of a checkout), built for the run.
        firmware: PathBuf,
        /// The module's device key file; the firmware is built with it.
        key_file: PathBuf,
    },
}

/// How to process a bundle.
#[derive(Clone, Default)]
pub struct ProcessOptions {
    /// The method.
    pub mode: Mode,
    /// How to read the bundle.
    pub open: OpenOptions,
    /// Where the module runs (with [`Mode::Metamoran`]).
    pub runner: Runner,
}

impl ProcessOptions {
    /// `mode` in this process, the bundle read as it is.
    pub fn mode(mode: Mode) -> Self {
        Self {
            mode,
            ..Self::default()
        }
    }
}

/// Processes every frame of the bundle in `dir`.
///
/// # Errors
/// [`ProcessError`] naming the file and field of a bad bundle, or why the mode or module cannot run.
pub fn process(dir: &Path, options: &ProcessOptions) -> Result<ProcessOutput, ProcessError> {
    process_streamed(dir, options, |_| Ok(())).map(|(out, _)| out)
}

/// One frame as it comes back, for views that update while a bundle is processed.
#[derive(Clone, Copy, Debug)]
pub struct FrameEvent<'a> {
    /// The frame's estimates.
    pub result: &'a FrameResult,
    /// Frames in the bundle.
    pub of: u32,
    /// Time from reading the frame's radar samples to its results: the read, the host's
    /// Doppler pass for movers and the module's round trip (QEMU) or search (in process).
    pub latency: std::time::Duration,
    /// The host's receive counters of the telemetry link (QEMU only).
    pub link: Option<metamoran_dsp::wire::LinkStats>,
}

/// [`process`], calling `on_frame` as each frame's results arrive (an error it returns stops
/// the run), and also returning what the QEMU module reported when it stopped.
///
/// # Errors
/// As [`process`], or `on_frame`'s.
pub fn process_streamed(
    dir: &Path,
    options: &ProcessOptions,
    mut on_frame: impl FnMut(FrameEvent<'_>) -> Result<(), Box<dyn std::error::Error + Send + Sync>>,
) -> Result<(ProcessOutput, Option<EdgeLog>), ProcessError> {
    let mode = options.mode;
    let mut bundle = Bundle::open(dir, options.open.clone())?;
    let mut module = start_module(&bundle, options)?;
    let camera = CameraModel::new(&bundle.scene.camera);
    let frame_options = FrameOptions {
        range_window: WindowKind::Hann,
        doppler_window: WindowKind::Rectangular,
        remove_static: false,
    };
    let mut proc = FrameProcessor::new(&bundle.scene.radar, frame_options)?;
    let (mut samples, mut raw) = (Vec::new(), Vec::new());
    let mut frames = Vec::new();
    let mut stopped = None;
    let max_range_m = bundle.scene.radar.max_range_m();
    for f in 0..bundle.frames() {
        let started = std::time::Instant::now();
        // A bad frame is counted and skipped; only a failed module or consumer stops the run.
        let estimated = (|| -> Result<Vec<ObjectEstimate>, ProcessError> {
            let cam = bundle.camera_frame(f)?;
            let objects = objects_of_interest(&camera, &cam);
            Ok(match mode {
                Mode::Monocular => objects.iter().map(monocular::estimate).collect(),
                Mode::Metamoran => {
                    bundle.read_radar_frame(f, &mut samples)?;
                    // The module calibrates as it sums: its share takes the frame as recorded.
                    let recorded = if bundle.calibration().is_some() {
                        bundle.read_raw_radar_frame(f, &mut raw)?;
                        &raw
                    } else {
                        &samples
                    };
                    metamoran_frame(
                        &bundle,
                        f,
                        (&samples, recorded),
                        &objects,
                        module.as_mut().map(|m| &mut m.edge),
                    )?
                }
                Mode::Naive => {
                    bundle.read_radar_frame(f, &mut samples)?;
                    let spectra = proc.process(&samples)?;
                    let ra = naive::RangeAzimuth::new(&mut proc, spectra.range_bins)?;
                    objects
                        .iter()
                        .map(|o| naive::estimate(&ra, &proc, o))
                        .collect()
                }
            })
        })();
        let result = match estimated {
            Ok(mut objects) => {
                for o in &mut objects {
                    o.keep_in_view(max_range_m);
                }
                FrameResult::new(f, objects)
            }
            Err(e @ ProcessError::Edge(_)) => {
                stopped = Some(e.to_string());
                break;
            }
            Err(e) => FrameResult {
                frame: f,
                objects: unprocessed(bundle.instances(f)),
                error: Some(e.to_string()),
            },
        };
        let consumed = on_frame(FrameEvent {
            result: &result,
            of: bundle.frames(),
            latency: started.elapsed(),
            link: module.as_ref().map(|m| m.edge.link_stats()),
        });
        frames.push(result);
        if let Err(e) = consumed {
            stopped = Some(ProcessError::Consumer(e).to_string());
            break;
        }
    }
    // A module that already failed cannot report; what it computed is kept.
    let log = match module {
        Some(q) if stopped.is_none() => Some(stop_module(q.edge)?),
        _ => None,
    };
    Ok((
        ProcessOutput {
            mode,
            frames,
            stopped,
        },
        log,
    ))
}

/// "Not detected" for every object of interest of `instances`, in id order: the entries of
/// a frame that could not be processed.
fn unprocessed(instances: &[metamoran_bundle::Instance]) -> Vec<ObjectEstimate> {
    let mut listed: Vec<_> = instances
        .iter()
        .filter(|i| i.is_object_of_interest())
        .collect();
    listed.sort_by_key(|i| i.id);
    listed
        .into_iter()
        .map(|i| ObjectEstimate::unprocessed(i.id, &i.class))
        .collect()
}

/// The module under QEMU, built, started and configured for `bundle`, if `options` run the
/// Metamoran mode there.
fn start_module(bundle: &Bundle, options: &ProcessOptions) -> Result<Option<Module>, ProcessError> {
    let (Mode::Metamoran, Runner::Qemu { firmware, key_file }) = (options.mode, &options.runner)
    else {
        return Ok(None);
    };
    if options.open.iq_order != metamoran_dsp::capture::IqOrder::Iiqq {
        return Err(ProcessError::IqOrder);
    }
    // The module reads one file in radar.bin's layout: an MMWCAS capture is copied into one.
    let copy = match bundle.scene.layout {
        metamoran_bundle::AdcLayout::Dca1000 => None,
        metamoran_bundle::AdcLayout::Mmwcas => {
            let io = |e| metamoran_bundle::error::InputError::write(&std::env::temp_dir(), e);
            let mut tmp = tempfile::NamedTempFile::new().map_err(io)?;
            let mut file = metamoran_bundle::RadarFile::open_mmwcas(
                &bundle.scene.adc_file,
                bundle.scene.radar.clone(),
            )?;
            file.write_dca1000(&mut std::io::BufWriter::new(tmp.as_file_mut()))?;
            Some(tmp)
        }
    };
    let capture = copy
        .as_ref()
        .map_or(bundle.scene.adc_file.as_path(), |t| t.path());
    let mut edge = QemuEdge::start(capture, key_file, firmware)?;
    edge.configure(&bundle.scene.radar)?;
    if let Some(calibration) = bundle.calibration() {
        edge.calibrate(calibration)?;
    }
    Ok(Some(Module {
        edge,
        _capture: copy,
    }))
}

/// The module under QEMU and the capture file it reads, kept while it runs.
struct Module {
    edge: QemuEdge,
    _capture: Option<tempfile::NamedTempFile>,
}

/// One frame of the Metamoran mode: the static search on `module` (QEMU, over the link) or in
/// this process, merged with the host's Doppler pass for movers. `samples` are the frame
/// calibrated and as recorded (the same when the bundle names no calibration): the module's
/// share calibrates as it sums, the Doppler pass takes the calibrated chirps.
fn metamoran_frame(
    bundle: &Bundle,
    frame: u32,
    (samples, recorded): (&[metamoran_dsp::fixed::CQ15], &[metamoran_dsp::fixed::CQ15]),
    objects: &[CameraObject],
    module: Option<&mut QemuEdge>,
) -> Result<Vec<ObjectEstimate>, ProcessError> {
    let radar = &bundle.scene.radar;
    let moving = metamoran::MovingScene::new(radar, samples)?;
    let beamwidth = metamoran::beamwidth_deg(&metamoran_dsp::array::VirtualArray::new(radar)?);
    let mut estimates = match module {
        Some(q) => module_frame(q, frame, objects, moving.as_ref(), beamwidth)?,
        None => {
            let mut scene =
                metamoran::StaticScene::calibrated(radar, recorded, bundle.calibration())?;
            objects
                .iter()
                .map(|o| metamoran::estimate(&mut scene, moving.as_ref(), o))
                .collect()
        }
    };
    let contest = contest::Radar {
        beam: beamwidth.to_radians().sin(),
        max_range_m: radar.max_range_m(),
        fold_mps: moving
            .as_ref()
            .map_or(f64::INFINITY, metamoran::MovingScene::fold_mps),
    };
    contest::settle(&mut estimates, objects, &contest, |v, d| {
        moving.as_ref()?.direction(v, d).map(f64::from)
    });
    Ok(estimates)
}

/// The module's share of one frame over the link, merged with the host's Doppler pass.
fn module_frame(
    q: &mut QemuEdge,
    frame: u32,
    objects: &[CameraObject],
    moving: Option<&metamoran::MovingScene>,
    beamwidth: f64,
) -> Result<Vec<ObjectEstimate>, ProcessError> {
    let hints: Vec<_> = objects
        .iter()
        .map(|o| metamoran::wire_hint(frame, o))
        .collect();
    let wire: Vec<_> = hints.iter().flatten().cloned().collect();
    // One result (or None) per sent hint, in order.
    let mut results = q.frame(frame, &wire)?.into_iter();
    Ok(objects
        .iter()
        .zip(&hints)
        .map(|(o, h)| match h {
            Some(h) => metamoran::merge(
                o,
                &ObjectHint::from_wire(h),
                results.next().flatten(),
                moving,
                beamwidth,
            ),
            None => ObjectEstimate::missed(o),
        })
        .collect())
}

/// Stops the module and returns what it reported, warning on stderr if it counted errors.
fn stop_module(q: QemuEdge) -> Result<EdgeLog, ProcessError> {
    let log = q.stop()?;
    let h = log.health;
    if h.capture_errors + h.pipeline_errors + h.protocol_errors > 0 {
        eprintln!("warning: the module counted errors: {h:?}");
    }
    Ok(log)
}
