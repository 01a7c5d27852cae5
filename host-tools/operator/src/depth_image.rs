//! The fused depth image for people and tools: a 16-bit PNG in the KITTI depth convention and a
//! PLY point cloud, from a frame's per-object points (radar frame, metres).
//!
//! KITTI: one `u16` per pixel, camera depth (along the optical axis) × 256, 0 where there is no
//! measurement; the nearest point wins a pixel.

use crate::OperatorError;
use metamoran_bundle::geometry::{CameraModel, Point};
use metamoran_process::FrameResult;
use std::io::Write;
use std::path::Path;

/// Largest depth the KITTI encoding holds, m (`u16::MAX / 256`).
pub const MAX_DEPTH_M: f64 = 65535.0 / 256.0;

/// The frame's points projected through `camera`: `width × height` row-major pixels, each the
/// nearest point's camera depth (m, along the optical axis) and its object's instance, `None`
/// where no point lands or the depth is beyond [`MAX_DEPTH_M`]. O(points).
pub fn rasterize(camera: &CameraModel, frame: &FrameResult) -> Vec<Option<(f64, u16)>> {
    let (w, h) = (camera.width as usize, camera.height as usize);
    let mut img = vec![None; w * h];
    for o in &frame.objects {
        for p in &o.points {
            let Some((u, v, z)) = camera.project(&Point::new(p[0], p[1], p[2])) else {
                continue;
            };
            let (u, v) = (u.floor(), v.floor());
            if !(u >= 0.0 && v >= 0.0 && (u as usize) < w && (v as usize) < h) || z > MAX_DEPTH_M {
                continue;
            }
            let px: &mut Option<(f64, u16)> = &mut img[v as usize * w + u as usize];
            if px.is_none_or(|(nearest, _)| z < nearest) {
                *px = Some((z, o.instance));
            }
        }
    }
    img
}

/// The frame's points projected through `camera`: `width × height` row-major KITTI values
/// (depth × 256, at least 1; 0 where there is none). O(points).
pub fn kitti_depth(camera: &CameraModel, frame: &FrameResult) -> Vec<u16> {
    rasterize(camera, frame)
        .into_iter()
        .map(|px| px.map_or(0, |(z, _)| ((z * 256.0).round() as u16).max(1)))
        .collect()
}

/// Writes `img` (`width × height` KITTI values) as a 16-bit grayscale PNG.
///
/// # Errors
/// [`OperatorError::Output`] naming the file.
pub fn write_png16(path: &Path, width: u32, height: u32, img: &[u16]) -> Result<(), OperatorError> {
    let err = |e: &dyn std::fmt::Display| OperatorError::output(path, "write the depth PNG", e);
    let file = std::fs::File::create(path).map_err(|e| err(&e))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Sixteen);
    let mut writer = enc.write_header().map_err(|e| err(&e))?;
    let bytes: Vec<u8> = img.iter().flat_map(|v| v.to_be_bytes()).collect();
    writer.write_image_data(&bytes).map_err(|e| err(&e))?;
    writer.finish().map_err(|e| err(&e))
}

/// Writes the frame's points as an ASCII PLY with `x y z` (float, m) and `instance` (int).
///
/// # Errors
/// [`OperatorError::Output`] naming the file.
pub fn write_ply(path: &Path, frame: &FrameResult) -> Result<(), OperatorError> {
    let err = |e: std::io::Error| OperatorError::output(path, "write the point cloud", e);
    let n: usize = frame.objects.iter().map(|o| o.points.len()).sum();
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(err)?);
    write!(
        out,
        "ply\nformat ascii 1.0\ncomment metamoran fused depth, frame {}, radar frame (x right, y down, z forward), m\n\
         element vertex {n}\nproperty float x\nproperty float y\nproperty float z\nproperty int instance\nend_header\n",
        frame.frame
    )
    .map_err(err)?;
    for o in &frame.objects {
        for p in &o.points {
            writeln!(out, "{} {} {} {}", p[0], p[1], p[2], o.instance).map_err(err)?;
        }
    }
    out.flush().map_err(err)
}

#[cfg(test)]
mod tests {
    use super::*;
    use metamoran_bundle::CameraConfig;
    use metamoran_process::ObjectEstimate;

    #[test]
    fn the_nearest_point_wins_a_pixel_and_depths_are_kitti_encoded() {
        let camera = CameraModel::new(&CameraConfig {
            width: 64,
            height: 36,
            fx: 50.0,
            fy: 50.0,
            cx: 32.0,
            cy: 18.0,
            translation_m: [0.0; 3],
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            roll_deg: 0.0,
        });
        // Pixel (42, 18) is crossed at x/z = (42.5 - 32) / 50.
        let on = |z: f64| [10.5 / 50.0 * z, 0.5 / 50.0 * z, z];
        let object = |instance, points| ObjectEstimate {
            points,
            ..ObjectEstimate::unprocessed(instance, "person")
        };
        let frame = FrameResult::new(
            0,
            vec![
                object(1, vec![on(12.0), on(300.0)]),
                object(2, vec![on(10.25), [0.0, 0.0, -5.0]]),
            ],
        );
        let img = kitti_depth(&camera, &frame);
        assert_eq!(img[18 * 64 + 42], 2624); // 10.25 m × 256
        assert_eq!(img.iter().filter(|&&v| v != 0).count(), 1);
        assert_eq!(rasterize(&camera, &frame)[18 * 64 + 42], Some((10.25, 2)));
    }
}
