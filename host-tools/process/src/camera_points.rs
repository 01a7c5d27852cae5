//! What the camera says about each object: its masked monocular points in the radar frame and
//! the azimuth span they cover.

use crate::ground::{Contact, GroundPlane, stands_on_ground};
use metamoran_bundle::CameraFrame;
use metamoran_bundle::geometry::{CameraModel, Point, azimuth, range_xz};

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
    /// Vertical extent of the mask; `None` for an empty mask.
    pub extent: Option<VerticalExtent>,
    /// Share of the mask's pixels with a monocular depth, 0–1 (0 for an empty mask).
    pub depth_coverage: f64,
    /// Where the object meets the frame's ground plane, for a class that stands on it and a
    /// mask the image does not cut ([`crate::ground`]).
    pub contact: Option<Contact>,
}

/// How tall a mask looks: the slopes `y / √(x² + z²)` (y down, radar frame) of its highest and
/// lowest pixel rays. An upright object `H` metres tall at horizontal range `r` spans
/// `H / r` of slope, whatever the camera's pitch and roll.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VerticalExtent {
    /// Slope of the highest pixel's ray.
    pub top: f64,
    /// Slope of the lowest pixel's ray.
    pub bottom: f64,
    /// Slope between adjacent pixel rows at the object (the quantization step).
    pub pitch: f64,
    /// The mask touches the image's top or bottom row: the object may continue beyond it.
    pub clipped: bool,
}

impl VerticalExtent {
    /// Slope the object spans: from the top of its highest pixel to the bottom of its lowest.
    pub fn span(&self) -> f64 {
        self.bottom - self.top + self.pitch
    }
}

/// Slope of a ray `d` below the horizontal plane (y down): `d.y / √(d.x² + d.z²)`.
fn slope(d: &Point) -> f64 {
    d.y / d.x.hypot(d.z).max(1e-12)
}

/// Share of an object's points, nearest first, read as segmentation outliers (mask pixels that
/// caught a nearer surface's depth) when taking its closest range.
pub const NEAR_OUTLIERS: f64 = 0.02;

/// Least share of a mask's pixels with a monocular depth for the depths to describe the
/// object's shape ([`CameraObject::has_shape`]). Below it the object lies beyond what the depth
/// image holds (256 m, or wherever the estimator gives up), and the depths left are the
/// neighbours' that bled into the mask's edge: a far car's grown bottom row on the ground. Their
/// range is still near the object's (the ground under it), but their spread across the mask is
/// the ground's, not a contour.
pub const MIN_DEPTH_COVERAGE: f64 = 0.5;

/// How far behind its closest point an object of `class` reaches, m; masked pixels farther back
/// show the background through the mask's edge (bleed).
pub fn depth_extent(class: &str) -> f64 {
    match class {
        "person" | "sign" => 1.5,
        _ => 6.0,
    }
}

impl CameraObject {
    /// The object's monocular depth: the x–z range of its nearest points, past the
    /// [`NEAR_OUTLIERS`] share of stray ones. O(n log n).
    pub fn closest_range(&self) -> Option<f64> {
        let mut r: Vec<f64> = self.points.iter().map(range_xz).collect();
        r.sort_by(f64::total_cmp);
        r.get((r.len() as f64 * NEAR_OUTLIERS) as usize).copied()
    }

    /// The depth image of the object anchored at radar depth `depth`: its own points (from
    /// [`Self::closest_range`] to [`depth_extent`] behind it; stray nearer ones and background
    /// seen through the mask's edge dropped) moved radially so the closest sits at `depth`.
    pub fn anchored(&self, depth: f64) -> Vec<Point> {
        let Some(closest) = self.closest_range() else {
            return Vec::new();
        };
        let reach = closest + depth_extent(&self.class);
        let body: Vec<Point> = self
            .points
            .iter()
            .filter(|p| (closest..=reach).contains(&range_xz(p)))
            .copied()
            .collect();
        shift_to_depth(&body, depth)
    }

    /// Whether the monocular points describe the object's shape: at least
    /// [`MIN_DEPTH_COVERAGE`] of its mask has a depth.
    pub fn has_shape(&self) -> bool {
        self.depth_coverage >= MIN_DEPTH_COVERAGE
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
/// count for the azimuth span (back-projected at 20 m). The ground plane is fitted once per
/// frame with a car or a person in it.
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
            extent: None,
            depth_coverage: 0.0,
            contact: None,
        })
        .collect();
    out.sort_by_key(|o| o.instance);
    let mut pixels = vec![0usize; out.len()];
    let w = frame.width;
    for (idx, &id) in frame.mask.iter().enumerate() {
        let Ok(k) = out.binary_search_by_key(&id, |o| o.instance) else {
            continue;
        };
        let (u, v) = (idx as u32 % w, idx as u32 / w);
        let depth = frame.depth_m(u, v);
        let p = camera.back_project(u, v, depth.unwrap_or(20.0) as f64);
        let az = azimuth(&p);
        pixels[k] += 1;
        let o = &mut out[k];
        o.span = Some(o.span.map_or((az, az), |(lo, hi)| (lo.min(az), hi.max(az))));
        let t = slope(&camera.ray(u, v).0);
        let edge = v == 0 || v + 1 == frame.height;
        o.extent = Some(match o.extent {
            None => {
                let below = camera.ray(u, v + 1).0;
                VerticalExtent {
                    top: t,
                    bottom: t,
                    pitch: (slope(&below) - t).abs(),
                    clipped: edge,
                }
            }
            Some(e) => VerticalExtent {
                top: e.top.min(t),
                bottom: e.bottom.max(t),
                clipped: e.clipped || edge,
                ..e
            },
        });
        if depth.is_some() {
            o.points.push(p);
        }
    }
    let ground = if out.iter().any(|o| stands_on_ground(&o.class)) {
        GroundPlane::fit(camera, frame)
    } else {
        None
    };
    for (o, &n) in out.iter_mut().zip(&pixels) {
        o.contact = ground
            .zip(o.extent)
            .zip(o.span)
            .and_then(|((g, e), (lo, hi))| {
                (stands_on_ground(&o.class) && !e.clipped)
                    .then(|| Contact::of(&g, camera.centre(), e.bottom, e.pitch, (lo + hi) / 2.0))
                    .flatten()
            });
        o.depth_coverage = o.points.len() as f64 / n.max(1) as f64;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stray_and_background_pixels_do_not_move_the_anchor() {
        // A car seen at 20–23.96 m straight ahead, one stray pixel at 5 m and ten pixels of a
        // wall at 60 m through the mask's edge.
        let at = |r: f64| Point::new(0.0, 0.0, r);
        let mut points: Vec<Point> = (0..100).map(|k| at(20.0 + 0.04 * f64::from(k))).collect();
        points.push(at(5.0));
        points.extend((0..10).map(|_| at(60.0)));
        let car = CameraObject {
            instance: 1,
            class: "car".into(),
            points,
            span: Some((0.0, 0.0)),
            extent: None,
            contact: None,
            depth_coverage: 1.0,
        };
        // 111 points: the 2 % share skips index 0 and 1 (5 m, 20 m).
        assert_eq!(car.closest_range(), Some(20.04));
        let fused = car.anchored(30.0);
        assert_eq!(fused.len(), 99, "the car's own points from 20.04 m");
        let ranges: Vec<f64> = fused.iter().map(range_xz).collect();
        assert!((ranges[0] - 30.0).abs() < 1e-9);
        assert!((ranges[98] - (30.0 + 0.04 * 98.0)).abs() < 1e-9);
    }

    /// A 64 × 16 frame, level camera (f = 100 px) at the radar: instance 1 fills columns 20–29
    /// of rows 4–11 (80 pixels) with `own` depth and its grown bottom row (row 12) the ground's.
    fn far_car(own: u16, ground: u16) -> CameraFrame {
        let (w, h) = (64u32, 16u32);
        let mut mask = vec![0u16; (w * h) as usize];
        let mut depth = vec![0u16; (w * h) as usize];
        for v in 4..=12u32 {
            for u in 20..30u32 {
                let i = (v * w + u) as usize;
                mask[i] = 1;
                depth[i] = if v == 12 {
                    ground + 64 * (u as u16 % 3)
                } else {
                    own
                };
            }
        }
        CameraFrame {
            width: w,
            height: h,
            mask,
            depth,
            instances: vec![metamoran_bundle::Instance {
                id: 1,
                class: "car".into(),
            }],
        }
    }

    fn camera() -> CameraModel {
        CameraModel::new(&metamoran_bundle::CameraConfig {
            width: 64,
            height: 16,
            fx: 100.0,
            fy: 100.0,
            cx: 32.0,
            cy: 8.0,
            translation_m: [0.0; 3],
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            roll_deg: 0.0,
        })
    }

    #[test]
    fn a_mask_with_depths_only_at_its_edge_has_no_shape() {
        // Beyond the depth image's 256 m: only the 10 ground pixels of its 90 have a depth.
        let far = objects_of_interest(&camera(), &far_car(0, 230 * 256));
        assert_eq!(far.len(), 1);
        assert!((far[0].depth_coverage - 10.0 / 90.0).abs() < 1e-12);
        assert!(!far[0].has_shape());
        assert_eq!(
            far[0].points.len(),
            10,
            "the points stay for the monocular range"
        );
        // Near: every pixel has one.
        let near = objects_of_interest(&camera(), &far_car(40 * 256, 41 * 256));
        assert_eq!(near[0].depth_coverage, 1.0);
        assert!(near[0].has_shape());
    }
}
