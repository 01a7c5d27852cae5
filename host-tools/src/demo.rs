//! `metamoran demo`: the whole system on a built-in scene, no hardware.
//!
//! Simulated radar frames of a watched perimeter stream into the module (the firmware under
//! QEMU when `qemu-system-arm` and the firmware sources are here, else the same `dsp` pipeline
//! in this process, and the report says which). As each frame's results come back over the
//! authenticated telemetry link, the host fuses them with the camera, the perimeter raises
//! alerts, MQTT publishes them and the live view redraws; the final operator view is printed.
//! Everything it makes goes to one folder.

use metamoran_bundle::OpenOptions;
use metamoran_bundle::geometry::CameraModel;
use metamoran_operator::alert_log::AlertLog;
use metamoran_operator::geofence::{Alert, Perimeter};
use metamoran_operator::live::{LiveView, OperatorState, TrackRow};
use metamoran_operator::mqtt::MqttConfig;
use metamoran_operator::outputs::{write, write_outputs};
use metamoran_operator::tracking::TrackerConfig;
use metamoran_operator::watch::Watch;
use metamoran_process::{FrameEvent, Mode, ProcessOptions, Runner, process_streamed};
use metamoran_sim::{layout::Preset, radar::RadarKind};
use serde::Serialize;
use std::fmt;
use std::path::{Path, PathBuf};

/// The built-in scene: a cascade radar watching a perimeter for 11 s, a car parked in the far
/// lot and a person who walks into the gate zone, lingers at its border and leaves.
pub const SCENE: (Preset, RadarKind, u64) = (Preset::Perimeter, RadarKind::Cascade, 3);

/// The built-in perimeter, written to `OUT/perimeter.toml` when none is given.
pub const PERIMETER: &str = r#"# Perimeter for `metamoran demo` (see README, "Geofencing").
restricted_classes = ["person", "car"]
min_confidence_db = 6.0
hysteresis_m = 1.0

[[zone]]
name = "far lot"
polygon = [[-10.0, 30.0], [20.0, 30.0], [20.0, 55.0], [-10.0, 55.0]]

[[zone]]
name = "gate"
polygon = [[-3.0, 8.0], [3.0, 8.0], [3.0, 16.0], [-3.0, 16.0]]
"#;

/// Where the module runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DemoEdge {
    /// QEMU if it is installed and the firmware builds, else in this process.
    #[default]
    Auto,
    /// The firmware under QEMU (an error if it cannot run).
    Qemu,
    /// The `dsp` pipeline in this process.
    InProcess,
}

/// What the demo did and made.
#[derive(Clone, Debug, Serialize)]
pub struct DemoReport {
    /// Output folder.
    pub out: PathBuf,
    /// Where the module ran, in words.
    pub edge: String,
    /// Frames processed.
    pub frames: usize,
    /// The confirmed tracks after the last frame.
    pub tracks: Vec<TrackRow>,
    /// Every alert, in order.
    pub alerts: Vec<Alert>,
    /// Link health from the module (QEMU only): frames and faults it counted.
    pub link: Option<String>,
    /// What went to the MQTT broker, if one was given.
    pub mqtt: Option<String>,
    /// What went to the NATS server, if one was given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nats: Option<String>,
    /// Where the radar samples came from when not the simulated capture: the live stream and
    /// what arrived.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radar: Option<String>,
    /// Frames that could not be processed, and why the run stopped early, if it did.
    pub faults: Option<String>,
    /// Files written, relative to `out`.
    pub files: Vec<String>,
}

impl fmt::Display for DemoReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "metamoran demo: built-in {} scene, {} frames, module {}",
            SCENE.0.name(),
            self.frames,
            self.edge
        )?;
        if let Some(radar) = &self.radar {
            writeln!(f, "radar: {radar}")?;
        }
        writeln!(
            f,
            "\ntracks after the last frame (? = coasting on its prediction):"
        )?;
        writeln!(
            f,
            "\n{:>4}  {:<7} {:>9} {:>8} {:>8}  zones",
            "id", "class", "depth m", "az °", "m/s"
        )?;
        for t in &self.tracks {
            writeln!(
                f,
                "{:>4}  {:<7} {:>9} {:>8.1} {:>8.1}  {}",
                t.id,
                t.class,
                format!("{:.2}{}", t.depth_m, if t.coasting { "?" } else { "" }),
                t.azimuth_deg,
                t.speed_mps,
                if t.zones.is_empty() {
                    "—".into()
                } else {
                    t.zones.join(", ")
                }
            )?;
        }
        writeln!(f, "\nalerts:")?;
        if self.alerts.is_empty() {
            writeln!(f, "  none")?;
        }
        for a in &self.alerts {
            writeln!(
                f,
                "  t={:.1} s frame {}: {:?} {} track {} {} at {:.2} m, {:+.1}°",
                a.time_s, a.frame, a.kind, a.class, a.track, a.zone, a.depth_m, a.azimuth_deg
            )?;
        }
        if let Some(l) = &self.link {
            writeln!(f, "\nlink: {l}")?;
        }
        if let Some(m) = &self.mqtt {
            writeln!(f, "published: {m}")?;
        }
        if let Some(n) = &self.nats {
            writeln!(f, "published: {n}")?;
        }
        if let Some(faults) = &self.faults {
            writeln!(f, "\nfaults (the other frames were processed):\n{faults}")?;
        }
        writeln!(f, "\noutputs in {}:", self.out.display())?;
        for file in &self.files {
            writeln!(f, "  {file}")?;
        }
        Ok(())
    }
}

/// The frames already published, across attempts: with `--edge auto`, when QEMU fails part
/// way, the in-process rerun replays the scene from its first frame; subscribers must not get
/// the frames (and their alerts) a second time. Frames arrive in order.
#[derive(Debug, Default)]
struct Published(std::cell::Cell<u32>);

impl Published {
    /// Whether `frame` is new (and from now on published).
    fn take(&self, frame: u32) -> bool {
        let new = frame >= self.0.get();
        if new {
            self.0.set(frame + 1);
        }
        new
    }
}

/// What the demo shows as each frame arrives: the perimeter's state, the alerts, the MQTT
/// publisher and the live view.
struct Operator<'a> {
    /// The tracker and the zone rules.
    watch: Watch,
    state: OperatorState,
    period_s: f64,
    publisher: Option<&'a metamoran_operator::mqtt::Publisher>,
    /// The site stream, if one was given.
    nats: Option<&'a metamoran_operator::nats::NatsPublisher>,
    published: &'a Published,
    /// `alerts.jsonl`: every alert is on disk before it is published.
    log: &'a std::cell::RefCell<AlertLog>,
    /// Play the frames at the scene's frame rate even without the live view.
    realtime: bool,
    view: Option<&'a mut LiveView>,
    /// When the first frame was sent (the live view paces the frames from it).
    started: std::time::Instant,
}

impl Operator<'_> {
    /// The confirmed tracks, with the zones they are in now.
    fn tracks(&self) -> Vec<TrackRow> {
        self.watch
            .tracks()
            .map(|t| {
                let zones = self.watch.zones_of(t.id).into_iter().map(String::from);
                TrackRow::of(t, zones.collect())
            })
            .collect()
    }

    /// Folds in one frame: zones and alerts, MQTT, the view.
    fn frame(&mut self, e: FrameEvent<'_>) -> Result<(), crate::Error> {
        let f = e.result;
        let time_s = f64::from(f.frame) * self.period_s;
        let alerts = self
            .watch
            .frame(f.frame, time_s, &f.objects)
            .map_err(|e| format!("frame {}: {e}", f.frame))?;
        let tracks = self.tracks();
        // A frame is logged and published once, across the attempts of `--edge auto`.
        let new = self.published.take(f.frame);
        if new {
            for a in &alerts {
                self.log.borrow_mut().append(a)?;
            }
            if let Some(p) = self.publisher {
                p.frame(f);
                for a in &alerts {
                    p.alert(a);
                }
            }
            if let Some(n) = self.nats {
                for a in &alerts {
                    n.alert(a);
                }
            }
        }
        let s = &mut self.state;
        s.frames_seen += 1;
        s.frames = e.of;
        s.time_s = time_s;
        s.alerts.extend(alerts);
        s.link.update(s.frames_seen, e.latency, e.link);
        s.tracks = tracks;
        if let Some(n) = self.nats
            && new
        {
            n.publish(
                "tracks",
                &serde_json::json!({ "frame": f.frame, "time_s": time_s, "tracks": s.tracks }),
            );
            n.publish(
                "health",
                &serde_json::json!({
                    "frame": f.frame,
                    "frames_seen": s.frames_seen,
                    "latency_ms": s.link.latency_ms,
                    "link": s.link,
                }),
            );
        }
        if let Some(view) = self.view.as_deref_mut() {
            view.show(&self.state)?;
        } else if !self.realtime {
            return Ok(());
        }
        // Live, the scene plays at its own frame rate, as a sensor would deliver it.
        let due = self.started + std::time::Duration::from_secs_f64(time_s + self.period_s);
        std::thread::sleep(due.saturating_duration_since(std::time::Instant::now()));
        Ok(())
    }
}

/// How to run the demo.
#[derive(Clone, Debug, Default)]
pub struct DemoOptions {
    /// Where the module runs.
    pub edge: DemoEdge,
    /// The firmware's Cargo workspace, for QEMU (`None`: the module runs in this process).
    pub firmware: Option<PathBuf>,
    /// A perimeter TOML instead of the built-in [`PERIMETER`].
    pub perimeter: Option<PathBuf>,
    /// Also publish to this MQTT broker.
    pub mqtt: Option<MqttConfig>,
    /// Also publish to this NATS server: tracks and health on core NATS, alerts into the
    /// site's JetStream stream.
    pub nats: Option<metamoran_operator::nats::NatsConfig>,
    /// Draw the operator view on this terminal as each frame arrives.
    pub live: bool,
    /// Deliver the frames at the scene's frame rate (as a sensor would) even without the live
    /// view.
    pub realtime: bool,
    /// Take the radar samples from this live DCA1000 stream instead of the simulated capture
    /// (the scene's camera products stay): a board replaying the scene, or
    /// `metamoran dca1000-emulate` sending its `radar.bin`.
    pub dca1000: Option<crate::live::Link>,
    /// Simulate the scene with the camera's instances numbered afresh every frame, as a real
    /// segmenter does; the tracks and alerts must not change.
    pub renumber_instances: bool,
}

/// Runs the demo into `out` (created; its earlier demo files are replaced).
///
/// # Errors
/// A message saying what failed and what to do.
pub fn run(out: &Path, options: &DemoOptions) -> Result<DemoReport, crate::Error> {
    let DemoOptions {
        edge,
        firmware,
        perimeter,
        mqtt,
        nats,
        live,
        realtime,
        dca1000,
        renumber_instances,
    } = options;
    let (edge, perimeter, mqtt, live) = (*edge, perimeter.as_deref(), mqtt.as_ref(), *live);
    let realtime = *realtime;
    std::fs::create_dir_all(out)
        .map_err(|e| format!("{}: cannot create the output folder ({e})", out.display()))?;
    let perimeter = install_perimeter(out, perimeter)?;
    let (preset, _, _) = SCENE;
    let bundle = &simulate_scene(out, *renumber_instances)?;
    let mut opts = OpenOptions::default();
    // Kept while the bundle is read: the recorded stream is removed when dropped.
    let stream = dca1000
        .as_ref()
        .map(|link| link.capture_for(bundle))
        .transpose()?;
    opts.capture = stream.as_ref().map(|s| s.capture.clone());
    // The bundle the module will process: its frame period and camera.
    let scene = metamoran_bundle::Bundle::open(bundle, opts.clone())
        .map_err(|e| e.to_string())?
        .scene;
    let period = scene.radar.frame_period_s;

    let publisher = mqtt
        .map(metamoran_operator::mqtt::Publisher::connect)
        .transpose()?;
    let nats_publisher = nats
        .as_ref()
        .map(metamoran_operator::nats::NatsPublisher::connect)
        .transpose()?;
    let published = Published::default();
    let log = std::cell::RefCell::new(AlertLog::create(&out.join("alerts.jsonl"))?);
    let mut view = if live { Some(LiveView::start()?) } else { None };
    let (runner, words, fallback) = plan(edge, firmware.as_deref())?;
    let mut run_on = |runner: Runner, words: &str| {
        let mut op = Operator {
            watch: Watch::new(perimeter.clone(), TrackerConfig::default()),
            state: OperatorState {
                title: format!(
                    "metamoran demo: built-in {} scene ({} frames)",
                    preset.name(),
                    scene.radar.frames
                ),
                edge: words.to_owned(),
                ..OperatorState::default()
            },
            period_s: period,
            publisher: publisher.as_ref(),
            nats: nats_publisher.as_ref(),
            published: &published,
            log: &log,
            realtime,
            view: view.as_mut(),
            started: std::time::Instant::now(),
        };
        let options = ProcessOptions {
            mode: Mode::Metamoran,
            open: opts.clone(),
            runner,
        };
        let r = process_streamed(bundle, &options, |e| op.frame(e))?;
        if let Some(why) = &r.0.stopped
            && fallback
        {
            return Err(why.clone().into());
        }
        Ok::<_, crate::Error>((r, op.state))
    };
    let ((output, log), state) = match run_on(runner, &words) {
        Ok(r) => r,
        Err(e) if fallback => run_on(
            Runner::InProcess,
            &format!("in this process: QEMU could not run the firmware ({e})"),
        )?,
        Err(e) => return Err(e),
    };
    drop(view);
    let OperatorState {
        edge: edge_words,
        tracks,
        alerts,
        ..
    } = state;
    // Everything is written before the broker is waited for: a broker that is away loses
    // nothing (the alerts are in alerts.jsonl already).
    let files = write_files(
        out,
        &CameraModel::new(&scene.camera),
        &output,
        period,
        &alerts,
    )?;
    let (published, unpublished) = match (mqtt, publisher) {
        (Some(config), Some(publisher)) => {
            let to = format!(
                "mqtt://{}:{} under {}",
                config.host,
                config.port,
                config.topic("#")
            );
            match publisher.close() {
                Ok(stats) => (
                    Some(format!(
                        "{} frame(s) and {} alert(s) to {to} ({} reconnection(s), {} objects \
                         message(s) dropped while the broker was away)",
                        output.frames.len(),
                        alerts.len(),
                        stats.reconnects,
                        stats.objects_dropped
                    )),
                    None,
                ),
                Err(e) => (Some(format!("to {to}: {e}")), Some(e)),
            }
        }
        _ => (None, None),
    };
    let (nats_words, nats_failed) = match (nats, nats_publisher) {
        (Some(config), Some(p)) => {
            let to = format!("{} on {}", config.subject("*"), config.url);
            match p.close(metamoran_operator::nats::CLOSE_TIMEOUT) {
                Ok(st) => (
                    Some(format!(
                        "{} alert(s) stored in JetStream stream {} and tracks and health per                          frame to {to} ({} resend(s), {} message(s) dropped)",
                        st.stored,
                        config.stream(),
                        st.retries,
                        st.dropped
                    )),
                    None,
                ),
                Err(e) => (Some(format!("to {to}: {e}")), Some(e)),
            }
        }
        _ => (None, None),
    };
    let link = log.map(|l| link_words(&l.health));
    let mut report = DemoReport {
        out: out.to_path_buf(),
        edge: edge_words,
        frames: output.frames.len(),
        tracks,
        alerts,
        link,
        mqtt: published,
        nats: nats_words,
        radar: stream.as_ref().zip(dca1000.as_ref()).map(|(s, link)| {
            let at = s.recording.local.unwrap_or(link.addr);
            let (r, a) = (&s.recording, s.recording.counters.assembly);
            format!(
                "DCA1000 stream on {}: {} frame(s) received, {} not whole (skipped); {} \
                 packet(s), {} lost, {} reordered, {} duplicate(s)",
                at,
                r.frames,
                s.capture.incomplete.len(),
                a.packets,
                a.lost(),
                a.reordered,
                a.duplicates
            )
        }),
        faults: output.faults(),
        files,
    };
    report.files.push("operator.txt".into());
    write(&out.join("operator.txt"), report.to_string().as_bytes())?;
    match (unpublished, nats_failed) {
        (Some(e), _) | (None, Some(e)) => Err(e.into()),
        (None, None) => Ok(report),
    }
}

/// Where the module runs for `edge`, in words, and whether a failure there falls back to this
/// process (`--edge auto` with QEMU).
fn plan(edge: DemoEdge, firmware: Option<&Path>) -> Result<(Runner, String, bool), crate::Error> {
    let qemu = firmware
        .map(|firmware| {
            Ok::<_, metamoran_edge::EdgeError>(Runner::Qemu {
                firmware: firmware.to_owned(),
                key_file: metamoran_edge::keys::checkout_key(firmware)?,
            })
        })
        .transpose()?;
    let qemu_words = "firmware under QEMU (mps2-an500, Cortex-M7)".to_owned();
    let here = |why: &str| (Runner::InProcess, format!("in this process{why}"), false);
    Ok(match (edge, qemu) {
        (DemoEdge::InProcess, _) => here(" (--edge in-process)"),
        (DemoEdge::Qemu, Some(q)) => (q, qemu_words, false),
        (DemoEdge::Qemu, None) => {
            return Err(
                "--edge qemu: the firmware sources were not found; give --firmware DIR".into(),
            );
        }
        (DemoEdge::Auto, Some(q)) if metamoran_edge::qemu::available() => (q, qemu_words, true),
        (DemoEdge::Auto, Some(_)) => {
            here(": qemu-system-arm is not installed (apt-get install -y qemu-system-arm)")
        }
        (DemoEdge::Auto, None) => {
            here(": no firmware sources to build (run from a checkout or give --firmware DIR)")
        }
    })
}

/// The perimeter to watch, written to `OUT/perimeter.toml`: the file given (checked, then
/// copied) or the built-in [`PERIMETER`].
fn install_perimeter(out: &Path, given: Option<&Path>) -> Result<Perimeter, crate::Error> {
    let perimeter_file = out.join("perimeter.toml");
    Ok(match given {
        Some(p) => {
            let scene_dir = out.join("scene");
            if let (Ok(file), Ok(replaced)) = (p.canonicalize(), scene_dir.canonicalize())
                && file.starts_with(&replaced)
            {
                return Err(format!(
                    "--perimeter {}: the demo replaces {} on every run; keep the perimeter \
                     elsewhere",
                    p.display(),
                    scene_dir.display()
                )
                .into());
            }
            let (loaded, text) = Perimeter::load_text(p)?;
            // Written from what was read, atomically: `--perimeter OUT/perimeter.toml` reads
            // the file and puts the same bytes back.
            write(&perimeter_file, text.as_bytes())?;
            loaded
        }
        None => {
            write(&perimeter_file, PERIMETER.as_bytes())?;
            Perimeter::parse(PERIMETER)?
        }
    })
}

/// Simulates the built-in [`SCENE`] afresh into `OUT/scene/`; returns its bundle folder.
fn simulate_scene(out: &Path, renumber: bool) -> Result<PathBuf, crate::Error> {
    let scenes = out.join("scene");
    if scenes.exists() {
        std::fs::remove_dir_all(&scenes)
            .map_err(|e| format!("{}: cannot replace ({e})", scenes.display()))?;
    }
    let (preset, radar, seed) = SCENE;
    let variant = metamoran_sim::Variant {
        renumber,
        ..Default::default()
    };
    let dirs = metamoran_sim::simulate_with(preset, radar, variant, seed, 1, &scenes, &|| ())?;
    Ok(dirs
        .into_iter()
        .next()
        .ok_or("the simulator wrote no scene")?)
}

/// Writes the run's files into `out` (see [`write_outputs`]); returns their names, with the
/// perimeter, the scene and `alerts.jsonl` written before.
fn write_files(
    out: &Path,
    camera: &CameraModel,
    output: &metamoran_process::ProcessOutput,
    period_s: f64,
    alerts: &[Alert],
) -> Result<Vec<String>, crate::Error> {
    let mut files = vec!["perimeter.toml".to_owned(), "scene/".to_owned()];
    files.extend(write_outputs(out, camera, output, period_s, alerts)?);
    // Appended and synced alert by alert as the run went (AlertLog).
    files.push("alerts.jsonl".into());
    Ok(files)
}

/// The module's health counters in words, for the report.
fn link_words(h: &metamoran_dsp::wire::Health) -> String {
    format!(
        "module counted {} frames; its link accepted {}, rejected {} bad tags and {} replays, \
         saw {} lost and {} reordered frames; {} capture, {} pipeline, {} protocol errors; \
         {} queued messages dropped; stack high-water {} B",
        h.frames,
        h.link.accepted,
        h.link.bad_tag,
        h.link.replayed,
        h.link.lost,
        h.link.reordered,
        h.capture_errors,
        h.pipeline_errors,
        h.protocol_errors,
        h.queue_dropped,
        h.stack_bytes
    )
}

#[cfg(test)]
mod tests {
    use super::Published;

    #[test]
    fn a_rerun_publishes_only_the_frames_the_failed_run_did_not() {
        let published = Published::default();
        // QEMU delivers frames 0..=2, then fails; the in-process rerun replays 0..=4.
        let first: Vec<bool> = (0..3).map(|f| published.take(f)).collect();
        let rerun: Vec<u32> = (0..5).filter(|&f| published.take(f)).collect();
        assert_eq!(first, [true; 3]);
        assert_eq!(rerun, [3, 4]);
    }
}
