//! An RGB image as the networks take it: planar (channel, row, column) `f32` in `0..=1`.

/// A planar RGB image.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// `3 × height × width` values in `0..=1`: all red, then green, then blue, rows top down.
    pub planes: Vec<f32>,
}

impl Image {
    /// From interleaved samples (`RGBRGB…` or `RGBARGBA…` with `channels` = 3 or 4) whose full
    /// scale is `max` (255 for 8-bit, 65535 for 16-bit PNGs). `None` if the sizes disagree.
    pub fn from_interleaved(
        width: usize,
        height: usize,
        channels: usize,
        max: f32,
        samples: &[u16],
    ) -> Option<Self> {
        if !(3..=4).contains(&channels) || samples.len() != width * height * channels {
            return None;
        }
        let n = width * height;
        let mut planes = vec![0.0; 3 * n];
        for (i, px) in samples.chunks_exact(channels).enumerate() {
            for c in 0..3 {
                planes[c * n + i] = f32::from(px[c]) / max;
            }
        }
        Some(Self {
            width,
            height,
            planes,
        })
    }

    /// Bilinear resize (pixel centres aligned, as ONNX `Resize` with `half_pixel`). O(3·w·h).
    pub fn resized(&self, width: usize, height: usize) -> Self {
        if (width, height) == (self.width, self.height) {
            return self.clone();
        }
        let (sx, sy) = (
            self.width as f32 / width as f32,
            self.height as f32 / height as f32,
        );
        let coord = |o: usize, s: f32, len: usize| {
            let x = ((o as f32 + 0.5) * s - 0.5).clamp(0.0, (len - 1) as f32);
            let i = x.floor() as usize;
            (i, (i + 1).min(len - 1), x - i as f32)
        };
        let (n_in, n_out) = (self.width * self.height, width * height);
        let mut planes = vec![0.0; 3 * n_out];
        for y in 0..height {
            let (y0, y1, fy) = coord(y, sy, self.height);
            for x in 0..width {
                let (x0, x1, fx) = coord(x, sx, self.width);
                for c in 0..3 {
                    let p = &self.planes[c * n_in..(c + 1) * n_in];
                    let at = |yy: usize, xx: usize| p[yy * self.width + xx];
                    let top = at(y0, x0) + fx * (at(y0, x1) - at(y0, x0));
                    let bottom = at(y1, x0) + fx * (at(y1, x1) - at(y1, x0));
                    planes[c * n_out + y * width + x] = top + fy * (bottom - top);
                }
            }
        }
        Self {
            width,
            height,
            planes,
        }
    }
}

/// Nearest-neighbour resize of a `channels × height × width` map to `width_out × height_out`.
pub fn nearest(
    map: &[f32],
    channels: usize,
    (width, height): (usize, usize),
    (width_out, height_out): (usize, usize),
) -> Vec<f32> {
    if (width, height) == (width_out, height_out) {
        return map.to_vec();
    }
    let mut out = Vec::with_capacity(channels * width_out * height_out);
    for c in 0..channels {
        let plane = &map[c * width * height..(c + 1) * width * height];
        for y in 0..height_out {
            let sy = ((y * height) / height_out).min(height - 1);
            for x in 0..width_out {
                let sx = ((x * width) / width_out).min(width - 1);
                out.push(plane[sy * width + sx]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interleaved_samples_become_planes() {
        let img = Image::from_interleaved(2, 1, 4, 255.0, &[255, 0, 51, 9, 0, 255, 0, 9]).unwrap();
        assert_eq!(img.planes, vec![1.0, 0.0, 0.0, 1.0, 0.2, 0.0]);
        assert!(Image::from_interleaved(2, 2, 3, 255.0, &[0; 6]).is_none());
    }

    #[test]
    fn bilinear_resize_of_a_ramp_is_exact() {
        // A linear ramp stays linear under bilinear resampling: value = x + 10·y at the output
        // pixel's centre, mapped back into the input (closed form).
        let (w, h) = (8, 4);
        let mut planes = Vec::new();
        for _ in 0..3 {
            for y in 0..h {
                for x in 0..w {
                    planes.push((x + 10 * y) as f32);
                }
            }
        }
        let img = Image {
            width: w,
            height: h,
            planes,
        };
        let small = img.resized(4, 2);
        for y in 0..2 {
            for x in 0..4 {
                let (ix, iy) = ((x as f32 + 0.5) * 2.0 - 0.5, (y as f32 + 0.5) * 2.0 - 0.5);
                assert!((small.planes[8 + y * 4 + x] - (ix + 10.0 * iy)).abs() < 1e-5);
            }
        }
        let same = nearest(&[1.0, 2.0, 3.0, 4.0], 1, (2, 2), (4, 2));
        assert_eq!(same, vec![1.0, 1.0, 2.0, 2.0, 3.0, 3.0, 4.0, 4.0]);
    }
}
