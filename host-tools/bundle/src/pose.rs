//! The radar's pose on the ground plane and the moves between frames of the radar frame.
//!
//! World frame: the radar frame of the first frame (x right, y down, z forward). Yaw is positive
//! turning left (from +z towards −x), so forward is `(−sin ψ, cos ψ)` and right `(cos ψ, sin ψ)`.

/// The radar's pose in the world frame: position `[x, z]` (m) and yaw (rad, positive left).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    /// Position `[x, z]`, m.
    pub position: [f64; 2],
    /// Heading, rad, positive turning left (from +z towards −x).
    pub yaw: f64,
}

impl Pose {
    /// Unit forward and right vectors in the world frame.
    pub fn axes(&self) -> ([f64; 2], [f64; 2]) {
        let (s, c) = self.yaw.sin_cos();
        ([-s, c], [c, s])
    }

    /// A world point `[x, z]` in the radar frame.
    pub fn to_radar(&self, p: [f64; 2]) -> [f64; 2] {
        let (f, r) = self.axes();
        let d = [p[0] - self.position[0], p[1] - self.position[1]];
        [d[0] * r[0] + d[1] * r[1], d[0] * f[0] + d[1] * f[1]]
    }

    /// A radar-frame point `[x, z]` in the world frame (the inverse of [`Pose::to_radar`]).
    pub fn to_world(&self, p: [f64; 2]) -> [f64; 2] {
        let (f, r) = self.axes();
        [
            self.position[0] + p[0] * r[0] + p[1] * f[0],
            self.position[1] + p[0] * r[1] + p[1] * f[1],
        ]
    }

    /// A world direction (velocity) in the radar frame.
    pub fn rotate_to_radar(&self, v: [f64; 2]) -> [f64; 2] {
        let (f, r) = self.axes();
        [v[0] * r[0] + v[1] * r[1], v[0] * f[0] + v[1] * f[1]]
    }

    /// The pose `dt` seconds later for a radar moving with velocity `v = [v_x, v_z]` in its own
    /// frame and turning at `yaw_rate` (rad/s, positive left), both constant meanwhile: the
    /// exact arc (its chord along the midpoint heading, `v·dt·sin(ωdt/2)/(ωdt/2)` long).
    pub fn advanced(&self, v: [f64; 2], yaw_rate: f64, dt: f64) -> Pose {
        let half = yaw_rate * dt / 2.0;
        let mid = Pose {
            yaw: self.yaw + half,
            ..*self
        };
        let chord = if half.abs() > 1e-12 {
            half.sin() / half
        } else {
            1.0
        };
        let (f, r) = mid.axes();
        let k = chord * dt;
        Pose {
            position: [
                self.position[0] + (v[0] * r[0] + v[1] * f[0]) * k,
                self.position[1] + (v[0] * r[1] + v[1] * f[1]) * k,
            ],
            yaw: self.yaw + yaw_rate * dt,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn world_and_radar_frames_are_inverse_and_turns_follow_the_arc() {
        let p = Pose {
            position: [3.0, -2.0],
            yaw: 0.7,
        };
        let q = p.to_world(p.to_radar([1.5, 9.0]));
        assert!((q[0] - 1.5).abs() < 1e-12 && (q[1] - 9.0).abs() < 1e-12);
        // A quarter circle of radius 10 m (v = 5 m/s, ω = 0.5 rad/s) in 7 steps: the radar
        // ends 10 m left and 10 m ahead, facing −x (closed form).
        let mut p = Pose::default();
        let steps = 7;
        let dt = std::f64::consts::PI / 2.0 / 0.5 / f64::from(steps);
        for _ in 0..steps {
            p = p.advanced([0.0, 5.0], 0.5, dt);
        }
        assert!(
            (p.position[0] + 10.0).abs() < 1e-9 && (p.position[1] - 10.0).abs() < 1e-9,
            "{p:?}"
        );
        assert!((p.yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}
