//! Camera geometry in the radar frame (x right, y down, z forward; bundle.md): pinhole
//! projection, back-projection and rays, and the range/azimuth of points.

use crate::CameraConfig;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// A 3D point or direction in the radar frame, metres.
pub type Point = Vector3<f64>;

/// Range in the x–z plane (the radar has no elevation resolution), m.
pub fn range_xz(p: &Point) -> f64 {
    p.x.hypot(p.z)
}

/// Azimuth atan2(x, z), radians, positive to the right.
pub fn azimuth(p: &Point) -> f64 {
    p.x.atan2(p.z)
}

/// A calibrated pinhole camera placed in the radar frame.
#[derive(Clone, Debug)]
pub struct CameraModel {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    fx: f64,
    fy: f64,
    cx: f64,
    cy: f64,
    /// Camera-to-radar rotation.
    rotation: Matrix3<f64>,
    /// Camera centre in the radar frame.
    centre: Point,
}

impl CameraModel {
    /// The camera of a bundle. The rotation applies yaw (about y), then pitch (about x), then
    /// roll (about z) to camera-frame vectors to express them in the radar frame.
    pub fn new(c: &CameraConfig) -> Self {
        let yaw = Rotation3::from_axis_angle(&Vector3::y_axis(), c.yaw_deg.to_radians());
        let pitch = Rotation3::from_axis_angle(&Vector3::x_axis(), c.pitch_deg.to_radians());
        let roll = Rotation3::from_axis_angle(&Vector3::z_axis(), c.roll_deg.to_radians());
        Self {
            width: c.width,
            height: c.height,
            fx: c.fx,
            fy: c.fy,
            cx: c.cx,
            cy: c.cy,
            rotation: (roll * pitch * yaw).into_inner(),
            centre: Vector3::from(c.translation_m),
        }
    }

    /// The camera centre in the radar frame.
    pub fn centre(&self) -> Point {
        self.centre
    }

    /// The unit ray through pixel centre (u + 0.5, v + 0.5), in the radar frame, and the
    /// z-component of the camera-frame ray (to turn distance along it into camera depth).
    pub fn ray(&self, u: u32, v: u32) -> (Point, f64) {
        let d = Vector3::new(
            (u as f64 + 0.5 - self.cx) / self.fx,
            (v as f64 + 0.5 - self.cy) / self.fy,
            1.0,
        );
        let n = d.norm();
        (self.rotation * (d / n), 1.0 / n)
    }

    /// The radar-frame point at pixel (u, v) with camera depth `z` (along the optical axis).
    pub fn back_project(&self, u: u32, v: u32, z: f64) -> Point {
        let d = Vector3::new(
            (u as f64 + 0.5 - self.cx) / self.fx * z,
            (v as f64 + 0.5 - self.cy) / self.fy * z,
            z,
        );
        self.rotation * d + self.centre
    }

    /// Pixel coordinates (continuous) and camera depth of a radar-frame point in front of the camera.
    pub fn project(&self, p: &Point) -> Option<(f64, f64, f64)> {
        let c = self.rotation.transpose() * (p - self.centre);
        (c.z > 1e-6).then(|| {
            (
                self.fx * c.x / c.z + self.cx,
                self.fy * c.y / c.z + self.cy,
                c.z,
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(yaw: f64) -> CameraModel {
        CameraModel::new(&CameraConfig {
            width: 640,
            height: 360,
            fx: 500.0,
            fy: 500.0,
            cx: 320.0,
            cy: 180.0,
            translation_m: [0.1, -0.15, 0.05],
            yaw_deg: yaw,
            pitch_deg: 2.0,
            roll_deg: -1.0,
        })
    }

    #[test]
    fn projection_and_back_projection_invert() {
        for yaw in [0.0, 7.0] {
            let cam = camera(yaw);
            let p = Vector3::new(-3.0, 0.4, 25.0);
            let (u, v, z) = cam.project(&p).unwrap();
            let q = cam.back_project((u - 0.5) as u32, (v - 0.5) as u32, z);
            // Integer pixels lose the sub-pixel part: within a pixel's footprint at 25 m.
            assert!((q - p).norm() < 25.0 / 500.0 * 1.5, "{q} vs {p}");
            let (dir, kz) = cam.ray(u as u32, v as u32);
            let hit = cam.centre() + dir * (z / kz);
            assert!((hit - p).norm() < 0.1);
        }
        assert!(
            (azimuth(&Vector3::new(1.0, 0.0, 1.0)) - std::f64::consts::FRAC_PI_4).abs() < 1e-12
        );
        assert_eq!(range_xz(&Vector3::new(3.0, 9.0, 4.0)), 5.0);
    }
}
