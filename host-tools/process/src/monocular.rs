//! The monocular baseline: the closest masked monocular point, as a range.

use super::ObjectEstimate;
use super::camera_points::CameraObject;

/// The monocular estimate for one object.
pub fn estimate(obj: &CameraObject) -> ObjectEstimate {
    match obj.closest_range() {
        Some(depth) => ObjectEstimate::found(obj, depth, obj.median_azimuth(), obj.points.clone()),
        None => ObjectEstimate::missed(obj),
    }
}
