//! The monocular baseline: the closest masked monocular point, as a range.

use super::ObjectResult;
use super::camera_points::CameraObject;

/// The monocular estimate for one object.
pub fn estimate(obj: &CameraObject) -> ObjectResult {
    match obj.closest_range() {
        Some(depth) => ObjectResult::found(obj, depth, obj.median_azimuth(), obj.points.clone()),
        None => ObjectResult::missed(obj),
    }
}
