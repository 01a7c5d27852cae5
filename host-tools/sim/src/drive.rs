//! The `drive` preset (dense radar mapping): a vehicle with the radar on its front bumper drives
//! down a street of walls, poles and parked cars at varying speed and turn rate, with other cars
//! moving (outliers for ego-motion). The world frame is the radar frame of frame 0; each frame
//! the world is moved into the radar's frame and given the velocity it has relative to the
//! radar, so the signal model sees the ego-motion as Doppler.

use super::object::{self, GROUND_Y, Scatterer, SceneObject};
use super::shape::Shape;
pub use metamoran_bundle::pose::Pose;
use metamoran_dsp::ego::{Mount, VehicleMotion};
use rand::Rng;
use std::f64::consts::{PI, TAU};

/// Frames of a drive scene.
pub const FRAMES: u16 = 20;
/// Time between frames, s (10 Hz, as the paper's radar).
pub const FRAME_PERIOD_S: f64 = 0.1;
/// Where the radar sits: 3.7 m ahead of the rear axle on the centre line, looking forward.
pub const MOUNT: Mount = Mount {
    forward_m: 3.7,
    left_m: 0.0,
    yaw_rad: 0.0,
};

/// The vehicle's motion over time: speed and yaw rate as slow sinusoids.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drive {
    /// Mean speed, m/s.
    pub speed: f64,
    /// Speed swing, m/s, and its period, s.
    pub speed_swing: (f64, f64),
    /// Yaw-rate amplitude, rad/s, and its period, s.
    pub turn: (f64, f64),
    /// Phases of the two sinusoids, rad.
    pub phases: (f64, f64),
}

impl Drive {
    /// Draws a drive: 3–8 m/s, ±0.5–1.5 m/s, yaw rate up to ±0.05–0.2 rad/s.
    pub fn draw(rng: &mut impl Rng) -> Self {
        Self {
            speed: rng.random_range(3.0..8.0),
            speed_swing: (rng.random_range(0.5..1.5), rng.random_range(1.5..4.0)),
            turn: (rng.random_range(0.05..0.2), rng.random_range(1.5..4.0)),
            phases: (rng.random_range(0.0..TAU), rng.random_range(0.0..TAU)),
        }
    }

    /// Speed (rear axle) and yaw rate at time `t`.
    pub fn motion(&self, t: f64) -> VehicleMotion {
        VehicleMotion {
            speed_mps: (self.speed
                + self.speed_swing.0 * (TAU * t / self.speed_swing.1 + self.phases.0).sin())
                as f32,
            yaw_rate_rps: (self.turn.0 * (TAU * t / self.turn.1 + self.phases.1).sin()) as f32,
        }
    }

    /// The radar's pose and world velocity at each frame, integrating the rear axle's motion in
    /// 1 ms steps (the radar is at the world origin, facing +z, at t = 0).
    pub fn poses(&self, frames: u16, period: f64) -> Vec<(Pose, [f64; 2])> {
        const DT: f64 = 1e-3;
        let l = f64::from(MOUNT.forward_m);
        // Rear axle, heading +z.
        let (mut x, mut z, mut yaw) = (0.0, -l, 0.0);
        let mut out = Vec::new();
        let mut t = 0.0;
        for f in 0..frames {
            let due = f64::from(f) * period;
            while t + DT / 2.0 < due {
                let m = self.motion(t + DT / 2.0);
                let (v, w) = (f64::from(m.speed_mps), f64::from(m.yaw_rate_rps));
                let mid = yaw + w * DT / 2.0;
                x -= v * mid.sin() * DT;
                z += v * mid.cos() * DT;
                yaw += w * DT;
                t += DT;
            }
            let pose_axle = Pose {
                position: [x, z],
                yaw,
            };
            let (fwd, right) = pose_axle.axes();
            let pose = Pose {
                position: [x + l * fwd[0], z + l * fwd[1]],
                yaw,
            };
            // The radar's velocity in its frame (Ackermann), then in the world.
            let v = MOUNT.radar_velocity(self.motion(t));
            let (vx, vz) = (f64::from(v[0]), f64::from(v[1]));
            let world = [vx * right[0] + vz * fwd[0], vx * right[1] + vz * fwd[1]];
            out.push((pose, world));
        }
        out
    }
}

/// A street wall: diffuse points every 0.5 m along it at heights from the ground to 3 m.
fn wall_points(rng: &mut impl Rng, a: [f64; 2], b: [f64; 2]) -> Vec<Scatterer> {
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let n = (len / 0.5) as usize;
    (0..=n)
        .map(|i| {
            let s = i as f64 / n.max(1) as f64;
            Scatterer {
                position: nalgebra::Vector3::new(
                    a[0] + s * (b[0] - a[0]),
                    GROUND_Y - rng.random_range(0.2..3.0),
                    a[1] + s * (b[1] - a[1]),
                ),
                rcs: rng.random_range(0.3..1.5),
                phase: rng.random_range(0.0..TAU),
            }
        })
        .collect()
}

/// A pole at `centre` of (radius, height) m: one strong scatterer (a sign or a lamp's bracket,
/// 3–15 m²) at a height drawn from `heights` (m over the ground).
fn pole(
    rng: &mut impl Rng,
    centre: [f64; 2],
    (radius, height): (f64, f64),
    heights: std::ops::Range<f64>,
) -> (Shape, Vec<Scatterer>) {
    let shape = Shape::Cylinder {
        centre,
        radius,
        y_top: GROUND_Y - height,
        y_bottom: GROUND_Y,
    };
    let pts = vec![Scatterer {
        position: nalgebra::Vector3::new(
            centre[0],
            GROUND_Y - rng.random_range(heights),
            centre[1],
        ),
        rcs: rng.random_range(3.0..15.0),
        phase: rng.random_range(0.0..TAU),
    }];
    (shape, pts)
}

/// The street in the world frame: walls on both sides (a tunnel when the street is narrow),
/// poles and parked cars along them, and 1–3 moving cars.
pub fn street(rng: &mut impl Rng) -> Vec<SceneObject> {
    let mut objects: Vec<SceneObject> = Vec::new();
    let mut push = |class: &'static str, shape: Shape, velocity, scatterers: Vec<Scatterer>| {
        let id = objects.len() as u16 + 1;
        objects.push(SceneObject {
            id,
            class,
            shape,
            velocity,
            scatterers,
        });
    };
    let (left, right) = (-rng.random_range(5.5..9.0), rng.random_range(5.5..9.0));
    for x in [left, right] {
        let (a, b) = ([x, -5.0], [x, 90.0]);
        let pts = wall_points(rng, a, b);
        let shape = Shape::Panel {
            a,
            b,
            y_top: GROUND_Y - 3.0,
            y_bottom: GROUND_Y,
        };
        push("wall", shape, [0.0; 2], pts);
    }
    for x in [left + 0.8, right - 0.8] {
        let mut z = rng.random_range(3.0..10.0);
        while z < 85.0 {
            let (shape, pts) = pole(rng, [x, z], (0.12, 6.0), 0.5..2.5);
            push("pole", shape, [0.0; 2], pts);
            z += rng.random_range(8.0..16.0);
        }
    }
    let car = |rng: &mut dyn rand::RngCore, centre: [f64; 2], heading: f64| Shape::Box {
        centre,
        half_length: 2.2 + 0.2 * (rng.next_u32() as f64 / f64::from(u32::MAX)),
        half_width: 0.9,
        heading,
        y_top: GROUND_Y - 1.5,
        y_bottom: GROUND_Y,
    };
    for x in [left + 2.0, right - 2.0] {
        let mut z = rng.random_range(5.0..20.0);
        while z < 80.0 {
            let shape = car(rng, [x, z], 0.0);
            let pts = object::vehicle(rng, &shape);
            push("vehicle_parked", shape, [0.0; 2], pts);
            z += rng.random_range(8.0..25.0);
        }
    }
    // Traffic: oncoming on the left of the centre line, or ahead in the same lane.
    for k in 0..rng.random_range(1..=3) {
        let oncoming = k % 2 == 0;
        let (x, v) = if oncoming {
            (-2.0, -rng.random_range(4.0..9.0))
        } else {
            (1.0, rng.random_range(2.0..6.0))
        };
        let z = rng.random_range(20.0..60.0);
        let shape = car(rng, [x, z], 0.0);
        let mut pts = object::vehicle(rng, &shape);
        object::random_phases(rng, &mut pts);
        push("car", shape, [0.0, v], pts);
    }
    objects
}

/// Where the vehicle drives (issue #21 wants more than one kind of place).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Environment {
    /// [`street`]: walls at 5.5–9 m, poles, parked cars, traffic (the `drive` preset, as it
    /// always was).
    Street,
    /// [`tunnel`]: close walls and a ceiling, densely scattering.
    Tunnel,
    /// [`parking_area`]: rows of parked cars, lamp posts, building fronts far off.
    ParkingArea,
    /// [`garage`]: a covered car park, a low ceiling over rows of columns and parked cars.
    Garage,
}

/// One environment's world: its objects, ground scatterers and, in a tunnel, the ceiling's
/// height over the road (m).
pub struct World {
    /// Objects in the world frame.
    pub objects: Vec<SceneObject>,
    /// Ground scatterers.
    pub ground: Vec<Scatterer>,
    /// Ceiling height over the ground, m, and its scatterers.
    pub ceiling: Option<(f64, Vec<Scatterer>)>,
}

impl World {
    /// The world at time `t` s in the radar frame of `pose`, moving relative to a radar with
    /// world velocity `radar_v` m/s: its objects (movers moved first), then its surfaces (the
    /// ground and any ceiling) as objects of their own, which hide nothing. What the signal
    /// model renders a frame from: the objects alone are what the camera and the lidar see.
    pub fn seen_from(
        &self,
        t: f64,
        pose: &Pose,
        radar_v: [f64; 2],
    ) -> (Vec<SceneObject>, Vec<SceneObject>) {
        let objects = super::motion::at(&self.objects, &[], t)
            .iter()
            .map(|o| in_radar_frame(o, pose, radar_v))
            .collect();
        // The ground moves like any static object: relative to the radar.
        let ground = SceneObject {
            id: 0,
            class: "ground",
            shape: Shape::Panel {
                a: [0.0; 2],
                b: [0.0; 2],
                y_top: GROUND_Y,
                y_bottom: GROUND_Y,
            },
            velocity: [0.0; 2],
            scatterers: self.ground.clone(),
        };
        let mut surfaces = vec![in_radar_frame(&ground, pose, radar_v)];
        if let Some((_, scatterers)) = &self.ceiling {
            let ceiling = SceneObject {
                class: "ceiling",
                scatterers: scatterers.clone(),
                ..ground
            };
            surfaces.push(in_radar_frame(&ceiling, pose, radar_v));
        }
        (objects, surfaces)
    }
}

/// Draws `env`'s world. The street draws as it always has (same seeds, same scenes).
pub fn world(env: Environment, rng: &mut impl Rng) -> World {
    match env {
        Environment::Street => {
            let objects = street(rng);
            let ground = ground(rng, 9.0);
            World {
                objects,
                ground,
                ceiling: None,
            }
        }
        Environment::Tunnel => tunnel(rng),
        Environment::ParkingArea => parking_area(rng),
        Environment::Garage => garage(rng),
    }
}

/// Diffuse scatterers every `step` m along `a`–`b` at heights `heights` (m over the ground),
/// reflectivity `rcs`.
fn surface(
    rng: &mut impl Rng,
    (a, b): ([f64; 2], [f64; 2]),
    step: f64,
    heights: std::ops::Range<f64>,
    rcs: std::ops::Range<f64>,
) -> Vec<Scatterer> {
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let n = (len / step) as usize;
    (0..=n)
        .map(|i| {
            let s = (i as f64 + rng.random_range(-0.3..0.3)).clamp(0.0, n as f64) / n.max(1) as f64;
            Scatterer {
                position: nalgebra::Vector3::new(
                    a[0] + s * (b[0] - a[0]),
                    GROUND_Y - rng.random_range(heights.clone()),
                    a[1] + s * (b[1] - a[1]),
                ),
                rcs: rng.random_range(rcs.clone()),
                phase: rng.random_range(0.0..TAU),
            }
        })
        .collect()
}

/// An object before numbering: class, shape, velocity (m/s) and scatterers.
type Placed = (&'static str, Shape, [f64; 2], Vec<Scatterer>);

/// Objects numbered 1.. in order.
fn numbered(objects: Vec<Placed>) -> Vec<SceneObject> {
    objects
        .into_iter()
        .enumerate()
        .map(|(i, (class, shape, velocity, scatterers))| SceneObject {
            id: i as u16 + 1,
            class,
            shape,
            velocity,
            scatterers,
        })
        .collect()
}

/// A car's box at `centre` with `heading` (rad from +z).
fn car_box(rng: &mut impl Rng, centre: [f64; 2], heading: f64) -> Shape {
    Shape::Box {
        centre,
        half_length: rng.random_range(2.1..2.4),
        half_width: 0.9,
        heading,
        y_top: GROUND_Y - 1.5,
        y_bottom: GROUND_Y,
    }
}

/// One or two other cars: oncoming in the left lane (starting 45–70 m out, so that in the
/// scene's 2 s it does not reach the radar and fill the view at a metre) or ahead in ours.
fn traffic(
    rng: &mut impl Rng,
    lanes: (f64, f64),
    out: &mut Vec<(&'static str, Shape, [f64; 2], Vec<Scatterer>)>,
) {
    for k in 0..rng.random_range(1..=2) {
        let (x, v) = if k % 2 == 0 {
            (lanes.0, -rng.random_range(4.0..9.0))
        } else {
            (lanes.1, rng.random_range(2.0..6.0))
        };
        let z = if v < 0.0 {
            rng.random_range(45.0..70.0)
        } else {
            rng.random_range(20.0..60.0)
        };
        let shape = car_box(rng, [x, z], 0.0);
        let mut pts = object::vehicle(rng, &shape);
        object::random_phases(rng, &mut pts);
        out.push(("car", shape, [0.0, v], pts));
    }
}

/// A road tunnel: walls 3.5–5 m either side from the road to a ceiling 4.5–5.5 m up, a
/// scatterer every 0.25 m along each wall and one per 1 m × 1 m of ceiling; one or two cars.
pub fn tunnel(rng: &mut impl Rng) -> World {
    let (left, right) = (-rng.random_range(3.5..5.0), rng.random_range(3.5..5.0));
    let height = rng.random_range(4.5..5.5);
    let mut objects = Vec::new();
    for x in [left, right] {
        objects.push(side_wall(rng, x, 0.25, height));
    }
    roofed(rng, objects, (left, right), height)
}

/// A wall along the road at `x` m across, from the road to a ceiling `height` m up, with a
/// scatterer every `spacing` m along it.
fn side_wall(rng: &mut impl Rng, x: f64, spacing: f64, height: f64) -> Placed {
    let (a, b) = ([x, -5.0], [x, 90.0]);
    let pts = surface(rng, (a, b), spacing, 0.2..height - 0.2, 0.3..1.5);
    let shape = Shape::Panel {
        a,
        b,
        y_top: GROUND_Y - height,
        y_bottom: GROUND_Y,
    };
    ("wall", shape, [0.0; 2], pts)
}

/// `objects` with traffic in the lane, under a ceiling `height` m up between the walls at
/// `left` and `right` m across.
fn roofed(
    rng: &mut impl Rng,
    mut objects: Vec<Placed>,
    (left, right): (f64, f64),
    height: f64,
) -> World {
    traffic(rng, (-1.5, 1.5), &mut objects);
    let ceiling = ceiling(rng, (left, right), height);
    World {
        objects: numbered(objects),
        ground: ground(rng, left.abs().max(right)),
        ceiling: Some((height, ceiling)),
    }
}

/// A ceiling `height` m over the road from `left` to `right` (m, across) and from 5 m behind
/// the start to 90 m ahead: one weak diffuse scatterer per 1 m × 1 m, jittered.
fn ceiling(rng: &mut impl Rng, (left, right): (f64, f64), height: f64) -> Vec<Scatterer> {
    let mut ceiling = Vec::new();
    let across = (right - left).floor() as i32;
    for i in 0..=across {
        for z in -5..90 {
            ceiling.push(Scatterer {
                position: nalgebra::Vector3::new(
                    left + f64::from(i) + rng.random_range(-0.3..0.3),
                    GROUND_Y - height,
                    f64::from(z) + rng.random_range(-0.4..0.4),
                ),
                rcs: rng.random_range(0.05..0.4),
                phase: rng.random_range(0.0..TAU),
            });
        }
    }
    ceiling
}

/// A covered car park (issue #21: an environment with a roof to train on, so that the tunnel
/// can stay held out): a ceiling 2.8–4.2 m over the floor out to walls 14–20 m either side
/// (one scatterer per m², as in the tunnel), columns 0.6 m across every 7.5–8.5 m on two
/// lines either side (3.2–4 m and 8.8–9.6 m out; a scatterer every 0.5 m up), cars parked
/// across between the lines (60 % of the 2.6 m bays taken), one or two cars in the lane.
pub fn garage(rng: &mut impl Rng) -> World {
    let height = rng.random_range(2.8..4.2);
    let inner = rng.random_range(3.2..4.0);
    let outer = inner + 5.6;
    let (left, right) = (-rng.random_range(14.0..20.0), rng.random_range(14.0..20.0));
    let mut objects = Vec::new();
    for side in [-1.0, 1.0] {
        for line in [inner, outer] {
            let mut z = rng.random_range(0.0..8.0);
            while z < 88.0 {
                let x = side * line;
                let shape = Shape::Cylinder {
                    centre: [x, z],
                    radius: 0.3,
                    y_top: GROUND_Y - height,
                    y_bottom: GROUND_Y,
                };
                let pts = (0..(2.0 * height) as usize)
                    .map(|k| Scatterer {
                        position: nalgebra::Vector3::new(
                            x - side * 0.3,
                            GROUND_Y - 0.25 - 0.5 * k as f64,
                            z,
                        ),
                        rcs: rng.random_range(0.3..1.5),
                        phase: rng.random_range(0.0..TAU),
                    })
                    .collect();
                objects.push(("pole", shape, [0.0; 2], pts));
                z += rng.random_range(7.5..8.5);
            }
        }
        parked_row(rng, side * (inner + 2.8), &mut objects);
        let x = if side < 0.0 { left } else { right };
        objects.push(side_wall(rng, x, 0.5, height));
    }
    roofed(rng, objects, (left, right), height)
}

/// A row of 2.6 m bays from 2–6 m to 85 m ahead, 60 % taken by a car parked across with
/// its centre `x` m across, pushed onto `objects`.
fn parked_row(rng: &mut impl Rng, x: f64, objects: &mut Vec<Placed>) {
    let mut z = rng.random_range(2.0..6.0);
    while z < 85.0 {
        if rng.random_bool(0.6) {
            let shape = car_box(rng, [x, z], PI / 2.0);
            let pts = object::vehicle(rng, &shape);
            objects.push(("vehicle_parked", shape, [0.0; 2], pts));
        }
        z += 2.6;
    }
}

/// An open parking area: two rows of cars parked across either side of the lane (3.5–5 m and
/// 9.5–11 m out, 60 % of the 2.6 m bays taken), lamp posts 7 m out every 15–25 m, building
/// fronts 18–30 m off (a scatterer every 0.5 m to 6 m up); one or two cars in the lane.
pub fn parking_area(rng: &mut impl Rng) -> World {
    let mut objects = Vec::new();
    for side in [-1.0, 1.0] {
        for row in [rng.random_range(3.5..5.0), rng.random_range(9.5..11.0)] {
            parked_row(rng, side * (row + 2.2), &mut objects);
        }
        let mut z = rng.random_range(3.0..12.0);
        while z < 85.0 {
            let x = side * 7.2;
            let (shape, pts) = pole(rng, [x, z], (0.1, 8.0), 0.5..3.0);
            objects.push(("pole", shape, [0.0; 2], pts));
            z += rng.random_range(15.0..25.0);
        }
        let x = side * rng.random_range(18.0..30.0);
        let (a, b) = ([x, -5.0], [x, 90.0]);
        let pts = surface(rng, (a, b), 0.5, 0.2..6.0, 0.3..1.5);
        let shape = Shape::Panel {
            a,
            b,
            y_top: GROUND_Y - 6.0,
            y_bottom: GROUND_Y,
        };
        objects.push(("wall", shape, [0.0; 2], pts));
    }
    traffic(rng, (-1.5, 1.5), &mut objects);
    World {
        objects: numbered(objects),
        ground: ground(rng, 30.0),
        ceiling: None,
    }
}

/// Ground scatterers along the street (world frame).
pub fn ground(rng: &mut impl Rng, half_width: f64) -> Vec<Scatterer> {
    (0..400)
        .map(|_| Scatterer {
            position: nalgebra::Vector3::new(
                rng.random_range(-half_width..half_width),
                GROUND_Y,
                rng.random_range(2.0..90.0),
            ),
            rcs: 0.02 * rng.random_range(0.2..1.8),
            phase: rng.random_range(0.0..PI * 2.0),
        })
        .collect()
}

/// `o` in the radar frame of `pose`, moving relative to a radar with world velocity `radar_v`.
pub fn in_radar_frame(o: &SceneObject, pose: &Pose, radar_v: [f64; 2]) -> SceneObject {
    // Moving objects first move in the world (their `velocity` is world, m/s, at t = 0 they are
    // where the layout put them); the caller passes them already moved.
    let map = |p: [f64; 2]| pose.to_radar(p);
    let shape = match o.shape.clone() {
        Shape::Box {
            centre,
            half_length,
            half_width,
            heading,
            y_top,
            y_bottom,
        } => Shape::Box {
            centre: map(centre),
            half_length,
            half_width,
            heading: heading + pose.yaw,
            y_top,
            y_bottom,
        },
        Shape::Cylinder {
            centre,
            radius,
            y_top,
            y_bottom,
        } => Shape::Cylinder {
            centre: map(centre),
            radius,
            y_top,
            y_bottom,
        },
        Shape::Panel {
            a,
            b,
            y_top,
            y_bottom,
        } => Shape::Panel {
            a: map(a),
            b: map(b),
            y_top,
            y_bottom,
        },
    };
    let scatterers = o
        .scatterers
        .iter()
        .map(|s| {
            let p = map([s.position.x, s.position.z]);
            Scatterer {
                position: nalgebra::Vector3::new(p[0], s.position.y, p[1]),
                ..*s
            }
        })
        .collect();
    let rel = [o.velocity[0] - radar_v[0], o.velocity[1] - radar_v[1]];
    SceneObject {
        id: o.id,
        class: o.class,
        shape,
        velocity: pose.rotate_to_radar(rel),
        scatterers,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// Seed `seed`'s world of `env`, its ceiling height (m, checked to be in `heights`) and
    /// the ceiling's scatterers.
    fn roofed_world(
        env: Environment,
        seed: u64,
        heights: std::ops::Range<f64>,
    ) -> (World, f64, Vec<Scatterer>) {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
        let w = world(env, &mut rng);
        let (height, roof) = w.ceiling.clone().expect("a roofed place has a ceiling");
        assert!(heights.contains(&height), "{height}");
        (w, height, roof)
    }

    #[test]
    fn a_tunnel_is_walled_and_roofed_and_the_lane_stays_clear() {
        for seed in 0..8 {
            let (w, height, roof) = roofed_world(Environment::Tunnel, seed, 4.5..5.5);
            // A scatterer per square metre of ceiling, on the ceiling.
            assert!(roof.len() > 7 * 95, "{}", roof.len());
            assert!(
                roof.iter()
                    .all(|s| (s.position.y - (GROUND_Y - height)).abs() < 1e-9)
            );
            let walls: Vec<_> = w.objects.iter().filter(|o| o.class == "wall").collect();
            assert_eq!(walls.len(), 2);
            for o in &walls {
                // Four per metre along 95 m, from the road to under the ceiling.
                assert!(o.scatterers.len() >= 4 * 95, "{}", o.scatterers.len());
                assert!(o.scatterers.iter().all(|s| {
                    let up = GROUND_Y - s.position.y;
                    (0.2..height).contains(&up) && (3.5..5.0).contains(&s.position.x.abs())
                }));
            }
            assert_clear(&w);
        }
    }

    #[test]
    fn a_parking_area_has_rows_of_cars_beside_a_clear_lane() {
        for seed in 0..8 {
            let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
            let w = world(Environment::ParkingArea, &mut rng);
            assert!(w.ceiling.is_none());
            let parked: Vec<_> = w
                .objects
                .iter()
                .filter(|o| o.class == "vehicle_parked")
                .collect();
            // Four rows of 32 bays, 60 % taken.
            assert!((40..110).contains(&parked.len()), "{}", parked.len());
            for o in &parked {
                let Shape::Box { centre, .. } = o.shape else {
                    panic!("a parked car is a box")
                };
                assert!(centre[0].abs() >= 3.5 + 2.1, "{centre:?}");
            }
            assert_clear(&w);
        }
    }

    #[test]
    fn a_garage_is_roofed_over_columns_and_parked_cars() {
        for seed in 0..8 {
            let (w, height, roof) = roofed_world(Environment::Garage, seed, 2.8..4.2);
            // A scatterer per square metre between walls 28-40 m apart, over 95 m.
            assert!(roof.len() > 28 * 95, "{}", roof.len());
            let columns: Vec<_> = w.objects.iter().filter(|o| o.class == "pole").collect();
            // Four lines of a column every 8.5 m or less over 80 m or more.
            assert!(columns.len() >= 4 * 9, "{}", columns.len());
            for o in &columns {
                // From near the floor to under the ceiling.
                let up: Vec<f64> = o
                    .scatterers
                    .iter()
                    .map(|s| GROUND_Y - s.position.y)
                    .collect();
                assert!(up.iter().all(|&u| (0.2..height).contains(&u)), "{up:?}");
                assert!(
                    up.iter().any(|&u| u > height - 0.8),
                    "{up:?} under {height}"
                );
            }
            let parked = w
                .objects
                .iter()
                .filter(|o| o.class == "vehicle_parked")
                .count();
            // Two rows of 32 bays, 60 % taken.
            assert!((20..55).contains(&parked), "{parked}");
            assert_clear(&w);
        }
    }

    /// Nothing static in the radar's lane (|x| < 2.5 m), and oncoming traffic starts 45 m or
    /// more ahead, so in 2 s at up to 17 m/s closing it stays in front of the radar.
    fn assert_clear(w: &World) {
        for o in &w.objects {
            let c = o.centre();
            if o.velocity[1] < 0.0 {
                assert!(c[1] >= 45.0 - 2.5, "{} at {c:?}", o.class);
            } else if o.velocity == [0.0; 2] {
                assert!(
                    o.scatterers.iter().all(|s| s.position.x.abs() > 2.5),
                    "{}",
                    o.class
                );
            }
        }
    }

    #[test]
    fn poses_follow_the_integrated_motion() {
        // Straight at constant speed: the radar moves along +z at that speed.
        let d = Drive {
            speed: 5.0,
            speed_swing: (0.0, 1.0),
            turn: (0.0, 1.0),
            phases: (0.0, 0.0),
        };
        let p = d.poses(11, 0.1);
        assert!((p[10].0.position[1] - 5.0).abs() < 1e-9 && p[10].0.position[0].abs() < 1e-12);
        assert_eq!(p[10].1, [0.0, 5.0]);
        // A constant left turn: the axle runs on a circle of radius v/ω; heading = ω t.
        let d = Drive {
            speed: 5.0,
            speed_swing: (0.0, 1.0),
            turn: (0.2, 1e9),
            phases: (0.0, PI / 2.0),
        };
        let p = d.poses(21, 0.1);
        let (pose, v) = p[20];
        assert!((pose.yaw - 0.4).abs() < 1e-6, "{pose:?}");
        // Axle position on the circle (closed form), then the 3.7 m lever to the radar.
        let r = 25.0;
        let axle = [-(r - r * 0.4f64.cos()), -3.7 + r * 0.4f64.sin()];
        let (fwd, right) = pose.axes();
        let radar = [axle[0] + 3.7 * fwd[0], axle[1] + 3.7 * fwd[1]];
        assert!(
            (pose.position[0] - radar[0]).abs() < 1e-4
                && (pose.position[1] - radar[1]).abs() < 1e-4
        );
        // Its velocity: 5 m/s forward and ω·L = 0.74 m/s to the left.
        let want = [
            5.0 * fwd[0] - 0.74 * right[0],
            5.0 * fwd[1] - 0.74 * right[1],
        ];
        assert!(
            (v[0] - want[0]).abs() < 1e-5 && (v[1] - want[1]).abs() < 1e-5,
            "{v:?} {want:?}"
        );
        // And a world point ahead is ahead in the radar frame.
        let ahead = [
            pose.position[0] + 10.0 * fwd[0],
            pose.position[1] + 10.0 * fwd[1],
        ];
        let q = pose.to_radar(ahead);
        assert!(q[0].abs() < 1e-9 && (q[1] - 10.0).abs() < 1e-9);
    }
}
