//! The radar's velocity from the radial velocities of static detections: RANSAC over the
//! cosine relation, then least squares on the inliers.
//!
//! A static point in direction `u` (unit line of sight) seen from a radar moving with velocity
//! `v = (v_x, 0, v_z)` has radial velocity `v_r = −u · v = −(u_x·v_x + u_z·v_z)` (positive
//! away). With no elevation, `u = (sin θ, 0, cos θ)` and this is the paper's cosine curve
//! `v_r = −|v| cos(θ − α)`. It is linear in `(v_x, v_z)`: two detections fix it, so RANSAC draws
//! pairs, keeps the model most detections agree with (within a threshold), and refits it by least
//! squares on those (nalgebra's Cholesky on the 2 × 2 normal equations). Deterministic: the
//! pairs come from a seeded xorshift generator.

use libm::{fabsf, sqrtf};
use nalgebra::{Matrix2, Vector2};

/// One detection as ego-motion sees it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DopplerDetection {
    /// Unit line of sight in the radar frame (x right, y down, z forward).
    pub direction: [f32; 3],
    /// Radial velocity, m/s, positive away from the radar.
    pub radial_velocity: f32,
}

impl DopplerDetection {
    /// A detection at azimuth `azimuth` and elevation `elevation` (rad; azimuth positive to the
    /// right, elevation positive up) with radial velocity `radial_velocity` (m/s).
    pub fn at(azimuth: f32, elevation: f32, radial_velocity: f32) -> Self {
        let (se, ce) = libm::sincosf(elevation);
        let (sa, ca) = libm::sincosf(azimuth);
        Self {
            direction: [ce * sa, -se, ce * ca],
            radial_velocity,
        }
    }

    /// How far (m/s) this detection's radial velocity is from a static point's under radar
    /// velocity `v = [v_x, v_z]`.
    pub fn residual(&self, v: [f32; 2]) -> f32 {
        self.radial_velocity + self.direction[0] * v[0] + self.direction[2] * v[1]
    }
}

/// RANSAC settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ransac {
    /// Pairs drawn.
    pub iterations: u16,
    /// Largest |residual| of an inlier, m/s (about three Doppler-noise sigmas).
    pub threshold_mps: f32,
    /// Fewest inliers for an estimate.
    pub min_inliers: u16,
    /// Seed of the pair generator (nonzero).
    pub seed: u32,
}

impl Default for Ransac {
    /// 200 pairs, 0.25 m/s, 6 inliers: with half the detections on movers a good pair is drawn
    /// with probability 1 − 0.75^200.
    fn default() -> Self {
        Self {
            iterations: 200,
            threshold_mps: 0.25,
            min_inliers: 6,
            seed: 0x9E37_79B9,
        }
    }
}

/// The radar's velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EgoVelocity {
    /// `[v_x, v_z]`, m/s, in the radar frame (x right, z forward).
    pub velocity: [f32; 2],
    /// Detections consistent with it (static).
    pub inliers: u16,
    /// Root mean square residual of the inliers, m/s.
    pub rms_mps: f32,
}

impl EgoVelocity {
    /// Speed, m/s.
    pub fn speed(&self) -> f32 {
        sqrtf(self.velocity[0] * self.velocity[0] + self.velocity[1] * self.velocity[1])
    }
}

/// Why there is no estimate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum EgoError {
    /// Fewer detections than [`Ransac::min_inliers`] agree on any velocity.
    TooFewInliers {
        /// The best consensus found.
        best: u16,
    },
    /// The inliers all lie along one line of sight: the velocity across it is unobservable.
    Degenerate,
    /// `inliers` (the mask) is shorter than the detections.
    MaskTooShort,
}

impl core::error::Error for EgoError {}

impl core::fmt::Display for EgoError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            EgoError::TooFewInliers { best } => write!(
                f,
                "only {best} detections agree on an ego-velocity; need more static reflectors in view (or a larger threshold)"
            ),
            EgoError::Degenerate => write!(
                f,
                "the static detections share one line of sight; the velocity across it cannot be seen"
            ),
            EgoError::MaskTooShort => write!(f, "the inlier mask is shorter than the detections"),
        }
    }
}

/// xorshift32: the pair generator.
struct XorShift(u32);

impl XorShift {
    fn below(&mut self, n: usize) -> usize {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        ((x as u64 * n as u64) >> 32) as usize
    }
}

/// Least squares `v` minimizing `Σ (v_r + u_x·v_x + u_z·v_z)²` over the detections `keep`
/// selects: the 2 × 2 normal equations `AᵀA v = −Aᵀ v_r` by Cholesky (nalgebra). `None` if
/// they are (near) singular: the lines of sight are parallel.
fn least_squares(dets: &[DopplerDetection], keep: impl Fn(usize) -> bool) -> Option<[f32; 2]> {
    let mut ata = Matrix2::<f32>::zeros();
    let mut atb = Vector2::<f32>::zeros();
    for (i, d) in dets.iter().enumerate() {
        if keep(i) {
            let a = Vector2::new(d.direction[0], d.direction[2]);
            ata += a * a.transpose();
            atb -= a * d.radial_velocity;
        }
    }
    // Relative to the scale of the sums: parallel lines of sight make the determinant vanish.
    let scale = ata[(0, 0)] * ata[(1, 1)];
    // Negated on purpose: a NaN determinant is rejected too.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    if !(ata.determinant() > 1e-6 * scale.max(f32::MIN_POSITIVE)) {
        return None;
    }
    let v = ata.cholesky()?.solve(&atb);
    Some([v[0], v[1]])
}

/// Estimates the radar's velocity from `dets`; marks the static ones (inliers) in `inliers`.
/// O(iterations · n).
///
/// # Errors
/// [`EgoError`] when too few detections agree, the inliers are degenerate, or the mask is short.
pub fn estimate(
    dets: &[DopplerDetection],
    config: &Ransac,
    inliers: &mut [bool],
) -> Result<EgoVelocity, EgoError> {
    let n = dets.len();
    if inliers.len() < n {
        return Err(EgoError::MaskTooShort);
    }
    let inliers = &mut inliers[..n];
    let thr = config.threshold_mps;
    let count = |v: [f32; 2]| dets.iter().filter(|d| fabsf(d.residual(v)) <= thr).count();
    let mut best: Option<([f32; 2], usize)> = None;
    if n >= 2 {
        let mut rng = XorShift(config.seed.max(1));
        for _ in 0..config.iterations {
            let a = rng.below(n);
            let b = (a + 1 + rng.below(n - 1)) % n;
            let Some(v) = least_squares(dets, |i| i == a || i == b) else {
                continue;
            };
            let c = count(v);
            if best.is_none_or(|(_, k)| c > k) {
                best = Some((v, c));
            }
        }
    }
    let (v, k) = best.unwrap_or(([0.0; 2], 0));
    if k < usize::from(config.min_inliers) {
        return Err(EgoError::TooFewInliers { best: k as u16 });
    }
    // Refit on the consensus, then take the consensus of the refit once more.
    let mut v = v;
    for _ in 0..2 {
        for (m, d) in inliers.iter_mut().zip(dets) {
            *m = fabsf(d.residual(v)) <= thr;
        }
        v = least_squares(dets, |i| inliers[i]).ok_or(EgoError::Degenerate)?;
    }
    let mut used = 0u16;
    let mut sq = 0f32;
    for (m, d) in inliers.iter_mut().zip(dets) {
        let r = d.residual(v);
        *m = fabsf(r) <= thr;
        if *m {
            used += 1;
            sq += r * r;
        }
    }
    if used < config.min_inliers {
        return Err(EgoError::TooFewInliers { best: used });
    }
    Ok(EgoVelocity {
        velocity: v,
        inliers: used,
        rms_mps: sqrtf(sq / f32::from(used)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;
    use std::vec::Vec;

    /// A deterministic scene: `n` static points over ±60° azimuth and ±10° elevation, radial
    /// velocities from radar velocity `v` plus uniform noise of ±`noise`, and `movers`
    /// detections with velocities of their own.
    fn scene(v: [f64; 2], n: usize, noise: f64, movers: usize) -> Vec<DopplerDetection> {
        let mut rng = XorShift(12345);
        let mut u = || rng.below(1 << 20) as f64 / f64::from(1 << 20);
        let mut out = Vec::new();
        for i in 0..n + movers {
            let az = (u() * 2.0 - 1.0) * 60f64.to_radians();
            let el = (u() * 2.0 - 1.0) * 10f64.to_radians();
            let (ux, uz) = (el.cos() * az.sin(), el.cos() * az.cos());
            let mut vr = -(ux * v[0] + uz * v[1]) + (u() * 2.0 - 1.0) * noise;
            if i >= n {
                vr += 2.0 + 6.0 * u(); // a mover: at least 2 m/s off the cosine
            }
            out.push(DopplerDetection::at(az as f32, el as f32, vr as f32));
        }
        out
    }

    #[test]
    fn exact_radial_velocities_give_the_velocity() {
        let v = [0.8, 11.5];
        let dets = scene(v, 40, 0.0, 0);
        let mut mask = [false; 40];
        let e = estimate(&dets, &Ransac::default(), &mut mask).unwrap();
        assert_eq!(e.inliers, 40);
        assert!((f64::from(e.velocity[0]) - v[0]).abs() < 1e-4, "{e:?}");
        assert!((f64::from(e.velocity[1]) - v[1]).abs() < 1e-4, "{e:?}");
        assert!((f64::from(e.speed()) - v[0].hypot(v[1])).abs() < 1e-4);
    }

    #[test]
    fn movers_are_outliers_and_noise_averages_out() {
        // 60 static points with ±0.1 m/s noise and 40 movers (40 % outliers).
        let v = [-1.2, 7.0];
        let dets = scene(v, 60, 0.1, 40);
        let mut mask = [false; 100];
        let e = estimate(&dets, &Ransac::default(), &mut mask).unwrap();
        assert!(
            mask[..60].iter().all(|&m| m),
            "every static point is an inlier"
        );
        assert!(mask[60..].iter().all(|&m| !m), "no mover is");
        // Least squares on 60 points with uniform ±0.1 noise (σ = 0.058): well under 0.05.
        let err = (f64::from(e.velocity[0]) - v[0]).hypot(f64::from(e.velocity[1]) - v[1]);
        assert!(err < 0.05, "error {err} m/s ({e:?})");
        assert!(e.rms_mps < 0.1);
    }

    #[test]
    fn too_few_or_degenerate_detections_are_errors() {
        let dets = scene([0.0, 5.0], 4, 0.0, 0);
        let mut mask = [false; 4];
        assert_eq!(
            estimate(&dets, &Ransac::default(), &mut mask),
            Err(EgoError::TooFewInliers { best: 4 })
        );
        // Every detection straight ahead: the sideways velocity is unobservable.
        let ahead = [DopplerDetection::at(0.0, 0.0, -5.0); 10];
        let mut mask = [false; 10];
        assert!(estimate(&ahead, &Ransac::default(), &mut mask).is_err());
        let mut short = [false; 3];
        assert_eq!(
            estimate(&ahead, &Ransac::default(), &mut short),
            Err(EgoError::MaskTooShort)
        );
        assert!(EgoError::Degenerate.to_string().contains("line of sight"));
    }
}
