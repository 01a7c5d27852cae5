//! Submaps (dense radar mapping, Sec. 3.2): the static points of the last frames, moved into the
//! current radar frame by the poses the Doppler odometry integrates. The density growth factor
//! is the paper's: filled pixels of the submap's depth image over those of the frame's alone.

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
}
