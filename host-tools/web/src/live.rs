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
