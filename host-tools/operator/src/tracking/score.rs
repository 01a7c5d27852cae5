//! CLEAR-MOT scoring of tracks against ground truth (Bernardin & Stiefelhagen 2008), the
//! figures issue #20 asks of the tracker: per frame, truth objects and tracks are matched one to
//! one within a distance (a match kept from the previous frame is kept while it stays within
//! it); a truth object matched to another track than before is an **id switch**, one left
//! unmatched a **miss**, a track left unmatched a **false track**.
//! `MOTA = 1 − (misses + false tracks + switches) / truth objects`.

use super::assign::assign;
use std::collections::BTreeMap;

/// What one frame holds: truth objects and tracks, each an id and a ground-plane position (m).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameObjects {
    /// Truth id and position.
    pub truth: Vec<(u32, [f64; 2])>,
    /// Track id and position.
    pub tracks: Vec<(u32, [f64; 2])>,
}

/// The CLEAR-MOT counts over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Clear {
    /// Truth objects summed over frames.
    pub truth: u32,
    /// Truth objects without a track within the distance.
    pub misses: u32,
    /// Tracks without a truth object within the distance.
    pub false_tracks: u32,
    /// Truth objects whose track changed.
    pub id_switches: u32,
    /// Matches summed over frames.
    pub matches: u32,
    /// Mean distance of the matches, m.
    pub motp_m: f64,
}

impl Clear {
    /// `1 − (misses + false tracks + id switches) / truth objects` (1 with no truth).
    pub fn mota(&self) -> f64 {
        if self.truth == 0 {
            return 1.0;
        }
        1.0 - f64::from(self.misses + self.false_tracks + self.id_switches) / f64::from(self.truth)
    }
}

/// Sums the counts of two runs; MOTP is the mean over both runs' matches.
impl std::ops::AddAssign for Clear {
    fn add_assign(&mut self, o: Self) {
        let matches = self.matches + o.matches;
        self.motp_m = if matches == 0 {
            0.0
        } else {
            (self.motp_m * f64::from(self.matches) + o.motp_m * f64::from(o.matches))
                / f64::from(matches)
        };
        self.truth += o.truth;
        self.misses += o.misses;
        self.false_tracks += o.false_tracks;
        self.id_switches += o.id_switches;
        self.matches = matches;
    }
}

impl std::fmt::Display for Clear {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "MOTA {:.3}, MOTP {:.2} m: {} truth objects, {} missed, {} false tracks, {} id switches",
            self.mota(),
            self.motp_m,
            self.truth,
            self.misses,
            self.false_tracks,
            self.id_switches
        )
    }
}

/// Scores `frames` with matches allowed within `within_m` metres. O(F · (T + K)³).
///
/// ```
/// use metamoran_operator::tracking::score::{FrameObjects, score};
/// let frame = |track: u32| FrameObjects {
///     truth: vec![(7, [0.0, 10.0])],
///     tracks: vec![(track, [0.1, 10.0])],
/// };
/// // The same object, its track renumbered once: one switch in three frames.
/// let c = score(&[frame(1), frame(1), frame(2)], 1.0);
/// assert_eq!((c.truth, c.id_switches, c.misses, c.false_tracks), (3, 1, 0, 0));
/// assert!((c.mota() - (1.0 - 1.0 / 3.0)).abs() < 1e-12);
/// ```
pub fn score(frames: &[FrameObjects], within_m: f64) -> Clear {
    let mut c = Clear::default();
    let mut last: BTreeMap<u32, u32> = BTreeMap::new();
    let mut distance = 0.0;
    let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    for fr in frames {
        c.truth += fr.truth.len() as u32;
        let (rows, cols) = (fr.truth.len(), fr.tracks.len());
        // Keep last frame's pairs that are still close: they cost nothing, so they win.
        let mut cost = vec![f64::INFINITY; rows * cols];
        for (i, (tid, tp)) in fr.truth.iter().enumerate() {
            for (j, (kid, kp)) in fr.tracks.iter().enumerate() {
                let d = dist(*tp, *kp);
                if d < within_m {
                    let kept = last.get(tid) == Some(kid);
                    cost[i * cols + j] = if kept { 0.0 } else { d + within_m };
                }
            }
        }
        let matched = assign(&cost, rows, cols, 2.0 * within_m + 1.0);
        let mut taken = vec![false; cols];
        for (i, m) in matched.iter().enumerate() {
            let (tid, tp) = fr.truth[i];
            match m {
                Some(j) => {
                    taken[*j] = true;
                    let (kid, kp) = fr.tracks[*j];
                    c.matches += 1;
                    distance += dist(tp, kp);
                    if last.insert(tid, kid).is_some_and(|before| before != kid) {
                        c.id_switches += 1;
                    }
                }
                None => c.misses += 1,
            }
        }
        c.false_tracks += taken.iter().filter(|t| !**t).count() as u32;
    }
    c.motp_m = if c.matches > 0 {
        distance / f64::from(c.matches)
    } else {
        0.0
    };
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn misses_false_tracks_and_switches_are_counted_by_their_definitions() {
        let frames = [
            // Both found.
            FrameObjects {
                truth: vec![(1, [0.0, 10.0]), (2, [5.0, 10.0])],
                tracks: vec![(10, [0.2, 10.0]), (20, [5.0, 10.3])],
            },
            // 2 missed, a false track far away.
            FrameObjects {
                truth: vec![(1, [0.0, 10.0]), (2, [5.0, 10.0])],
                tracks: vec![(10, [0.1, 10.0]), (30, [20.0, 40.0])],
            },
            // 2 back on another track: a switch.
            FrameObjects {
                truth: vec![(1, [0.0, 10.0]), (2, [5.0, 10.0])],
                tracks: vec![(10, [0.0, 10.0]), (40, [5.0, 10.0])],
            },
        ];
        let c = score(&frames, 1.0);
        assert_eq!(
            (c.truth, c.matches, c.misses, c.false_tracks, c.id_switches),
            (6, 5, 1, 1, 1)
        );
        assert!((c.mota() - 0.5).abs() < 1e-12);
        assert!((c.motp_m - (0.2 + 0.3 + 0.1 + 0.0 + 0.0) / 5.0).abs() < 1e-12);
    }

    #[test]
    fn a_kept_match_is_not_stolen_by_a_closer_track() {
        // Track 20 is nearer in frame 2, but 10 still fits: keeping it is no switch.
        let frames = [
            FrameObjects {
                truth: vec![(1, [0.0, 10.0])],
                tracks: vec![(10, [0.1, 10.0])],
            },
            FrameObjects {
                truth: vec![(1, [0.0, 10.0])],
                tracks: vec![(10, [0.8, 10.0]), (20, [0.05, 10.0])],
            },
        ];
        let c = score(&frames, 1.0);
        assert_eq!((c.id_switches, c.false_tracks), (0, 1));
    }
}
