//! What the page shows, kept by the server: the site fusion fed by the sensors' messages, each
//! site track's trail, the alerts with their acknowledgements, and each sensor's health
//! (a sensor silent for longer than the limit raises a `silent` alert itself).

use metamoran_operator::site::{SensorTracks, Site, SiteAlert};
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::time::Instant;

/// Trail points kept per track.
pub const TRAIL: usize = 40;
/// Alerts kept for the page (the stream keeps them all).
pub const ALERTS_KEPT: usize = 500;

/// Who acknowledged an alert, and when.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Ack {
    /// The operator's user name.
    pub by: String,
    /// Seconds since the Unix epoch.
    pub at_unix_s: f64,
}

/// One alert as the page lists it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AlertEntry {
    /// Id on this server (1, 2, …).
    pub id: u64,
    /// `enter`, `exit`, `dwell`, `approach`, `lost` or `silent`.
    pub kind: String,
    /// Zone (empty for `silent`).
    pub zone: String,
    /// Site track (none for `silent`).
    pub track: Option<u32>,
    /// Class (empty for `silent`).
    pub class: String,
    /// Site time, s.
    pub time_s: f64,
    /// The sensors that saw it (for `silent`, the sensor).
    pub sensors: Vec<String>,
    /// The acknowledgement, once given.
    pub acked: Option<Ack>,
}

/// The server's view of the site.
#[derive(Debug)]
pub struct Live {
    site: Site,
    trails: BTreeMap<u32, VecDeque<[f64; 2]>>,
    alerts: VecDeque<AlertEntry>,
    next_alert: u64,
    /// When each sensor was last heard from.
    heard: BTreeMap<String, Instant>,
    silent: BTreeSet<String>,
    started: Instant,
    /// Seconds without a message after which a sensor is silent.
    silence_s: f64,
    /// Bumped at every change.
    pub version: u64,
}

fn kind_word(k: metamoran_operator::geofence::AlertKind) -> String {
    serde_json::to_value(k)
        .ok()
        .and_then(|v| v.as_str().map(String::from))
        .unwrap_or_default()
}

impl Live {
    /// Nothing seen yet; sensors silent for `silence_s` raise an alert.
    pub fn new(site: Site, silence_s: f64) -> Self {
        Self {
            site,
            trails: BTreeMap::new(),
            alerts: VecDeque::new(),
            next_alert: 1,
            heard: BTreeMap::new(),
            silent: BTreeSet::new(),
            started: Instant::now(),
            silence_s,
            version: 0,
        }
    }

    /// The site fusion.
    pub fn site(&self) -> &Site {
        &self.site
    }

    fn push_alert(&mut self, entry: AlertEntry) {
        self.alerts.push_back(entry);
        while self.alerts.len() > ALERTS_KEPT {
            self.alerts.pop_front();
        }
        self.next_alert += 1;
    }

    /// Takes one sensor message (refused ones count in the sensor's health); returns the
    /// alerts it raised.
    pub fn ingest(&mut self, sensor: &str, m: &SensorTracks, now: Instant) -> Vec<SiteAlert> {
        self.version += 1;
        let Ok(alerts) = self.site.ingest(sensor, m) else {
            return Vec::new();
        };
        self.heard.insert(sensor.to_owned(), now);
        self.silent.remove(sensor);
        for a in &alerts {
            let entry = AlertEntry {
                id: self.next_alert,
                kind: kind_word(a.alert.kind),
                zone: a.alert.zone.clone(),
                track: Some(a.alert.track),
                class: a.alert.class.clone(),
                time_s: a.alert.time_s,
                sensors: a.sensors.clone(),
                acked: None,
            };
            self.push_alert(entry);
        }
        let tracks = self.site.tracks();
        self.trails
            .retain(|id, _| tracks.iter().any(|t| t.id == *id));
        for t in &tracks {
            let trail = self.trails.entry(t.id).or_default();
            trail.push_back(t.position_m);
            while trail.len() > TRAIL {
                trail.pop_front();
            }
        }
        alerts
    }

    /// Counts a message of `sensor` that could not be read at all (`problem` in words).
    pub fn refuse(&mut self, sensor: &str, problem: String) {
        self.version += 1;
        self.site.reject(&metamoran_operator::site::SiteError {
            sensor: sensor.to_owned(),
            field: "message".into(),
            problem,
        });
    }

    /// Raises a `silent` alert for each sensor not heard from for `silence_s` (once per
    /// silence); whether any was raised.
    pub fn check_silence(&mut self, now: Instant) -> bool {
        let ids: Vec<String> = self
            .site
            .file()
            .sensors
            .iter()
            .map(|s| s.id.clone())
            .collect();
        let mut raised = false;
        for id in ids {
            let last = self.heard.get(&id).copied().unwrap_or(self.started);
            if now.duration_since(last).as_secs_f64() > self.silence_s
                && self.silent.insert(id.clone())
            {
                let entry = AlertEntry {
                    id: self.next_alert,
                    kind: "silent".into(),
                    zone: String::new(),
                    track: None,
                    class: String::new(),
                    time_s: now.duration_since(self.started).as_secs_f64(),
                    sensors: vec![id],
                    acked: None,
                };
                self.push_alert(entry);
                raised = true;
            }
        }
        if raised {
            self.version += 1;
        }
        raised
    }

    /// Acknowledges alert `id` as `by`; the entry, or `None` for an unknown id.
    pub fn acknowledge(&mut self, id: u64, by: &str, at_unix_s: f64) -> Option<AlertEntry> {
        let a = self.alerts.iter_mut().find(|a| a.id == id)?;
        if a.acked.is_none() {
            a.acked = Some(Ack {
                by: by.to_owned(),
                at_unix_s,
            });
        }
        self.version += 1;
        Some(a.clone())
    }

    /// The page's state: tracks with trails, the latest alerts, each sensor's health.
    pub fn snapshot(&self, now: Instant) -> serde_json::Value {
        let tracks: Vec<serde_json::Value> = self
            .site
            .tracks()
            .into_iter()
            .map(|t| {
                let trail: Vec<[f64; 2]> = self
                    .trails
                    .get(&t.id)
                    .map(|v| v.iter().copied().collect())
                    .unwrap_or_default();
                serde_json::json!({
                    "id": t.id, "class": t.class, "position": t.position_m,
                    "velocity": t.velocity_mps, "sensors": t.sensors, "trail": trail,
                })
            })
            .collect();
        let health: Vec<serde_json::Value> = self
            .site
            .health()
            .map(|(id, h)| {
                let age = self
                    .heard
                    .get(id)
                    .map(|t| now.duration_since(*t).as_secs_f64());
                serde_json::json!({
                    "id": id, "accepted": h.accepted, "rejected": h.rejected,
                    "last_problem": h.last_problem, "last_frame": h.last_frame,
                    "age_s": age, "silent": self.silent.contains(id),
                })
            })
            .collect();
        let alerts: Vec<&AlertEntry> = self.alerts.iter().rev().take(50).collect();
        serde_json::json!({
            "version": self.version,
            "tracks": tracks,
            "alerts": alerts,
            "health": health,
            "unknown_messages": self.site.unknown_messages(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use metamoran_operator::site::{SiteConfig, SiteFile};
    use std::time::Duration;

    fn live() -> Live {
        let file = SiteFile::parse(
            "name = \"s\"\nextent = [[-10.0, -10.0], [10.0, 10.0]]\n\
             [[sensor]]\nid = \"a\"\nposition = [0.0, 0.0]\nheading_deg = 0.0\n\
             [[sensor]]\nid = \"b\"\nposition = [1.0, 0.0]\nheading_deg = 0.0\n\
             [perimeter]\nrestricted_classes = [\"person\"]\n\
             [[perimeter.zone]]\nname = \"z\"\npolygon = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]]\n",
        )
        .unwrap();
        Live::new(Site::new(file, SiteConfig::default()), 2.0)
    }

    #[test]
    fn a_silent_sensor_raises_one_alert_until_it_is_heard_again() {
        let mut l = live();
        let t0 = l.started;
        let m = |frame| SensorTracks {
            frame,
            time_s: f64::from(frame),
            tracks: Vec::new(),
        };
        l.ingest("a", &m(0), t0 + Duration::from_secs(1));
        assert!(!l.check_silence(t0 + Duration::from_millis(1500)));
        // At 2.5 s, b has never been heard (2.5 s): silent; a was heard 1.5 s ago: not yet.
        assert!(l.check_silence(t0 + Duration::from_millis(2500)));
        let silent: Vec<_> = l
            .alerts
            .iter()
            .map(|a| (a.kind.as_str(), a.sensors[0].as_str()))
            .collect();
        assert_eq!(silent, [("silent", "b")]);
        // Once per silence: nothing new at 2.6 s for b; a goes silent at 3.1 s.
        assert!(!l.check_silence(t0 + Duration::from_millis(2600)));
        assert!(l.check_silence(t0 + Duration::from_millis(3100)));
        assert_eq!(l.alerts.len(), 2);
        // b is heard again, then silent again: a second alert for b.
        l.ingest("b", &m(0), t0 + Duration::from_secs(4));
        assert!(!l.check_silence(t0 + Duration::from_millis(5000)));
        assert!(l.check_silence(t0 + Duration::from_millis(6500)));
        assert_eq!(l.alerts.back().unwrap().sensors, ["b"]);
        // An acknowledgement records who, once.
        let id = l.alerts.back().unwrap().id;
        assert_eq!(
            l.acknowledge(id, "alice", 1.0).unwrap().acked.unwrap().by,
            "alice"
        );
        assert_eq!(
            l.acknowledge(id, "bob", 2.0).unwrap().acked.unwrap().by,
            "alice"
        );
        assert!(l.acknowledge(999, "bob", 2.0).is_none());
    }
}
