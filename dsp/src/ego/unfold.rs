//! The radar's velocity when its radial velocities are folded: a board with many TDM slots
//! (the 4D imaging board's twelve) measures radial velocity only modulo `span = 2·v_max`
//! (±5 m/s), less than a street's static world moves past a car. Before any estimate exists
//! (the first frame, or after a frame without one) a grid search over the radar's velocity
//! finds the one most detections agree with modulo the span; that prior lets the point cloud
//! unfold each direction (`points::CloudOptions::velocity_prior`) and RANSAC
//! ([`super::velocity`]) refine it.
//!
//! Two velocities agree with a static scene modulo the span only if they differ by a multiple of
//! `span / cos θ` at every azimuth θ seen, so over a field of view of ±30° or more the true one
//! stands out.

use super::velocity::DopplerDetection;
use libm::{fabsf, roundf};

/// The velocities searched.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnfoldGrid {
    /// Largest forward speed `|v_z|`, m/s.
    pub max_forward_mps: f32,
    /// Largest sideways speed `|v_x|`, m/s.
    pub max_lateral_mps: f32,
    /// Grid step, m/s (at most the inlier threshold, so the true velocity's neighbour counts).
    pub step_mps: f32,
    /// Largest |residual| modulo the span of an agreeing detection, m/s.
    pub threshold_mps: f32,
}

impl Default for UnfoldGrid {
    /// ±40 m/s forward, ±4 m/s sideways, 0.2 m/s steps, 0.25 m/s (the RANSAC threshold): 401 ×
    /// 41 velocities.
    fn default() -> Self {
        Self {
            max_forward_mps: 40.0,
            max_lateral_mps: 4.0,
            step_mps: 0.2,
            threshold_mps: 0.25,
        }
    }
}

/// `r` folded into `[−span/2, span/2)`.
fn wrap(r: f32, span: f32) -> f32 {
    r - span * roundf(r / span)
}

/// The grid velocity `[v_x, v_z]` (m/s, radar frame) that the most of `dets` agree with modulo
/// `span_mps`, and how many; `None` without detections or with a span that is not positive.
/// O(grid · detections): about 16 000 · n residuals with the default grid.
pub fn search(
    dets: &[DopplerDetection],
    span_mps: f32,
    grid: &UnfoldGrid,
) -> Option<([f32; 2], usize)> {
    // Negated on purpose: a NaN span is refused too.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    if dets.is_empty() || !(span_mps > 0.0) || !(grid.step_mps > 0.0) {
        return None;
    }
    let steps = |max: f32| (max / grid.step_mps) as i32;
    let (nz, nx) = (steps(grid.max_forward_mps), steps(grid.max_lateral_mps));
    let mut best: Option<([f32; 2], usize)> = None;
    for iz in -nz..=nz {
        for ix in -nx..=nx {
            let v = [ix as f32 * grid.step_mps, iz as f32 * grid.step_mps];
            let agree = dets
                .iter()
                .filter(|d| fabsf(wrap(d.residual(v), span_mps)) <= grid.threshold_mps)
                .count();
            // Ties go to the slower velocity (equal counts at neighbouring grid points).
            let better = best.is_none_or(|(b, k)| {
                agree > k || (agree == k && v[0] * v[0] + v[1] * v[1] < b[0] * b[0] + b[1] * b[1])
            });
            if better {
                best = Some((v, agree));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    /// Static points over ±`fov`° azimuth seen from radar velocity `v`, radial velocities folded
    /// into ±span/2, plus movers at velocities of their own.
    fn folded(v: [f64; 2], fov: f64, span: f64, movers: usize) -> Vec<DopplerDetection> {
        (0..60 + movers)
            .map(|i| {
                let az = ((i % 60) as f64 / 59.0 * 2.0 - 1.0) * fov.to_radians();
                let mut vr = -(az.sin() * v[0] + az.cos() * v[1]);
                if i >= 60 {
                    vr += 1.3 + 0.37 * (i - 60) as f64;
                }
                let vr = vr - span * (vr / span).round();
                DopplerDetection::at(az as f32, 0.0, vr as f32)
            })
            .collect()
    }

    #[test]
    fn a_street_folded_into_ten_metres_per_second_gives_the_velocity() {
        let span = 10.26;
        for v in [[0.0, 3.0], [0.4, 8.7], [-1.1, 13.9], [0.0, -6.2]] {
            let dets = folded(v, 40.0, span, 15);
            let (got, agree) = search(&dets, span as f32, &UnfoldGrid::default()).unwrap();
            assert!(agree >= 60, "{v:?}: {agree}");
            for k in 0..2 {
                // Within one grid step.
                assert!(
                    (f64::from(got[k]) - v[k]).abs() <= 0.2 + 1e-4,
                    "{v:?} {got:?}"
                );
            }
        }
    }

    #[test]
    fn no_detections_or_no_span_give_nothing() {
        let grid = UnfoldGrid::default();
        assert_eq!(search(&[], 10.0, &grid), None);
        let dets = folded([0.0, 3.0], 40.0, 10.0, 0);
        assert_eq!(search(&dets, 0.0, &grid), None);
        assert_eq!(search(&dets, f32::NAN, &grid), None);
    }
}
