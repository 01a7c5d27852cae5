//! What the camera says about each object: its masked monocular points in the radar frame and
//! the azimuth span they cover.

use crate::bundle::CameraFrame;
use crate::geometry::{CameraModel, Point, azimuth, range_xz};

/// Most points kept per object (evenly subsampled beyond that).
pub const MAX_POINTS: usize = 2000;

/// One object as the camera sees it.
#[derive(Clone, Debug)]
pub struct CameraObject {
    /// Instance id.
    pub instance: u16,
    /// Class word.
    pub class: String,
    /// Masked pixels with a monocular depth, back-projected into the radar frame.
    pub points: Vec<Point>,
    /// Azimuth span of the mask, radians (min, max); `None` for an empty mask.
    pub span: Option<(f64, f64)>,
}

impl CameraObject {
    /// The smallest x–z range of the points (the monocular depth of the object).
    pub fn closest_range(&self) -> Option<f64> {
        self.points.iter().map(range_xz).min_by(f64::total_cmp)
    }

    /// The median azimuth of the points, radians.
    pub fn median_azimuth(&self) -> Option<f64> {
        let mut a: Vec<f64> = self.points.iter().map(azimuth).collect();
        if a.is_empty() {
            return None;
        }
        a.sort_by(f64::total_cmp);
        Some(a[a.len() / 2])
    }
}

/// The objects of interest of a frame, in id order. Pixels without a monocular depth still
/// count for the azimuth span (back-projected at 20 m).
pub fn objects_of_interest(camera: &CameraModel, frame: &CameraFrame) -> Vec<CameraObject> {
    let mut out: Vec<CameraObject> = frame
        .instances
        .iter()
        .filter(|i| i.is_object_of_interest())
        .map(|i| CameraObject {
            instance: i.id,
            class: i.class.clone(),
            points: Vec::new(),
            span: None,
        })
        .collect();
    out.sort_by_key(|o| o.instance);
    let w = frame.width;
    for (idx, &id) in frame.mask.iter().enumerate() {
        let Ok(k) = out.binary_search_by_key(&id, |o| o.instance) else {
            continue;
        };
        let (u, v) = (idx as u32 % w, idx as u32 / w);
        let depth = frame.depth_m(u, v);
        let p = camera.back_project(u, v, depth.unwrap_or(20.0) as f64);
        let az = azimuth(&p);
        let o = &mut out[k];
        o.span = Some(o.span.map_or((az, az), |(lo, hi)| (lo.min(az), hi.max(az))));
        if depth.is_some() {
            o.points.push(p);
        }
    }
    for o in &mut out {
        if o.points.len() > MAX_POINTS {
            let step = o.points.len().div_ceil(MAX_POINTS);
            o.points = o.points.iter().step_by(step).copied().collect();
        }
    }
    out
}

/// Moves every point radially (in x–z, keeping its height) so that the closest sits at
/// range `depth`: the depth-imaging step that anchors a camera shape at a radar depth.
pub fn shift_to_depth(points: &[Point], depth: f64) -> Vec<Point> {
    let Some(closest) = points.iter().map(range_xz).min_by(f64::total_cmp) else {
        return Vec::new();
    };
    let delta = depth - closest;
    points
        .iter()
        .map(|p| {
            let r = range_xz(p).max(1e-9);
            Point::new(p.x + delta * p.x / r, p.y, p.z + delta * p.z / r)
        })
        .collect()
}
