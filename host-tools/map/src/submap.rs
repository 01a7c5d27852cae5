//! Submaps (dense radar mapping, Sec. 3.2): the static points of the last frames, moved into the
//! current radar frame by the poses the Doppler odometry integrates. The density growth factor
//! is the paper's: filled pixels of the submap's depth image over those of the frame's alone.
//!
//! Which earlier points a submap keeps is [`Keep`]: all of them (the paper's submap), or only
//! those the current frame sees again, the consistency check across frames that keeps out what
//! has since been hidden (by something the radar does not report) or was never there.

use super::cylinder::DepthImage;
use metamoran_bundle::pose::Pose;

/// Points of frames `first..=last` (each `(pose, points in its radar frame)`) in frame `last`'s
/// radar frame. O(points).
pub fn accumulate(frames: &[(Pose, Vec<[f64; 3]>)], first: usize, last: usize) -> Vec<[f64; 3]> {
    let here = frames[last].0;
    frames[first..=last]
        .iter()
        .flat_map(|(pose, points)| {
            points.iter().map(move |p| {
                let w = pose.to_world([p[0], p[2]]);
                let q = here.to_radar(w);
                [q[0], p[1], q[1]]
            })
        })
        .collect()
}

/// Which points of earlier frames a submap keeps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Keep {
    /// Every static point of every frame.
    #[default]
    All,
    /// The current frame's points, and an earlier frame's point only where one of the current
    /// frame's is within `within_m` of it (3D, m).
    SeenAgain {
        /// How near a current point must be, m.
        within_m: f64,
    },
}

impl Keep {
    /// [`Keep::SeenAgain`] within 0.5 m: about two of the imaging board's 0.23 m range bins,
    /// and its 1.8° beam at 16 m.
    pub const SEEN_AGAIN: Self = Self::SeenAgain { within_m: 0.5 };
}

/// [`accumulate`], keeping what `keep` says. `SeenAgain` is O(points · points of frame
/// `last`).
pub fn accumulate_keeping(
    frames: &[(Pose, Vec<[f64; 3]>)],
    first: usize,
    last: usize,
    keep: Keep,
) -> Vec<[f64; 3]> {
    let points = accumulate(frames, first, last);
    let Keep::SeenAgain { within_m } = keep else {
        return points;
    };
    let now = &frames[last].1;
    let near = |p: &&[f64; 3]| {
        now.iter().any(|q| {
            (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)
                <= within_m * within_m
        })
    };
    // The current frame's own points are the last ones `accumulate` returns: all stay.
    let (earlier, current) = points.split_at(points.len() - now.len());
    earlier
        .iter()
        .filter(near)
        .chain(current)
        .copied()
        .collect()
}

/// The density growth factor of a submap over its last frame (`None` if the frame is empty).
pub fn density_growth(frame: &DepthImage, submap: &DepthImage) -> Option<f64> {
    let f = frame.filled();
    (f > 0).then(|| submap.filled() as f64 / f as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_static_point_stays_put_across_frames() {
        // The radar drives 2 m forward while turning 0.1 rad left; a post at world (3, 20) is seen
        // from both poses; in the second frame's view both sightings coincide (closed form).
        let a = Pose::default();
        let b = Pose {
            position: [-0.1, 2.0],
            yaw: 0.1,
        };
        let post = [3.0, 20.0];
        let seen = |p: &Pose| {
            let q = p.to_radar(post);
            vec![[q[0], -1.0, q[1]]]
        };
        let frames = vec![(a, seen(&a)), (b, seen(&b))];
        let sub = accumulate(&frames, 0, 1);
        assert_eq!(sub.len(), 2);
        for k in 0..3 {
            assert!((sub[0][k] - sub[1][k]).abs() < 1e-9, "{sub:?}");
        }
        let img = DepthImage::project(sub.iter().copied());
        assert_eq!(
            density_growth(&DepthImage::project(seen(&b)), &img),
            Some(1.0)
        );
    }

    #[test]
    fn an_earlier_point_stays_only_where_the_current_frame_sees_it_again() {
        // Frame 0 sees a post at world (3, 20) and a wall point at (-2, 30); frame 1, 2 m on,
        // sees the post 0.3 m off where frame 0 put it and not the wall point (hidden now).
        let (a, b) = (
            Pose::default(),
            Pose {
                position: [0.0, 2.0],
                yaw: 0.0,
            },
        );
        let at = |p: &Pose, w: [f64; 2], y: f64| {
            let q = p.to_radar(w);
            [q[0], y, q[1]]
        };
        let frames = vec![
            (
                a,
                vec![at(&a, [3.0, 20.0], -1.0), at(&a, [-2.0, 30.0], 0.0)],
            ),
            (b, vec![at(&b, [3.3, 20.0], -1.0)]),
        ];
        assert_eq!(accumulate_keeping(&frames, 0, 1, Keep::All).len(), 3);
        let kept = accumulate_keeping(&frames, 0, 1, Keep::SEEN_AGAIN);
        assert_eq!(
            kept,
            vec![at(&b, [3.0, 20.0], -1.0), at(&b, [3.3, 20.0], -1.0)]
        );
        // 0.3 m is beyond a 0.25 m tolerance: only the current point stays.
        let strict = Keep::SeenAgain { within_m: 0.25 };
        assert_eq!(
            accumulate_keeping(&frames, 0, 1, strict),
            vec![at(&b, [3.3, 20.0], -1.0)]
        );
    }
}
