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

/// Which pixels a nearer one hides: a pixel is dropped when a pixel within `cols` columns and
/// `rows` rows of it is nearer by more than `margin_m` plus `relative` of its range. A radar
/// beam is wider than a pixel, so a submap's points of a wall seen past a pole or a parked car
/// from earlier poses land beside that object's own points in the current view, where the
/// lidar sees the object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Visibility {
    /// Columns either side (0.25° each).
    pub cols: usize,
    /// Rows either side (0.5° each).
    pub rows: usize,
    /// Nearer by at least this, m …
    pub margin_m: f32,
    /// … plus this share of the pixel's range.
    pub relative: f32,
}

impl Visibility {
    /// The imaging board's beam: ±6 columns (1.5°), ±4 rows (2°); nearer by 1 m + 5 %.
    pub const IMAGING_BEAM: Self = Self {
        cols: 6,
        rows: 4,
        margin_m: 1.0,
        relative: 0.05,
    };
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

    /// The image without the pixels something nearer hides ([`Visibility`]). O(pixels ·
    /// window).
    pub fn visible(&self, v: &Visibility) -> Self {
        let Visibility {
            cols,
            rows,
            margin_m,
            relative,
        } = *v;
        let mut out = self.clone();
        for r in 0..HEIGHT {
            for c in 0..WIDTH {
                let here = self.range_m[r * WIDTH + c];
                if here <= 0.0 {
                    continue;
                }
                let limit = here - margin_m - relative * here;
                let hidden = (r.saturating_sub(rows)..(r + rows + 1).min(HEIGHT)).any(|rr| {
                    (c.saturating_sub(cols)..(c + cols + 1).min(WIDTH)).any(|cc| {
                        let v = self.range_m[rr * WIDTH + cc];
                        v > 0.0 && v < limit
                    })
                });
                if hidden {
                    out.range_m[r * WIDTH + c] = 0.0;
                }
            }
        }
        out
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
    fn a_pixel_beside_a_nearer_one_is_hidden_and_others_stay() {
        let mut img = DepthImage::default();
        let mut set = |row: usize, col: usize, r: f32| img.range_m[row * WIDTH + col] = r;
        set(40, 100, 5.0); // a pole
        set(43, 105, 20.0); // the wall behind it, 3 rows and 5 columns off: hidden
        set(40, 108, 20.0); // 7 columns past the nearest: outside the window, kept
        set(39, 101, 5.8); // nearer by less than 1 m + 5 %: the pole itself, kept
        let v = img.visible(&Visibility::IMAGING_BEAM);
        let at = |row: usize, col: usize| v.range_m[row * WIDTH + col];
        assert_eq!(
            (at(40, 100), at(43, 105), at(40, 108), at(39, 101)),
            (5.0, 0.0, 20.0, 5.8)
        );
        assert_eq!(v.filled(), 3);
    }

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
