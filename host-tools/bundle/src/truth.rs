//! `truth.json`: ground truth per frame (optional in a bundle).

use crate::error::{InputError, parse_json};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Ground truth of a capture.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Truth {
    /// One entry per frame.
    pub frames: Vec<TruthFrame>,
}

/// Ground truth of one frame.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TruthFrame {
    /// Frame number.
    pub frame: u32,
    /// Platform pose and velocity in the world frame of frame 0.
    pub ego: Ego,
    /// Objects of interest.
    pub objects: Vec<TruthObject>,
}

/// Platform pose and velocity.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Ego {
    /// Position x, m.
    pub x: f64,
    /// Position z, m.
    pub z: f64,
    /// Heading, rad.
    pub yaw: f64,
    /// Velocity x, m/s.
    pub vx: f64,
    /// Velocity z, m/s.
    pub vz: f64,
}

/// One object's truth.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TruthObject {
    /// Instance id in the camera products of this frame.
    pub instance: u16,
    /// The object's identity across frames where the camera numbers its instances afresh
    /// every frame (`simulate --renumber-instances`); absent: `instance` is that identity.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object: Option<u16>,
    /// Class word.
    pub class: String,
    /// Range of the closest point, m.
    pub depth_m: f64,
    /// Azimuth, degrees.
    pub azimuth_deg: f64,
    /// Radial velocity, m/s (positive away).
    pub radial_velocity_mps: f64,
    /// Lidar-like sample of the visible surface, radar frame, m.
    pub points: Vec<[f64; 3]>,
}

impl TruthObject {
    /// The object's identity across frames: [`TruthObject::object`], else the instance id.
    pub fn identity(&self) -> u16 {
        self.object.unwrap_or(self.instance)
    }
}

impl Truth {
    /// Reads and checks `truth.json` for a capture of `frames` frames.
    ///
    /// # Errors
    /// [`InputError`] naming the file and field.
    pub fn read(path: &Path, frames: u32) -> Result<Self, InputError> {
        let bytes = crate::error::read(path, crate::limits::MAX_TRUTH_BYTES)?;
        Self::parse(path, &bytes, frames)
    }

    /// Parses and checks the contents of `truth.json` (`path` names it in errors) for a capture
    /// of `frames` frames.
    ///
    /// # Errors
    /// [`InputError`] naming the file and field.
    pub fn parse(path: &Path, bytes: &[u8], frames: u32) -> Result<Self, InputError> {
        let truth: Truth = parse_json(path, bytes)?;
        for (i, f) in truth.frames.iter().enumerate() {
            if f.frame >= frames {
                return Err(InputError::field(
                    path,
                    format!("frames[{i}].frame"),
                    format!("{} but the capture has {frames} frames", f.frame),
                ));
            }
            for (j, o) in f.objects.iter().enumerate() {
                let at = |k: &str| format!("frames[{i}].objects[{j}].{k}");
                if !(o.depth_m.is_finite() && o.depth_m >= 0.0) {
                    return Err(InputError::field(
                        path,
                        at("depth_m"),
                        "must be a finite, non-negative number of metres",
                    ));
                }
                if !o.azimuth_deg.is_finite() || !o.radial_velocity_mps.is_finite() {
                    return Err(InputError::field(
                        path,
                        at("azimuth_deg"),
                        "azimuth and velocity must be finite",
                    ));
                }
                if let Some(k) = o
                    .points
                    .iter()
                    .position(|p| p.iter().any(|v| !v.is_finite()))
                {
                    return Err(InputError::field(
                        path,
                        at(&format!("points[{k}]")),
                        "coordinates must be finite",
                    ));
                }
            }
        }
        Ok(truth)
    }
}
