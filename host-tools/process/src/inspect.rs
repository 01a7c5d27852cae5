//! `metamoran inspect`: what the radar saw for each object of a frame, for the engineer who
//! wants to know why the module chose a depth. The range–azimuth map before and after SIC (the
//! module's own fixed-point beams and residual), the object's span, the reflectors SIC
//! cancelled, the chosen depth, and the correlation score `P(d)` of the coarse search (drawn by
//! `metamoran_operator::plot`).

use crate::ProcessError;
use crate::camera_points::objects_of_interest;
use crate::metamoran::{StaticScene, prepare};
use metamoran_bundle::Bundle;
use metamoran_bundle::geometry::CameraModel;
use serde::Serialize;

/// Azimuth grid of the maps, degrees each side of boresight.
pub const MAX_AZIMUTH_DEG: f64 = 60.0;
/// Azimuth step of the maps, degrees.
pub const AZIMUTH_STEP_DEG: f64 = 0.5;

/// A range–azimuth power map: `azimuth_deg.len()` rows of `bins` range cells, dB.
#[derive(Clone, Debug)]
pub struct Map {
    /// Azimuth of each row, degrees.
    pub azimuth_deg: Vec<f64>,
    /// Range cells per row (bin `k` is `k · bin_m` metres).
    pub bins: usize,
    /// Metres per range bin.
    pub bin_m: f64,
    /// Power per cell, dB (arbitrary reference, the same for both maps of an object).
    pub db: Vec<f32>,
}

impl Map {
    /// The strongest cell, dB.
    pub fn max_db(&self) -> f32 {
        self.db.iter().copied().fold(f32::NEG_INFINITY, f32::max)
    }

    /// Power at the cell nearest to (`azimuth_deg`, `range_m`), dB.
    pub fn at(&self, azimuth_deg: f64, range_m: f64) -> Option<f32> {
        let row = ((azimuth_deg + MAX_AZIMUTH_DEG) / AZIMUTH_STEP_DEG).round();
        let k = (range_m / self.bin_m).round();
        if row < 0.0 || k < 0.0 || row as usize >= self.azimuth_deg.len() || k as usize >= self.bins
        {
            return None;
        }
        self.db.get(row as usize * self.bins + k as usize).copied()
    }
}

/// One object of a frame as the module saw it.
#[derive(Clone, Debug, Serialize)]
pub struct ObjectView {
    /// Instance id.
    pub instance: u16,
    /// Class word.
    pub class: String,
    /// The mask's azimuth span, degrees.
    pub span_deg: (f64, f64),
    /// The monocular depth the hint carried, m.
    pub prior_m: f64,
    /// The search's depth of the object's closest point, m.
    pub depth_m: f64,
    /// Whether the module's own test trusts it (peak over floor and uniqueness).
    pub detected: bool,
    /// The module's confidence, dB of `P(d*)` over the median score.
    pub confidence_db: f64,
    /// The range window the mask's apparent height allowed the search, m (0: none).
    pub window_m: (f64, f64),
    /// What the host's trust test weighed (the static search's candidates and the camera's cues;
    /// `process` adds the Doppler path's for movers).
    pub evidence: crate::trust::Evidence,
    /// Its choice and confidence.
    pub verdict: Option<crate::trust::Verdict>,
    /// The reflectors SIC cancelled, in order: (range m, azimuth degrees).
    pub cancelled: Vec<(f64, f64)>,
    /// The coarse score per candidate depth of the closest point: (m, `P`).
    pub scores: Vec<(f64, f32)>,
    /// The median score (the floor a real object must clear).
    pub floor: f32,
    /// The map before SIC.
    #[serde(skip)]
    pub before: Map,
    /// The map after SIC (what the search correlated with).
    #[serde(skip)]
    pub after: Map,
}

/// Inspects every object of interest in frame `frame` of `bundle`. O(objects · grid · bins · E).
///
/// # Errors
/// [`ProcessError`] naming the file and field of a bad bundle or frame.
pub fn inspect_frame(bundle: &mut Bundle, frame: u32) -> Result<Vec<ObjectView>, ProcessError> {
    if frame >= bundle.frames() {
        return Err(ProcessError::NoFrame {
            frame,
            frames: bundle.frames(),
        });
    }
    let camera = CameraModel::new(&bundle.scene.camera);
    let cam = bundle.camera_frame(frame)?;
    // As `process` does: the module's share calibrates the frame as recorded while it sums.
    let mut samples = Vec::new();
    bundle.read_raw_radar_frame(frame, &mut samples)?;
    let mut scene = StaticScene::calibrated(&bundle.scene.radar, &samples, bundle.calibration())?;
    let bin_m = scene.edge().geometry().bin_m as f64;
    let bins = scene.edge().max_bin();
    let azimuth_deg: Vec<f64> = (0..)
        .map(|i| -MAX_AZIMUTH_DEG + i as f64 * AZIMUTH_STEP_DEG)
        .take_while(|&a| a <= MAX_AZIMUTH_DEG + 1e-9)
        .collect();
    let sin_grid: Vec<f32> = azimuth_deg
        .iter()
        .map(|a| a.to_radians().sin() as f32)
        .collect();
    let mut views = Vec::new();
    for obj in objects_of_interest(&camera, &cam) {
        let Some(p) = prepare(&mut scene, &obj) else {
            continue; // an empty mask: nothing to look at
        };
        let (report, scores) = scene.search_scored(&p.hint, &p.reflectors)?;
        let map = |db| Map {
            azimuth_deg: azimuth_deg.clone(),
            bins,
            bin_m,
            db,
        };
        let before = map(scene.range_azimuth_db(&[], &sin_grid, bins)?);
        let after = map(scene.range_azimuth_db(&p.reflectors, &sin_grid, bins)?);
        let deg = |s: f32| (s as f64).asin().to_degrees();
        let wire = report.to_wire();
        let beamwidth = crate::metamoran::beamwidth_deg(scene.edge().array());
        let evidence = crate::metamoran::evidence(&obj, Some(&wire), &[], beamwidth);
        let verdict = evidence.judge();
        views.push(ObjectView {
            instance: obj.instance,
            class: obj.class.clone(),
            span_deg: (deg(p.hint.span.0), deg(p.hint.span.1)),
            prior_m: p.hint.prior_m as f64,
            depth_m: wire.depth_m(),
            detected: report.detected(),
            confidence_db: wire.score.over_floor_db(),
            window_m: (p.hint.window_m.0 as f64, p.hint.window_m.1 as f64),
            evidence,
            verdict,
            cancelled: p
                .reflectors
                .iter()
                .map(|r| (r.range_bins as f64 * bin_m, deg(r.sin_az)))
                .collect(),
            scores: scores
                .iter()
                .enumerate()
                .filter(|(_, s)| **s > 0.0)
                .map(|(k, &s)| (k as f64 * bin_m, s))
                .collect(),
            floor: report.search.floor,
            before,
            after,
        });
    }
    Ok(views)
}
