//! Scene objects and their radar scatterers.
//!
//! Each object is a [`Shape`] with a class and a velocity; its radar signature is a set of point
//! scatterers on the surface the radar sees, with radar cross sections from simple physics:
//! flat faces flash only near normal incidence (specular), corners and wheels are bright spots,
//! people are weak diffuse scatterers, buildings are long and very strong.

use super::shape::Shape;
use metamoran_bundle::geometry::Point;
use nalgebra::Vector3;
use rand::Rng;
use std::f64::consts::PI;

/// Height of the radar above the ground (the ground plane is y = GROUND_Y; y points down), m.
pub const GROUND_Y: f64 = 1.0;

/// A point reflector: position, radar cross section and scattering phase.
#[derive(Clone, Copy, Debug)]
pub struct Scatterer {
    /// Position in the radar frame, m.
    pub position: Point,
    /// Radar cross section, m².
    pub rcs: f64,
    /// Scattering phase, rad.
    pub phase: f64,
}

/// One object of the scene.
#[derive(Clone, Debug)]
pub struct SceneObject {
    /// Instance id in the camera products (0 for things with no instance: the ground).
    pub id: u16,
    /// Class word (bundle.md).
    pub class: &'static str,
    /// Geometry.
    pub shape: Shape,
    /// Velocity in the x–z plane, m/s.
    pub velocity: [f64; 2],
    /// Radar scatterers.
    pub scatterers: Vec<Scatterer>,
}

impl SceneObject {
    /// Radial velocity (positive away) of a point of this object.
    pub fn radial_velocity(&self, p: &Point) -> f64 {
        let r = p.x.hypot(p.z).max(1e-9);
        (self.velocity[0] * p.x + self.velocity[1] * p.z) / r
    }

    /// The object moved so its footprint centre is at `centre`, moving with `velocity` (m/s):
    /// its pose in a later frame.
    pub fn placed(&self, centre: [f64; 2], velocity: [f64; 2]) -> SceneObject {
        let c = self.centre();
        let d = [centre[0] - c[0], centre[1] - c[1]];
        let mut o = self.clone();
        o.shape = self.shape.translated(d);
        o.velocity = velocity;
        for s in &mut o.scatterers {
            s.position.x += d[0];
            s.position.z += d[1];
        }
        o
    }

    /// Centre of the footprint.
    pub fn centre(&self) -> [f64; 2] {
        match self.shape {
            Shape::Box { centre, .. } | Shape::Cylinder { centre, .. } => centre,
            Shape::Panel { a, b, .. } => [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0],
        }
    }
}

/// A scatterer with phase 0 ([`random_phases`] draws them once an object is complete).
pub(crate) fn scatterer(x: f64, y: f64, z: f64, rcs: f64) -> Scatterer {
    Scatterer {
        position: Vector3::new(x, y, z),
        rcs,
        phase: 0.0,
    }
}

/// Gives every scatterer a random scattering phase.
pub fn random_phases(rng: &mut impl Rng, scatterers: &mut [Scatterer]) {
    for s in scatterers {
        s.phase = rng.random_range(0.0..2.0 * PI);
    }
}

/// Angle between the line of sight to `p` and the normal of a face with direction `e`, rad
/// (0 = the radar looks straight at the face).
fn incidence(p: [f64; 2], e: [f64; 2]) -> f64 {
    let len = e[0].hypot(e[1]).max(1e-12);
    let r = p[0].hypot(p[1]).max(1e-12);
    // |sin| of the angle between the LOS and the face = |cos| of the angle to its normal.
    let along = ((p[0] * e[0] + p[1] * e[1]) / (len * r)).abs();
    along.clamp(0.0, 1.0).asin()
}

/// Scatterers along a face from `a` to `b`: diffuse points every `spacing`, and a specular flash
/// of `flash_rcs` at the point of the face nearest to normal incidence, falling off with a
/// Gaussian of `lobe` radians.
#[allow(clippy::too_many_arguments)]
fn face(
    rng: &mut impl Rng,
    a: [f64; 2],
    b: [f64; 2],
    y: f64,
    spacing: f64,
    diffuse_rcs: f64,
    flash_rcs: f64,
    lobe: f64,
) -> Vec<Scatterer> {
    let e = [b[0] - a[0], b[1] - a[1]];
    let len = e[0].hypot(e[1]);
    let n = (len / spacing).ceil().max(1.0) as usize;
    let mut out: Vec<Scatterer> = (0..=n)
        .map(|i| {
            let s = i as f64 / n as f64;
            let rcs = diffuse_rcs * rng.random_range(0.3..1.7);
            scatterer(a[0] + s * e[0], y, a[1] + s * e[1], rcs)
        })
        .collect();
    // Foot of the perpendicular from the radar, clamped to the face.
    let s = (-(a[0] * e[0] + a[1] * e[1]) / (len * len).max(1e-12)).clamp(0.0, 1.0);
    let foot = [a[0] + s * e[0], a[1] + s * e[1]];
    let beta = incidence(foot, e);
    let rcs = flash_rcs * (-(beta / lobe).powi(2)).exp();
    if rcs > 1e-3 {
        out.push(scatterer(foot[0], y, foot[1], rcs));
    }
    out
}

/// Whether the outward side of face `a`→`b` of a shape centred at `c` faces the radar.
fn faces_radar(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
    let out = [mid[0] - c[0], mid[1] - c[1]];
    out[0] * mid[0] + out[1] * mid[1] < 0.0
}

/// Scatterers of a vehicle box: visible faces (diffuse + door/bumper flash), corners, wheels.
pub fn vehicle(rng: &mut impl Rng, shape: &Shape) -> Vec<Scatterer> {
    let Shape::Box {
        centre,
        half_length,
        ..
    } = *shape
    else {
        return Vec::new();
    };
    let y = GROUND_Y - 0.55;
    let mut out = Vec::new();
    for (i, (a, b)) in shape.segments().into_iter().enumerate() {
        if !faces_radar(a, b, centre) {
            continue;
        }
        out.extend(face(rng, a, b, y, 0.15, 0.03, 25.0, 4f64.to_radians()));
        for corner in [a, b] {
            out.push(scatterer(
                corner[0],
                y,
                corner[1],
                rng.random_range(0.8..2.5),
            ));
        }
        // Long sides (0 and 2) carry two wheels each.
        if i % 2 == 0 {
            let e = [b[0] - a[0], b[1] - a[1]];
            let len = e[0].hypot(e[1]);
            for s in [0.8 / len, 1.0 - 0.8 / (2.0 * half_length)] {
                out.push(scatterer(
                    a[0] + s * e[0],
                    GROUND_Y - 0.3,
                    a[1] + s * e[1],
                    rng.random_range(0.5..1.5),
                ));
            }
        }
    }
    out
}

/// Scatterers of a person: weak and diffuse, about 0.5 m² in all.
pub fn person(rng: &mut impl Rng, shape: &Shape) -> Vec<Scatterer> {
    let Shape::Cylinder { centre, radius, .. } = *shape else {
        return Vec::new();
    };
    let toward = (-centre[0]).atan2(-centre[1]);
    (0..6)
        .map(|k| {
            let ang = toward + (k as f64 - 2.5) * 0.4;
            let y = GROUND_Y - rng.random_range(0.6..1.5);
            scatterer(
                centre[0] + radius * ang.sin(),
                y,
                centre[1] + radius * ang.cos(),
                0.5 / 6.0 * rng.random_range(0.5..1.5),
            )
        })
        .collect()
}

/// Scatterers of a metal sign plate: a strong specular flash near normal incidence, weak edges.
pub fn sign(rng: &mut impl Rng, shape: &Shape) -> Vec<Scatterer> {
    let Shape::Panel {
        a,
        b,
        y_top,
        y_bottom,
    } = *shape
    else {
        return Vec::new();
    };
    let y = (y_top + y_bottom) / 2.0;
    let mut out = face(rng, a, b, y, 0.15, 0.02, 60.0, 3f64.to_radians());
    out.push(scatterer(a[0], y, a[1], 0.2));
    out.push(scatterer(b[0], y, b[1], 0.2));
    out
}

/// Scatterers of a long facade (building or wall): dense diffuse points, bright details and a
/// very strong specular flash where the radar sees it at normal incidence.
pub fn facade(
    rng: &mut impl Rng,
    shape: &Shape,
    diffuse: f64,
    flash: f64,
    details_every: f64,
) -> Vec<Scatterer> {
    let Shape::Panel { a, b, .. } = *shape else {
        return Vec::new();
    };
    let y = rng.random_range(-0.5..0.5);
    let mut out = face(rng, a, b, y, 0.25, diffuse, flash, 2f64.to_radians());
    let e = [b[0] - a[0], b[1] - a[1]];
    let len = e[0].hypot(e[1]);
    let n = (len / details_every) as usize;
    for _ in 0..n {
        let s: f64 = rng.random_range(0.0..1.0);
        out.push(scatterer(
            a[0] + s * e[0],
            y,
            a[1] + s * e[1],
            rng.random_range(1.0..6.0),
        ));
    }
    out
}

/// Scatterers of a fence: posts every 2.5 m and weak rails between them.
pub fn fence(rng: &mut impl Rng, shape: &Shape) -> Vec<Scatterer> {
    let Shape::Panel { a, b, .. } = *shape else {
        return Vec::new();
    };
    let e = [b[0] - a[0], b[1] - a[1]];
    let len = e[0].hypot(e[1]);
    let mut out = face(rng, a, b, GROUND_Y - 0.8, 0.2, 0.04, 5.0, 2f64.to_radians());
    let posts = (len / 2.5) as usize;
    for k in 0..=posts {
        let s = k as f64 / posts.max(1) as f64;
        out.push(scatterer(
            a[0] + s * e[0],
            GROUND_Y - 0.8,
            a[1] + s * e[1],
            rng.random_range(0.5..1.5),
        ));
    }
    out
}

/// A pole: one strong, azimuth-independent scatterer.
pub fn pole(shape: &Shape, rcs: f64) -> Vec<Scatterer> {
    let Shape::Cylinder { centre, radius, .. } = *shape else {
        return Vec::new();
    };
    let r = centre[0].hypot(centre[1]);
    let k = (r - radius) / r;
    vec![scatterer(centre[0] * k, 0.0, centre[1] * k, rcs)]
}

/// A tree: weak random points inside the crown.
pub fn tree(rng: &mut impl Rng, shape: &Shape) -> Vec<Scatterer> {
    let Shape::Cylinder { centre, radius, .. } = *shape else {
        return Vec::new();
    };
    (0..20)
        .map(|_| {
            let (r, a) = (
                radius * rng.random_range(0.0f64..1.0).sqrt(),
                rng.random_range(0.0..2.0 * PI),
            );
            scatterer(
                centre[0] + r * a.sin(),
                rng.random_range(-2.0..0.5),
                centre[1] + r * a.cos(),
                rng.random_range(0.05..0.3),
            )
        })
        .collect()
}
