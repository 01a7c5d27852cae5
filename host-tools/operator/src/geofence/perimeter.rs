//! The perimeter file: polygon zones on the ground plane, restricted classes, a least
//! confidence, and per-zone loitering and approach thresholds; loaded, checked field by field,
//! and the polygon geometry the rules need ([`signed_distance`], [`nearest_on_boundary`]).
//!
//! The ground plane is the radar frame's `x` (right) and `z` (forward), metres; an object stands
//! at `(d·sin az, d·cos az)` for its depth `d` and azimuth `az`.
//!
//! ```toml
//! restricted_classes = ["person", "car"]
//! min_confidence_db = 6.0   # the module's peak over its search floor, dB (0: any detection)
//! hysteresis_m = 1.0
//!
//! [[zone]]
//! name = "gate"
//! polygon = [[-8.0, 5.0], [8.0, 5.0], [8.0, 30.0], [-8.0, 30.0]]   # [x, z], m
//! dwell_s = 20.0            # optional: alert when a track stays inside longer (loitering)
//! approach_mps = 3.0        # optional: alert when a track outside closes in faster
//! approach_within_m = 30.0  # … within this distance of the zone (default 30 m)
//! ```

use crate::OperatorError;
use metamoran_bundle::limits::MAX_TOML_BYTES;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One zone: a simple polygon on the ground plane.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Zone {
    /// Name shown in alerts.
    pub name: String,
    /// Vertices `[x, z]`, metres, in order (either direction); at least 3.
    pub polygon: Vec<[f64; 2]>,
    /// Loitering: a `dwell` alert when a track has been inside for longer, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dwell_s: Option<f64>,
    /// Approach: an `approach` alert when a track outside closes in on the zone faster, m/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub approach_mps: Option<f64>,
    /// How near the zone, m, an approach counts ([`DEFAULT_APPROACH_WITHIN_M`] when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub approach_within_m: Option<f64>,
}

/// How near a zone, m, a track's approach counts when the zone does not say.
pub const DEFAULT_APPROACH_WITHIN_M: f64 = 30.0;

impl Zone {
    /// How near, m, an approach counts.
    pub fn approach_within_m(&self) -> f64 {
        self.approach_within_m.unwrap_or(DEFAULT_APPROACH_WITHIN_M)
    }
}

/// A perimeter configuration (TOML; see the module docs).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Perimeter {
    /// Classes that raise alerts (`car`, `person`, `sign`, …).
    pub restricted_classes: Vec<String>,
    /// Least confidence, dB of the depth search's peak over its floor; objects without a
    /// confidence (the baselines) pass.
    #[serde(default)]
    pub min_confidence_db: f64,
    /// How far outside a zone, metres, an object inside it must go to leave it.
    #[serde(default = "default_hysteresis")]
    pub hysteresis_m: f64,
    /// The zones.
    #[serde(rename = "zone")]
    pub zones: Vec<Zone>,
}

fn default_hysteresis() -> f64 {
    1.0
}

impl Perimeter {
    /// Reads and checks a perimeter file.
    ///
    /// # Errors
    /// [`OperatorError::Perimeter`] naming the file and the field that is missing, malformed or
    /// out of range.
    pub fn load(path: &Path) -> Result<Self, OperatorError> {
        Self::load_text(path).map(|(p, _)| p)
    }

    /// [`Perimeter::load`], also returning the file's text.
    ///
    /// # Errors
    /// As [`Perimeter::load`].
    pub fn load_text(path: &Path) -> Result<(Self, String), OperatorError> {
        let source_name = path.display().to_string();
        let bytes = metamoran_bundle::limits::read_bounded(path, MAX_TOML_BYTES).map_err(|e| {
            OperatorError::Perimeter {
                source_name: source_name.clone(),
                problem: format!("{e}; give a TOML file as in the README"),
            }
        })?;
        let text = String::from_utf8(bytes).map_err(|_| OperatorError::Perimeter {
            source_name: source_name.clone(),
            problem: "not UTF-8 text; give a TOML file as in the README".into(),
        })?;
        let perimeter = Self::parse_problem(&text).map_err(|problem| OperatorError::Perimeter {
            source_name,
            problem,
        })?;
        Ok((perimeter, text))
    }

    /// Parses and checks perimeter TOML.
    ///
    /// # Errors
    /// [`OperatorError::Perimeter`] naming the field that is missing, malformed or out of range.
    pub fn parse(text: &str) -> Result<Self, OperatorError> {
        Self::parse_problem(text).map_err(|problem| OperatorError::Perimeter {
            source_name: "perimeter TOML".to_owned(),
            problem,
        })
    }

    /// [`Perimeter::parse`], the problem in words.
    fn parse_problem(text: &str) -> Result<Self, String> {
        let de = toml::Deserializer::parse(text).map_err(|e| e.to_string())?;
        let p: Perimeter =
            serde_path_to_error::deserialize(de).map_err(|e| format!("{}: {}", e.path(), e))?;
        p.check()?;
        Ok(p)
    }

    /// Checks every field; the problem in words, naming the field.
    pub(crate) fn check(&self) -> Result<(), String> {
        if !(self.hysteresis_m.is_finite() && self.hysteresis_m >= 0.0) {
            return Err("hysteresis_m: give a distance ≥ 0 in metres".into());
        }
        if !self.min_confidence_db.is_finite() {
            return Err("min_confidence_db: give a finite number of dB".into());
        }
        check_classes(&self.restricted_classes)?;
        if self.zones.is_empty() {
            return Err("zone: add at least one [[zone]] with a name and a polygon".into());
        }
        for (i, z) in self.zones.iter().enumerate() {
            if z.name.trim().is_empty() {
                return Err(format!("zone[{i}].name: give the zone a name"));
            }
            if let Some(j) = self.zones[..i].iter().position(|o| o.name == z.name) {
                return Err(format!(
                    "zone[{i}].name: \"{}\" is also zone[{j}]'s name; alerts name zones, so \
                     give each its own",
                    z.name
                ));
            }
            check_polygon(&z.polygon)
                .map_err(|problem| format!("zone[{i}].polygon ({}): {problem}", z.name))?;
            for (field, value, unit) in [
                ("dwell_s", z.dwell_s, "seconds"),
                ("approach_mps", z.approach_mps, "m/s"),
                ("approach_within_m", z.approach_within_m, "metres"),
            ] {
                if let Some(v) = value
                    && !(v.is_finite() && v > 0.0)
                {
                    return Err(format!(
                        "zone[{i}].{field} ({}): {v} is not a time or speed the rule can use; \
                         give a number of {unit} > 0, or leave it out",
                        z.name
                    ));
                }
            }
        }
        Ok(())
    }
}

/// Checks `restricted_classes`: at least one, each an object of interest of bundle.md
/// (the only classes whose position is measured), lowercase, none twice.
fn check_classes(classes: &[String]) -> Result<(), String> {
    let known = metamoran_bundle::OBJECTS_OF_INTEREST;
    if classes.is_empty() {
        return Err(format!(
            "restricted_classes: empty, so no object could ever raise an alert; list some of {}",
            known.join(", ")
        ));
    }
    for (i, c) in classes.iter().enumerate() {
        if known.contains(&c.as_str()) {
            if classes[..i].contains(c) {
                return Err(format!("restricted_classes[{i}]: \"{c}\" is listed twice"));
            }
            continue;
        }
        let lower = c.to_lowercase();
        return Err(if known.contains(&lower.as_str()) {
            format!(
                "restricted_classes[{i}]: \"{c}\": class names are lowercase; write \"{lower}\""
            )
        } else {
            format!(
                "restricted_classes[{i}]: \"{c}\" is not a class whose position is measured; \
                 use {}",
                known.join(", ")
            )
        });
    }
    Ok(())
}

/// Twice the signed area of a polygon (shoelace), m²: positive counter-clockwise.
fn twice_area(polygon: &[[f64; 2]]) -> f64 {
    (0..polygon.len())
        .map(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum()
}

/// Whether closed segments `p1–p2` and `q1–q2` share a point.
fn segments_meet(p1: [f64; 2], p2: [f64; 2], q1: [f64; 2], q2: [f64; 2]) -> bool {
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let on = |a: [f64; 2], b: [f64; 2], p: [f64; 2]| {
        p[0] >= a[0].min(b[0])
            && p[0] <= a[0].max(b[0])
            && p[1] >= a[1].min(b[1])
            && p[1] <= a[1].max(b[1])
    };
    let (d1, d2) = (cross(q1, q2, p1), cross(q1, q2, p2));
    let (d3, d4) = (cross(p1, p2, q1), cross(p1, p2, q2));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && on(q1, q2, p1))
        || (d2 == 0.0 && on(q1, q2, p2))
        || (d3 == 0.0 && on(p1, p2, q1))
        || (d4 == 0.0 && on(p1, p2, q2))
}

/// Smallest zone area, m²: a zone must be able to hold a person.
pub const MIN_ZONE_AREA_M2: f64 = 0.25;

/// Checks that `polygon` is a simple polygon (edges meet only at shared vertices, none
/// repeated) of finite vertices enclosing at least [`MIN_ZONE_AREA_M2`]. O(vertices²).
fn check_polygon(polygon: &[[f64; 2]]) -> Result<(), String> {
    let n = polygon.len();
    if n < 3 {
        return Err("give at least 3 [x, z] vertices".into());
    }
    if polygon.iter().flatten().any(|v| !v.is_finite()) {
        return Err("vertices must be finite metres".into());
    }
    for i in 0..n {
        if let Some(j) = polygon[..i].iter().position(|&v| v == polygon[i]) {
            return Err(format!(
                "vertex {i} repeats vertex {j}; list each corner once (the polygon closes itself)"
            ));
        }
    }
    let edge = |i: usize| (polygon[i], polygon[(i + 1) % n]);
    for i in 0..n {
        for j in i + 1..n {
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            let ((a, b), (c, d)) = (edge(i), edge(j));
            let meet = if adjacent {
                // Adjacent edges share one vertex; they may not fold back over each other.
                let (shared, p, q) = if j == i + 1 { (b, a, d) } else { (a, b, c) };
                let cross = (p[0] - shared[0]) * (q[1] - shared[1])
                    - (p[1] - shared[1]) * (q[0] - shared[0]);
                let dot = (p[0] - shared[0]) * (q[0] - shared[0])
                    + (p[1] - shared[1]) * (q[1] - shared[1]);
                cross == 0.0 && dot > 0.0
            } else {
                segments_meet(a, b, c, d)
            };
            if meet {
                return Err(format!(
                    "edges {i}–{} and {j}–{} cross; give the corners in order around the zone \
                     (a simple polygon)",
                    (i + 1) % n,
                    (j + 1) % n
                ));
            }
        }
    }
    let area = twice_area(polygon).abs() / 2.0;
    if area < MIN_ZONE_AREA_M2 {
        return Err(format!(
            "encloses {area} m²; a zone needs at least {MIN_ZONE_AREA_M2} m² (are the corners on \
             one line?)"
        ));
    }
    Ok(())
}

/// The point of the polygon's boundary nearest to `p`, and whether `p` is inside (even–odd
/// rule). O(vertices).
pub fn nearest_on_boundary(polygon: &[[f64; 2]], p: [f64; 2]) -> ([f64; 2], bool) {
    let mut inside = false;
    let (mut best, mut nearest) = (f64::INFINITY, p);
    for (i, &a) in polygon.iter().enumerate() {
        let b = polygon[(i + 1) % polygon.len()];
        // Crossing test of a ray towards +x.
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if p[0] < x {
                inside = !inside;
            }
        }
        // The nearest point of the segment a–b.
        let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
        let len2 = dx * dx + dz * dz;
        let t = if len2 > 0.0 {
            (((p[0] - a[0]) * dx + (p[1] - a[1]) * dz) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = [a[0] + t * dx, a[1] + t * dz];
        let d = (q[0] - p[0]).hypot(q[1] - p[1]);
        if d < best {
            (best, nearest) = (d, q);
        }
    }
    (nearest, inside)
}

/// Signed distance from `p` to the polygon's boundary, metres: positive inside, negative outside
/// (even–odd rule). O(vertices).
pub fn signed_distance(polygon: &[[f64; 2]], p: [f64; 2]) -> f64 {
    let (q, inside) = nearest_on_boundary(polygon, p);
    let d = (q[0] - p[0]).hypot(q[1] - p[1]);
    if inside { d } else { -d }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: [[f64; 2]; 4] = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];

    #[test]
    fn signed_distance_of_a_square() {
        // Closed forms: inside, the distance to the nearest side; outside, to the nearest point.
        assert!((signed_distance(&SQUARE, [5.0, 5.0]) - 5.0).abs() < 1e-12);
        assert!((signed_distance(&SQUARE, [1.0, 7.0]) - 1.0).abs() < 1e-12);
        assert!((signed_distance(&SQUARE, [-3.0, 5.0]) + 3.0).abs() < 1e-12);
        assert!((signed_distance(&SQUARE, [13.0, 14.0]) + 5.0).abs() < 1e-12);
        // Clockwise order and a concave L give the same sign rule.
        let mut cw = SQUARE;
        cw.reverse();
        assert!((signed_distance(&cw, [5.0, 5.0]) - 5.0).abs() < 1e-12);
        let l = [
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 1.0],
            [1.0, 1.0],
            [1.0, 4.0],
            [0.0, 4.0],
        ];
        assert!(signed_distance(&l, [0.5, 3.0]) > 0.0);
        assert!(signed_distance(&l, [3.0, 3.0]) < 0.0);
    }

    /// Issue #18, item 7: each of these loaded silently and raised no alert.
    #[test]
    fn perimeters_that_cannot_work_are_refused() {
        let file = |classes: &str, polygon: &str| {
            format!("restricted_classes = {classes}\n[[zone]]\nname = \"z\"\npolygon = {polygon}\n")
        };
        let square = "[[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]]";
        let err = |text: String| Perimeter::parse(&text).unwrap_err().to_string();
        assert!(Perimeter::parse(&file("[\"person\"]", square)).is_ok());
        let e = err(file("[]", square));
        assert!(
            e.contains("restricted_classes") && e.contains("person"),
            "{e}"
        );
        let e = err(file("[\"Person\"]", square));
        assert!(
            e.contains("restricted_classes[0]") && e.contains("\"person\""),
            "{e}"
        );
        let e = err(file("[\"car\", \"dog\"]", square));
        assert!(
            e.contains("restricted_classes[1]") && e.contains("\"dog\""),
            "{e}"
        );
        let e = err(file("[\"car\", \"car\"]", square));
        assert!(
            e.contains("restricted_classes[1]") && e.contains("twice"),
            "{e}"
        );
        // A bow tie: edges 1–2 and 3–0 cross.
        let e = err(file(
            "[\"car\"]",
            "[[0.0, 0.0], [4.0, 0.0], [0.0, 4.0], [4.0, 4.0]]",
        ));
        assert!(e.contains("zone[0].polygon") && e.contains("cross"), "{e}");
        // Three corners on a line: zero area (and the middle edge folds back).
        let e = err(file("[\"car\"]", "[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]]"));
        assert!(e.contains("zone[0].polygon"), "{e}");
        let e = err(file(
            "[\"car\"]",
            "[[0.0, 0.0], [1.0, 0.0], [1.0, 0.1], [0.0, 0.1]]",
        ));
        assert!(e.contains("m²"), "{e}");
        let e = err(file(
            "[\"car\"]",
            "[[0.0, 0.0], [4.0, 0.0], [4.0, 0.0], [4.0, 4.0]]",
        ));
        assert!(e.contains("vertex 2 repeats vertex 1"), "{e}");
        // A spike folding back along its own edge.
        let e = err(file(
            "[\"car\"]",
            "[[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [4.0, 2.0], [0.0, 4.0]]",
        ));
        assert!(e.contains("cross"), "{e}");
        let two = format!(
            "{}[[zone]]\nname = \"z\"\npolygon = {square}\n",
            file("[\"car\"]", square)
        );
        assert!(err(two).contains("zone[1].name"));
    }

    /// Whether segments `p1–p2` and `q1–q2` (integer corners, neither a point) share a point,
    /// in exact integer arithmetic: Cramer's rule for the crossing, interval overlap when they
    /// lie on one line. The reference for [`segments_meet`].
    fn meet_exactly(p1: [i64; 2], p2: [i64; 2], q1: [i64; 2], q2: [i64; 2]) -> bool {
        let cross = |a: [i64; 2], b: [i64; 2]| a[0] * b[1] - a[1] * b[0];
        let sub = |a: [i64; 2], b: [i64; 2]| [a[0] - b[0], a[1] - b[1]];
        let (r, u, w) = (sub(p2, p1), sub(q2, q1), sub(q1, p1));
        let denom = cross(r, u);
        if denom != 0 {
            // p1 + s·r = q1 + t·u with s = cross(w, u)/denom, t = cross(w, r)/denom in [0, 1].
            let within = |num: i64| {
                let (n, d) = if denom < 0 {
                    (-num, -denom)
                } else {
                    (num, denom)
                };
                (0..=d).contains(&n)
            };
            return within(cross(w, u)) && within(cross(w, r));
        }
        if cross(w, r) != 0 {
            return false; // parallel, on different lines
        }
        // One line: project onto r and compare the intervals.
        let dot = |a: [i64; 2], b: [i64; 2]| a[0] * b[0] + a[1] * b[1];
        let (a, b) = (dot(w, r), dot(sub(q2, p1), r));
        a.max(b) >= 0 && a.min(b) <= dot(r, r)
    }

    #[test]
    fn segments_meet_as_exact_arithmetic_says() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % 7) as i64 - 3
        };
        let (mut crossing, mut touching) = (0, 0);
        for _ in 0..200_000 {
            let mut corner = || [next(), next()];
            let (p1, p2, q1, q2) = (corner(), corner(), corner(), corner());
            if p1 == p2 || q1 == q2 {
                continue;
            }
            let f = |v: [i64; 2]| [v[0] as f64, v[1] as f64];
            let expected = meet_exactly(p1, p2, q1, q2);
            assert_eq!(
                segments_meet(f(p1), f(p2), f(q1), f(q2)),
                expected,
                "{p1:?}–{p2:?} and {q1:?}–{q2:?}"
            );
            touching += usize::from([p1, p2].iter().any(|v| *v == q1 || *v == q2));
            crossing += usize::from(expected);
        }
        // The draw covers shared corners and crossings alike.
        assert!(
            crossing > 10_000 && touching > 10_000,
            "{crossing} {touching}"
        );
    }

    /// A star-shaped (so simple) polygon of `n` corners around (5, 5): angles increasing, radii
    /// 1–5 m, from `next` (uniform in 0..1).
    fn star(n: usize, next: &mut impl FnMut() -> f64) -> Vec<[f64; 2]> {
        let mut angles: Vec<f64> = (0..n).map(|_| next() * std::f64::consts::TAU).collect();
        angles.sort_by(f64::total_cmp);
        angles
            .iter()
            .map(|&a| {
                let r = 1.0 + 4.0 * next();
                [5.0 + r * a.cos(), 5.0 + r * a.sin()]
            })
            .collect()
    }

    #[test]
    fn signed_distance_agrees_with_winding_and_sampled_edges() {
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut inside, mut outside) = (0, 0);
        for _ in 0..300 {
            let polygon = star(3 + (next() * 8.0) as usize, &mut next);
            for _ in 0..20 {
                let p = [10.0 * next(), 10.0 * next()];
                // Winding number by summing the angles each edge subtends (not a ray count).
                let winding: f64 = (0..polygon.len())
                    .map(|i| {
                        let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
                        let (ua, ub) = ([a[0] - p[0], a[1] - p[1]], [b[0] - p[0], b[1] - p[1]]);
                        (ua[0] * ub[1] - ua[1] * ub[0]).atan2(ua[0] * ub[0] + ua[1] * ub[1])
                    })
                    .sum();
                let is_inside = winding.abs() > std::f64::consts::PI;
                // Distance to the boundary by sampling every edge at 4,000 points.
                let sampled = (0..polygon.len())
                    .flat_map(|i| {
                        let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
                        (0..=4000).map(move |k| {
                            let t = f64::from(k) / 4000.0;
                            [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
                        })
                    })
                    .map(|q| (q[0] - p[0]).hypot(q[1] - p[1]))
                    .fold(f64::INFINITY, f64::min);
                let d = signed_distance(&polygon, p);
                assert_eq!(d > 0.0, is_inside, "{polygon:?} at {p:?}: {d}");
                // Sampling overestimates by at most half a step (10 m / 4,000 / 2).
                assert!(
                    d.abs() <= sampled + 1e-12 && d.abs() >= sampled - 2e-3,
                    "{polygon:?} at {p:?}: {d} vs {sampled}"
                );
                if is_inside {
                    inside += 1;
                } else {
                    outside += 1;
                }
            }
        }
        assert!(inside > 500 && outside > 500, "{inside} {outside}");
    }

    #[test]
    fn polygons_at_the_edge_of_what_is_allowed() {
        let zone = |polygon: &str| {
            Perimeter::parse(&format!(
                "restricted_classes = [\"car\"]\n[[zone]]\nname = \"z\"\npolygon = {polygon}\n"
            ))
            .map_err(|e| e.to_string())
        };
        // Acute corners, a straight-through corner, and exactly the least area: all fine.
        zone("[[0.0, 0.0], [4.0, 0.0], [4.0, 4.0]]").unwrap();
        zone("[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]]").unwrap();
        zone("[[0.0, 0.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]]").unwrap();
        // Two corners are not a zone.
        let e = zone("[[0.0, 0.0], [4.0, 0.0]]").unwrap_err();
        assert!(e.contains("at least 3"), "{e}");
        // A triangle whose third corner folds back onto its first edge: reported as a fold
        // (edges that cross) before its zero area.
        let e = zone("[[0.0, 0.0], [4.0, 0.0], [2.0, 0.0]]").unwrap_err();
        assert!(e.contains("cross"), "{e}");
        let e = zone("[[0.0, 0.0], [4.0, 0.0], [6.0, 0.0]]").unwrap_err();
        assert!(e.contains("cross"), "{e}");
        // The same along a diagonal, where both coordinates enter the fold test, and along
        // the z axis, where one of them is zero.
        for folded in [
            "[[0.0, 0.0], [4.0, 4.0], [2.0, 2.0]]",
            "[[0.0, 0.0], [4.0, 2.0], [-2.0, -1.0]]",
            "[[0.0, 0.0], [0.0, 4.0], [0.0, 2.0]]",
        ] {
            let e = zone(folded).unwrap_err();
            assert!(e.contains("cross"), "{folded}: {e}");
        }
        // Straight-through corners on steep and shallow lines, short edge in and long edge out
        // (exactly collinear in binary: slopes of 1/8 and 8). The fold test's dot product is
        // negative there; a mis-signed or mis-combined term makes it positive and refuses a
        // valid zone.
        for straight in [
            // Shallow: (1, 0.875) → (2, 1) → (12, 2.25).
            "[[1.0, 0.875], [2.0, 1.0], [12.0, 2.25], [12.0, 8.0], [1.0, 8.0]]",
            // Steep through (2, 1): (1.875, 0) → (2, 1) → (3.25, 11).
            "[[1.875, 0.0], [2.0, 1.0], [3.25, 11.0], [-4.0, 11.0], [-4.0, 0.0]]",
            // Steep through (2, −20): (1.875, −21) → (2, −20) → (3.25, −10).
            "[[1.875, -21.0], [2.0, -20.0], [3.25, -10.0], [-4.0, -10.0], [-4.0, -21.0]]",
        ] {
            zone(straight).unwrap_or_else(|e| panic!("{straight}: {e}"));
        }
    }

    #[test]
    fn the_hysteresis_defaults_to_a_metre() {
        let p = Perimeter::parse(
            "restricted_classes = [\"car\"]\n[[zone]]\nname = \"z\"\npolygon = [[0.0, 0.0], [4.0, 0.0], [4.0, 4.0]]\n",
        )
        .unwrap();
        assert_eq!(p.hysteresis_m, 1.0);
    }

    #[test]
    fn bad_files_name_the_field() {
        let e = Perimeter::parse(
            "restricted_classes = [\"car\"]\n[[zone]]\nname = \"a\"\npolygon = [[0.0, 0.0], [1.0, 1.0]]\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("zone[0].polygon"), "{e}");
        let e = Perimeter::parse("restricted_classes = [\"car\"]\nhysteresis_m = -1.0\n[[zone]]\nname = \"a\"\npolygon = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0]]\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("hysteresis_m"), "{e}");
        let e = Perimeter::parse("restricted_classes = \"car\"\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("restricted_classes"), "{e}");
        for (field, value) in [
            ("dwell_s", "-1.0"),
            ("approach_mps", "nan"),
            ("approach_within_m", "0.0"),
        ] {
            let e = Perimeter::parse(&format!(
                "restricted_classes = [\"car\"]\n[[zone]]\nname = \"a\"\npolygon = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0]]\n{field} = {value}\n"
            ))
            .unwrap_err()
            .to_string();
            assert!(e.contains(&format!("zone[0].{field} (a)")), "{e}");
        }
        let e = Perimeter::load(Path::new("/nonexistent/perimeter.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/perimeter.toml"), "{e}");
    }
}
