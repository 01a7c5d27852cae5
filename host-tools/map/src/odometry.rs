//! Doppler odometry: per frame, the radar's velocity by RANSAC over its point cloud
//! (`metamoran_dsp::ego`), the vehicle's speed and yaw rate by the Ackermann relation, the integrated
//! pose, and, where the bundle has truth, the errors against it. Its poses and static points
//! are what [`super::depth`] builds submaps from.

use super::cloud::{Clouds, default_options};
use crate::MapError;
use metamoran_bundle::pose::Pose;
use metamoran_bundle::{Bundle, OpenOptions};
use metamoran_dsp::ego::{DopplerDetection, Mount, Ransac, UnfoldGrid, estimate, unfold_search};
use metamoran_dsp::points::{CloudOptions, RadarPoint};
use serde::Serialize;
use std::path::Path;

/// One frame's odometry.
#[derive(Clone, Debug, Serialize)]
pub struct OdometryFrame {
    /// Frame number.
    pub frame: u32,
    /// Points in the cloud.
    pub points: usize,
    /// Of them, static (RANSAC inliers).
    pub inliers: usize,
    /// The radar's velocity `[v_x, v_z]` in its frame (x right, z forward), m/s; `None` when
    /// too few points agree.
    pub velocity_mps: Option<[f64; 2]>,
    /// Vehicle speed (rear axle), m/s, under the mount given.
    pub speed_mps: Option<f64>,
    /// Vehicle yaw rate, rad/s, positive left.
    pub yaw_rate_rps: Option<f64>,
    /// The truth's radar velocity in the radar frame, m/s.
    pub truth_mps: Option<[f64; 2]>,
    /// |estimate − truth|, m/s.
    pub error_mps: Option<f64>,
}

/// A bundle's odometry.
#[derive(Clone, Debug, Serialize)]
pub struct Odometry {
    /// Per frame.
    pub frames: Vec<OdometryFrame>,
    /// Mean error norm over the frames with an estimate and truth, m/s.
    pub ego_velocity_error_mps: Option<f64>,
    /// Distance between the integrated and the true position of the radar at the last frame, m.
    pub final_position_error_m: Option<f64>,
    /// Per frame, the integrated pose and the static points (RANSAC inliers) in that frame's
    /// radar frame (x right, y down, z forward, m): what submaps are built from.
    #[serde(skip)]
    pub tracked: Vec<(Pose, Vec<[f64; 3]>)>,
}

/// The cloud as ego-motion sees it: bundle.md's range and radial velocity are in the x–z
/// plane, so the cosine relation is in azimuth alone, as the paper fits it.
fn detections(points: &[RadarPoint]) -> Vec<DopplerDetection> {
    points
        .iter()
        .map(|p| DopplerDetection::at(p.azimuth, 0.0, p.radial_velocity_mps))
        .collect()
}

/// Runs Doppler odometry over every frame of the bundle in `dir`, for a radar on `mount`, with
/// the mapping's detector ([`default_options`]). Radial velocities are unfolded
/// ([`metamoran_dsp::ego::unfold`]) where the board's unambiguous span is less than the static
/// world's speed past it.
///
/// # Errors
/// [`MapError`] naming the file and field of a bad bundle.
pub fn run(dir: &Path, mount: &Mount) -> Result<Odometry, MapError> {
    run_with(dir, mount, default_options())
}

/// [`run`] with the detector of `options` (its velocity prior is each frame's own).
///
/// # Errors
/// [`MapError`] naming the file and field of a bad bundle.
pub fn run_with(dir: &Path, mount: &Mount, options: CloudOptions) -> Result<Odometry, MapError> {
    let mut bundle = Bundle::open(dir, OpenOptions::default())?;
    let mut clouds = Clouds::new(&bundle, options)?;
    let truth = bundle.truth.clone();
    let period = bundle.scene.radar.frame_period_s;
    let mut frames = Vec::new();
    // Per frame: the pose integrated so far and the static points (radar frame).
    let mut tracked: Vec<(Pose, Vec<[f64; 3]>)> = Vec::new();
    let mut last_motion: Option<([f64; 2], f64)> = None;
    let mut last_velocity: Option<[f32; 2]> = None;
    for f in 0..bundle.frames() {
        // Radial velocities unfold towards the last estimate; without one, towards the
        // velocity a grid search finds the folded cloud agrees with.
        let points = match last_velocity {
            Some(v) => clouds.frame(&mut bundle, f, Some(v))?,
            None => {
                let span = clouds.velocity_span_mps();
                clouds.frame_unfolded(&mut bundle, f, |folded| {
                    unfold_search(&detections(folded), span, &UnfoldGrid::default()).map(|(v, _)| v)
                })?
            }
        };
        let dets = detections(&points);
        let mut mask = vec![false; dets.len()];
        let est = estimate(&dets, &Ransac::default(), &mut mask).ok();
        if est.is_none() {
            // A failed fit may have marked a consensus it then rejected.
            mask.fill(false);
        }
        let truth_v = truth
            .as_ref()
            .and_then(|t| t.frames.get(f as usize))
            .map(|t| {
                // World velocity into the radar frame of this frame's yaw (positive left).
                let (s, c) = t.ego.yaw.sin_cos();
                let (fwd, right) = ([-s, c], [c, s]);
                [
                    t.ego.vx * right[0] + t.ego.vz * right[1],
                    t.ego.vx * fwd[0] + t.ego.vz * fwd[1],
                ]
            });
        let v = est.map(|e| [f64::from(e.velocity[0]), f64::from(e.velocity[1])]);
        last_velocity = est.map(|e| e.velocity);
        let motion = est.map(|e| mount.motion(e.velocity));
        // Integrate with the mean of the two frames' estimates over the interval between them
        // (a frame without an estimate repeats the last one).
        let now = v.zip(motion).map(|(v, m)| (v, f64::from(m.yaw_rate_rps)));
        let pose = match (tracked.last(), last_motion.or(now), now.or(last_motion)) {
            (Some((p, _)), Some((v0, w0)), Some((v1, w1))) => p.advanced(
                [(v0[0] + v1[0]) / 2.0, (v0[1] + v1[1]) / 2.0],
                (w0 + w1) / 2.0,
                period,
            ),
            (Some((p, _)), _, _) => *p,
            _ => Pose::default(),
        };
        last_motion = now.or(last_motion);
        // Only the RANSAC inliers: a frame without an estimate adds no points (its movers
        // and ghosts cannot be told from the static scene).
        let statics = points
            .iter()
            .zip(&mask)
            .filter(|&(_, &m)| m)
            .map(|(p, _)| p.position.map(f64::from))
            .collect();
        tracked.push((pose, statics));
        frames.push(OdometryFrame {
            frame: f,
            points: points.len(),
            inliers: est.map_or(0, |e| usize::from(e.inliers)),
            velocity_mps: v,
            speed_mps: motion.map(|m| f64::from(m.speed_mps)),
            yaw_rate_rps: motion.map(|m| f64::from(m.yaw_rate_rps)),
            truth_mps: truth_v,
            error_mps: v
                .zip(truth_v)
                .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1])),
        });
    }
    let velocity_errors: Vec<f64> = frames.iter().filter_map(|f| f.error_mps).collect();
    let final_position_error_m = truth
        .as_ref()
        .and_then(|t| t.frames.last())
        .zip(tracked.last())
        .map(|(t, (p, _))| (t.ego.x - p.position[0]).hypot(t.ego.z - p.position[1]));
    Ok(Odometry {
        ego_velocity_error_mps: (!velocity_errors.is_empty())
            .then(|| velocity_errors.iter().sum::<f64>() / velocity_errors.len() as f64),
        final_position_error_m,
        frames,
        tracked,
    })
}
