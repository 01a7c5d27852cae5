//! Cylindrical depth images (dense radar mapping, Sec. 3.3): each point at azimuth θ and
//! elevation φ lands in one pixel of a 320 × 80 grid over θ ∈ −40..40° (0.25°) and
//! φ ∈ −20..20° (0.5°); the pixel keeps the nearest point's horizontal range, which drops what
//! only diffraction lets the radar see behind it. Row 0 is the top (+20°), column 0 the left
//! (−40°). 0 means no point.

pub use metamoran_bundle::lidar::{AZ_STEP_DEG, EL_STEP_DEG, HEIGHT, WIDTH, pixel};

/// A depth image: horizontal range (m) per pixel, row-major, 0 = empty.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthImage {
    /// `WIDTH × HEIGHT` ranges, m.
    pub range_m: Vec<f32>,
}

impl Default for DepthImage {
    fn default() -> Self {
        Self {
            range_m: vec![0.0; WIDTH * HEIGHT],
        }
    }
}

impl DepthImage {
    /// Projects `points`, keeping the nearest per pixel. O(n).
    pub fn project(points: impl IntoIterator<Item = [f64; 3]>) -> Self {
        let mut img = Self::default();
        for p in points {
            if let Some((row, col, r)) = pixel(p) {
                let px = &mut img.range_m[row * WIDTH + col];
                if *px == 0.0 || (r as f32) < *px {
                    *px = r as f32;
                }
            }
        }
        img
    }

    /// Pixels with a point.
    pub fn filled(&self) -> usize {
        self.range_m.iter().filter(|&&r| r > 0.0).count()
    }

    /// The pixels' points (radar frame, m): each filled pixel's centre ray at its range.
    pub fn points(&self) -> Vec<[f64; 3]> {
        self.range_m
            .iter()
            .enumerate()
            .filter(|&(_, &r)| r > 0.0)
            .map(|(i, &r)| {
                let d = metamoran_bundle::lidar::ray(i / WIDTH, i % WIDTH);
                // The ray's horizontal length is cos(elevation); the pixel keeps horizontal range.
                let t = f64::from(r) / d[0].hypot(d[2]);
                [d[0] * t, d[1] * t, d[2] * t]
            })
            .collect()
    }

    /// KITTI encoding (m × 256, 0 = none) for a 16-bit PNG.
    pub fn kitti(&self) -> Vec<u16> {
        self.range_m
            .iter()
            .map(|&r| (f64::from(r) * 256.0).round().clamp(0.0, 65535.0) as u16)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_land_in_their_pixels_and_the_nearest_wins() {
        // Straight ahead at 10 m, level: column 160, row 40 (the pixel below the centre line's
        // top edge: elevation 0 is the top of row 40).
        assert_eq!(pixel([0.0, 0.0, 10.0]), Some((40, 160, 10.0)));
        // 30° left, 10° up, 20 m horizontal: column (−30 + 40)/0.25 = 40, row (20 − 10)/0.5 = 20.
        let (az, el, r) = ((-30.1f64).to_radians(), 9.9f64.to_radians(), 20.0);
        let p = [r * az.sin(), -r * el.tan(), r * az.cos()];
        let (row, col, range) = pixel(p).unwrap();
        assert_eq!((row, col), (20, 39));
        assert!((range - 20.0).abs() < 1e-9);
        assert_eq!(pixel([10.0, 0.0, 1.0]), None, "84° right is outside");
        let img = DepthImage::project([[0.0, 0.0, 10.0], [0.0, 0.0, 7.0], [0.0, 0.0, 12.0]]);
        assert_eq!(img.filled(), 1);
        assert_eq!(img.range_m[40 * WIDTH + 160], 7.0);
        assert_eq!(img.kitti()[40 * WIDTH + 160], 7 * 256);
        // Back to a point on the pixel's centre ray (0.125° right, 0.25° down) at 7 m.
        let back = img.points();
        assert_eq!(back.len(), 1);
        assert_eq!(pixel(back[0]).map(|(r, c, _)| (r, c)), Some((40, 160)));
        let (az, el) = (0.125f64.to_radians(), (-0.25f64).to_radians());
        let want = [7.0 * az.sin(), -7.0 * el.tan(), 7.0 * az.cos()];
        for k in 0..3 {
            assert!((back[0][k] - want[k]).abs() < 1e-9, "{back:?} vs {want:?}");
        }
    }
}
