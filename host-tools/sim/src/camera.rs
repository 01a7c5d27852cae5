//! The camera side of a simulated scene: z-buffered rendering of the instance mask and true
//! depth, then what a segmenter and a monocular depth network would make of it.
//!
//! Monocular depth keeps an object's shape roughly right but misses its absolute depth by an
//! amount that grows with range, drawn so that the median absolute error follows the
//! Metamoran paper's Table I (≈0.6 m at 0–20 m, ≈7 m at 20–40 m, ≈19 m at 40–60 m).
//! Mask boundaries bleed toward the background depth, and masks are sometimes a pixel too
//! large or too small.

use super::object::{GROUND_Y, SceneObject};
use crate::Difficulty;
use metamoran_bundle::geometry::CameraModel;
use rand::Rng;
use rand_distr::StandardNormal;

/// The rendered truth: instance id and camera depth per pixel (row-major).
pub struct Render {
    /// Instance id, 0 for ground and sky.
    pub ids: Vec<u16>,
    /// Camera depth (along the optical axis), m; infinite for sky.
    pub depth: Vec<f64>,
}

/// Ray-casts every pixel against the objects and the ground plane.
pub fn render(cam: &CameraModel, objects: &[SceneObject]) -> Render {
    let (w, h) = (cam.width, cam.height);
    let o = cam.centre();
    let mut ids = vec![0u16; (w * h) as usize];
    let mut depth = vec![f64::INFINITY; (w * h) as usize];
    for v in 0..h {
        for u in 0..w {
            let (d, kz) = cam.ray(u, v);
            let mut best = if d.y > 1e-9 {
                (GROUND_Y - o.y) / d.y
            } else {
                f64::INFINITY
            };
            let mut id = 0;
            for obj in objects {
                if let Some(t) = obj.shape.intersect(&o, &d) {
                    if t < best {
                        best = t;
                        id = obj.id;
                    }
                }
            }
            let i = (v * w + u) as usize;
            ids[i] = id;
            depth[i] = best * kz;
        }
    }
    Render { ids, depth }
}

/// Median absolute monocular depth error at depth `z` under `difficulty`: Table I extrapolated
/// linearly ([`Difficulty::Standard`]), or growing on past 50 m at Table I's 30–50 m slope
/// (0.63 m per m: 45 m at 90 m, 177 m at 300 m; [`Difficulty::Hard`]).
pub fn median_error_for(z: f64, difficulty: Difficulty) -> f64 {
    match difficulty {
        Difficulty::Hard if z > 50.0 => 19.4 + (19.4 - 7.0) / 20.0 * (z - 50.0),
        _ => median_error(z),
    }
}

/// Median absolute monocular depth error at depth `z` (Table I, extrapolated linearly).
pub fn median_error(z: f64) -> f64 {
    const KNOTS: [(f64, f64); 6] = [
        (0.0, 0.1),
        (10.0, 0.6),
        (30.0, 7.0),
        (50.0, 19.0),
        (90.0, 40.0),
        (300.0, 150.0),
    ];
    for win in KNOTS.windows(2) {
        let ((z0, e0), (z1, e1)) = (win[0], win[1]);
        if z <= z1 {
            return e0 + (e1 - e0) * (z - z0).max(0.0) / (z1 - z0);
        }
    }
    KNOTS[KNOTS.len() - 1].1
}

/// What the segmenter and the monocular network output.
pub struct CameraProducts {
    /// Instance mask (with segmentation errors).
    pub mask: Vec<u16>,
    /// Monocular depth, metres × 256, 0 = none.
    pub depth_png: Vec<u16>,
}

/// Turns the rendered truth into segmenter and monocular-depth outputs.
pub fn products(
    render: &Render,
    width: u32,
    height: u32,
    difficulty: Difficulty,
    rng: &mut impl Rng,
) -> CameraProducts {
    let (w, h) = (width as usize, height as usize);
    let n = w * h;
    let max_id = render.ids.iter().copied().max().unwrap_or(0) as usize;
    // One absolute error per instance (and one for the ground), sized by its nearest depth.
    let mut nearest = vec![f64::INFINITY; max_id + 1];
    for (&id, &z) in render.ids.iter().zip(&render.depth) {
        nearest[id as usize] = nearest[id as usize].min(z);
    }
    let offsets: Vec<f64> = nearest
        .iter()
        .map(|&z| {
            let z = if z.is_finite() { z } else { 10.0 };
            let g: f64 = rng.sample(StandardNormal);
            // |N(0,1)| has median 0.6745: scale so the median |error| is median_error(z).
            let e = g * median_error_for(z, difficulty) / 0.6745;
            e.max(0.5 - z)
        })
        .collect();
    let mut est: Vec<f64> = (0..n)
        .map(|i| {
            let z = render.depth[i];
            if !z.is_finite() {
                return 0.0;
            }
            let id = render.ids[i] as usize;
            let shape_noise: f64 =
                rng.sample::<f64, _>(StandardNormal) * (0.02 + 0.01 * (z - nearest[id]).max(0.0));
            let ground_scale = if id == 0 {
                z / nearest[0].max(1.0)
            } else {
                1.0
            };
            (z + offsets[id] * ground_scale.min(3.0) + shape_noise).max(0.5)
        })
        .collect();
    // Segmentation errors per instance: grow or shrink by a pixel (up to two when hard).
    let mut mask = render.ids.clone();
    for id in 1..=max_id as u16 {
        let times = match difficulty {
            Difficulty::Standard => 1,
            Difficulty::Hard => rng.random_range(1..=2),
        };
        match rng.random_range(0..10) {
            0..=3 => (0..times).for_each(|_| grow(&mut mask, w, h, id)),
            4..=5 => (0..times).for_each(|_| shrink(&mut mask, w, h, id)),
            _ => {}
        }
    }
    // Boundary bleed: mask pixels next to another depth take part of that depth.
    let snapshot = est.clone();
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            if mask[i] == 0 {
                continue;
            }
            let neighbours = [
                (x > 0).then(|| i - 1),
                (x + 1 < w).then(|| i + 1),
                (y > 0).then(|| i - w),
                (y + 1 < h).then(|| i + w),
            ];
            let outside = neighbours
                .into_iter()
                .flatten()
                .filter(|&j| mask[j] != mask[i])
                .map(|j| snapshot[j])
                .fold(0.0, f64::max);
            if outside > snapshot[i] && rng.random_range(0.0..1.0) < 0.6 {
                let t: f64 = rng.random_range(0.2..0.9);
                est[i] = snapshot[i] + t * (outside - snapshot[i]);
            }
        }
    }
    let depth_png = est
        .iter()
        .map(|&z| {
            if z > 0.0 && z < 255.99 {
                (z * 256.0).round() as u16
            } else {
                0
            }
        })
        .collect();
    CameraProducts { mask, depth_png }
}

fn grow(mask: &mut [u16], w: usize, h: usize, id: u16) {
    let src = mask.to_vec();
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            if src[i] == 0
                && ((x > 0 && src[i - 1] == id)
                    || (x + 1 < w && src[i + 1] == id)
                    || (y > 0 && src[i - w] == id)
                    || (y + 1 < h && src[i + w] == id))
            {
                mask[i] = id;
            }
        }
    }
}

fn shrink(mask: &mut [u16], w: usize, h: usize, id: u16) {
    let src = mask.to_vec();
    let count = src.iter().filter(|&&m| m == id).count();
    if count < 30 {
        return; // keep small (distant) objects whole
    }
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            if src[i] == id
                && ((x > 0 && src[i - 1] != id)
                    || (x + 1 < w && src[i + 1] != id)
                    || (y > 0 && src[i - w] != id)
                    || (y + 1 < h && src[i + w] != id))
            {
                mask[i] = 0;
            }
        }
    }
}

#[cfg(test)]
mod difficulty_tests {
    use super::{Difficulty, median_error, median_error_for};

    #[test]
    fn hard_monocular_error_keeps_table_one_slope_past_50_m() {
        for z in [5.0, 30.0, 50.0] {
            assert_eq!(median_error_for(z, Difficulty::Hard), median_error(z));
        }
        // Table I: 7 m at 30 m, 19.4 m at 50 m; 0.62 m per m on from there.
        assert!((median_error_for(90.0, Difficulty::Hard) - 44.2).abs() < 1e-9);
        assert!((median_error_for(300.0, Difficulty::Hard) - 174.4).abs() < 1e-9);
        assert!(median_error_for(300.0, Difficulty::Hard) > median_error(300.0));
    }
}
