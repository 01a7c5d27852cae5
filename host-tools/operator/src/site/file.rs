//! The site file (TOML): the plan's extent, each sensor's place and heading on it, and the
//! perimeter (zones in plan coordinates). Loaded and checked field by field.
//!
//! The plan's frame: `x` east, `y` north, metres; a heading is degrees clockwise from north.
//!
//! ```toml
//! name = "yard"
//! extent = [[-40.0, -5.0], [40.0, 55.0]]   # [x, y] of two opposite corners, m
//!
//! [[sensor]]
//! id = "pole-a"
//! position = [-18.0, 0.0]
//! heading_deg = 35.0
//! range_m = 50.0     # coverage drawn on the plan (default 60)
//! fov_deg = 60.0     # (default 90)
//!
//! [perimeter]
//! restricted_classes = ["person", "car"]
//! [[perimeter.zone]]
//! name = "yard"
//! polygon = [[-4.0, 17.0], [4.0, 17.0], [4.0, 27.0], [-4.0, 27.0]]
//! ```

use crate::OperatorError;
use crate::geofence::Perimeter;
use metamoran_bundle::limits::MAX_TOML_BYTES;
use metamoran_bundle::pose::Pose;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One sensor's place on the plan.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SensorPlace {
    /// Sensor id (its subject token in the site stream).
    pub id: String,
    /// Position `[x, y]`, m.
    pub position: [f64; 2],
    /// Boresight, degrees clockwise from north.
    pub heading_deg: f64,
    /// Coverage radius drawn on the plan, m.
    #[serde(default = "default_range")]
    pub range_m: f64,
    /// Coverage width drawn on the plan, degrees.
    #[serde(default = "default_fov")]
    pub fov_deg: f64,
}

fn default_range() -> f64 {
    60.0
}

fn default_fov() -> f64 {
    90.0
}

impl SensorPlace {
    /// The sensor's pose on the plan.
    pub fn pose(&self) -> Pose {
        Pose {
            position: self.position,
            yaw: -self.heading_deg.to_radians(),
        }
    }

    /// A point of the sensor's ground plane (`[x right, z forward]`) on the plan.
    pub fn to_plan(&self, p: [f64; 2]) -> [f64; 2] {
        self.pose().to_world(p)
    }

    /// A velocity of the sensor's ground plane on the plan.
    pub fn velocity_to_plan(&self, v: [f64; 2]) -> [f64; 2] {
        let (f, r) = self.pose().axes();
        [v[0] * r[0] + v[1] * f[0], v[0] * r[1] + v[1] * f[1]]
    }
}

/// A site: its plan, sensors and perimeter.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SiteFile {
    /// Site name (its subject token in the site stream).
    pub name: String,
    /// Two opposite corners of the plan `[x, y]`, m: positions outside are refused.
    pub extent: [[f64; 2]; 2],
    /// The sensors.
    #[serde(rename = "sensor")]
    pub sensors: Vec<SensorPlace>,
    /// Zones (plan coordinates) and rules.
    pub perimeter: Perimeter,
}

impl SiteFile {
    /// Reads and checks a site file.
    ///
    /// # Errors
    /// [`OperatorError::Site`] naming the file and the field that is missing, malformed or out
    /// of range.
    pub fn load(path: &Path) -> Result<Self, OperatorError> {
        let source_name = path.display().to_string();
        let err = |problem: String| OperatorError::Site {
            source_name: source_name.clone(),
            problem,
        };
        let bytes = metamoran_bundle::limits::read_bounded(path, MAX_TOML_BYTES)
            .map_err(|e| err(format!("{e}; give a site TOML file as in the README")))?;
        let text = String::from_utf8(bytes).map_err(|_| err("not UTF-8 text".into()))?;
        Self::parse_problem(&text).map_err(err)
    }

    /// Parses and checks site TOML.
    ///
    /// # Errors
    /// [`OperatorError::Site`] naming the field.
    pub fn parse(text: &str) -> Result<Self, OperatorError> {
        Self::parse_problem(text).map_err(|problem| OperatorError::Site {
            source_name: "site TOML".into(),
            problem,
        })
    }

    fn parse_problem(text: &str) -> Result<Self, String> {
        let de = toml::Deserializer::parse(text).map_err(|e| e.to_string())?;
        let s: SiteFile =
            serde_path_to_error::deserialize(de).map_err(|e| format!("{}: {}", e.path(), e))?;
        s.check()?;
        Ok(s)
    }

    /// Whether `p` is on the plan.
    pub fn contains(&self, p: [f64; 2]) -> bool {
        let [a, b] = self.extent;
        (a[0].min(b[0])..=a[0].max(b[0])).contains(&p[0])
            && (a[1].min(b[1])..=a[1].max(b[1])).contains(&p[1])
    }

    /// The sensor called `id`.
    pub fn sensor(&self, id: &str) -> Option<&SensorPlace> {
        self.sensors.iter().find(|s| s.id == id)
    }

    fn check(&self) -> Result<(), String> {
        if !crate::nats::is_token(&self.name) {
            return Err(format!(
                "name: {:?}: use 1–64 letters, digits, - or _ (it is a subject token)",
                self.name
            ));
        }
        let [a, b] = self.extent;
        if a.iter().chain(&b).any(|v| !v.is_finite()) || a[0] == b[0] || a[1] == b[1] {
            return Err(
                "extent: give two opposite corners [[x, y], [x, y]] of finite metres, \
                        apart in both x and y"
                    .into(),
            );
        }
        if self.sensors.is_empty() {
            return Err(
                "sensor: add at least one [[sensor]] with an id, position and heading".into(),
            );
        }
        for (i, s) in self.sensors.iter().enumerate() {
            let at = |field: &str| format!("sensor[{i}].{field} ({})", s.id);
            if !crate::nats::is_token(&s.id) {
                return Err(format!(
                    "sensor[{i}].id: {:?}: use 1–64 letters, digits, - or _",
                    s.id
                ));
            }
            if let Some(j) = self.sensors[..i].iter().position(|o| o.id == s.id) {
                return Err(format!(
                    "{}: also sensor[{j}]'s id; give each its own",
                    at("id")
                ));
            }
            if !self.contains(s.position) {
                return Err(format!(
                    "{}: {:?} is not a finite point inside the extent",
                    at("position"),
                    s.position
                ));
            }
            if !s.heading_deg.is_finite() {
                return Err(format!(
                    "{}: give degrees clockwise from north",
                    at("heading_deg")
                ));
            }
            if !(s.range_m.is_finite() && s.range_m > 0.0) {
                return Err(format!("{}: give metres > 0", at("range_m")));
            }
            if !(s.fov_deg.is_finite() && s.fov_deg > 0.0 && s.fov_deg <= 360.0) {
                return Err(format!("{}: give degrees in (0, 360]", at("fov_deg")));
            }
        }
        self.perimeter
            .check()
            .map_err(|problem| format!("perimeter.{problem}"))?;
        for (i, z) in self.perimeter.zones.iter().enumerate() {
            if let Some(v) = z.polygon.iter().position(|&p| !self.contains(p)) {
                return Err(format!(
                    "perimeter.zone[{i}].polygon ({}): vertex {v} is outside the extent",
                    z.name
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
name = "yard"
extent = [[-40.0, -5.0], [40.0, 55.0]]
[[sensor]]
id = "pole-a"
position = [-18.0, 0.0]
heading_deg = 35.0
[[sensor]]
id = "pole-c"
position = [0.0, 48.0]
heading_deg = 180.0
[perimeter]
restricted_classes = ["person"]
[[perimeter.zone]]
name = "yard"
polygon = [[-4.0, 17.0], [4.0, 17.0], [4.0, 27.0], [-4.0, 27.0]]
"#;

    #[test]
    fn a_sensor_facing_south_sees_east_on_its_left() {
        let site = SiteFile::parse(GOOD).unwrap();
        let c = site.sensor("pole-c").unwrap();
        // 10 m ahead of a pole at (0, 48) facing south is (0, 38); 2 m to its right is west.
        let p = c.to_plan([2.0, 10.0]);
        assert!(
            (p[0] + 2.0).abs() < 1e-12 && (p[1] - 38.0).abs() < 1e-12,
            "{p:?}"
        );
        let v = c.velocity_to_plan([0.0, 1.0]);
        assert!(v[0].abs() < 1e-12 && (v[1] + 1.0).abs() < 1e-12, "{v:?}");
        // Pole a faces 35° east of north: its boresight point 10 m out.
        let a = site.sensor("pole-a").unwrap().to_plan([0.0, 10.0]);
        let (s, co) = 35f64.to_radians().sin_cos();
        assert!((a[0] - (-18.0 + 10.0 * s)).abs() < 1e-12 && (a[1] - 10.0 * co).abs() < 1e-12);
    }

    #[test]
    fn bad_site_files_name_the_field() {
        let bad = |from: &str, to: &str| {
            assert!(GOOD.contains(from), "{from}");
            SiteFile::parse(&GOOD.replacen(from, to, 1))
                .unwrap_err()
                .to_string()
        };
        for (from, to, field) in [
            ("name = \"yard\"", "name = \"yard.north\"", "name"),
            (
                "extent = [[-40.0, -5.0], [40.0, 55.0]]",
                "extent = [[0.0, -5.0], [0.0, 55.0]]",
                "extent",
            ),
            (
                "position = [-18.0, 0.0]",
                "position = [-80.0, 0.0]",
                "sensor[0].position (pole-a)",
            ),
            (
                "heading_deg = 35.0",
                "heading_deg = nan",
                "sensor[0].heading_deg",
            ),
            (
                "id = \"pole-c\"",
                "id = \"pole-a\"",
                "sensor[1].id (pole-a)",
            ),
            (
                "restricted_classes = [\"person\"]",
                "restricted_classes = [\"dog\"]",
                "perimeter.restricted_classes[0]",
            ),
            (
                "[-4.0, 17.0], [4.0, 17.0]",
                "[-4.0, 17.0], [60.0, 17.0]",
                "perimeter.zone[0].polygon (yard): vertex 1",
            ),
            (
                "heading_deg = 180.0",
                "heading_deg = 180.0\nrange_m = -1.0",
                "sensor[1].range_m",
            ),
            (
                "heading_deg = 180.0",
                "heading_deg = 180.0\ncolour = 1",
                "colour",
            ),
        ] {
            let e = bad(from, to);
            assert!(e.contains(field), "{field}: {e}");
        }
        let e = SiteFile::load(Path::new("/nonexistent/site.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/site.toml"), "{e}");
    }
}
