//! Perimeter alerts (Metamoran's application), the last step of the fusion stage: the
//! [`Perimeter`]'s zone rules run on the tracker's confirmed tracks ([`Sighting`]s), so an alert
//! follows one object however the camera numbers its instances.
//!
//! ```text
//! estimates ─▶ tracking::Tracker ─▶ confirmed tracks ─▶ Geofence::update ─▶ alerts
//! ```
//!
//! Rules, per track and zone, for restricted classes (the track's class vote):
//! - **enter** when a measured position is inside the polygon; **exit** only when a measured
//!   position is more than `hysteresis_m` outside it (a Schmitt trigger on the signed distance to
//!   the boundary), so an object on the border does not flap. A frame in which the track only
//!   coasts on its prediction changes neither.
//! - **dwell** once per stay, when the track has been inside for longer than the zone's
//!   `dwell_s` (loitering).
//! - **approach** when the track, outside the zone and within `approach_within_m` of it, closes
//!   in on its nearest boundary point faster than `approach_mps`; raised again only after the
//!   closing speed fell below half the threshold or the track entered.
//! - **lost** when a track inside the zone is deleted (no detection for the tracker's
//!   confirmed-miss count): where it went is unknown, so the operator is told.

mod perimeter;

pub use perimeter::{
    DEFAULT_APPROACH_WITHIN_M, MIN_ZONE_AREA_M2, Perimeter, Zone, nearest_on_boundary,
    signed_distance,
};

use serde::Serialize;
use std::collections::BTreeMap;

/// What an alert says happened.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AlertKind {
    /// A restricted object entered the zone.
    Enter,
    /// It left (more than the hysteresis outside).
    Exit,
    /// It has been inside for longer than the zone's `dwell_s`.
    Dwell,
    /// It is closing in on the zone faster than the zone's `approach_mps`.
    Approach,
    /// Its track was deleted while inside: it is no longer seen.
    Lost,
}

/// One alert.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Alert {
    /// What happened.
    pub kind: AlertKind,
    /// Zone name.
    pub zone: String,
    /// Track id (stable across frames).
    pub track: u32,
    /// The camera's instance id of the detection the track took in this frame (`None`: it
    /// coasted, or was lost); it indexes this frame's `results.json` objects.
    pub instance: Option<u16>,
    /// Class (the track's vote).
    pub class: String,
    /// Range of the track from the sensor, m.
    pub depth_m: f64,
    /// Azimuth of the track, degrees.
    pub azimuth_deg: f64,
    /// Ground position `[x, z]`, m.
    pub position_m: [f64; 2],
    /// Ground velocity `[vx, vz]`, m/s.
    pub velocity_mps: [f64; 2],
    /// Speed towards the zone, m/s (`approach` alerts).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closing_mps: Option<f64>,
    /// Time inside the zone, s (`dwell` alerts).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inside_s: Option<f64>,
    /// Frame number.
    pub frame: u32,
    /// Time of the frame, s from the start.
    pub time_s: f64,
}

/// One confirmed track in one frame, as the geofence needs it.
#[derive(Clone, Debug, PartialEq)]
pub struct Sighting {
    /// Track id.
    pub track: u32,
    /// Class (the track's vote).
    pub class: String,
    /// Ground position `[x, z]`, m.
    pub position_m: [f64; 2],
    /// Ground velocity, m/s.
    pub velocity_mps: [f64; 2],
    /// The camera instance of this frame's detection, where there is one camera.
    pub instance: Option<u16>,
    /// Whether the position was measured this frame; a coasting prediction moves no zone
    /// state.
    pub measured: bool,
}

impl Sighting {
    /// A confirmed track's sighting; `instance` is that of the detection it took, if any.
    pub fn of(track: &crate::tracking::Track, instance: Option<u16>) -> Self {
        Self {
            track: track.id,
            class: track.class.clone(),
            position_m: track.position_m,
            velocity_mps: track.velocity_mps,
            instance: track.detection.and(instance),
            measured: track.detection.is_some(),
        }
    }

    /// The alert of `kind` in `zone` this sighting raises at `frame`, `time_s`.
    fn alert(&self, kind: AlertKind, zone: &str, frame: u32, time_s: f64) -> Alert {
        let [x, z] = self.position_m;
        Alert {
            kind,
            zone: zone.to_owned(),
            track: self.track,
            instance: self.instance,
            class: self.class.clone(),
            depth_m: x.hypot(z),
            azimuth_deg: x.atan2(z).to_degrees(),
            position_m: self.position_m,
            velocity_mps: self.velocity_mps,
            closing_mps: None,
            inside_s: None,
            frame,
            time_s,
        }
    }
}

/// One track's state in one zone.
#[derive(Clone, Copy, Debug, Default)]
struct InZone {
    /// Inside (with hysteresis).
    inside: bool,
    /// When it entered, s.
    since_s: f64,
    /// The dwell alert of this stay was raised.
    dwelled: bool,
    /// An approach alert was raised and not yet re-armed.
    approaching: bool,
}

/// Zone state of every track over time.
#[derive(Clone, Debug)]
pub struct Geofence {
    perimeter: Perimeter,
    /// `(track, zone index)` → state.
    state: BTreeMap<(u32, usize), InZone>,
    /// The last sighting of each track with state, for `lost` alerts.
    last: BTreeMap<u32, Sighting>,
}

impl Geofence {
    /// Every track outside every zone.
    pub fn new(perimeter: Perimeter) -> Self {
        Self {
            perimeter,
            state: BTreeMap::new(),
            last: BTreeMap::new(),
        }
    }

    /// The configuration.
    pub fn perimeter(&self) -> &Perimeter {
        &self.perimeter
    }

    /// Names of the zones `track` is in now.
    pub fn zones_of(&self, track: u32) -> Vec<&str> {
        self.perimeter
            .zones
            .iter()
            .enumerate()
            .filter(|(z, _)| self.state.get(&(track, *z)).is_some_and(|s| s.inside))
            .map(|(_, zone)| zone.name.as_str())
            .collect()
    }

    /// Forgets `track` without a `lost` alert: it did not vanish, it became another track
    /// (the site merging two tracks of one object).
    pub fn forget(&mut self, track: u32) {
        self.last.remove(&track);
        self.state.retain(|(t, _), _| *t != track);
    }

    /// Updates the state with one frame's confirmed tracks and returns the alerts it raises:
    /// `lost` first, then by track and zone. A track with state that is not among `sightings`
    /// was deleted. O(tracks × zones × vertices).
    ///
    /// # Example
    /// A person track 12 m straight ahead, inside the gate zone, raises one `Enter` alert:
    /// ```
    /// use metamoran_operator::geofence::{AlertKind, Geofence, Perimeter, Sighting};
    ///
    /// let perimeter = Perimeter::parse(
    ///     r#"
    ///     restricted_classes = ["person"]
    ///     [[zone]]
    ///     name = "gate"
    ///     polygon = [[-3.0, 8.0], [3.0, 8.0], [3.0, 16.0], [-3.0, 16.0]]
    ///     "#,
    /// )?;
    /// let mut fence = Geofence::new(perimeter);
    /// let person = Sighting {
    ///     track: 7,
    ///     class: "person".into(),
    ///     position_m: [0.0, 12.0],
    ///     velocity_mps: [0.0, 0.0],
    ///     instance: Some(4),
    ///     measured: true,
    /// };
    /// let alerts = fence.update(0, 0.0, &[person.clone()]);
    /// assert_eq!(alerts.len(), 1);
    /// assert_eq!((alerts[0].kind, alerts[0].zone.as_str(), alerts[0].track), (AlertKind::Enter, "gate", 7));
    /// assert!(fence.update(1, 0.5, &[person]).is_empty(), "still inside: no new alert");
    /// # Ok::<(), metamoran_operator::OperatorError>(())
    /// ```
    pub fn update(&mut self, frame: u32, time_s: f64, sightings: &[Sighting]) -> Vec<Alert> {
        let mut out = Vec::new();
        self.lose_deleted(frame, time_s, sightings, &mut out);
        for s in sightings {
            if !self.perimeter.restricted_classes.contains(&s.class) {
                continue;
            }
            for (z, zone) in self.perimeter.zones.iter().enumerate() {
                let alert = |kind| s.alert(kind, &zone.name, frame, time_s);
                let (nearest, inside) = nearest_on_boundary(&zone.polygon, s.position_m);
                let (dx, dz) = (nearest[0] - s.position_m[0], nearest[1] - s.position_m[1]);
                let distance = dx.hypot(dz);
                let signed = if inside { distance } else { -distance };
                let st = self.state.entry((s.track, z)).or_default();
                if s.measured {
                    match (st.inside, signed) {
                        (false, d) if d >= 0.0 => {
                            *st = InZone {
                                inside: true,
                                since_s: time_s,
                                dwelled: false,
                                approaching: false,
                            };
                            out.push(alert(AlertKind::Enter));
                        }
                        (true, d) if d < -self.perimeter.hysteresis_m => {
                            st.inside = false;
                            out.push(alert(AlertKind::Exit));
                        }
                        _ => {}
                    }
                }
                if let Some(limit) = zone.dwell_s
                    && st.inside
                    && !st.dwelled
                    && time_s - st.since_s > limit
                {
                    st.dwelled = true;
                    out.push(Alert {
                        inside_s: Some(time_s - st.since_s),
                        ..alert(AlertKind::Dwell)
                    });
                }
                if let Some(limit) = zone.approach_mps
                    && s.measured
                    && !st.inside
                {
                    let closing = if distance > 0.0 {
                        (s.velocity_mps[0] * dx + s.velocity_mps[1] * dz) / distance
                    } else {
                        0.0
                    };
                    if closing < limit / 2.0 {
                        st.approaching = false;
                    } else if closing > limit
                        && !st.approaching
                        && distance <= zone.approach_within_m()
                    {
                        st.approaching = true;
                        out.push(Alert {
                            closing_mps: Some(closing),
                            ..alert(AlertKind::Approach)
                        });
                    }
                }
            }
            self.last.insert(s.track, s.clone());
        }
        out
    }

    /// `lost` alerts for the tracks with state that are gone from `sightings`; forgets them.
    fn lose_deleted(
        &mut self,
        frame: u32,
        time_s: f64,
        sightings: &[Sighting],
        out: &mut Vec<Alert>,
    ) {
        let gone: Vec<u32> = self
            .last
            .keys()
            .copied()
            .filter(|id| sightings.iter().all(|s| s.track != *id))
            .collect();
        for id in gone {
            let Some(s) = self.last.remove(&id) else {
                continue;
            };
            for (z, zone) in self.perimeter.zones.iter().enumerate() {
                if self.state.remove(&(id, z)).is_some_and(|st| st.inside) {
                    out.push(Alert {
                        instance: None,
                        ..s.alert(AlertKind::Lost, &zone.name, frame, time_s)
                    });
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(track: u32, class: &str, x: f64, z: f64) -> Sighting {
        Sighting {
            track,
            class: class.into(),
            position_m: [x, z],
            velocity_mps: [0.0; 2],
            instance: Some(1),
            measured: true,
        }
    }

    fn perimeter(extra: &str) -> Perimeter {
        Perimeter::parse(&format!(
            "restricted_classes = [\"person\"]\nhysteresis_m = 1.0\n\
             [[zone]]\nname = \"yard\"\npolygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]\n{extra}",
        ))
        .unwrap()
    }

    fn kinds(alerts: &[Alert]) -> Vec<(AlertKind, u32)> {
        alerts.iter().map(|a| (a.kind, a.frame)).collect()
    }

    #[test]
    fn hysteresis_keeps_a_border_object_from_flapping() {
        let mut g = Geofence::new(perimeter(""));
        // A person walking along x = 10 ± 0.5 m (the border) for 20 frames, then away.
        let mut alerts = Vec::new();
        for f in 0..25u32 {
            let x = if f < 20 {
                10.0 + if f % 2 == 0 { -0.5 } else { 0.5 }
            } else {
                12.0
            };
            alerts.extend(g.update(f, f64::from(f) * 0.1, &[at(3, "person", x, 5.0)]));
        }
        assert_eq!(
            kinds(&alerts),
            vec![(AlertKind::Enter, 0), (AlertKind::Exit, 20)]
        );
        assert_eq!((alerts[0].zone.as_str(), alerts[0].track), ("yard", 3));
        assert!((alerts[0].position_m[0] - 9.5).abs() < 1e-9);
        assert!((alerts[0].depth_m - 9.5f64.hypot(5.0)).abs() < 1e-12);
        assert!(g.zones_of(3).is_empty());
    }

    #[test]
    fn classes_and_coasting_frames() {
        let mut g = Geofence::new(perimeter(""));
        // A car (not restricted) raises nothing.
        assert!(g.update(0, 0.0, &[at(1, "car", 5.0, 5.0)]).is_empty());
        assert_eq!(g.update(1, 0.1, &[at(2, "person", 5.0, 5.0)]).len(), 1);
        // A frame where the track coasts on its prediction keeps it inside, wherever the
        // prediction is.
        let mut coasting = at(2, "person", 50.0, 50.0);
        coasting.measured = false;
        assert!(g.update(2, 0.2, &[coasting]).is_empty());
        assert_eq!(g.zones_of(2), vec!["yard"]);
    }

    #[test]
    fn a_loiterer_raises_one_dwell_alert_per_stay() {
        let mut g = Geofence::new(perimeter("dwell_s = 2.0\n"));
        let mut alerts = Vec::new();
        // Inside from t = 0 to 4 s, out at 4.5 s (2 m outside), back in at 5 s until 8 s.
        for f in 0..=16u32 {
            let t = f64::from(f) * 0.5;
            let x = if f == 9 { 12.0 } else { 5.0 };
            alerts.extend(g.update(f, t, &[at(4, "person", x, 5.0)]));
        }
        assert_eq!(
            kinds(&alerts),
            vec![
                (AlertKind::Enter, 0),
                // Inside 2.5 s > 2 s at frame 5 (t = 2.5 s).
                (AlertKind::Dwell, 5),
                (AlertKind::Exit, 9),
                (AlertKind::Enter, 10),
                (AlertKind::Dwell, 15),
            ]
        );
        assert_eq!(alerts[1].inside_s, Some(2.5));
    }

    #[test]
    fn an_approach_is_the_speed_towards_the_nearest_boundary_point() {
        let mut g = Geofence::new(perimeter("approach_mps = 3.0\napproach_within_m = 20.0\n"));
        let walk = |track, x: f64, z: f64, vx: f64, vz: f64| Sighting {
            velocity_mps: [vx, vz],
            ..at(track, "person", x, z)
        };
        // 25 m out to the right (beyond 20 m) at 4 m/s towards the zone: not yet.
        assert!(
            g.update(0, 0.0, &[walk(1, 35.0, 5.0, -4.0, 0.0)])
                .is_empty()
        );
        // 15 m out, 4 m/s: closing at 4 m/s > 3.
        let a = g.update(1, 1.0, &[walk(1, 25.0, 5.0, -4.0, 0.0)]);
        assert_eq!(kinds(&a), vec![(AlertKind::Approach, 1)]);
        assert!((a[0].closing_mps.unwrap() - 4.0).abs() < 1e-12);
        // Still closing: no second alert; slowing to 1 m/s re-arms it, then 5 m/s raises again.
        assert!(
            g.update(2, 2.0, &[walk(1, 21.0, 5.0, -4.0, 0.0)])
                .is_empty()
        );
        assert!(
            g.update(3, 3.0, &[walk(1, 20.0, 5.0, -1.0, 0.0)])
                .is_empty()
        );
        assert_eq!(g.update(4, 4.0, &[walk(1, 15.0, 5.0, -5.0, 0.0)]).len(), 1);
        // Fast but tangential (along the zone's side, 3 m out): closing speed 0, nothing.
        assert!(g.update(0, 0.0, &[walk(2, 13.0, 5.0, 0.0, 9.0)]).is_empty());
        // Diagonal towards the corner (10, 10) from (13, 14): the speed along the line to it.
        let a = g.update(1, 1.0, &[walk(3, 13.0, 14.0, -3.0, -4.0)]);
        assert_eq!(kinds(&a), vec![(AlertKind::Approach, 1)]);
        assert!((a[0].closing_mps.unwrap() - 5.0).abs() < 1e-12);
    }

    #[test]
    fn a_track_deleted_inside_a_zone_is_reported_lost() {
        let mut g = Geofence::new(perimeter(""));
        assert_eq!(
            g.update(
                0,
                0.0,
                &[at(5, "person", 5.0, 5.0), at(6, "person", 20.0, 5.0)]
            )
            .len(),
            1
        );
        // Track 5 gone: lost in the yard; track 6 (outside everything) goes silently.
        let a = g.update(1, 0.5, &[]);
        assert_eq!(kinds(&a), vec![(AlertKind::Lost, 1)]);
        assert_eq!((a[0].track, a[0].instance), (5, None));
        assert!(g.update(2, 1.0, &[]).is_empty());
    }

    /// Two zones, overlapping: a track is in both, then only in the second, and each zone's
    /// alerts name that zone.
    #[test]
    fn each_zone_keeps_its_own_state() {
        let p = Perimeter::parse(
            "restricted_classes = [\"car\"]\nhysteresis_m = 0.5\n\
             [[zone]]\nname = \"near\"\npolygon = [[-5.0, 0.0], [5.0, 0.0], [5.0, 10.0], [-5.0, 10.0]]\n\
             [[zone]]\nname = \"far\"\npolygon = [[-5.0, 8.0], [5.0, 8.0], [5.0, 20.0], [-5.0, 20.0]]\n",
        )
        .unwrap();
        let mut g = Geofence::new(p);
        let names = |a: &[Alert]| {
            a.iter()
                .map(|a| (a.kind, a.zone.clone()))
                .collect::<Vec<_>>()
        };
        let a = g.update(0, 0.0, &[at(1, "car", 0.0, 9.0)]);
        assert_eq!(
            names(&a),
            [
                (AlertKind::Enter, "near".into()),
                (AlertKind::Enter, "far".into())
            ]
        );
        assert_eq!(g.zones_of(1), vec!["near", "far"]);
        let a = g.update(1, 0.1, &[at(1, "car", 0.0, 15.0)]);
        assert_eq!(names(&a), [(AlertKind::Exit, "near".into())]);
        assert_eq!(g.zones_of(1), vec!["far"]);
        // Another track has its own state.
        let a = g.update(2, 0.2, &[at(1, "car", 0.0, 15.0), at(2, "car", 0.0, 5.0)]);
        assert_eq!(names(&a), [(AlertKind::Enter, "near".into())]);
    }
}
