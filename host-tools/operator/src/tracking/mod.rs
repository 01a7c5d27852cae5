//! Multi-object tracking in the ground plane (issue #20 part 1), the fusion stage's memory:
//! each frame's detections (range, azimuth, class, confidence, radial velocity where the Doppler
//! path gave one) are associated with the tracks so far and filtered, so an object keeps one id
//! across frames however the camera numbers its instances.
//!
//! ```text
//! detections ─▶ polar → (x, z) with covariance ─▶ χ² gate ─▶ assign (least total) ─▶ Kalman update
//!                                                              └▶ unmatched: births, misses, deletions
//! ```
//!
//! **Model.** State `(x, z, vₓ, v_z)` in metres and m/s on the sensor's ground plane (x to the
//! right, z along boresight), constant velocity with white acceleration noise of
//! [`TrackerConfig::accel_sigma_mps2`]. A detection at range r and azimuth θ measures
//! `(r sin θ, r cos θ)` with the covariance of [`TrackerConfig::range_sigma_m`] and
//! [`TrackerConfig::azimuth_sigma_deg`] carried through the polar-to-Cartesian Jacobian (so a
//! far object is uncertain across the line of sight). A radial velocity, where given, seeds a
//! new track's velocity along the line of sight.
//!
//! **Rules.** A detection is a candidate for a track when its squared Mahalanobis distance to
//! the prediction is below [`TrackerConfig::gate_chi2`] (χ² with two degrees of freedom); among
//! candidates the assignment with the least summed distance wins ([`assign`]), so two people
//! crossing are not swapped by whichever is considered first. A detection no track takes starts
//! a *tentative* track; a tentative track is *confirmed* after [`TrackerConfig::confirm_hits`]
//! hits and deleted after [`TrackerConfig::tentative_misses`] consecutive misses; a confirmed
//! track is deleted after [`TrackerConfig::confirmed_misses`] consecutive misses (it coasts on
//! its prediction until then). The class is the majority of the votes its detections cast,
//! weighted by their confidence. Ids are never reused; a frame's new tracks take them nearest
//! first, so they do not depend on the order the detections came in.

pub mod assign;
pub mod score;

use nalgebra::{Matrix2, Matrix2x4, Matrix4, Vector2, Vector4};
use std::collections::BTreeMap;

/// The tracker's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackerConfig {
    /// White acceleration noise, m/s² (a walking person turns at about 1; a braking car
    /// reaches 5, but only for a second).
    pub accel_sigma_mps2: f64,
    /// Range noise of a detection, m.
    pub range_sigma_m: f64,
    /// Azimuth noise of a detection, degrees.
    pub azimuth_sigma_deg: f64,
    /// Gate: the squared Mahalanobis distance a detection may have to a track's prediction
    /// (9.21 keeps 99 % of true detections, χ²₂). Tighter than 99.9 % on purpose: an
    /// occluded person given the occluder's depth lands about 1.5 m off its track, which a
    /// 13.8 gate let pull the track onto the wrong person (the crossing scene, issue #20).
    pub gate_chi2: f64,
    /// Hits that confirm a tentative track.
    pub confirm_hits: u32,
    /// Consecutive misses that delete a tentative track.
    pub tentative_misses: u32,
    /// Consecutive misses that delete a confirmed track.
    pub confirmed_misses: u32,
    /// Standard deviation of a new track's unknown velocity, m/s.
    pub birth_speed_sigma_mps: f64,
}

impl Default for TrackerConfig {
    fn default() -> Self {
        Self {
            accel_sigma_mps2: 1.0,
            range_sigma_m: 0.3,
            azimuth_sigma_deg: 1.5,
            gate_chi2: 9.21,
            confirm_hits: 3,
            tentative_misses: 2,
            confirmed_misses: 5,
            birth_speed_sigma_mps: 5.0,
        }
    }
}

/// One object of one frame, as the depth search and the camera report it.
#[derive(Clone, Debug, PartialEq)]
pub struct Detection {
    /// Range of the object's closest point, m.
    pub depth_m: f64,
    /// Azimuth, degrees (positive to the right).
    pub azimuth_deg: f64,
    /// Class word from the segmentation.
    pub class: String,
    /// Confidence that the depth is right, 0…1 (weights the class vote).
    pub confidence: f64,
    /// Radial velocity, m/s (positive away), where the Doppler path gave one.
    pub radial_velocity_mps: Option<f64>,
}

impl Detection {
    /// The detection an estimate makes, if the method trusted it and placed it (depth and
    /// azimuth known); its confidence is the trust test's, 0.5 where there is none.
    pub fn from_estimate(o: &metamoran_process::ObjectEstimate) -> Option<Self> {
        let (Some(depth_m), Some(azimuth_deg), true) = (o.depth_m, o.azimuth_deg, o.detected)
        else {
            return None;
        };
        Some(Self {
            depth_m,
            azimuth_deg,
            class: o.class.clone(),
            confidence: o.confidence.unwrap_or(0.5),
            radial_velocity_mps: o.radial_velocity_mps,
        })
    }
}

/// Where a track is in its life.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum TrackState {
    /// Seen fewer than [`TrackerConfig::confirm_hits`] times.
    Tentative,
    /// Confirmed: reported, and what zones and alerts see.
    Confirmed,
}

/// A track: a stable id and the filtered state.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Track {
    /// Id, unique over the tracker's life.
    pub id: u32,
    /// Life stage.
    pub state: TrackState,
    /// Position on the ground plane, m: (x right, z along boresight).
    pub position_m: [f64; 2],
    /// Velocity, m/s.
    pub velocity_mps: [f64; 2],
    /// Standard deviation of the position, m (the larger axis).
    pub position_sigma_m: f64,
    /// The class most votes gave.
    pub class: String,
    /// Detections taken.
    pub hits: u32,
    /// Consecutive frames without a detection.
    pub misses: u32,
    /// The index of this frame's detection it took, if any.
    pub detection: Option<usize>,
}

impl Track {
    /// Range from the sensor, m.
    pub fn range_m(&self) -> f64 {
        self.position_m[0].hypot(self.position_m[1])
    }

    /// Azimuth, degrees.
    pub fn azimuth_deg(&self) -> f64 {
        self.position_m[0].atan2(self.position_m[1]).to_degrees()
    }

    /// Speed toward the sensor (positive closing), m/s.
    pub fn closing_speed_mps(&self) -> f64 {
        let r = self.range_m().max(1e-9);
        -(self.position_m[0] * self.velocity_mps[0] + self.position_m[1] * self.velocity_mps[1]) / r
    }
}

/// Why the tracker refused a frame.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum TrackError {
    /// The frame's time is before the previous one, or not finite.
    #[error(
        "frame time {now_s} s is not after the previous frame's {before_s} s: frames must come in time order"
    )]
    Time {
        /// The previous frame's time, s.
        before_s: f64,
        /// This frame's time, s.
        now_s: f64,
    },
}

/// A track's filter state.
#[derive(Clone, Debug)]
struct Filter {
    track: Track,
    x: Vector4<f64>,
    p: Matrix4<f64>,
    votes: BTreeMap<String, f64>,
}

/// The tracks of one sensor.
#[derive(Clone, Debug, Default)]
pub struct Tracker {
    config: TrackerConfig,
    filters: Vec<Filter>,
    next_id: u32,
    time_s: Option<f64>,
}

/// Position measurement matrix.
fn h() -> Matrix2x4<f64> {
    Matrix2x4::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0)
}

impl Tracker {
    /// A tracker with `config` and no tracks.
    pub fn new(config: TrackerConfig) -> Self {
        Self {
            config,
            ..Self::default()
        }
    }

    /// Every live track (tentative ones included), oldest id first.
    pub fn tracks(&self) -> impl Iterator<Item = &Track> {
        self.filters.iter().map(|f| &f.track)
    }

    /// The confirmed tracks.
    pub fn confirmed(&self) -> impl Iterator<Item = &Track> {
        self.tracks().filter(|t| t.state == TrackState::Confirmed)
    }

    /// A detection as a ground-plane measurement and its covariance. `None` for a non-finite
    /// or negative range or azimuth.
    fn measure(&self, d: &Detection) -> Option<(Vector2<f64>, Matrix2<f64>)> {
        let (r, th) = (d.depth_m, d.azimuth_deg.to_radians());
        if !(r.is_finite() && th.is_finite() && r >= 0.0) {
            return None;
        }
        let (s, c) = th.sin_cos();
        let j = Matrix2::new(s, r * c, c, -r * s);
        let noise = Matrix2::new(
            self.config.range_sigma_m.powi(2),
            0.0,
            0.0,
            self.config.azimuth_sigma_deg.to_radians().powi(2),
        );
        Some((Vector2::new(r * s, r * c), j * noise * j.transpose()))
    }

    /// Takes frame `detections` at `time_s`: predicts every track, associates, updates, and
    /// applies the birth, confirmation and deletion rules. Detections with a non-finite
    /// position are ignored. O(T·D·(T + D)) for T tracks and D detections.
    ///
    /// # Errors
    /// [`TrackError::Time`] if `time_s` is before the previous frame's (the tracks are kept).
    ///
    /// # Example
    /// A person walking across at 1.4 m/s, 10 m away, keeps one id.
    /// ```
    /// use metamoran_operator::tracking::{Detection, Tracker, TrackerConfig};
    /// let mut t = Tracker::new(TrackerConfig::default());
    /// for k in 0..10 {
    ///     let x: f64 = -3.0 + 1.4 * 0.5 * k as f64;
    ///     let d = Detection {
    ///         depth_m: x.hypot(10.0),
    ///         azimuth_deg: x.atan2(10.0).to_degrees(),
    ///         class: "person".into(),
    ///         confidence: 0.9,
    ///         radial_velocity_mps: None,
    ///     };
    ///     t.update(0.5 * k as f64, &[d])?;
    /// }
    /// let tracks: Vec<_> = t.confirmed().collect();
    /// assert_eq!(tracks.len(), 1);
    /// assert!((tracks[0].velocity_mps[0] - 1.4).abs() < 0.2, "{:?}", tracks[0]);
    /// # Ok::<(), metamoran_operator::tracking::TrackError>(())
    /// ```
    pub fn update(&mut self, time_s: f64, detections: &[Detection]) -> Result<(), TrackError> {
        let before = self.time_s.unwrap_or(time_s);
        if !time_s.is_finite() || time_s < before {
            return Err(TrackError::Time {
                before_s: before,
                now_s: time_s,
            });
        }
        let dt = time_s - before;
        self.time_s = Some(time_s);
        self.predict(dt);
        let measured: Vec<_> = detections.iter().map(|d| self.measure(d)).collect();
        // Squared Mahalanobis distances; the gate is the price of leaving one unmatched.
        let (rows, cols) = (self.filters.len(), detections.len());
        let mut cost = vec![f64::INFINITY; rows * cols];
        for (i, f) in self.filters.iter().enumerate() {
            let s_pred = h() * f.p * h().transpose();
            let z_pred = h() * f.x;
            for (j, m) in measured.iter().enumerate() {
                if let Some((z, r)) = m
                    && let Some(inv) = (s_pred + r).try_inverse()
                {
                    let nu = z - z_pred;
                    cost[i * cols + j] = (nu.transpose() * inv * nu)[0];
                }
            }
        }
        let matched = assign::assign(&cost, rows, cols, self.config.gate_chi2);
        let mut taken = vec![false; cols];
        for (f, m) in self.filters.iter_mut().zip(&matched) {
            f.track.detection = *m;
            match m.and_then(|j| measured[j].map(|zr| (j, zr))) {
                Some((j, (z, r))) => {
                    taken[j] = true;
                    Self::correct(f, z, r);
                    let d = &detections[j];
                    *f.votes.entry(d.class.clone()).or_default() += d.confidence.clamp(0.01, 1.0);
                    f.track.hits += 1;
                    f.track.misses = 0;
                    if f.track.hits >= self.config.confirm_hits {
                        f.track.state = TrackState::Confirmed;
                    }
                }
                None => f.track.misses += 1,
            }
        }
        let (tentative, confirmed) = (self.config.tentative_misses, self.config.confirmed_misses);
        self.filters.retain(|f| match f.track.state {
            TrackState::Tentative => f.track.misses < tentative,
            TrackState::Confirmed => f.track.misses < confirmed,
        });
        // Births in order of position (nearest first), not of the detection list, so ids do
        // not depend on how the camera numbered or listed its instances.
        let mut born: Vec<(usize, Vector2<f64>, Matrix2<f64>)> = (0..cols)
            .filter(|&j| !taken[j])
            .filter_map(|j| measured[j].map(|(z, r)| (j, z, r)))
            .collect();
        born.sort_by(|a, b| {
            (a.1.norm(), a.1[0])
                .partial_cmp(&(b.1.norm(), b.1[0]))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        for (j, z, r) in born {
            self.birth(j, &detections[j], z, r);
        }
        for f in &mut self.filters {
            Self::publish(f);
        }
        Ok(())
    }

    /// Moves every track `dt` seconds along its velocity, growing its covariance.
    fn predict(&mut self, dt: f64) {
        let f = Matrix4::new(
            1.0, 0.0, dt, 0.0, //
            0.0, 1.0, 0.0, dt, //
            0.0, 0.0, 1.0, 0.0, //
            0.0, 0.0, 0.0, 1.0,
        );
        let (q4, q3, q2) = (dt.powi(4) / 4.0, dt.powi(3) / 2.0, dt * dt);
        let a2 = self.config.accel_sigma_mps2.powi(2);
        let q = Matrix4::new(
            q4, 0.0, q3, 0.0, //
            0.0, q4, 0.0, q3, //
            q3, 0.0, q2, 0.0, //
            0.0, q3, 0.0, q2,
        ) * a2;
        for t in &mut self.filters {
            t.x = f * t.x;
            t.p = f * t.p * f.transpose() + q;
        }
    }

    /// The Kalman update of `f` with measurement `z` of covariance `r` (Joseph form, so the
    /// covariance stays symmetric and positive).
    fn correct(f: &mut Filter, z: Vector2<f64>, r: Matrix2<f64>) {
        let hm = h();
        let s = hm * f.p * hm.transpose() + r;
        let Some(inv) = s.try_inverse() else {
            return;
        };
        let k = f.p * hm.transpose() * inv;
        f.x += k * (z - hm * f.x);
        let i_kh = Matrix4::identity() - k * hm;
        f.p = i_kh * f.p * i_kh.transpose() + k * r * k.transpose();
    }

    /// A tentative track from detection `j`.
    fn birth(&mut self, j: usize, d: &Detection, z: Vector2<f64>, r: Matrix2<f64>) {
        let sv = self.config.birth_speed_sigma_mps.powi(2);
        // A radial velocity is the velocity's component along the line of sight.
        let (mut vx, mut vz) = (0.0, 0.0);
        if let Some(v) = d.radial_velocity_mps.filter(|v| v.is_finite()) {
            let n = z.norm().max(1e-9);
            (vx, vz) = (v * z[0] / n, v * z[1] / n);
        }
        let mut p = Matrix4::zeros();
        p.fixed_view_mut::<2, 2>(0, 0).copy_from(&r);
        p[(2, 2)] = sv;
        p[(3, 3)] = sv;
        let mut votes = BTreeMap::new();
        votes.insert(d.class.clone(), d.confidence.clamp(0.01, 1.0));
        let id = self.next_id;
        self.next_id += 1;
        let state = if self.config.confirm_hits <= 1 {
            TrackState::Confirmed
        } else {
            TrackState::Tentative
        };
        self.filters.push(Filter {
            track: Track {
                id,
                state,
                position_m: [0.0; 2],
                velocity_mps: [0.0; 2],
                position_sigma_m: 0.0,
                class: d.class.clone(),
                hits: 1,
                misses: 0,
                detection: Some(j),
            },
            x: Vector4::new(z[0], z[1], vx, vz),
            p,
            votes,
        });
    }

    /// Copies the filter's state into its public track.
    fn publish(f: &mut Filter) {
        let t = &mut f.track;
        t.position_m = [f.x[0], f.x[1]];
        t.velocity_mps = [f.x[2], f.x[3]];
        let pos = f.p.fixed_view::<2, 2>(0, 0).into_owned();
        t.position_sigma_m = pos.symmetric_eigenvalues().max().max(0.0).sqrt();
        if let Some((class, _)) = f
            .votes
            .iter()
            .max_by(|a, b| a.1.total_cmp(b.1).then_with(|| b.0.cmp(a.0)))
        {
            t.class.clone_from(class);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: f64, z: f64, class: &str) -> Detection {
        Detection {
            depth_m: x.hypot(z),
            azimuth_deg: x.atan2(z).to_degrees(),
            class: class.into(),
            confidence: 0.9,
            radial_velocity_mps: None,
        }
    }

    /// Two noiseless measurements, a vague prior and no process noise: the filter's velocity
    /// is the finite difference, its position the last measurement (the closed form).
    #[test]
    fn two_exact_measurements_give_the_finite_difference() {
        let config = TrackerConfig {
            accel_sigma_mps2: 0.0,
            range_sigma_m: 1e-6,
            azimuth_sigma_deg: 1e-6,
            birth_speed_sigma_mps: 1e3,
            ..TrackerConfig::default()
        };
        let mut t = Tracker::new(config);
        t.update(0.0, &[at(1.0, 20.0, "car")]).unwrap();
        t.update(0.5, &[at(2.0, 19.0, "car")]).unwrap();
        let track = t.tracks().next().unwrap();
        assert!((track.velocity_mps[0] - 2.0).abs() < 1e-3, "{track:?}");
        assert!((track.velocity_mps[1] + 2.0).abs() < 1e-3, "{track:?}");
        assert!(
            (track.position_m[0] - 2.0).abs() < 1e-4 && (track.position_m[1] - 19.0).abs() < 1e-4
        );
        // Closing at 2 m/s mostly along boresight: (x·vₓ + z·v_z)/r with the sign flipped.
        let want = -(2.0 * 2.0 + 19.0 * -2.0) / 2.0f64.hypot(19.0);
        assert!((track.closing_speed_mps() - want).abs() < 1e-3);
    }

    /// Two people crossing paths in an X, detections listed in an order that swaps every
    /// frame: both keep their ids and classes through the crossing.
    #[test]
    fn two_people_crossing_keep_their_ids() {
        let mut t = Tracker::new(TrackerConfig::default());
        let mut noise = 99u64;
        let mut n = || {
            noise = noise
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((noise >> 40) as f64 / (1u64 << 24) as f64 - 0.5) * 0.2
        };
        let mut ids: Option<(u32, u32)> = None;
        for k in 0..40 {
            let s = 0.5 * k as f64;
            // A walks left to right, B right to left, 1.5 m apart in depth at the crossing.
            let a = at(-7.0 + 0.7 * s + n(), 15.0 + 0.05 * s + n(), "person");
            let b = at(7.0 - 0.7 * s + n(), 16.5 - 0.05 * s + n(), "person");
            let dets = if k % 2 == 0 { vec![a, b] } else { vec![b, a] };
            t.update(s, &dets).unwrap();
            let confirmed: Vec<_> = t.confirmed().collect();
            if confirmed.len() == 2 {
                // The one on the left at the start is A.
                let (left, right) = if k < 20 {
                    let l = confirmed
                        .iter()
                        .min_by(|p, q| p.position_m[0].total_cmp(&q.position_m[0]));
                    let r = confirmed
                        .iter()
                        .max_by(|p, q| p.position_m[0].total_cmp(&q.position_m[0]));
                    (l.unwrap().id, r.unwrap().id)
                } else {
                    ids.unwrap()
                };
                let now = ids.get_or_insert((left, right));
                assert_eq!(*now, (left, right), "frame {k}");
                // A stays on its own line through the crossing: a swap puts its track on B's.
                let a_track = confirmed.iter().find(|c| c.id == now.0).unwrap();
                let want_x = -7.0 + 0.7 * s;
                assert!(
                    (a_track.position_m[0] - want_x).abs() < 0.6,
                    "frame {k}: {a_track:?}"
                );
            }
        }
        assert!(ids.is_some(), "both were confirmed");
        assert_eq!(t.confirmed().count(), 2);
    }

    #[test]
    fn births_confirmations_and_deletions_follow_the_rules() {
        let config = TrackerConfig::default();
        let mut t = Tracker::new(config);
        // A single spurious detection: tentative, then gone after two misses.
        t.update(0.0, &[at(5.0, 30.0, "sign")]).unwrap();
        assert_eq!(t.tracks().count(), 1);
        assert_eq!(t.confirmed().count(), 0);
        t.update(0.5, &[]).unwrap();
        t.update(1.0, &[]).unwrap();
        assert_eq!(t.tracks().count(), 0);
        // A steady car: confirmed on its third hit, coasts four misses, deleted at the fifth.
        for k in 0..3 {
            t.update(1.5 + 0.5 * f64::from(k), &[at(0.0, 40.0, "car")])
                .unwrap();
        }
        let id = t.confirmed().next().unwrap().id;
        assert_eq!(id, 1, "ids are never reused");
        for k in 0..4 {
            t.update(3.0 + 0.5 * f64::from(k), &[]).unwrap();
            assert_eq!(t.confirmed().count(), 1, "coasting miss {k}");
        }
        t.update(5.0, &[]).unwrap();
        assert_eq!(t.tracks().count(), 0);
        // Time going backwards is refused.
        assert!(matches!(t.update(4.0, &[]), Err(TrackError::Time { .. })));
        assert!(t.update(f64::NAN, &[]).is_err());
    }

    #[test]
    fn the_class_is_the_confidence_weighted_majority() {
        let mut t = Tracker::new(TrackerConfig::default());
        let mut d = at(0.0, 12.0, "person");
        for (k, (class, conf)) in [
            ("person", 0.9),
            ("sign", 0.3),
            ("sign", 0.3),
            ("person", 0.8),
        ]
        .into_iter()
        .enumerate()
        {
            d.class = class.into();
            d.confidence = conf;
            t.update(0.5 * k as f64, std::slice::from_ref(&d)).unwrap();
        }
        assert_eq!(t.tracks().next().unwrap().class, "person");
    }

    #[test]
    fn a_radial_velocity_seeds_the_line_of_sight_velocity() {
        let mut t = Tracker::new(TrackerConfig::default());
        let mut d = at(0.0, 100.0, "car");
        d.radial_velocity_mps = Some(-12.0);
        t.update(0.0, &[d.clone(), at(f64::NAN, 1.0, "car")])
            .unwrap();
        let track = t.tracks().next().unwrap();
        assert_eq!(
            t.tracks().count(),
            1,
            "a non-finite detection starts nothing"
        );
        assert!((track.velocity_mps[1] + 12.0).abs() < 1e-9 && track.velocity_mps[0].abs() < 1e-9);
    }
}
