//! Solid shapes of a scene (vertical prisms standing on the ground) and ray intersection.
//!
//! Everything the simulator renders or lets the radar see is one of these, described by its
//! footprint in the x–z plane and a vertical extent `y_top..y_bottom` (y points down).

use metamoran_bundle::geometry::Point;

/// A footprint in the x–z plane with a vertical extent.
#[derive(Clone, Debug)]
pub enum Shape {
    /// A box (car, parked vehicle).
    Box {
        /// Centre (x, z), m.
        centre: [f64; 2],
        /// Half its length along its heading, m.
        half_length: f64,
        /// Half its width, m.
        half_width: f64,
        /// Heading, rad from +z towards +x.
        heading: f64,
        /// Top (y grows downwards), m.
        y_top: f64,
        /// Bottom, m.
        y_bottom: f64,
    },
    /// A vertical cylinder (person, pole, tree crown).
    Cylinder {
        /// Axis (x, z), m.
        centre: [f64; 2],
        /// Radius, m.
        radius: f64,
        /// Top (y grows downwards), m.
        y_top: f64,
        /// Bottom, m.
        y_bottom: f64,
    },
    /// A vertical panel from `a` to `b` (wall, building facade, fence, sign plate).
    Panel {
        /// One end (x, z), m.
        a: [f64; 2],
        /// The other end (x, z), m.
        b: [f64; 2],
        /// Top (y grows downwards), m.
        y_top: f64,
        /// Bottom, m.
        y_bottom: f64,
    },
}

/// Nearest `t > 0` where the 2D ray `o + t·d` (x–z) meets segment `a`–`b`.
fn hit_segment(o: [f64; 2], d: [f64; 2], a: [f64; 2], b: [f64; 2]) -> Option<f64> {
    let e = [b[0] - a[0], b[1] - a[1]];
    let den = d[0] * e[1] - d[1] * e[0];
    if den.abs() < 1e-12 {
        return None;
    }
    let w = [a[0] - o[0], a[1] - o[1]];
    let t = (w[0] * e[1] - w[1] * e[0]) / den;
    let s = (w[0] * d[1] - w[1] * d[0]) / den;
    (t > 1e-9 && (0.0..=1.0).contains(&s)).then_some(t)
}

impl Shape {
    /// Vertical extent (top, bottom) in y.
    fn extent(&self) -> (f64, f64) {
        match *self {
            Shape::Box {
                y_top, y_bottom, ..
            }
            | Shape::Cylinder {
                y_top, y_bottom, ..
            }
            | Shape::Panel {
                y_top, y_bottom, ..
            } => (y_top, y_bottom),
        }
    }

    /// The same shape moved by `d` in the x–z plane, m.
    pub fn translated(&self, d: [f64; 2]) -> Shape {
        let mv = |p: [f64; 2]| [p[0] + d[0], p[1] + d[1]];
        let mut s = self.clone();
        match &mut s {
            Shape::Box { centre, .. } | Shape::Cylinder { centre, .. } => *centre = mv(*centre),
            Shape::Panel { a, b, .. } => (*a, *b) = (mv(*a), mv(*b)),
        }
        s
    }

    /// The footprint's boundary segments (boxes and panels).
    pub fn segments(&self) -> Vec<([f64; 2], [f64; 2])> {
        match *self {
            Shape::Box {
                centre,
                half_length,
                half_width,
                heading,
                ..
            } => {
                let (s, c) = heading.sin_cos();
                let corner =
                    |l: f64, w: f64| [centre[0] + l * s + w * c, centre[1] + l * c - w * s];
                let k = [
                    corner(half_length, half_width),
                    corner(half_length, -half_width),
                    corner(-half_length, -half_width),
                    corner(-half_length, half_width),
                ];
                (0..4).map(|i| (k[i], k[(i + 1) % 4])).collect()
            }
            Shape::Panel { a, b, .. } => vec![(a, b)],
            Shape::Cylinder { .. } => Vec::new(),
        }
    }

    /// Distance along the unit ray `o + t·d` to the first hit with the shape's side surface.
    pub fn intersect(&self, o: &Point, d: &Point) -> Option<f64> {
        let (o2, d2) = ([o.x, o.z], [d.x, d.z]);
        let t = match *self {
            Shape::Cylinder { centre, radius, .. } => {
                let (px, pz) = (o.x - centre[0], o.z - centre[1]);
                let a = d.x * d.x + d.z * d.z;
                let b = 2.0 * (px * d.x + pz * d.z);
                let c = px * px + pz * pz - radius * radius;
                let disc = b * b - 4.0 * a * c;
                if a < 1e-12 || disc < 0.0 {
                    return None;
                }
                let t = (-b - disc.sqrt()) / (2.0 * a);
                (t > 1e-9).then_some(t)?
            }
            _ => self
                .segments()
                .into_iter()
                .filter_map(|(a, b)| hit_segment(o2, d2, a, b))
                .min_by(f64::total_cmp)?,
        };
        let y = o.y + t * d.y;
        let (top, bottom) = self.extent();
        (top..=bottom).contains(&y).then_some(t)
    }

    /// The footprint point closest to the radar (origin), in the x–z plane.
    pub fn closest_point(&self) -> [f64; 2] {
        let closest_on = |a: [f64; 2], b: [f64; 2]| {
            let e = [b[0] - a[0], b[1] - a[1]];
            let len2 = e[0] * e[0] + e[1] * e[1];
            let s = if len2 > 0.0 {
                (-(a[0] * e[0] + a[1] * e[1]) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            [a[0] + s * e[0], a[1] + s * e[1]]
        };
        match *self {
            Shape::Cylinder { centre, radius, .. } => {
                let r = centre[0].hypot(centre[1]);
                let k = (r - radius).max(0.0) / r.max(1e-9);
                [centre[0] * k, centre[1] * k]
            }
            _ => self
                .segments()
                .into_iter()
                .map(|(a, b)| closest_on(a, b))
                .min_by(|p, q| p[0].hypot(p[1]).total_cmp(&q[0].hypot(q[1])))
                .unwrap_or([0.0, 0.0]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn rays_hit_the_near_face() {
        let car = Shape::Box {
            centre: [0.0, 20.0],
            half_length: 2.25,
            half_width: 0.9,
            heading: 0.0,
            y_top: -0.5,
            y_bottom: 1.0,
        };
        let t = car
            .intersect(&Vector3::zeros(), &Vector3::new(0.0, 0.0, 1.0))
            .unwrap();
        assert!((t - 17.75).abs() < 1e-9);
        assert!(
            car.intersect(&Vector3::zeros(), &Vector3::new(0.0, -0.2, 1.0).normalize())
                .is_none(),
            "above the roof"
        );
        let c = car.closest_point();
        assert!((c[1] - 17.75).abs() < 1e-9 && c[0].abs() < 1e-9);
        let pole = Shape::Cylinder {
            centre: [3.0, 4.0],
            radius: 0.5,
            y_top: -5.0,
            y_bottom: 1.0,
        };
        let d = Vector3::new(3.0, 0.0, 4.0).normalize();
        assert!((pole.intersect(&Vector3::zeros(), &d).unwrap() - 4.5).abs() < 1e-9);
        assert!((pole.closest_point()[0].hypot(pole.closest_point()[1]) - 4.5).abs() < 1e-9);
    }
}
