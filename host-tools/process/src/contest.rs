//! One reflection, one object. Each object of a frame is judged on its own
//! ([`crate::trust`]), but a radar whose beam is wider than the gap between two objects' masks
//! offers both the same reflections: a far sign behind a near mover, two cars in one 14° beam.
//! Each may then choose the reflection that is the other's, and the weaker one's camera cues
//! rarely rule it out at range: a sign at 299 m took a mover's reflection at 92 m, 8.7° away.
//! This step runs after every object's verdict and before the frame's estimates leave:
//!
//! ```text
//! per object: evidence ─▶ verdict ─┐
//! radar: the reflection's direction ┼▶ contest ─▶ the loser judged again without that reflection
//! camera: each mask's span and cues ┘
//! ```
//!
//! Two verdicts contest a reflection when both are the Doppler path's, in one Doppler bin
//! (velocities within [`SAME_MOVER_MPS`] once folded by the bin's aliases: each object focuses
//! the bin with the alias that suits its own direction), the returns they rest on are within
//! [`SAME_DEPTH_M`] (a mover's body, behind the leading edge it reports), and their masks lie
//! within [`REACH_BEAMS`] beamwidths of each other (a wrong alias steers a reflection by up to a
//! beam). The radar then measures where the reflection comes from
//! ([`crate::metamoran::MovingScene::direction`]), far finer than the beam at a mover's
//! signal-to-noise: the mask it lies nearer to owns it. Only when the masks are within
//! [`CAMERA_REACH_BEAMS`] and too close for that does the camera decide: the object whose cues make
//! that depth more likely ([`Evidence::camera_log_density`]); a tie loses both. A loser is
//! judged again on its other candidates, and the contest repeats until no two objects claim one
//! reflection.
//!
//! Static reflections are not contested: the host does not hold the static frame when the
//! module searches on the edge, and two static objects at one range within a beam are often
//! both there (two parked cars 29° apart at 14 m, each right, on fresh seeds); the camera alone
//! picked the wrong one of them.

use crate::ObjectEstimate;
use crate::camera_points::CameraObject;
use crate::trust::{Evidence, SAME_MOVER_MPS, Verdict};

/// Depths this close, m, are one reflection (several range bins of every board; two objects
/// that close within one beam are one return to the radar).
pub const SAME_DEPTH_M: f64 = 1.0;

/// How much nearer to one mask than to the other, in beamwidths, a mover's measured direction
/// must lie to decide the contest; nearer than that the camera decides (for masks within
/// [`CAMERA_REACH_BEAMS`]) or nobody loses.
pub const DIRECTION_MARGIN_BEAMS: f64 = 0.125;

/// How far apart two masks may lie, in beamwidths, for the camera to decide a contest the
/// radar's direction does not: masks further apart the beam itself tells apart.
pub const CAMERA_REACH_BEAMS: f64 = 1.0;

/// How far apart two masks may lie, in beamwidths, for their objects to contest one mover's
/// reflection: a beam, and another for the wrong Doppler alias. Each object focuses a Doppler
/// bin with the alias that suits its own direction, and with TDM a wrong alias steers the beam:
/// by a whole beamwidth on a two-slot board (the second slot's half of the array flipped by π),
/// which puts a mover's reflection into a mask a beam and more away, past the guard of the
/// object's own check against other directions. Beyond a beam apart only the radar's measured
/// direction decides.
pub const REACH_BEAMS: f64 = 2.0;

/// What a contest needs to know of the radar.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Radar {
    /// Azimuth beamwidth at boresight, sin(azimuth).
    pub beam: f64,
    /// Maximum range, m: the camera's flat prior without a monocular range.
    pub max_range_m: f64,
    /// Span of radial velocities one Doppler bin's aliases repeat over, m/s (infinite without
    /// the Doppler path): two velocities a multiple of it apart are one mover's bin, each
    /// object having focused it with the alias that suits its own direction.
    pub fold_mps: f64,
}

impl Radar {
    /// Whether radial velocities `v` and `w` (m/s) are one mover's Doppler bin.
    fn same_bin(&self, v: f64, w: f64) -> bool {
        let d = v - w;
        let folds = if self.fold_mps.is_finite() && self.fold_mps > 0.0 {
            (d / self.fold_mps).round()
        } else {
            0.0
        };
        (d - folds * self.fold_mps).abs() <= SAME_MOVER_MPS
    }
}

/// One object's claim: its mask's span and what it was judged on.
#[derive(Clone, Copy, Debug)]
pub struct Claim<'a> {
    /// sin(azimuth) of the mask's left and right edges.
    pub span: (f64, f64),
    /// What the trust test weighed.
    pub evidence: &'a Evidence,
    /// What it chose.
    pub verdict: &'a Verdict,
}

impl Claim<'_> {
    /// The gap between `self`'s and `other`'s masks, in beamwidths of `radar`, if they claim
    /// one reflection (`None` otherwise).
    fn contests(&self, other: &Claim<'_>, radar: &Radar) -> Option<f64> {
        let (a, b) = (self.verdict, other.verdict);
        let same_bin = match (a.velocity_mps, b.velocity_mps) {
            (Some(v), Some(w)) => radar.same_bin(v, w),
            _ => false,
        };
        let gap = (self.span.0.max(other.span.0) - self.span.1.min(other.span.1)) / radar.beam;
        (same_bin && (a.reflection_m - b.reflection_m).abs() <= SAME_DEPTH_M && gap <= REACH_BEAMS)
            .then_some(gap)
    }

    /// How far sin(azimuth) `s` lies outside the mask's span (0 inside).
    fn off(&self, s: f64) -> f64 {
        (self.span.0 - s).max(s - self.span.1).max(0.0)
    }
}

/// Which of a frame's `claims` (`None` for objects without a verdict) lose a reflection to
/// another on `radar`; `direction(velocity_mps, depth_m)` is the sin(azimuth) the radar
/// measures for a mover's reflection (`None` where it cannot).
/// O(claims² + contests · direction).
pub fn losers(
    claims: &[Option<Claim<'_>>],
    radar: &Radar,
    direction: impl Fn(f64, f64) -> Option<f64>,
) -> Vec<bool> {
    let mut lost = vec![false; claims.len()];
    for (i, a) in claims.iter().enumerate() {
        for (j, b) in claims.iter().enumerate().skip(i + 1) {
            let (Some(a), Some(b)) = (a, b) else {
                continue;
            };
            let Some(gap) = a.contests(b, radar) else {
                continue;
            };
            // The radar's side: where a mover's reflection comes from.
            let measured = a
                .verdict
                .velocity_mps
                .and_then(|v| direction(v, a.verdict.reflection_m))
                .map(|s| a.off(s) - b.off(s))
                .filter(|d| d.abs() > DIRECTION_MARGIN_BEAMS * radar.beam);
            // The camera's side, for masks within CAMERA_REACH_BEAMS: which object makes that
            // depth more likely. Masks further apart the radar tells apart; if it cannot say
            // which one the reflection comes from, both keep it.
            let camera = || {
                b.evidence
                    .camera_log_density(b.verdict.depth_m, radar.max_range_m)
                    - a.evidence
                        .camera_log_density(a.verdict.depth_m, radar.max_range_m)
            };
            let Some(nearer) = measured.or_else(|| (gap <= CAMERA_REACH_BEAMS).then(camera)) else {
                continue;
            };
            if nearer >= 0.0 {
                lost[i] = true;
            }
            if nearer <= 0.0 {
                lost[j] = true;
            }
        }
    }
    lost
}

/// Settles the contests of one frame: `estimates` are those of `objects` in order; each loser
/// is judged again without the reflection it lost ([`Evidence::without`]), until no two
/// objects claim one reflection (each round removes candidates, so at most one round per
/// candidate). Arguments as for [`losers`].
pub fn settle(
    estimates: &mut [ObjectEstimate],
    objects: &[CameraObject],
    radar: &Radar,
    direction: impl Fn(f64, f64) -> Option<f64>,
) {
    loop {
        let claims: Vec<Option<Claim<'_>>> = estimates
            .iter()
            .zip(objects)
            .map(|(e, o)| {
                let (evidence, verdict) = e.evidence.as_deref()?;
                let (lo, hi) = o.span?;
                Some(Claim {
                    span: (lo.sin(), hi.sin()),
                    evidence,
                    verdict: verdict.as_ref()?,
                })
            })
            .collect();
        let lost = losers(&claims, radar, &direction);
        let judged_again: Vec<(usize, Evidence)> = claims
            .iter()
            .zip(&lost)
            .enumerate()
            .filter_map(|(i, (c, &l))| {
                let c = c.as_ref().filter(|_| l)?;
                Some((
                    i,
                    c.evidence
                        .without(c.verdict.depth_m, c.verdict.velocity_mps),
                ))
            })
            .collect();
        if judged_again.is_empty() {
            return;
        }
        for (i, evidence) in judged_again {
            estimates[i] = crate::metamoran::conclude(&objects[i], evidence);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trust::{Candidate, HeightCue};

    /// An 8-element board: a 14.5° beam, 300 m, one Doppler bin's aliases 29 m/s apart.
    const SMALL: Radar = Radar {
        beam: 0.25,
        max_range_m: 300.0,
        fold_mps: 28.97,
    };

    /// Evidence of one Doppler candidate at `depth_m` moving at `v` m/s, with height bounds.
    fn mover(depth_m: f64, v: Option<f64>, bounds: (f64, f64)) -> Evidence {
        Evidence {
            candidates: vec![Candidate {
                depth_m,
                over_floor_db: 40.0,
                survives: true,
                velocity_mps: v,
            }],
            monocular_m: None,
            height: Some(HeightCue {
                near_m: bounds.0,
                far_m: bounds.1,
                rows: 20.0,
            }),
            ground: None,
            beamwidth_deg: 14.5,
            extent_m: 1.5,
        }
    }

    fn lost(
        a: (&Evidence, (f64, f64)),
        b: (&Evidence, (f64, f64)),
        radar: &Radar,
        measured: Option<f64>,
    ) -> Vec<bool> {
        let (va, vb) = (a.0.judge().unwrap(), b.0.judge().unwrap());
        let claims = [
            Some(Claim {
                span: a.1,
                evidence: a.0,
                verdict: &va,
            }),
            Some(Claim {
                span: b.1,
                evidence: b.0,
                verdict: &vb,
            }),
        ];
        losers(&claims, radar, |_, _| measured)
    }

    /// Session 27's fresh seed 12114-0018: a sign at 299 m (mask at −8.7°) and a sign moving
    /// at 92 m (0°); the far one focused the near one's Doppler bin with another alias.
    #[test]
    fn the_reflection_goes_to_the_mask_it_comes_from() {
        let far = mover(92.26, Some(-41.64), (50.0, 455.0));
        let near = mover(92.49, Some(-12.67), (80.0, 110.0));
        let (far_span, near_span) = ((-0.153, -0.149), (-0.003, 0.003));
        let measured = Some(0.0);
        let l = lost((&far, far_span), (&near, near_span), &SMALL, measured);
        assert_eq!(l, [true, false]);
        // Measured in the far mask, the near sign loses it, whatever the camera says.
        let l = lost((&far, far_span), (&near, near_span), &SMALL, Some(-0.15));
        assert_eq!(l, [false, true]);
        // Without the fold the two velocities are two movers: no contest.
        let unfolded = Radar {
            fold_mps: f64::INFINITY,
            ..SMALL
        };
        let l = lost((&far, far_span), (&near, near_span), &unfolded, measured);
        assert_eq!(l, [false, false]);
    }

    /// Session 28's fresh seed 12308-0035: a person nearly still at 176 m (mask at −12.1°) took
    /// the reflection of a car at 125 m (6.2…8.4°, −3.6 m/s) with the alias one fold down, which
    /// steers it a beam toward the person, past the guard of its own check; the masks are 1.3
    /// beams apart.
    #[test]
    fn a_wrong_alias_steers_a_reflection_a_beam_away() {
        let person = mover(127.617, Some(-32.59), (109.6, 971.7));
        let mut car = mover(127.617, Some(-3.621), (100.6, 803.2));
        let (person_span, car_span) = ((-0.210, -0.210), (0.108, 0.145));
        let measured_at_the_car = Some(0.127);
        let person_loses = |car: &Evidence| {
            lost(
                (&person, person_span),
                (car, car_span),
                &SMALL,
                measured_at_the_car,
            ) == [true, false]
        };
        assert!(person_loses(&car));
        // The car reports its leading edge 1.8 m in front: the body behind it is still the
        // reflection the person claims.
        car.extent_m = 6.0;
        car.candidates.push(Candidate {
            depth_m: 125.77,
            over_floor_db: 34.0,
            survives: true,
            velocity_mps: Some(-3.621),
        });
        let v = car.judge().unwrap();
        assert_eq!((v.depth_m, v.reflection_m), (125.77, 127.617));
        assert!(person_loses(&car));
    }

    #[test]
    fn only_one_movers_reflection_within_reach_is_contested() {
        let a = mover(92.3, Some(-12.7), (50.0, 455.0));
        let b = mover(92.5, Some(-12.6), (80.0, 110.0));
        // Masks more than two beams apart: no alias steers a reflection that far.
        let (sa, sb) = ((-0.60, -0.55), (0.0, 0.01));
        assert_eq!(lost((&a, sa), (&b, sb), &SMALL, Some(0.0)), [false, false]);
        // Between one and two beams apart only the measured direction decides, never the
        // camera (b's tighter height bounds would have it win).
        let (sa, sb) = ((-0.30, -0.28), (0.0, 0.01));
        assert_eq!(lost((&a, sa), (&b, sb), &SMALL, Some(0.0)), [true, false]);
        assert_eq!(lost((&a, sa), (&b, sb), &SMALL, Some(-0.29)), [false, true]);
        assert_eq!(lost((&a, sa), (&b, sb), &SMALL, None), [false, false]);
        assert_eq!(
            lost((&a, sa), (&b, sb), &SMALL, Some(-0.14)),
            [false, false]
        );
        // Depths more than 1 m apart, or another Doppler bin: two reflections.
        let sa = (-0.20, -0.18);
        let deeper = mover(93.6, Some(-12.7), (50.0, 455.0));
        assert_eq!(
            lost((&deeper, sa), (&b, sb), &SMALL, Some(0.0)),
            [false, false]
        );
        let other_bin = mover(92.3, Some(-5.0), (50.0, 455.0));
        assert_eq!(
            lost((&other_bin, sa), (&b, sb), &SMALL, Some(0.0)),
            [false, false]
        );
        // Static claims are never contested.
        let (sa0, sb0) = (
            mover(92.3, None, (50.0, 455.0)),
            mover(92.5, None, (80.0, 110.0)),
        );
        assert_eq!(lost((&sa0, sa), (&sb0, sb), &SMALL, None), [false, false]);
        // Within all of that, one loses.
        assert_eq!(lost((&a, sa), (&b, sb), &SMALL, Some(0.0)), [true, false]);
    }

    #[test]
    fn masks_too_close_for_the_radar_leave_it_to_the_camera() {
        let a = mover(92.3, Some(-12.7), (50.0, 455.0));
        let b = mover(92.5, Some(-12.6), (80.0, 110.0));
        let (sa, sb) = ((-0.02, -0.01), (0.0, 0.01));
        // Measured between the masks, nearer b by less than an eighth of a beam: b's tighter
        // height bounds hold 92 m and win.
        assert_eq!(
            lost((&a, sa), (&b, sb), &SMALL, Some(-0.004)),
            [true, false]
        );
        let a_tight = mover(92.3, Some(-12.7), (85.0, 100.0));
        assert_eq!(
            lost((&a_tight, sa), (&b, sb), &SMALL, Some(-0.004)),
            [false, true]
        );
        // Equal cues: a tie loses both.
        let b_same = mover(92.3, Some(-12.6), (50.0, 455.0));
        assert_eq!(
            lost((&a, sa), (&b_same, sb), &SMALL, Some(-0.004)),
            [true, true]
        );
    }
}
