//! The host's trust test: which of the module's depth candidates the camera supports, and how
//! likely that depth is to be right. It sits after the module's search (which sees only the
//! radar) and before depth imaging:
//!
//! ```text
//! module: candidates (depth, dB over floor) ─┐
//! camera: monocular range, mask height ──────┴▶ choose ─┬▶ confidence = P(|error| ≤ 1 m) ─▶ detected?
//! camera: ground contact ────────────────────────────────┘
//! ```
//!
//! Two camera cues weigh each candidate: the monocular range, whose error grows with range
//! (Table I of the paper, and faster past 60 m), and the mask's apparent height against the
//! class's height range, which bounds the range independently of the monocular network. A
//! third checks the choice: for a car or a person, where its mask's bottom meets the ground
//! plane the near monocular depths give ([`crate::ground`]), which a pixel row bounds more
//! tightly than the height to about 60 m. The confidence is a logistic function of the chosen
//! candidate's evidence, its coefficients fitted on simulated scenes of other seeds
//! (`scripts/calibrate-trust.py`);
//! `metamoran eval` shows its reliability on fresh ones.

use crate::camera_points::{CameraObject, VerticalExtent};
use crate::ground::Contact;
use serde::Serialize;

/// Nats of camera log-prior one dB of radar score is worth when candidates are compared.
pub const RADAR_NATS_PER_DB: f64 = 0.15;
/// Nats a candidate of the Doppler path gains over a static one: a reflection that moves and
/// survives the check against other directions is rarely clutter.
pub const DOPPLER_NATS: f64 = 4.0;
/// Nats a candidate that does not survive the module's survival test loses against one that
/// does.
pub const SIDE_LOBE_NATS: f64 = 2.0;
/// A depth is reported as detected when its confidence reaches this probability.
pub const DETECTION_CONFIDENCE: f64 = 0.8;
/// ...and when it holds at least this log-odds of the candidates' softmax share (62 %): two
/// explanations the radar and the camera cannot tell apart mean the answer is a guess. On the
/// 873 training objects (seeds 71xx-74xx) this cut the confidently-wrong rate from 2.9 % to
/// 2.0 % for 2.4 points of detection.
pub const MIN_LOG_ODDS: f64 = 0.5;
/// Relative spread of the height bound's log penalty beyond the far bound (a mask can look no
/// smaller than the whole object but for segmentation error, already in the bound), for masks
/// tall enough that a pixel row is a smaller share.
pub const FAR_SPREAD: f64 = 0.05;
/// The same below the near bound: an occluded or truncated mask looks smaller, so farther.
pub const NEAR_SPREAD: f64 = 0.1;
/// Pixel rows a mask's height may be off by (segmentation growing or shrinking it by a pixel
/// at each end, and a pixel of rasterization).
pub const ROWS_OFF: f64 = 3.0;
/// Vagueness of a camera that gives no height bounds (a range ratio of e³ ≈ 20).
pub const VAGUE: f64 = 3.0;
/// Doppler-path candidates below this height over their floor, dB, are noise: the movers the
/// path finds stand 29 dB or more above it (5th percentile on our scenes), the rest 9 dB (median).
pub const MIN_DOPPLER_DB: f64 = 20.0;
/// A Doppler candidate of the same mover in front of the strongest one, within the object's
/// extent and this much weaker at most, dB, is the mover's closest point: the strongest
/// return of a far car is often its body, 1–5 m behind ([`Evidence::judge`]).
pub const LEAD_DB: f64 = 10.0;
/// Radial velocities this close, m/s, are one mover's (a bin or two apart on every board).
pub const SAME_MOVER_MPS: f64 = 1.0;
/// Narrowest log-ratio of height bounds [`Evidence::camera_log_density`] counts (a 1 % range
/// window): the bounds are never that tight, this only keeps the logarithm finite.
const MIN_LOG_WIDTH: f64 = 0.01;
/// Log-odds given to a candidate that has no rival, nats.
const NO_RIVAL_MARGIN: f64 = 8.0;

/// Logistic coefficients of the confidence: bias, then [`Features`] in order. Fitted by
/// `scripts/calibrate-trust.py --score 0.15,4,2` (the score's constants above kept) on the 854
/// objects of the training seeds (7101–7107 and their hard twins).
pub const COEFFICIENTS: [f64; 9] = [
    0.9238, 0.0, 0.5240, 0.0, 1.5473, -0.1152, -1.1461, 1.8601, 1.6273,
];

/// Height range of an object of `class`, m: what a mask's vertical extent is measured against.
/// `None` for classes without one.
pub fn class_height_m(class: &str) -> Option<(f64, f64)> {
    match class {
        "car" => Some((1.4, 1.6)),
        "person" => Some((1.5, 1.9)),
        "sign" => Some((0.6, 0.9)),
        _ => None,
    }
}

/// The range the mask's apparent height allows for an object of its class: the class's height
/// range over the mask's slope span, ± [`ROWS_OFF`] pixel rows of segmentation error, and how
/// soft those bounds are.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct HeightCue {
    /// Nearest horizontal range, m (0 for a mask cut by the image's edge: it bounds only the far
    /// side).
    pub near_m: f64,
    /// Farthest horizontal range, m.
    pub far_m: f64,
    /// The mask's height, pixel rows.
    pub rows: f64,
}

impl HeightCue {
    /// The cue of a mask with vertical `extent` for `class`; `None` for classes without a
    /// height range or an empty extent.
    pub fn of(class: &str, extent: &VerticalExtent) -> Option<Self> {
        let (h_lo, h_hi) = class_height_m(class)?;
        let span = extent.span();
        if !(span.is_finite() && extent.pitch.is_finite()) || span <= 0.0 || extent.pitch <= 0.0 {
            return None;
        }
        let near_m = if extent.clipped {
            0.0
        } else {
            h_lo / (span + ROWS_OFF * extent.pitch)
        };
        let far_m = h_hi / (span - ROWS_OFF * extent.pitch).max(extent.pitch);
        Some(Self {
            near_m,
            far_m,
            rows: span / extent.pitch,
        })
    }

    /// Relative spreads of the log penalty beyond the far and the near bound. Segmentation
    /// grows a mask by whole pixels, so one row more is the least the far bound can be off by:
    /// a mask a few rows tall (a car at 200 m) bounds its range only loosely from above, and a
    /// penalty of [`FAR_SPREAD`] per 5 % would rule out the truth after one row of growth too
    /// many. The near side keeps [`NEAR_SPREAD`]: widening it lets nearer clutter crowd the
    /// module's few candidates and Doppler bins (measured: it lost more movers than it found).
    pub fn spreads(&self) -> (f64, f64) {
        (
            FAR_SPREAD.max(1.0 / (self.rows - ROWS_OFF).max(1.0)),
            NEAR_SPREAD,
        )
    }

    /// Log-prior of horizontal range `d` m: 0 inside the bounds, the log-distance beyond over
    /// the bound's spread.
    pub fn log_prior(&self, d: f64) -> f64 {
        let (far_spread, near_spread) = self.spreads();
        if d > self.far_m {
            -(d / self.far_m).ln() / far_spread
        } else if d < self.near_m {
            -(self.near_m / d.max(1e-3)).ln() / near_spread
        } else {
            0.0
        }
    }

    /// The ranges (m) the module searches: [`WINDOW_MARGIN`] around the bounds of a tall
    /// mask, and beyond the far bound as far as the same log-prior (4.5 nats) for a smaller one
    /// (the margin raised to the spread's ratio to [`FAR_SPREAD`]): 2.1× for a mask 9 rows
    /// tall, the whole range for 4 rows or fewer.
    pub fn window_m(&self) -> (f64, f64) {
        let (far_spread, _) = self.spreads();
        (
            self.near_m * WINDOW_MARGIN.0,
            self.far_m * WINDOW_MARGIN.1.powf(far_spread / FAR_SPREAD),
        )
    }
}

/// Margin around a tall mask's height bounds of the window the module searches: the far bound
/// is off by 8 % at most on our scenes, the near bound only when the mask is occluded (clutter
/// in front of an object would crowd the module's few candidates, so the near side is not
/// widened further).
pub const WINDOW_MARGIN: (f64, f64) = (0.8, 1.25);

/// The ranges (m) the module searches for `obj`: [`HeightCue::window_m`]; 0 where unknown
/// (the module then searches from its monocular prior to its maximum range).
pub fn search_window_m(obj: &CameraObject) -> (f32, f32) {
    obj.extent
        .and_then(|e| HeightCue::of(&obj.class, &e))
        .map_or((0.0, 0.0), |cue| {
            let (near, far) = cue.window_m();
            (near as f32, far as f32)
        })
}

/// Median absolute error of monocular depth at range `r` m: Table I of the paper (0.6 m at
/// 0–20 m, 6.75 m at 20–40 m, 19.4 m at 40–60 m, placed at the bins' centres), then growing
/// on at the 30–50 m slope (0.63 m per m; 177 m at 300 m).
pub fn monocular_error_m(r: f64) -> f64 {
    const KNOTS: [(f64, f64); 4] = [(0.0, 0.3), (10.0, 0.6), (30.0, 6.75), (50.0, 19.4)];
    const SLOPE: f64 = (19.4 - 6.75) / 20.0;
    for w in KNOTS.windows(2) {
        let ((r0, e0), (r1, e1)) = (w[0], w[1]);
        if r <= r1 {
            return e0 + (e1 - e0) * (r - r0).max(0.0) / (r1 - r0);
        }
    }
    19.4 + SLOPE * (r - 50.0)
}

/// One depth the module's search offers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Candidate {
    /// Depth, m.
    pub depth_m: f64,
    /// Its score over the search floor, dB.
    pub over_floor_db: f64,
    /// Whether it survives the module's cancellation of the strongest direction outside the
    /// object's span at its range (`dsp::search::survival`): a candidate that does not is most
    /// likely that direction's side lobe.
    pub survives: bool,
    /// Radial velocity, m/s, for a candidate of the Doppler path (static clutter removed: a
    /// mover's reflection); `None` for the static search's.
    pub velocity_mps: Option<f64>,
}

/// What the trust test knows about one object.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Evidence {
    /// The module's candidates, its own choice first.
    pub candidates: Vec<Candidate>,
    /// Monocular range of the closest point, m.
    pub monocular_m: Option<f64>,
    /// What the mask's height says about the range.
    pub height: Option<HeightCue>,
    /// Where the object meets the ground, for a car or a person whose mask the image does not
    /// cut ([`crate::ground`]).
    pub ground: Option<Contact>,
    /// The radar's azimuth beamwidth, degrees: a wide beam holds more clutter in an object's
    /// span, so the same evidence is worth less.
    pub beamwidth_deg: f64,
    /// How far the object reaches behind its closest point, m: candidates that far behind a
    /// depth are its body's reflections, not another explanation.
    pub extent_m: f64,
}

/// The chosen candidate's evidence, the inputs of the confidence.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Features {
    /// Radar score over the search floor, dB.
    pub over_floor_db: f64,
    /// Log-odds of the chosen depth against the other candidates: the softmax share of the
    /// scores from 1 m in front of it to the object's extent behind it over the rest, nats
    /// (capped at 8 when nothing competes).
    pub margin: f64,
    /// Monocular log-prior (≤ 0).
    pub monocular: f64,
    /// Height log-prior (≤ 0).
    pub height: f64,
    /// The radar's azimuth beamwidth, degrees.
    pub beamwidth_deg: f64,
    /// How little the camera pins the range down: the log ratio of the height bounds (capped
    /// at [`VAGUE`], its value without bounds).
    pub vagueness: f64,
    /// 1 if the candidate survives the module's survival test, else 0.
    pub survives: f64,
    /// Ground-contact log-prior (≤ 0; 0 without the cue). It enters the confidence only, not
    /// the choice: as a prior on the choice it also added confidently wrong answers (16 → 21
    /// of 1486 on fresh seeds: the ground under a grown or occluded mask is 10–20 % off), as
    /// a check none.
    pub ground: f64,
}

/// The trust test's answer for one object.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Verdict {
    /// Chosen depth, m.
    pub depth_m: f64,
    /// Depth of the strongest return the choice rests on, m: the chosen depth, or, when that
    /// is a mover's leading edge, its body's return behind it (what another object may claim:
    /// [`crate::contest`]).
    pub reflection_m: f64,
    /// Probability that the depth is within 1 m of the truth.
    pub confidence: f64,
    /// Radial velocity of the chosen candidate, m/s, when the Doppler path found it.
    pub velocity_mps: Option<f64>,
    /// What the confidence was computed from.
    pub features: Features,
}

impl Verdict {
    /// Whether the depth is trusted: [`DETECTION_CONFIDENCE`] or more, and no near tie
    /// ([`MIN_LOG_ODDS`]).
    pub fn detected(&self) -> bool {
        self.confidence >= DETECTION_CONFIDENCE && self.features.margin >= MIN_LOG_ODDS
    }
}

impl Evidence {
    /// Monocular log-prior of depth `d` m: Laplace around the monocular range with the median
    /// error at the larger of the two.
    fn monocular(&self, d: f64) -> f64 {
        self.monocular_m.map_or(0.0, |m| {
            let b = monocular_error_m(d.max(m)) / std::f64::consts::LN_2;
            -(d - m).abs() / b
        })
    }

    /// Height log-prior of depth `d` m ([`HeightCue::log_prior`]; 0 without the cue).
    fn height(&self, d: f64) -> f64 {
        self.height.map_or(0.0, |h| h.log_prior(d))
    }

    /// Ground-contact log-prior of depth `d` m ([`Contact::log_prior`]; 0 without the cue).
    fn ground(&self, d: f64) -> f64 {
        self.ground.map_or(0.0, |g| g.log_prior(d))
    }

    /// Radar score plus camera log-prior of candidate `c`.
    fn score(&self, c: &Candidate) -> f64 {
        let doppler = if c.velocity_mps.is_some() {
            DOPPLER_NATS
        } else {
            0.0
        };
        let side_lobe = if c.survives { 0.0 } else { SIDE_LOBE_NATS };
        RADAR_NATS_PER_DB * c.over_floor_db + doppler - side_lobe
            + self.monocular(c.depth_m)
            + self.height(c.depth_m)
    }

    /// Log-density of the camera's cues at horizontal range `d` m, for comparing two objects'
    /// claims on one reflection ([`crate::contest`]): the monocular Laplace's (its log-prior
    /// less ln 2b; without a monocular range, flat over `max_range_m`) plus the height bound's,
    /// flat in log-range between its bounds (its log-prior less the log of their log-ratio,
    /// [`VAGUE`] without bounds). A narrow cue that holds `d` outweighs a wide one that also
    /// holds it. O(1).
    pub fn camera_log_density(&self, d: f64, max_range_m: f64) -> f64 {
        let monocular = self.monocular_m.map_or(-max_range_m.max(1.0).ln(), |m| {
            let b = monocular_error_m(d.max(m)) / std::f64::consts::LN_2;
            self.monocular(d) - (2.0 * b).ln()
        });
        let width = self
            .height
            .map_or(VAGUE, |h| (h.far_m / h.near_m.max(1e-3)).ln().min(VAGUE));
        monocular + self.height(d) - width.max(MIN_LOG_WIDTH).ln()
    }

    /// This evidence without the candidates of one reflection: those from 1 m in front of
    /// `depth_m` to the object's extent behind it, of the same mover as `velocity_mps` (within
    /// [`SAME_MOVER_MPS`]) or, for `None`, static. What the object is judged on when another
    /// object owns that reflection ([`crate::contest`]).
    pub fn without(&self, depth_m: f64, velocity_mps: Option<f64>) -> Self {
        let reach = self.extent_m.max(1.0);
        let same = |c: &Candidate| {
            let behind = c.depth_m - depth_m;
            let mover = match (c.velocity_mps, velocity_mps) {
                (None, None) => true,
                (Some(a), Some(b)) => (a - b).abs() <= SAME_MOVER_MPS,
                _ => false,
            };
            mover && (-1.0..=reach).contains(&behind)
        };
        Self {
            candidates: self
                .candidates
                .iter()
                .filter(|c| !same(c))
                .copied()
                .collect(),
            ..self.clone()
        }
    }

    /// The candidate the radar and the camera together support best, with its confidence;
    /// `None` without candidates. When it is a mover's, its depth is that of the nearest
    /// candidate of the same mover within the object's extent in front of it and
    /// [`LEAD_DB`] of its score: the closest point, as the static search's contour gives it
    /// (behind a mover's Doppler bin there is nothing but the mover). O(candidates).
    pub fn judge(&self) -> Option<Verdict> {
        let scored: Vec<(f64, &Candidate)> = self
            .candidates
            .iter()
            .filter(|c| c.velocity_mps.is_none() || c.over_floor_db >= MIN_DOPPLER_DB)
            .map(|c| (self.score(c), c))
            .collect();
        let &(best, strongest) = scored.iter().max_by(|a, b| a.0.total_cmp(&b.0))?;
        let chosen = self.leading_edge(&scored, strongest);
        // The chosen depth's share of the candidates' evidence (softmax of the scores), counting
        // those from 1 m in front of it to the object's extent behind it as the same answer (the
        // depth is the closest point: the body reflects behind it).
        let (mut same, mut all) = (0.0, 0.0);
        for &(s, c) in &scored {
            let w = (s - best).exp();
            all += w;
            let behind = c.depth_m - chosen.depth_m;
            if (-1.0..=self.extent_m.max(1.0)).contains(&behind) {
                same += w;
            }
        }
        let rest = all - same;
        let features = Features {
            over_floor_db: chosen.over_floor_db,
            margin: if rest > 0.0 {
                (same / rest).ln().min(NO_RIVAL_MARGIN)
            } else {
                NO_RIVAL_MARGIN
            },
            monocular: self.monocular(chosen.depth_m),
            height: self.height(chosen.depth_m),
            beamwidth_deg: self.beamwidth_deg,
            vagueness: self
                .height
                .map_or(VAGUE, |h| (h.far_m / h.near_m.max(1e-3)).ln().min(VAGUE)),
            survives: f64::from(u8::from(chosen.survives)),
            ground: self.ground(chosen.depth_m),
        };
        Some(Verdict {
            depth_m: chosen.depth_m,
            reflection_m: strongest.depth_m,
            velocity_mps: strongest.velocity_mps,
            confidence: confidence(&features),
            features,
        })
    }

    /// The nearest candidate of the mover `strongest` is (same velocity within
    /// [`SAME_MOVER_MPS`], up to the object's extent in front, at most [`LEAD_DB`] weaker);
    /// `strongest` itself for a static candidate or when none is nearer.
    fn leading_edge<'a>(
        &self,
        scored: &[(f64, &'a Candidate)],
        strongest: &'a Candidate,
    ) -> &'a Candidate {
        let Some(v) = strongest.velocity_mps else {
            return strongest;
        };
        let reach = strongest.depth_m - self.extent_m.max(1.0);
        scored
            .iter()
            .map(|&(_, c)| c)
            .filter(|c| {
                c.velocity_mps
                    .is_some_and(|w| (w - v).abs() <= SAME_MOVER_MPS)
                    && (reach..strongest.depth_m).contains(&c.depth_m)
                    && c.over_floor_db >= strongest.over_floor_db - LEAD_DB
            })
            .min_by(|a, b| a.depth_m.total_cmp(&b.depth_m))
            .unwrap_or(strongest)
    }
}

/// The logistic confidence of [`COEFFICIENTS`].
pub fn confidence(f: &Features) -> f64 {
    let [
        b,
        w_db,
        w_margin,
        w_mono,
        w_height,
        w_beam,
        w_vague,
        w_survives,
        w_ground,
    ] = COEFFICIENTS;
    let z = b
        + w_db * f.over_floor_db
        + w_margin * f.margin
        + w_mono * f.monocular
        + w_height * f.height
        + w_beam * f.beamwidth_deg
        + w_vague * f.vagueness
        + w_survives * f.survives
        + w_ground * f.ground;
    1.0 / (1.0 + (-z).exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A person 1.7 m tall at horizontal range 40 m, level camera with fy = 1000 px.
    fn person_at_40m() -> VerticalExtent {
        let pitch = 1e-3;
        // Pixel centres from the top row to the bottom row: 1.7 / 40 of slope minus a pixel.
        VerticalExtent {
            top: -0.02,
            bottom: -0.02 + 1.7 / 40.0 - pitch,
            pitch,
            clipped: false,
        }
    }

    #[test]
    fn height_bounds_follow_the_closed_form() {
        let e = person_at_40m();
        let HeightCue {
            near_m: near,
            far_m: far,
            rows,
        } = HeightCue::of("person", &e).unwrap();
        let span = 1.7 / 40.0;
        assert!((near - 1.5 / (span + 3e-3)).abs() < 1e-9, "{near}");
        assert!((far - 1.9 / (span - 3e-3)).abs() < 1e-9, "{far}");
        assert!(near < 40.0 && far > 40.0);
        assert!((rows - 1.7 / 40.0 / 1e-3).abs() < 1e-9, "{rows}");
        // A mask cut by the image's edge bounds only the far side.
        let cut = VerticalExtent { clipped: true, ..e };
        assert_eq!(HeightCue::of("person", &cut).unwrap().near_m, 0.0);
        assert_eq!(HeightCue::of("tree", &e), None);
    }

    #[test]
    fn monocular_error_follows_table_one_and_keeps_growing() {
        assert!((monocular_error_m(10.0) - 0.6).abs() < 1e-12);
        assert!((monocular_error_m(30.0) - 6.75).abs() < 1e-12);
        assert!((monocular_error_m(50.0) - 19.4).abs() < 1e-12);
        assert!(
            (monocular_error_m(50.0 + 1e-9) - 19.4).abs() < 1e-6,
            "continuous"
        );
        assert!((monocular_error_m(300.0) - (19.4 + 0.6325 * 250.0)).abs() < 1e-9);
    }

    /// The cue of a mask 100 rows tall with these bounds.
    fn cue(near_m: f64, far_m: f64) -> Option<HeightCue> {
        Some(HeightCue {
            near_m,
            far_m,
            rows: 100.0,
        })
    }

    #[test]
    fn a_mask_of_a_few_rows_bounds_the_range_loosely() {
        // A car 1.5 m tall at 220 m seen at 2 mrad per row is 3.4 rows; grown by two rows at
        // each end, its mask is 9 rows and its far bound 1.6 m / 6 rows = 133 m.
        let pitch = 2e-3;
        let grown = VerticalExtent {
            top: 0.0,
            bottom: 8.0 * pitch,
            pitch,
            clipped: false,
        };
        let small = HeightCue::of("car", &grown).unwrap();
        assert!(
            (small.far_m - 1.6 / (6.0 * pitch)).abs() < 1e-9,
            "{small:?}"
        );
        // Its window reaches the truth; a tall mask's is WINDOW_MARGIN, as before the cue knew
        // its rows.
        assert!(small.window_m().1 > 220.0, "{:?}", small.window_m());
        let tall = cue(30.0, 40.0).unwrap();
        assert_eq!(tall.window_m(), (30.0 * 0.8, 40.0 * 1.25));
        // The window's edge costs the small mask what it costs the tall one.
        let edge = |c: &HeightCue| c.log_prior(c.window_m().1 * (1.0 + 1e-9));
        assert!(
            (edge(&small) - edge(&tall)).abs() < 1e-6,
            "{}",
            edge(&small)
        );
        // 31 % beyond the far bound costs the small mask what 8.5 % costs the tall one.
        let beyond = small.log_prior(1.313 * small.far_m);
        assert!(
            (beyond - tall.log_prior(1.085 * 40.0)).abs() < 0.1,
            "{beyond}"
        );
        assert!(beyond < -1.0);
    }

    fn candidate(depth_m: f64, over_floor_db: f64) -> Candidate {
        Candidate {
            depth_m,
            over_floor_db,
            survives: true,
            velocity_mps: None,
        }
    }

    /// Issue #17's example: a sign at 40.6 m whose span holds a wall's side-lobe ridge at
    /// 29.4 m that scores higher.
    fn sign_behind_a_ridge(height: Option<HeightCue>) -> Evidence {
        Evidence {
            candidates: vec![candidate(29.4, 22.5), candidate(40.6, 20.0)],
            monocular_m: Some(34.0),
            height,
            ground: None,
            beamwidth_deg: 1.33,
            extent_m: 1.5,
        }
    }

    #[test]
    fn the_mask_height_overrules_a_stronger_ridge_at_the_wrong_range() {
        // A 0.6–0.9 m plate 15 px tall at fy = 1000: 40–60 m.
        let v = sign_behind_a_ridge(cue(37.0, 62.0)).judge().unwrap();
        assert_eq!(v.depth_m, 40.6);
        assert!(v.features.margin > 1.0 && v.detected(), "{v:?}");
        // Without the height cue, the radar's choice stands but is not trusted: the monocular
        // prior cannot tell 29.4 from 40.6 at this range.
        let blind = sign_behind_a_ridge(None).judge().unwrap();
        assert_eq!(blind.depth_m, 29.4);
        assert!(!blind.detected(), "{blind:?}");
        assert!(v.confidence > blind.confidence);
    }

    #[test]
    fn a_choice_the_ground_contact_contradicts_is_not_trusted() {
        // The 8-element radar's 14.5° beam holds a car at 30 m and, 3 dB stronger, clutter at
        // 40 m; the mask's height allows both (26–45 m) and the monocular range (33 m) cannot
        // tell them apart, so the clutter is chosen.
        let e = |ground| Evidence {
            candidates: vec![candidate(40.0, 30.0), candidate(30.0, 27.0)],
            monocular_m: Some(33.0),
            height: cue(26.0, 45.0),
            ground,
            beamwidth_deg: 14.5,
            extent_m: 6.0,
        };
        let at = |range_m| {
            e(Some(Contact {
                range_m,
                tolerance: 0.05,
            }))
            .judge()
            .unwrap()
        };
        let blind = e(None).judge().unwrap();
        assert_eq!(blind.depth_m, 40.0);
        // The mask's bottom meets the ground at 30.2 m: the choice stands (the cue does not
        // choose), but its confidence falls under the threshold.
        let contradicted = at(30.2);
        assert_eq!(contradicted.depth_m, 40.0);
        assert!(contradicted.features.ground < -1.0, "{contradicted:?}");
        assert!(contradicted.confidence < blind.confidence && !contradicted.detected());
        // A contact that agrees (within its tolerance) leaves the verdict as it was.
        let agreed = at(40.5);
        assert_eq!(agreed.features.ground, 0.0);
        assert_eq!(agreed.confidence, blind.confidence);
    }

    #[test]
    fn confidence_grows_with_the_lead_over_the_rival() {
        let mut f = Features {
            over_floor_db: 30.0,
            margin: 0.0,
            monocular: 0.0,
            height: 0.0,
            beamwidth_deg: 1.33,
            vagueness: 0.5,
            survives: 1.0,
            ground: 0.0,
        };
        let mut last = 0.0;
        for m in [0.0, 1.0, 2.0, 4.0, 8.0] {
            f.margin = m;
            let c = confidence(&f);
            assert!(c > last && c < 1.0, "{m}: {c}");
            last = c;
        }
        // A depth the mask's height rules out is not trusted however strong the radar peak.
        f.height = -(1.3f64).ln() / FAR_SPREAD;
        assert!(confidence(&f) < DETECTION_CONFIDENCE);
    }

    #[test]
    fn a_near_tie_is_not_detected() {
        // Two depths 12 m apart, 0.5 dB apart, both inside the height bounds and equally far
        // from the monocular range.
        let e = Evidence {
            candidates: vec![candidate(40.0, 30.0), candidate(52.0, 29.5)],
            monocular_m: Some(46.0),
            height: cue(35.0, 60.0),
            ground: None,
            beamwidth_deg: 1.33,
            extent_m: 1.5,
        };
        let v = e.judge().unwrap();
        assert!(v.features.margin.abs() < 0.1, "{v:?}");
        assert!(!v.detected(), "{v:?}");
    }

    #[test]
    fn a_side_lobe_loses_to_a_weaker_candidate_that_survives() {
        // Two depths the camera cannot tell apart; the stronger one is another direction's
        // side lobe (it does not survive the module's test).
        let mut lobe = candidate(30.0, 35.0);
        lobe.survives = false;
        let e = Evidence {
            candidates: vec![lobe, candidate(38.0, 30.0)],
            monocular_m: Some(34.0),
            height: cue(25.0, 45.0),
            ground: None,
            beamwidth_deg: 14.5,
            extent_m: 6.0,
        };
        let v = e.judge().unwrap();
        // 0.15 nats/dB · 5 dB < SIDE_LOBE_NATS: the survivor wins.
        const { assert!(RADAR_NATS_PER_DB * 5.0 < SIDE_LOBE_NATS) };
        assert_eq!(v.depth_m, 38.0);
        assert_eq!(v.features.survives, 1.0);
        // The same verdict on a candidate that does not survive is less confident.
        let f = Features {
            survives: 0.0,
            ..v.features
        };
        assert!(confidence(&f) < v.confidence);
    }

    #[test]
    fn reflections_of_the_body_behind_the_depth_are_not_rivals() {
        // A car's closest point at 120 m and its body 3 m behind it (a mover's Doppler
        // candidates), a clutter candidate 40 m away.
        let mover = |d: f64, db: f64| Candidate {
            velocity_mps: Some(-8.0),
            ..candidate(d, db)
        };
        let e = |extent_m: f64| Evidence {
            candidates: vec![
                mover(120.0, 45.0),
                mover(123.0, 40.0),
                candidate(80.0, 30.0),
            ],
            monocular_m: None,
            height: cue(60.0, 400.0),
            ground: None,
            beamwidth_deg: 1.33,
            extent_m,
        };
        let car = e(6.0).judge().unwrap();
        let point = e(0.0).judge().unwrap();
        assert_eq!((car.depth_m, point.depth_m), (120.0, 120.0));
        // Counted as the same answer, the body raises the chosen depth's share.
        assert!(
            car.features.margin > point.features.margin + 1.0,
            "{car:?} {point:?}"
        );
        // Another mover's candidate in front of the chosen depth is a rival whatever the extent.
        let other = Candidate {
            velocity_mps: Some(-12.0),
            ..candidate(116.0, 44.0)
        };
        let front = Evidence {
            candidates: vec![mover(120.0, 45.0), other],
            ..e(6.0)
        };
        assert!(front.judge().unwrap().features.margin < 1.0);
    }

    #[test]
    fn a_mover_s_depth_is_its_nearest_return() {
        // A far car (case far-moving-10502-0018): its strongest return at 273.6 m is the body,
        // its closest point 268.7 m; the Doppler path reports three depths of the one mover.
        let mover = |d: f64, db: f64, v: f64| Candidate {
            velocity_mps: Some(v),
            ..candidate(d, db)
        };
        let e = |candidates| Evidence {
            candidates,
            monocular_m: None,
            height: cue(100.0, 800.0),
            ground: None,
            beamwidth_deg: 1.33,
            extent_m: 6.0,
        };
        let car = e(vec![
            mover(273.6, 46.0, -6.3),
            mover(271.3, 40.0, -6.3),
            mover(269.4, 40.0, -6.5),
            candidate(129.7, 46.0),
        ])
        .judge()
        .unwrap();
        assert_eq!(car.depth_m, 269.4);
        assert_eq!(car.velocity_mps, Some(-6.3), "the strongest return's");
        // All three are one answer: no rival but the clutter far off.
        assert!(car.features.margin > 3.0 && car.detected(), "{car:?}");
        // Not the mover's: another velocity, more than LEAD_DB weaker, or beyond its extent.
        for other in [
            mover(269.4, 40.0, -8.0),
            mover(269.4, 35.0, -6.3),
            mover(267.0, 40.0, -6.3),
        ] {
            let v = e(vec![mover(273.6, 46.0, -6.3), other]).judge().unwrap();
            assert_eq!(v.depth_m, 273.6, "{other:?}");
        }
    }

    #[test]
    fn no_candidates_no_verdict() {
        let e = Evidence {
            candidates: Vec::new(),
            monocular_m: None,
            height: None,
            ground: None,
            beamwidth_deg: 1.33,
            extent_m: 1.5,
        };
        assert_eq!(e.judge(), None);
    }

    #[test]
    fn a_narrow_camera_cue_that_holds_the_depth_is_the_likelier_owner() {
        let e = |monocular_m, height| Evidence {
            candidates: vec![candidate(90.0, 30.0)],
            monocular_m,
            height,
            ground: None,
            beamwidth_deg: 14.5,
            extent_m: 6.0,
        };
        let d = 90.0;
        // Closed form without cues: flat over 300 m, and the vague height's ln 3.
        let blind = e(None, None).camera_log_density(d, 300.0);
        assert!(
            (blind - (-(300.0f64).ln() - VAGUE.ln())).abs() < 1e-12,
            "{blind}"
        );
        // Height bounds 80-100 m hold 90 m more tightly than 50-450 m.
        let tight = e(None, cue(80.0, 100.0)).camera_log_density(d, 300.0);
        let wide = e(None, cue(50.0, 450.0)).camera_log_density(d, 300.0);
        assert!(
            (tight - wide - ((450.0f64 / 50.0).ln() / (100.0f64 / 80.0).ln()).ln()).abs() < 1e-9
        );
        assert!(tight > wide && wide > blind, "{tight} {wide} {blind}");
        // Bounds that exclude the depth fall below the wide ones.
        let elsewhere = e(None, cue(150.0, 200.0)).camera_log_density(d, 300.0);
        assert!(elsewhere < wide, "{elsewhere} {wide}");
        // A monocular range at the depth beats none; one 60 m off does not.
        let b = monocular_error_m(d) / std::f64::consts::LN_2;
        let on = e(Some(d), None).camera_log_density(d, 300.0);
        assert!((on - (-(2.0 * b).ln() - VAGUE.ln())).abs() < 1e-12, "{on}");
        assert!(on > blind);
        assert!(e(Some(d + 150.0), None).camera_log_density(d, 300.0) < on);
    }

    #[test]
    fn without_drops_one_reflection_and_keeps_the_rest() {
        let mover = |depth_m, velocity_mps| Candidate {
            velocity_mps,
            ..candidate(depth_m, 30.0)
        };
        let e = Evidence {
            candidates: vec![
                mover(91.5, Some(-12.7)), // 1 m in front: the same reflection
                mover(92.3, Some(-12.7)),
                mover(96.0, Some(-12.2)), // behind, within the 6 m extent, same mover
                mover(92.3, Some(3.0)),   // another mover at the same range
                mover(92.3, None),        // a static candidate there
                mover(99.0, Some(-12.7)), // beyond the extent
                mover(90.0, Some(-12.7)), // more than 1 m in front
            ],
            monocular_m: None,
            height: None,
            ground: None,
            beamwidth_deg: 14.5,
            extent_m: 6.0,
        };
        let kept: Vec<_> = e
            .without(92.3, Some(-12.7))
            .candidates
            .iter()
            .map(|c| (c.depth_m, c.velocity_mps))
            .collect();
        assert_eq!(
            kept,
            [
                (92.3, Some(3.0)),
                (92.3, None),
                (99.0, Some(-12.7)),
                (90.0, Some(-12.7))
            ]
        );
        let statics = e.without(92.3, None).candidates;
        assert_eq!(statics.len(), 6);
        assert!(statics.iter().all(|c| c.velocity_mps.is_some()));
    }
}
