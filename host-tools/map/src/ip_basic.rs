//! Depth completion by image morphology (IP-Basic, Ku et al. 2018, `fill_in_fast` with Gaussian
//! blur and no extrapolation), the paper's completion of radar depth images:
//!
//! 1. invert the valid depths (`100 − d`), so that dilation prefers the nearest surface;
//! 2. dilate with a 5 × 5 diamond; 3. close (dilate, then erode) with a 5 × 5 square;
//! 4. fill empty pixels from a 7 × 7 dilation; 5. fill what is still empty from a 31 × 31
//!    dilation; 6. 5 × 5 median; 7. 5 × 5 Gaussian (1 4 6 4 1)/16 on the valid pixels;
//! 8. invert back.
//!
//! Border handling follows OpenCV's defaults, which the reference test runs: morphology ignores
//! pixels outside, the median replicates the edge, the Gaussian reflects (`dcb|abcd|cba`).

use super::cylinder::{HEIGHT, WIDTH};

/// Depth (m) the inversion subtracts from; valid depths must be below it.
pub const MAX_DEPTH: f32 = 100.0;

/// A kernel as the list of its offsets from the centre.
fn square(size: i32) -> Vec<(i32, i32)> {
    let h = size / 2;
    (-h..=h)
        .flat_map(|dy| (-h..=h).map(move |dx| (dy, dx)))
        .collect()
}

fn diamond5() -> Vec<(i32, i32)> {
    square(5)
        .into_iter()
        .filter(|(dy, dx)| dy.abs() + dx.abs() <= 2)
        .collect()
}

/// Grey dilation (`max`) or erosion (`min`) over `kernel`, ignoring pixels outside.
fn morph(img: &[f32], kernel: &[(i32, i32)], max: bool) -> Vec<f32> {
    let (w, h) = (WIDTH as i32, HEIGHT as i32);
    let mut out = vec![0.0; img.len()];
    for y in 0..h {
        for x in 0..w {
            let mut v = if max {
                f32::NEG_INFINITY
            } else {
                f32::INFINITY
            };
            for &(dy, dx) in kernel {
                let (yy, xx) = (y + dy, x + dx);
                if (0..h).contains(&yy) && (0..w).contains(&xx) {
                    let s = img[(yy * w + xx) as usize];
                    v = if max { v.max(s) } else { v.min(s) };
                }
            }
            out[(y * w + x) as usize] = v;
        }
    }
    out
}

/// [`morph`] over a `size × size` square, as two passes: along rows, then along columns. The
/// extreme of a square is the extreme of its rows' extremes, so the result is the same value
/// for value. Each pass is van Herk / Gil-Werman's: about three comparisons per pixel whatever
/// the size, so O(pixels) where the full kernel is O(pixels · size²).
fn morph_square(img: &[f32], size: i32, max: bool) -> Vec<f32> {
    let (w, h) = (WIDTH, HEIGHT);
    let mut rows = vec![0.0; img.len()];
    let mut line = Line::new(size as usize, max);
    for y in 0..h {
        line.run(&img[y * w..(y + 1) * w], &mut rows[y * w..(y + 1) * w]);
    }
    let (mut column, mut out_column) = (vec![0.0; h], vec![0.0; h]);
    let mut out = vec![0.0; img.len()];
    for x in 0..w {
        for (y, c) in column.iter_mut().enumerate() {
            *c = rows[y * w + x];
        }
        line.run(&column, &mut out_column);
        for (y, &v) in out_column.iter().enumerate() {
            out[y * w + x] = v;
        }
    }
    out
}

/// The running maximum (or minimum) of every window of `size` along a line, pixels outside
/// ignored (padded with the identity, −∞ or +∞, which never wins: every window holds at least
/// its own centre). The padded line is cut into blocks of `size`; a prefix extreme runs forward
/// and a suffix extreme backward within each block, and a window, which spans at most two
/// blocks, is the extreme of the first one's suffix and the second one's prefix.
struct Line {
    size: usize,
    max: bool,
    padded: Vec<f32>,
    prefix: Vec<f32>,
    suffix: Vec<f32>,
}

impl Line {
    fn new(size: usize, max: bool) -> Self {
        Self {
            size,
            max,
            padded: Vec::new(),
            prefix: Vec::new(),
            suffix: Vec::new(),
        }
    }

    fn pick(&self, a: f32, b: f32) -> f32 {
        if self.max { a.max(b) } else { a.min(b) }
    }

    fn run(&mut self, src: &[f32], out: &mut [f32]) {
        let (k, r) = (self.size, self.size / 2);
        let identity = if self.max {
            f32::NEG_INFINITY
        } else {
            f32::INFINITY
        };
        // src in the middle, r identities before it and enough after to fill the last block
        let n = (src.len() + 2 * r).div_ceil(k) * k;
        self.padded.clear();
        self.padded.resize(r, identity);
        self.padded.extend_from_slice(src);
        self.padded.resize(n, identity);
        self.prefix.resize(n, identity);
        self.suffix.resize(n, identity);
        for i in 0..n {
            let v = self.padded[i];
            self.prefix[i] = if i % k == 0 {
                v
            } else {
                self.pick(self.prefix[i - 1], v)
            };
        }
        for i in (0..n).rev() {
            let v = self.padded[i];
            self.suffix[i] = if i % k == k - 1 {
                v
            } else {
                self.pick(self.suffix[i + 1], v)
            };
        }
        // output i is the window padded[i ..= i + k − 1]
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.pick(self.suffix[i], self.prefix[i + k - 1]);
        }
    }
}

fn fill_empty(img: &mut [f32], size: i32) {
    let dilated = morph_square(img, size, true);
    for (v, d) in img.iter_mut().zip(dilated) {
        if *v < 0.1 {
            *v = d;
        }
    }
}

/// 5 × 5 median with replicated edges.
fn median5(img: &[f32]) -> Vec<f32> {
    let (w, h) = (WIDTH as i32, HEIGHT as i32);
    let mut out = vec![0.0; img.len()];
    let mut window = [0f32; 25];
    let kernel = square(5);
    for y in 0..h {
        for x in 0..w {
            for (k, &(dy, dx)) in kernel.iter().enumerate() {
                let (yy, xx) = ((y + dy).clamp(0, h - 1), (x + dx).clamp(0, w - 1));
                window[k] = img[(yy * w + xx) as usize];
            }
            out[(y * w + x) as usize] = *window.select_nth_unstable_by(12, f32::total_cmp).1;
        }
    }
    out
}

/// Index `i` of an axis of length `n`, reflected without repeating the edge (`dcb|abcd|cba`).
fn reflect101(i: i32, n: i32) -> i32 {
    if i < 0 {
        -i
    } else if i >= n {
        2 * n - 2 - i
    } else {
        i
    }
}

/// 5 × 5 Gaussian (OpenCV's fixed kernel for σ = 0: 1 4 6 4 1 / 16), separable: rows, then
/// columns.
fn gaussian5(img: &[f32]) -> Vec<f32> {
    const K: [f32; 5] = [0.0625, 0.25, 0.375, 0.25, 0.0625];
    let (w, h) = (WIDTH as i32, HEIGHT as i32);
    let mut rows = vec![0.0; img.len()];
    for y in 0..h {
        for x in 0..w {
            rows[(y * w + x) as usize] = (0..5)
                .map(|k| K[k as usize] * img[(y * w + reflect101(x + k - 2, w)) as usize])
                .sum();
        }
    }
    let mut out = vec![0.0; img.len()];
    for y in 0..h {
        for x in 0..w {
            out[(y * w + x) as usize] = (0..5)
                .map(|k| K[k as usize] * rows[(reflect101(y + k - 2, h) * w + x) as usize])
                .sum();
        }
    }
    out
}

/// Completes a `WIDTH × HEIGHT` depth image (m, 0 = empty). O(pixels · 31) for the large fill.
pub fn complete(depth: &[f32]) -> Vec<f32> {
    let mut img: Vec<f32> = depth
        .iter()
        .map(|&d| if d > 0.1 { MAX_DEPTH - d } else { d })
        .collect();
    img = morph(&img, &diamond5(), true);
    img = morph_square(&morph_square(&img, 5, true), 5, false);
    fill_empty(&mut img, 7);
    fill_empty(&mut img, 31);
    img = median5(&img);
    let blurred = gaussian5(&img);
    for (v, b) in img.iter_mut().zip(blurred) {
        if *v > 0.1 {
            *v = b;
        }
    }
    for v in &mut img {
        if *v > 0.1 {
            *v = MAX_DEPTH - *v;
        }
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separable_squares_are_the_full_kernels_value_for_value() {
        // A sparse image with distinct values (a few hundred depths, the rest empty), as IP-Basic
        // sees after inversion; the edges and corners test the clipping.
        let mut img = vec![0.0f32; WIDTH * HEIGHT];
        let mut state = 12_345u32;
        for _ in 0..400 {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let i = (state >> 8) as usize % img.len();
            img[i] = (state % 9_000) as f32 / 100.0 + 1.0;
        }
        for &i in &[0, WIDTH - 1, WIDTH * (HEIGHT - 1), WIDTH * HEIGHT - 1] {
            img[i] = 77.25;
        }
        for size in [5, 7, 31] {
            for max in [true, false] {
                let dense = morph(&img, &square(size), max);
                assert_eq!(
                    morph_square(&img, size, max),
                    dense,
                    "size {size}, max {max}"
                );
                // and on a dense image, where erosion has something to find
                assert_eq!(
                    morph_square(&dense, size, !max),
                    morph(&dense, &square(size), !max),
                    "dense, size {size}, max {}",
                    !max
                );
            }
        }
    }
}
