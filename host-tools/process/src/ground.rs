//! The ground the camera sees, and the range it gives an object standing on it: the trust
//! test's check of a chosen depth ([`crate::trust`]), beside the monocular range and the
//! mask's apparent height that choose it.
//!
//! ```text
//! near ground pixels (no instance, 2–15 m, monocular depth) ─▶ plane y = h + b·z ─┐
//! mask's lowest pixel row (car, person) ───────────────────────────────────────────┴▶ contact range
//! ```
//!
//! The monocular estimate is good near the camera (Table I: 0.6 m at 0–20 m), so the plane is
//! fitted there, and the ray through the bottom edge of an object's mask meets it where the
//! object stands. Unlike the monocular range this does not degrade with the estimator: its
//! error is the mask's bottom row (a pixel is 1/(fy·slope) of the range: 2 % at 10 m, 10 % at
//! 50 m on a 500 px focal length 0.9 m above the ground) and the ground's flatness out to the
//! object. A frame whose near pixels do not lie on one plane gives no cue.

use metamoran_bundle::CameraFrame;
use metamoran_bundle::geometry::{CameraModel, Point, range_xz};

/// Nearest and farthest horizontal range of the pixels the plane is fitted on, m.
pub const FIT_RANGE_M: (f64, f64) = (2.0, 15.0);
/// Fewest pixels a plane is fitted on.
pub const MIN_PIXELS: usize = 200;
/// Largest median distance of the fitted pixels from the plane, m: more, and the near ground is
/// not one plane (steps, kerbs, a hill) or not ground.
pub const MAX_RESIDUAL_M: f64 = 0.05;
/// Steepest slope of the plane along the boresight, dy/dz (±6°).
pub const MAX_TILT: f64 = 0.1;
/// Least height of the radar over the plane, m.
pub const MIN_HEIGHT_M: f64 = 0.2;
/// Least relative tolerance of a contact range (the plane's flatness out to the object).
pub const MIN_TOLERANCE: f64 = 0.05;
/// Largest relative tolerance of a contact range: a mask whose bottom is so near the horizon
/// that a pixel moves its contact by more than this (e^0.5: 65 %) gives no cue.
pub const MAX_TOLERANCE: f64 = 0.5;
/// Relative spread of the contact range's log penalty beyond its tolerance: the mask's bottom
/// can be hidden (an occluder in front) or grown into the ground, so the penalty is soft.
pub const SPREAD: f64 = 0.2;

/// The ground near the sensor, in the radar frame (y down): `y = height_m + tilt · z`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundPlane {
    /// The radar's height over the ground at its foot, m.
    pub height_m: f64,
    /// Slope along the boresight, dy/dz (positive: the ground falls away).
    pub tilt: f64,
    /// Median distance of the inlier pixels from the plane, m.
    pub residual_m: f64,
    /// Inlier pixels it was fitted on.
    pub pixels: usize,
}

/// Least-squares line `y = a + b·z` through `(z, y)` pairs; `None` when degenerate.
fn line(pairs: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = pairs.len() as f64;
    let (sz, sy) = pairs
        .iter()
        .fold((0.0, 0.0), |(sz, sy), &(z, y)| (sz + z, sy + y));
    let (mz, my) = (sz / n, sy / n);
    let (szz, szy) = pairs.iter().fold((0.0, 0.0), |(a, b), &(z, y)| {
        (a + (z - mz) * (z - mz), b + (z - mz) * (y - my))
    });
    (szz > 1e-9).then(|| {
        let b = szy / szz;
        (my - b * mz, b)
    })
}

/// The median of `v` (reordered); 0 for an empty slice.
fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f64::total_cmp).1
}

impl GroundPlane {
    /// The plane through the frame's ground pixels: no instance, a monocular depth, below the
    /// radar and within [`FIT_RANGE_M`]; least squares trimmed three times to the pixels within
    /// three robust deviations. `None` when fewer than [`MIN_PIXELS`] remain or the plane is
    /// not plausible ([`MAX_RESIDUAL_M`], [`MAX_TILT`], [`MIN_HEIGHT_M`]). O(pixels).
    ///
    /// # Example
    /// A level camera 500 px wide, 1 m over a level ground that its estimator gives exactly.
    /// ```
    /// use metamoran_bundle::{CameraConfig, CameraFrame, geometry::CameraModel};
    /// use metamoran_process::ground::GroundPlane;
    ///
    /// let config = CameraConfig {
    ///     width: 640, height: 360, fx: 500.0, fy: 500.0, cx: 320.0, cy: 180.0,
    ///     translation_m: [0.0, 0.0, 0.0], yaw_deg: 0.0, pitch_deg: 0.0, roll_deg: 0.0,
    /// };
    /// let camera = CameraModel::new(&config);
    /// // Below the horizon a row v sees the ground at depth 1 m · fy / (v + 0.5 − cy).
    /// let depth = (0..360u32)
    ///     .flat_map(|v| {
    ///         let z = if v >= 180 { 500.0 / (v as f64 + 0.5 - 180.0) } else { 0.0 };
    ///         std::iter::repeat_n((z.min(255.0) * 256.0).round() as u16, 640)
    ///     })
    ///     .collect();
    /// let frame = CameraFrame { width: 640, height: 360, mask: vec![0; 640 * 360], depth, instances: vec![] };
    /// let plane = GroundPlane::fit(&camera, &frame).unwrap();
    /// assert!((plane.height_m - 1.0).abs() < 0.01 && plane.tilt.abs() < 1e-3, "{plane:?}");
    /// ```
    pub fn fit(camera: &CameraModel, frame: &CameraFrame) -> Option<Self> {
        let mut pairs = Vec::new();
        for v in 0..frame.height {
            for u in 0..frame.width {
                let i = (v * frame.width + u) as usize;
                if frame.mask.get(i) != Some(&0) {
                    continue;
                }
                let Some(z) = frame.depth_m(u, v) else {
                    continue;
                };
                let p = camera.back_project(u, v, f64::from(z));
                let r = range_xz(&p);
                if p.y > 0.0 && (FIT_RANGE_M.0..=FIT_RANGE_M.1).contains(&r) {
                    pairs.push((p.z, p.y));
                }
            }
        }
        for _ in 0..3 {
            if pairs.len() < MIN_PIXELS {
                return None;
            }
            let (a, b) = line(&pairs)?;
            let mut dev: Vec<f64> = pairs.iter().map(|&(z, y)| (y - a - b * z).abs()).collect();
            let keep = (3.0 * 1.4826 * median(&mut dev)).max(0.02);
            pairs.retain(|&(z, y)| (y - a - b * z).abs() <= keep);
        }
        let (height_m, tilt) = line(&pairs)?;
        let mut dev: Vec<f64> = pairs
            .iter()
            .map(|&(z, y)| (y - height_m - tilt * z).abs())
            .collect();
        let plane = Self {
            height_m,
            tilt,
            residual_m: median(&mut dev),
            pixels: pairs.len(),
        };
        (plane.pixels >= MIN_PIXELS
            && plane.residual_m <= MAX_RESIDUAL_M
            && plane.tilt.abs() <= MAX_TILT
            && plane.height_m >= MIN_HEIGHT_M)
            .then_some(plane)
    }

    /// Where a ray from `from` (radar frame) at azimuth `azimuth` (radians) and slope `slope`
    /// (y per metre of horizontal distance, y down) meets the plane: its horizontal range from
    /// the radar, m; `None` if it meets the plane behind or not at all.
    pub fn meet(&self, from: Point, slope: f64, azimuth: f64) -> Option<f64> {
        let (sin, cos) = azimuth.sin_cos();
        let down = slope - self.tilt * cos;
        let t = (self.height_m + self.tilt * from.z - from.y) / down;
        (down > 0.0 && t.is_finite() && t > 0.0).then(|| (from.x + t * sin).hypot(from.z + t * cos))
    }
}

/// Whether the lowest row of a `class` mask is where the object meets the ground (a sign's
/// plate stands on a pole, so it is not).
pub fn stands_on_ground(class: &str) -> bool {
    matches!(class, "car" | "person")
}

/// The range the ground gives an object: where the ray under its mask's lowest row meets the
/// plane.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Contact {
    /// Horizontal range, m.
    pub range_m: f64,
    /// Relative tolerance: one pixel row of the mask's bottom, at least [`MIN_TOLERANCE`].
    pub tolerance: f64,
}

impl Contact {
    /// The contact of a mask whose lowest pixel row's centre has ray slope `bottom` and whose
    /// rows are `pitch` of slope apart, at azimuth `azimuth` (radians), seen from the camera
    /// centre `from`: the ray under the row's bottom edge meets `plane`. `None` if it does not,
    /// or if one row moves it by more than [`MAX_TOLERANCE`].
    pub fn of(
        plane: &GroundPlane,
        from: Point,
        bottom: f64,
        pitch: f64,
        azimuth: f64,
    ) -> Option<Self> {
        let edge = bottom + pitch / 2.0;
        let range_m = plane.meet(from, edge, azimuth)?;
        // One row less steep: how far the contact moves per pixel.
        let farther = plane
            .meet(from, edge - pitch, azimuth)
            .unwrap_or(f64::INFINITY);
        let tolerance = (farther / range_m).ln().max(MIN_TOLERANCE);
        (tolerance <= MAX_TOLERANCE).then_some(Self { range_m, tolerance })
    }

    /// Log-prior of horizontal range `d` m: 0 within the tolerance of the contact's log range,
    /// the excess over [`SPREAD`] beyond.
    pub fn log_prior(&self, d: f64) -> f64 {
        let off = (d.max(1e-3) / self.range_m).ln().abs();
        -(off - self.tolerance).max(0.0) / SPREAD
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use metamoran_bundle::CameraConfig;

    /// The simulator's camera (640 × 360, fy = 500 px), its centre `translation` in the radar
    /// frame and pitched by `pitch_deg`.
    fn camera(translation: [f64; 3], pitch_deg: f64) -> CameraModel {
        CameraModel::new(&CameraConfig {
            translation_m: translation,
            pitch_deg,
            ..metamoran_sim::camera_config()
        })
    }

    /// The frame an exact estimator gives of the plane `y = h + b·z` (radar frame), with the
    /// pixels `other(u, v)` names given depth `z` instead (something that is not ground).
    fn frame(
        cam: &CameraModel,
        h: f64,
        b: f64,
        other: impl Fn(u32, u32) -> Option<f64>,
    ) -> CameraFrame {
        let c = cam.centre();
        let mut depth = vec![0u16; 640 * 360];
        for v in 0..360 {
            for u in 0..640 {
                let (d, zc) = cam.ray(u, v);
                // c + t·d on the plane: c.y + t d.y = h + b (c.z + t d.z).
                let t = (h + b * c.z - c.y) / (d.y - b * d.z);
                let z = other(u, v).or((t > 0.0).then_some(t * zc));
                if let Some(z) = z.filter(|z| *z < 255.0) {
                    depth[(v * 640 + u) as usize] = (z * 256.0).round() as u16;
                }
            }
        }
        CameraFrame {
            width: 640,
            height: 360,
            mask: vec![0; 640 * 360],
            depth,
            instances: vec![],
        }
    }

    #[test]
    fn the_plane_is_found_through_a_tilt_a_pitch_and_something_that_is_not_ground() {
        let cam = camera([0.05, -0.15, 0.1], 2.0);
        // A kerb-high box 6 m ahead covers a block of near pixels at the wrong height.
        let f = frame(&cam, 0.9, 0.02, |u, v| {
            ((300..380).contains(&u) && (230..300).contains(&v)).then_some(6.0)
        });
        let p = GroundPlane::fit(&cam, &f).unwrap();
        // The depth PNG's 1/256 m steps are the only error left.
        assert!((p.height_m - 0.9).abs() < 0.01, "{p:?}");
        assert!((p.tilt - 0.02).abs() < 2e-3, "{p:?}");
        assert!(p.residual_m < 0.01 && p.pixels >= MIN_PIXELS, "{p:?}");
    }

    #[test]
    fn a_frame_without_near_ground_gives_no_plane() {
        let cam = camera([0.0; 3], 0.0);
        // A wall 5 m ahead fills the view: nothing lies on one plane below the radar.
        let wall = frame(&cam, 0.9, 0.0, |_, _| Some(5.0));
        assert_eq!(GroundPlane::fit(&cam, &wall), None);
        // A road and, on the left half of the view, a ditch 0.3 m below it: two planes, each
        // with about half the pixels.
        let low = frame(&cam, 1.2, 0.0, |_, _| None);
        let mut two = frame(&cam, 0.9, 0.0, |_, _| None);
        for v in 0..360u32 {
            for u in 0..320 {
                let i = (v * 640 + u) as usize;
                two.depth[i] = low.depth[i];
            }
        }
        let p = GroundPlane::fit(&cam, &two);
        assert_eq!(p, None, "{p:?}");
    }

    #[test]
    fn a_mask_standing_on_the_plane_gets_its_range_within_a_pixel() {
        let cam = camera([0.0, -0.15, 0.0], 0.0);
        let plane = GroundPlane {
            height_m: 0.9,
            tilt: 0.0,
            residual_m: 0.0,
            pixels: MIN_PIXELS,
        };
        let from = cam.centre();
        for r in [5.0_f64, 20.0, 40.0, 80.0] {
            // The lowest row of an object standing at range r: its bottom edge's ray meets the
            // ground there (the centre of that row is half a pitch higher).
            let pitch = 1.0 / 500.0;
            let edge = (0.9 + 0.15) / r;
            let c = Contact::of(&plane, from, edge - pitch / 2.0, pitch, 0.0).unwrap();
            assert!((c.range_m - r).abs() < 1e-9 * r, "{r}: {c:?}");
            // A pixel row moves it by ln(edge / (edge − pitch)).
            let closed = (edge / (edge - pitch)).ln().max(MIN_TOLERANCE);
            assert!(
                (c.tolerance - closed).abs() < 1e-9,
                "{r}: {c:?} against {closed}"
            );
            assert_eq!(c.log_prior(r * (1.0 + c.tolerance / 2.0)), 0.0);
            assert!(c.log_prior(r * 1.5) < c.log_prior(r * 1.3));
            assert!(c.log_prior(r / 1.5) < c.log_prior(r / 1.3));
        }
        // Near the horizon one row moves the contact too far to say anything.
        assert_eq!(Contact::of(&plane, from, 0.004, 0.002, 0.0), None);
        // A ray above the horizon never meets it.
        assert_eq!(plane.meet(from, -0.01, 0.0), None);
    }
}
