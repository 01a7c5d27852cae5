//! How objects move across a scene's frames: straight on at their velocity, or along a scripted
//! path (the perimeter preset's walker).

use super::object::SceneObject;

/// A walk through waypoints at constant speed; the object stands still at the last one.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    /// Instance id of the object that walks it.
    pub id: u16,
    /// Footprint centres `[x, z]`, m, in order; the first is where the object is at t = 0.
    pub waypoints: Vec<[f64; 2]>,
    /// Walking speed, m/s.
    pub speed: f64,
}

impl Path {
    /// Footprint centre (m) and velocity (m/s) at time `t` (s) after the first frame.
    pub fn pose(&self, t: f64) -> ([f64; 2], [f64; 2]) {
        let mut left = (t * self.speed).max(0.0);
        for w in self.waypoints.windows(2) {
            let (a, b) = (w[0], w[1]);
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            if len > 0.0 && left < len {
                let u = [(b[0] - a[0]) / len, (b[1] - a[1]) / len];
                let at = [a[0] + u[0] * left, a[1] + u[1] * left];
                return (at, [u[0] * self.speed, u[1] * self.speed]);
            }
            left -= len;
        }
        (self.waypoints.last().copied().unwrap_or_default(), [0.0; 2])
    }

    /// Length of the walk, m.
    pub fn length(&self) -> f64 {
        self.waypoints
            .windows(2)
            .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
            .sum()
    }
}

/// The scene at time `t` (s): objects with a path where it puts them, the others moved straight
/// on at their velocity. At `t = 0` without paths this is the scene as laid out.
pub fn at(objects: &[SceneObject], paths: &[Path], t: f64) -> Vec<SceneObject> {
    objects
        .iter()
        .map(|o| match paths.iter().find(|p| p.id == o.id) {
            Some(p) => {
                let (centre, velocity) = p.pose(t);
                o.placed(centre, velocity)
            }
            None if t == 0.0 || o.velocity == [0.0; 2] => o.clone(),
            None => {
                let c = o.centre();
                let centre = [c[0] + o.velocity[0] * t, c[1] + o.velocity[1] * t];
                o.placed(centre, o.velocity)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_is_walked_at_its_speed_and_ends_standing() {
        let p = Path {
            id: 1,
            waypoints: vec![[0.0, 10.0], [4.0, 10.0], [4.0, 7.0]],
            speed: 2.0,
        };
        assert_eq!(p.length(), 7.0);
        assert_eq!(p.pose(0.0), ([0.0, 10.0], [2.0, 0.0]));
        assert_eq!(p.pose(1.5), ([3.0, 10.0], [2.0, 0.0]));
        // 2.5 s: 5 m along, 1 m into the second leg, walking towards −z.
        let (c, v) = p.pose(2.5);
        assert!((c[0] - 4.0).abs() < 1e-12 && (c[1] - 9.0).abs() < 1e-12);
        assert_eq!(v, [0.0, -2.0]);
        assert_eq!(p.pose(10.0), ([4.0, 7.0], [0.0, 0.0]));
    }
}
