//! The site process's fusion (issue #20 part 2): every sensor's confirmed tracks, moved onto
//! the site plan, become site tracks (the same person seen by two poles is one), the zones are
//! evaluated once on them, and each alert says which sensors saw the object.
//!
//! ```text
//! sensor A tracks ─┐  validate ─▶ plan coordinates ─▶ associate (per sensor track) ─▶ site tracks ─▶ Geofence ─▶ SiteAlert
//! sensor B tracks ─┘
//! ```
//!
//! **Association.** A sensor track keeps the site track it joined for its whole life. A new one
//! joins the nearest site track that no track of the same sensor already feeds, of the same
//! class, whose position (extrapolated to the message's time) is within the class's gate
//! ([`SiteConfig::gate_m`]: poles see different faces of a car, so its gate is wider); else it
//! starts a site track. Two site tracks of one class within the gate whose members come from
//! different sensors are one object seen twice: they merge into the older (the younger's id
//! ends without a `lost` alert). A site track's position and velocity are the mean of its
//! members', each extrapolated to the latest time; it ends when its last member does (the
//! sensors' own deletion rules). Site track ids are never reused.
//!
//! **Validation.** A message from an unknown sensor, with a frame number or time that went
//! backwards, a non-finite number, an unknown class or a position off the plan is refused as a
//! whole with the sensor and field named ([`SiteError`]), counted in that sensor's health, and
//! changes nothing.

pub mod file;

pub use file::{SensorPlace, SiteFile};

use crate::geofence::{Alert, Geofence, Sighting};
use crate::live::TrackRow;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One sensor's message to the site: its confirmed tracks after one frame.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SensorTracks {
    /// The sensor's frame number (increasing).
    pub frame: u32,
    /// Time of the frame, s (not decreasing).
    pub time_s: f64,
    /// Its confirmed tracks, in its own ground frame.
    pub tracks: Vec<TrackRow>,
}

/// Each sensor's id and its messages, frame by frame: a site's recording, or a replay.
pub type SiteMessages = Vec<(String, Vec<SensorTracks>)>;

/// The site fusion's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SiteConfig {
    /// How near, m, a sensor track of a person or sign must be to a site track to join it.
    pub gate_m: f64,
    /// The same for a car (its position is the face each pole sees: up to a car length apart).
    pub car_gate_m: f64,
}

impl Default for SiteConfig {
    fn default() -> Self {
        Self {
            gate_m: 2.0,
            car_gate_m: 4.5,
        }
    }
}

impl SiteConfig {
    /// The gate of `class`, m.
    pub fn gate(&self, class: &str) -> f64 {
        if class == "car" {
            self.car_gate_m
        } else {
            self.gate_m
        }
    }
}

/// Why a sensor message was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("sensor {sensor}: {field}: {problem}; the message was dropped")]
pub struct SiteError {
    /// The sensor, as the message named it.
    pub sensor: String,
    /// The field at fault.
    pub field: String,
    /// What is wrong.
    pub problem: String,
}

/// One sensor's health as the site sees it.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SensorHealth {
    /// Messages taken.
    pub accepted: u64,
    /// Messages refused.
    pub rejected: u64,
    /// The last refusal, in words.
    pub last_problem: Option<String>,
    /// The last frame taken.
    pub last_frame: Option<u32>,
    /// Its time, s.
    pub last_time_s: Option<f64>,
}

/// A site track.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SiteTrack {
    /// Id, unique over the site process's life.
    pub id: u32,
    /// Class.
    pub class: String,
    /// Position on the plan `[x, y]`, m.
    pub position_m: [f64; 2],
    /// Velocity on the plan, m/s.
    pub velocity_mps: [f64; 2],
    /// The sensors that see it now.
    pub sensors: Vec<String>,
}

/// An alert of the site: the zone rule's alert on a site track, and who saw it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SiteAlert {
    /// The alert (`track` is the site track; positions on the plan).
    #[serde(flatten)]
    pub alert: Alert,
    /// The sensors that saw the object when it was raised.
    pub sensors: Vec<String>,
}

/// A sensor track's position and velocity on the plan.
type OnPlan = ([f64; 2], [f64; 2]);

/// A member: one sensor track feeding a site track, on the plan.
#[derive(Clone, Debug)]
struct Member {
    position: [f64; 2],
    velocity: [f64; 2],
    time_s: f64,
    /// The sensor's frame and camera instance of the latest detection it took (kept while
    /// the sensor track coasts).
    detected: Option<(u32, u16)>,
}

#[derive(Clone, Debug)]
struct Fused {
    id: u32,
    class: String,
    /// `(sensor index, sensor track id)` → member.
    members: BTreeMap<(usize, u32), Member>,
}

impl Fused {
    /// Mean position and velocity of the members at `t`.
    fn state(&self, t: f64) -> ([f64; 2], [f64; 2]) {
        let n = self.members.len().max(1) as f64;
        let (mut p, mut v) = ([0.0; 2], [0.0; 2]);
        for m in self.members.values() {
            let dt = (t - m.time_s).max(0.0);
            for k in 0..2 {
                p[k] += (m.position[k] + m.velocity[k] * dt) / n;
                v[k] += m.velocity[k] / n;
            }
        }
        (p, v)
    }
}

/// The site process's state.
#[derive(Clone, Debug)]
pub struct Site {
    file: SiteFile,
    config: SiteConfig,
    fence: Geofence,
    tracks: Vec<Fused>,
    next_id: u32,
    health: Vec<SensorHealth>,
    /// Messages from sensors the site file does not know.
    unknown: u64,
    time_s: f64,
}

impl Site {
    /// A site with no tracks.
    pub fn new(file: SiteFile, config: SiteConfig) -> Self {
        let fence = Geofence::new(file.perimeter.clone());
        let health = vec![SensorHealth::default(); file.sensors.len()];
        Self {
            file,
            config,
            fence,
            tracks: Vec::new(),
            next_id: 0,
            health,
            unknown: 0,
            time_s: 0.0,
        }
    }

    /// The site file.
    pub fn file(&self) -> &SiteFile {
        &self.file
    }

    /// Each sensor's health, in the site file's order.
    pub fn health(&self) -> impl Iterator<Item = (&str, &SensorHealth)> {
        self.file
            .sensors
            .iter()
            .map(|s| s.id.as_str())
            .zip(&self.health)
    }

    /// Messages refused because no sensor of the site has their id.
    pub fn unknown_messages(&self) -> u64 {
        self.unknown
    }

    /// The site tracks now, oldest id first.
    pub fn tracks(&self) -> Vec<SiteTrack> {
        self.tracks
            .iter()
            .map(|t| {
                let (position_m, velocity_mps) = t.state(self.time_s);
                SiteTrack {
                    id: t.id,
                    class: t.class.clone(),
                    position_m,
                    velocity_mps,
                    sensors: self.sensors_of(t),
                }
            })
            .collect()
    }

    /// Where site track `id` was last detected: for each member that took a detection, its
    /// sensor, that frame and the detection's camera instance; the latest first.
    pub fn sources(&self, id: u32) -> Vec<(String, u32, u16)> {
        let mut out: Vec<(String, u32, u16)> = self
            .tracks
            .iter()
            .find(|t| t.id == id)
            .into_iter()
            .flat_map(|t| t.members.iter())
            .filter_map(|((k, _), m)| {
                m.detected
                    .map(|(frame, instance)| (self.file.sensors[*k].id.clone(), frame, instance))
            })
            .collect();
        out.sort_by_key(|s| std::cmp::Reverse(s.1));
        out
    }

    fn sensors_of(&self, t: &Fused) -> Vec<String> {
        let mut s: Vec<String> = t
            .members
            .keys()
            .map(|(k, _)| self.file.sensors[*k].id.clone())
            .collect();
        s.dedup();
        s
    }

    /// Checks one message of `sensor`: the sensor's index and every track on the plan
    /// (position, velocity).
    fn validate(&self, sensor: &str, m: &SensorTracks) -> Result<(usize, Vec<OnPlan>), SiteError> {
        let refuse = |field: String, problem: String| SiteError {
            sensor: sensor.to_owned(),
            field,
            problem,
        };
        let k = self
            .file
            .sensors
            .iter()
            .position(|s| s.id == sensor)
            .ok_or_else(|| {
                refuse(
                    "sensor".into(),
                    "not in the site file; add a [[sensor]] for it".into(),
                )
            })?;
        let h = &self.health[k];
        if let Some(last) = h.last_frame
            && m.frame <= last
        {
            return Err(refuse(
                "frame".into(),
                format!(
                    "{} is not after the last frame taken, {last} (a counter went backwards or repeated)",
                    m.frame
                ),
            ));
        }
        if !m.time_s.is_finite() || h.last_time_s.is_some_and(|t| m.time_s < t) {
            return Err(refuse(
                "time_s".into(),
                format!("{} is not finite or went backwards", m.time_s),
            ));
        }
        let place = &self.file.sensors[k];
        let mut out = Vec::with_capacity(m.tracks.len());
        for (i, t) in m.tracks.iter().enumerate() {
            let field = |f: &str| format!("tracks[{i}].{f}");
            if let Some(f) = [
                ("position_m", t.position_m.iter().all(|v| v.is_finite())),
                ("velocity_mps", t.velocity_mps.iter().all(|v| v.is_finite())),
                ("depth_m", t.depth_m.is_finite()),
                ("azimuth_deg", t.azimuth_deg.is_finite()),
                ("speed_mps", t.speed_mps.is_finite()),
            ]
            .iter()
            .find(|(_, ok)| !ok)
            {
                return Err(refuse(field(f.0), "not a finite number".into()));
            }
            if !metamoran_bundle::OBJECTS_OF_INTEREST.contains(&t.class.as_str()) {
                return Err(refuse(
                    field("class"),
                    format!(
                        "{:?} is not one of {}",
                        t.class,
                        metamoran_bundle::OBJECTS_OF_INTEREST.join(", ")
                    ),
                ));
            }
            if let Some(j) = m.tracks[..i].iter().position(|o| o.id == t.id) {
                return Err(refuse(
                    field("id"),
                    format!("{} is also tracks[{j}]'s", t.id),
                ));
            }
            let p = place.to_plan(t.position_m);
            if !self.file.contains(p) {
                return Err(refuse(
                    field("position_m"),
                    format!(
                        "on the plan at [{:.1}, {:.1}] m, outside the site's extent",
                        p[0], p[1]
                    ),
                ));
            }
            out.push((p, place.velocity_to_plan(t.velocity_mps)));
        }
        Ok((k, out))
    }

    /// Counts refusal `e` in its sensor's health (or as a message from an unknown sensor):
    /// for messages refused before they could be read, as well as by [`Site::ingest`].
    pub fn reject(&mut self, e: &SiteError) {
        match self.file.sensors.iter().position(|s| s.id == e.sensor) {
            Some(k) => {
                self.health[k].rejected += 1;
                self.health[k].last_problem = Some(e.to_string());
            }
            None => self.unknown += 1,
        }
    }

    /// Takes one message of `sensor` and returns the site alerts it raises.
    /// O(tracks × site tracks + site tracks × zones × vertices).
    ///
    /// # Errors
    /// [`SiteError`] naming the sensor and field when the message is refused; it is counted in
    /// the sensor's health (or as unknown) and changes nothing else.
    pub fn ingest(&mut self, sensor: &str, m: &SensorTracks) -> Result<Vec<SiteAlert>, SiteError> {
        let (k, placed) = match self.validate(sensor, m) {
            Ok(v) => v,
            Err(e) => {
                self.reject(&e);
                return Err(e);
            }
        };
        let h = &mut self.health[k];
        h.accepted += 1;
        h.last_frame = Some(m.frame);
        h.last_time_s = Some(m.time_s);
        let t = m.time_s;
        self.time_s = self.time_s.max(t);
        // This sensor's tracks that ended leave their site tracks.
        for f in &mut self.tracks {
            f.members
                .retain(|(s, id), _| *s != k || m.tracks.iter().any(|r| r.id == *id));
        }
        self.tracks.retain(|f| !f.members.is_empty());
        for (row, (position, velocity)) in m.tracks.iter().zip(placed) {
            let mut member = Member {
                position,
                velocity,
                time_s: t,
                detected: row.instance.map(|i| (m.frame, i)),
            };
            if let Some(f) = self
                .tracks
                .iter_mut()
                .find(|f| f.members.contains_key(&(k, row.id)))
            {
                if let Some(old) = f.members.get(&(k, row.id)) {
                    member.detected = member.detected.or(old.detected);
                }
                f.members.insert((k, row.id), member);
                continue;
            }
            let gate = self.config.gate(&row.class);
            let nearest = self
                .tracks
                .iter_mut()
                .filter(|f| f.class == row.class && !f.members.keys().any(|(s, _)| *s == k))
                .map(|f| {
                    let (p, _) = f.state(t);
                    ((p[0] - position[0]).hypot(p[1] - position[1]), f)
                })
                .filter(|(d, _)| *d <= gate)
                .min_by(|a, b| a.0.total_cmp(&b.0));
            match nearest {
                Some((_, f)) => {
                    f.members.insert((k, row.id), member);
                }
                None => {
                    let mut members = BTreeMap::new();
                    members.insert((k, row.id), member);
                    self.tracks.push(Fused {
                        id: self.next_id,
                        class: row.class.clone(),
                        members,
                    });
                    self.next_id += 1;
                }
            }
        }
        self.merge(t);
        let sightings: Vec<Sighting> = self
            .tracks
            .iter()
            .map(|f| {
                let (position_m, velocity_mps) = f.state(t);
                Sighting {
                    track: f.id,
                    class: f.class.clone(),
                    position_m,
                    velocity_mps,
                    instance: None,
                    measured: f.members.keys().any(|(s, _)| *s == k),
                }
            })
            .collect();
        let alerts = self.fence.update(m.frame, t, &sightings);
        Ok(alerts
            .into_iter()
            .map(|alert| {
                let sensors = self
                    .tracks
                    .iter()
                    .find(|f| f.id == alert.track)
                    .map(|f| self.sensors_of(f))
                    .unwrap_or_default();
                SiteAlert { alert, sensors }
            })
            .collect())
    }
}

impl Site {
    /// Merges site tracks that are one object seen by different sensors (see the module docs).
    fn merge(&mut self, t: f64) {
        let mut i = 0;
        while i < self.tracks.len() {
            let (pi, _) = self.tracks[i].state(t);
            let gate = self.config.gate(&self.tracks[i].class);
            let twin = (i + 1..self.tracks.len()).find(|&j| {
                let (a, b) = (&self.tracks[i], &self.tracks[j]);
                let (pj, _) = b.state(t);
                a.class == b.class
                    && (pi[0] - pj[0]).hypot(pi[1] - pj[1]) <= gate
                    && !a
                        .members
                        .keys()
                        .any(|(s, _)| b.members.keys().any(|(r, _)| r == s))
            });
            match twin {
                Some(j) => {
                    let younger = self.tracks.remove(j);
                    self.fence.forget(younger.id);
                    self.tracks[i].members.extend(younger.members);
                }
                None => i += 1,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn site() -> Site {
        let file = SiteFile::parse(
            r#"
name = "yard"
extent = [[-40.0, -5.0], [40.0, 55.0]]
[[sensor]]
id = "south"
position = [0.0, 0.0]
heading_deg = 0.0
[[sensor]]
id = "north"
position = [0.0, 40.0]
heading_deg = 180.0
[perimeter]
restricted_classes = ["person"]
[[perimeter.zone]]
name = "yard"
polygon = [[-4.0, 15.0], [4.0, 15.0], [4.0, 25.0], [-4.0, 25.0]]
"#,
        )
        .unwrap();
        Site::new(file, SiteConfig::default())
    }

    /// A row for a track at sensor-frame `[x, z]`.
    fn row(id: u32, class: &str, x: f64, z: f64) -> TrackRow {
        TrackRow {
            id,
            class: class.into(),
            depth_m: x.hypot(z),
            azimuth_deg: x.atan2(z).to_degrees(),
            speed_mps: 0.0,
            position_m: [x, z],
            velocity_mps: [0.0; 2],
            coasting: false,
            instance: Some(9),
            zones: Vec::new(),
        }
    }

    fn msg(frame: u32, tracks: Vec<TrackRow>) -> SensorTracks {
        SensorTracks {
            frame,
            time_s: f64::from(frame) * 0.25,
            tracks,
        }
    }

    #[test]
    fn one_person_seen_by_two_poles_is_one_site_track_and_one_alert() {
        let mut s = site();
        // The person at (1, 20) on the plan: 20 m ahead of south; 20 m ahead and 1 m to the
        // left of north (which faces south, so east is its left).
        let a = s
            .ingest("south", &msg(0, vec![row(7, "person", 1.0, 20.0)]))
            .unwrap();
        assert_eq!(a.len(), 1);
        assert_eq!(a[0].sensors, vec!["south"]);
        let a = s
            .ingest("north", &msg(0, vec![row(3, "person", -1.2, 20.1)]))
            .unwrap();
        assert!(a.is_empty(), "already inside: {a:?}");
        let tracks = s.tracks();
        assert_eq!(tracks.len(), 1, "{tracks:?}");
        assert_eq!(tracks[0].sensors, vec!["south", "north"]);
        assert_eq!(
            s.sources(tracks[0].id),
            [("south".to_owned(), 0, 9), ("north".to_owned(), 0, 9)]
        );
        // The mean of (1, 20) and (1.2, 19.9).
        assert!((tracks[0].position_m[0] - 1.1).abs() < 1e-9);
        assert!((tracks[0].position_m[1] - 19.95).abs() < 1e-9);
        // A car there is another object; a person 10 m away is another track.
        s.ingest(
            "north",
            &msg(
                1,
                vec![
                    row(3, "person", -1.2, 20.1),
                    row(4, "car", -1.0, 19.0),
                    row(5, "person", 0.0, 30.0),
                ],
            ),
        )
        .unwrap();
        assert_eq!(s.tracks().len(), 3);
        // South's track ends: the site track goes on with north alone.
        s.ingest("south", &msg(1, vec![])).unwrap();
        let t = s.tracks();
        assert_eq!(t.len(), 3);
        assert_eq!(t[0].sensors, vec!["north"]);
        // North's ends too: the site track is gone, and lost inside the yard.
        let a = s
            .ingest(
                "north",
                &msg(
                    2,
                    vec![row(4, "car", -1.0, 19.0), row(5, "person", 0.0, 30.0)],
                ),
            )
            .unwrap();
        assert_eq!(a.len(), 1);
        assert_eq!(a[0].alert.kind, crate::geofence::AlertKind::Lost);
        assert_eq!(s.tracks().len(), 2);
    }

    #[test]
    fn bad_messages_are_refused_named_and_counted() {
        let mut s = site();
        s.ingest("south", &msg(5, vec![row(1, "person", 0.0, 10.0)]))
            .unwrap();
        let before = s.tracks();
        let mut nan = row(2, "person", 0.0, 10.0);
        nan.position_m[1] = f64::NAN;
        let mut dog = row(2, "person", 0.0, 10.0);
        dog.class = "dog".into();
        for (sensor, m, field) in [
            ("east", msg(6, vec![]), "sensor"),
            ("south", msg(5, vec![]), "frame"),
            ("south", msg(4, vec![]), "frame"),
            ("south", msg(6, vec![nan]), "tracks[0].position_m"),
            ("south", msg(6, vec![dog]), "tracks[0].class"),
            (
                "south",
                msg(6, vec![row(2, "person", 0.0, 90.0)]),
                "tracks[0].position_m",
            ),
            (
                "south",
                msg(
                    6,
                    vec![row(2, "person", 0.0, 9.0), row(2, "person", 1.0, 9.0)],
                ),
                "tracks[1].id",
            ),
            (
                "south",
                SensorTracks {
                    time_s: f64::INFINITY,
                    ..msg(6, vec![])
                },
                "time_s",
            ),
        ] {
            let e = s.ingest(sensor, &m).unwrap_err();
            assert_eq!(
                (e.sensor.as_str(), e.field.as_str()),
                (sensor, field),
                "{e}"
            );
        }
        assert_eq!(s.tracks(), before, "nothing changed");
        assert_eq!(s.unknown_messages(), 1);
        let south = s.health().next().unwrap().1;
        assert_eq!((south.accepted, south.rejected), (1, 7));
        assert!(south.last_problem.as_deref().unwrap().contains("time_s"));
        // A good message after all that is taken.
        s.ingest("south", &msg(6, vec![row(1, "person", 0.0, 10.5)]))
            .unwrap();
    }
}
