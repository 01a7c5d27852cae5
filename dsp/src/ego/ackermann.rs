//! From the radar's velocity to the vehicle's: forward speed and yaw rate under the Ackermann
//! assumption (no side slip at the rear axle, the centre of rotation's forward position).
//!
//! In the vehicle frame (X forward, Y left) a radar mounted `L` ahead of and `B` left of the
//! rear axle's centre moves with `V_X = V − ω·B` and `V_Y = ω·L` (paper, Sec. 3.2), so
//! `ω = V_Y / L` and `V = V_X + ω·B`.

/// Where the radar sits on the vehicle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mount {
    /// Forward offset from the rear axle's centre, m (`L`; must not be 0).
    pub forward_m: f32,
    /// Leftward offset from the rear axle's centre, m (`B`).
    pub left_m: f32,
    /// Boresight yaw relative to the vehicle's forward axis, rad, positive to the left (`β`).
    pub yaw_rad: f32,
}

/// The vehicle's motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VehicleMotion {
    /// Forward speed at the rear axle, m/s.
    pub speed_mps: f32,
    /// Yaw rate, rad/s, positive turning left.
    pub yaw_rate_rps: f32,
}

impl Mount {
    /// The radar's velocity `[v_x, v_z]` (radar frame: x right, z forward) in the vehicle
    /// frame `[V_X, V_Y]` (forward, left).
    pub fn to_vehicle(&self, v: [f32; 2]) -> [f32; 2] {
        let (s, c) = libm::sincosf(self.yaw_rad);
        // Radar forward is (cos β, sin β) in the vehicle frame, radar right is (sin β, −cos β).
        [v[1] * c + v[0] * s, v[1] * s - v[0] * c]
    }

    /// The radar's velocity in its own frame for vehicle motion `m`: the inverse of
    /// [`Mount::motion`] (for simulation and tests).
    pub fn radar_velocity(&self, m: VehicleMotion) -> [f32; 2] {
        let vx = m.speed_mps - m.yaw_rate_rps * self.left_m;
        let vy = m.yaw_rate_rps * self.forward_m;
        let (s, c) = libm::sincosf(self.yaw_rad);
        // Inverse rotation of `to_vehicle`.
        [vx * s - vy * c, vx * c + vy * s]
    }

    /// Vehicle speed and yaw rate from the radar's velocity `[v_x, v_z]` (radar frame).
    pub fn motion(&self, v: [f32; 2]) -> VehicleMotion {
        let [vx, vy] = self.to_vehicle(v);
        let omega = vy / self.forward_m;
        VehicleMotion {
            speed_mps: vx + omega * self.left_m,
            yaw_rate_rps: omega,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_radar_ahead_of_the_axle_sees_the_turn_as_sideways_motion() {
        // Closed form: boresight forward (β = 0), 3.6 m ahead, on the centre line. Turning left at
        // 0.2 rad/s at 10 m/s, the radar moves left (−x) at ω·L = 0.72 m/s, forward at 10 m/s.
        let m = Mount {
            forward_m: 3.6,
            left_m: 0.0,
            yaw_rad: 0.0,
        };
        let motion = VehicleMotion {
            speed_mps: 10.0,
            yaw_rate_rps: 0.2,
        };
        let v = m.radar_velocity(motion);
        assert!(
            (v[0] + 0.72).abs() < 1e-6 && (v[1] - 10.0).abs() < 1e-6,
            "{v:?}"
        );
        // And back, for a mount off the centre line and yawed.
        let m = Mount {
            forward_m: 2.1,
            left_m: -0.6,
            yaw_rad: 0.5,
        };
        let back = m.motion(m.radar_velocity(motion));
        assert!((back.speed_mps - 10.0).abs() < 1e-5 && (back.yaw_rate_rps - 0.2).abs() < 1e-6);
    }
}
