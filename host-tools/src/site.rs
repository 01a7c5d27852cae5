//! `metamoran site`: a whole site in one process, no hardware. Each pole's bundle (as
//! `simulate --preset site` writes them beside `site.toml`) is processed as its sensor would,
//! tracked in the sensor's frame, and its tracks fused by the site process frame by frame:
//! site tracks, zone alerts with the sensors that saw each object, per-sensor health.

use metamoran_operator::live::TrackRow;
use metamoran_operator::site::{
    SensorHealth, SensorTracks, Site, SiteAlert, SiteConfig, SiteFile, SiteMessages, SiteTrack,
};
use metamoran_operator::tracking::{Detection, Tracker, TrackerConfig};
use metamoran_process::{Mode, ProcessOptions, process};
use serde::Serialize;
use std::fmt;
use std::path::{Path, PathBuf};

/// What a site run did.
#[derive(Clone, Debug, Serialize)]
pub struct SiteReport {
    /// The site folder.
    pub dir: PathBuf,
    /// Site name.
    pub site: String,
    /// Frames per sensor.
    pub frames: usize,
    /// The site tracks after each frame.
    pub tracks: Vec<Vec<SiteTrack>>,
    /// Every site alert, in order.
    pub alerts: Vec<SiteAlert>,
    /// Each sensor's health.
    pub health: Vec<(String, SensorHealth)>,
}

impl fmt::Display for SiteReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "metamoran site {}: {} sensor(s), {} frames",
            self.site,
            self.health.len(),
            self.frames
        )?;
        writeln!(f, "\nsite tracks after the last frame:")?;
        for t in self.tracks.last().into_iter().flatten() {
            writeln!(
                f,
                "  {:>4} {:<7} at [{:>6.2}, {:>6.2}] m, {:.1} m/s, seen by {}",
                t.id,
                t.class,
                t.position_m[0],
                t.position_m[1],
                t.velocity_mps[0].hypot(t.velocity_mps[1]),
                t.sensors.join(", ")
            )?;
        }
        writeln!(f, "\nalerts:")?;
        if self.alerts.is_empty() {
            writeln!(f, "  none")?;
        }
        for a in &self.alerts {
            let x = &a.alert;
            writeln!(
                f,
                "  t={:.2} s: {:?} {} site track {} {} at [{:.2}, {:.2}] m, seen by {}",
                x.time_s,
                x.kind,
                x.class,
                x.track,
                x.zone,
                x.position_m[0],
                x.position_m[1],
                a.sensors.join(", ")
            )?;
        }
        writeln!(f, "\nsensor health:")?;
        for (id, h) in &self.health {
            writeln!(
                f,
                "  {id}: {} message(s) taken, {} refused{}",
                h.accepted,
                h.rejected,
                h.last_problem
                    .as_deref()
                    .map_or(String::new(), |p| format!(" (last: {p})"))
            )?;
        }
        Ok(())
    }
}

/// One sensor's confirmed tracks after each frame of its bundle (the Metamoran estimates,
/// tracked in its own ground frame).
///
/// # Errors
/// The bundle cannot be processed.
pub fn sensor_tracks(bundle: &Path) -> Result<Vec<SensorTracks>, crate::Error> {
    let out = process(bundle, &ProcessOptions::mode(Mode::Metamoran))?;
    let period = metamoran_bundle::Bundle::open(bundle, Default::default())
        .map_err(|e| e.to_string())?
        .scene
        .radar
        .frame_period_s;
    let mut tracker = Tracker::new(TrackerConfig::default());
    let mut messages = Vec::with_capacity(out.frames.len());
    for result in &out.frames {
        let time_s = f64::from(result.frame) * period;
        let (instances, detections): (Vec<u16>, Vec<Detection>) = result
            .objects
            .iter()
            .filter_map(|o| Detection::from_estimate(o).map(|d| (o.instance, d)))
            .unzip();
        tracker
            .update(time_s, &detections)
            .map_err(|e| format!("{}: frame {}: {e}", bundle.display(), result.frame))?;
        let row = |t: &metamoran_operator::tracking::Track| TrackRow {
            instance: t.detection.and_then(|j| instances.get(j).copied()),
            ..TrackRow::of(t, Vec::new())
        };
        messages.push(SensorTracks {
            frame: result.frame,
            time_s,
            tracks: tracker.confirmed().map(row).collect(),
        });
    }
    Ok(messages)
}

/// Runs the site in `dir` (`site.toml` and a bundle folder per sensor id).
///
/// # Errors
/// A bad site file, or a sensor's bundle that cannot be processed.
pub fn run(dir: &Path) -> Result<SiteReport, crate::Error> {
    let file = SiteFile::load(&dir.join("site.toml"))?;
    let (sensors, _) = replay_messages(dir, &file)?;
    let frames = sensors.iter().map(|s| s.1.len()).max().unwrap_or(0);
    let mut site = Site::new(file, SiteConfig::default());
    let (mut tracks, mut alerts) = (Vec::with_capacity(frames), Vec::new());
    for f in 0..frames {
        for (id, messages) in &sensors {
            if let Some(m) = messages.get(f) {
                // A refused message is counted in the sensor's health; the run goes on.
                if let Ok(a) = site.ingest(id, m) {
                    alerts.extend(a);
                }
            }
        }
        tracks.push(site.tracks());
    }
    Ok(SiteReport {
        dir: dir.to_owned(),
        site: site.file().name.clone(),
        frames,
        tracks,
        alerts,
        health: site
            .health()
            .map(|(id, h)| (id.to_owned(), h.clone()))
            .collect(),
    })
}

/// Each sensor's messages of the simulated site in `dir` (a bundle folder per sensor of
/// `file`), and the frame period, for a real-time replay.
///
/// # Errors
/// A sensor's bundle that cannot be processed.
pub fn replay_messages(dir: &Path, file: &SiteFile) -> Result<(SiteMessages, f64), crate::Error> {
    let sensors: SiteMessages = file
        .sensors
        .iter()
        .map(|s| Ok((s.id.clone(), sensor_tracks(&dir.join(&s.id))?)))
        .collect::<Result<_, crate::Error>>()?;
    let period = file
        .sensors
        .first()
        .and_then(|s| metamoran_bundle::Bundle::open(&dir.join(&s.id), Default::default()).ok())
        .map_or(0.25, |b| b.scene.radar.frame_period_s);
    Ok((sensors, period))
}

/// Plays the site in `dir` as its sensors would: each sensor's tracks and health published to
/// the NATS server of `server(sensor)` at the bundles' frame rate, `laps` times over (0: until
/// stopped), frame numbers and times going on across laps. The site process (`serve --nats`)
/// fuses them.
///
/// # Errors
/// A bad site file or bundle, or a server that refuses a sensor.
pub fn publish_sensors(
    dir: &Path,
    server: &dyn Fn(&str, &str) -> Result<metamoran_operator::nats::NatsConfig, crate::Error>,
    laps: u32,
) -> Result<u64, crate::Error> {
    let file = SiteFile::load(&dir.join("site.toml"))?;
    let (sensors, period) = replay_messages(dir, &file)?;
    let publishers: Vec<_> = sensors
        .iter()
        .map(|(id, _)| {
            let config = server(&file.name, id)?;
            Ok(metamoran_operator::nats::NatsPublisher::connect(&config)?)
        })
        .collect::<Result<_, crate::Error>>()?;
    let frames = sensors.iter().map(|s| s.1.len()).max().unwrap_or(0);
    let start = std::time::Instant::now();
    let mut sent = 0u64;
    for lap in (0..).take_while(|&l| laps == 0 || l < laps) {
        for f in 0..frames {
            let k = u64::from(lap) * frames as u64 + f as u64;
            let due = start + std::time::Duration::from_secs_f64(k as f64 * period);
            std::thread::sleep(due.saturating_duration_since(std::time::Instant::now()));
            for ((_, messages), p) in sensors.iter().zip(&publishers) {
                let Some(m) = messages.get(f) else { continue };
                let m = SensorTracks {
                    frame: m.frame + lap * frames as u32,
                    time_s: m.time_s + f64::from(lap) * frames as f64 * period,
                    tracks: m.tracks.clone(),
                };
                p.publish("tracks", &serde_json::to_value(&m)?);
                p.publish(
                    "health",
                    &serde_json::json!({ "frame": m.frame, "time_s": m.time_s }),
                );
                sent += 1;
            }
        }
    }
    for p in publishers {
        p.close(metamoran_operator::nats::CLOSE_TIMEOUT)?;
    }
    Ok(sent)
}
