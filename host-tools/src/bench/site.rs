//! `metamoran bench site`: the site stream under load (issue #20 part 3). N simulated sensors
//! publish their tracks at a frame rate and an alert a second each through one `nats-server`
//! (started here on a free loopback port, JetStream on file, a login) to one site process
//! (`metamoran serve --nats`, in this process); a page client reads the server-sent events.
//! Measured: track messages and alerts per second, and each frame's latency from its publish to
//! the first page update that shows it, against the frame period.

use metamoran_operator::live::TrackRow;
use metamoran_operator::nats::{NatsConfig, NatsPublisher};
use metamoran_operator::site::SensorTracks;
use serde::Serialize;
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// What the run measured.
#[derive(Clone, Debug, Serialize)]
pub struct SiteBench {
    /// Sensors.
    pub sensors: usize,
    /// Frames per second per sensor.
    pub rate_hz: f64,
    /// Seconds published.
    pub seconds: f64,
    /// Track messages published, and per second.
    pub track_messages: u64,
    /// Track messages per second through the server.
    pub track_messages_per_s: f64,
    /// Alerts the stream acknowledged as stored, and per second.
    pub alerts_stored: u64,
    /// Alerts per second stored.
    pub alerts_per_s: f64,
    /// Alerts queued but not stored.
    pub alerts_lost: u64,
    /// Frames the page never showed.
    pub frames_unseen: u64,
    /// Publish → page latency, ms: median, 99th percentile, largest.
    pub latency_ms: [f64; 3],
    /// The 99th percentile over the frame period.
    pub p99_over_period: f64,
}

impl std::fmt::Display for SiteBench {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "site stream: {} sensors at {} Hz for {} s through one nats-server and one site process",
            self.sensors, self.rate_hz, self.seconds
        )?;
        writeln!(
            f,
            "  track messages: {} ({:.0}/s); alerts stored: {} ({:.1}/s), {} not stored",
            self.track_messages,
            self.track_messages_per_s,
            self.alerts_stored,
            self.alerts_per_s,
            self.alerts_lost
        )?;
        let [p50, p99, max] = self.latency_ms;
        writeln!(
            f,
            "  frame → page latency: median {p50:.1} ms, p99 {p99:.1} ms, max {max:.1} ms; p99 = {:.2}× the frame period; {} frame(s) never shown",
            self.p99_over_period, self.frames_unseen
        )
    }
}

fn free_port() -> Result<u16, crate::Error> {
    Ok(std::net::TcpListener::bind("127.0.0.1:0")?
        .local_addr()?
        .port())
}

/// The benchmark's site file: `n` poles on a 150 m ring facing its centre, one zone there.
fn site_toml(n: usize) -> String {
    let mut t = String::from("name = \"bench\"\nextent = [[-200.0, -200.0], [200.0, 200.0]]\n");
    for k in 0..n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        t.push_str(&format!(
            "[[sensor]]\nid = \"s{k}\"\nposition = [{:.3}, {:.3}]\nheading_deg = {:.3}\n",
            150.0 * a.sin(),
            150.0 * a.cos(),
            (a.to_degrees() + 180.0) % 360.0
        ));
    }
    t.push_str(
        "[perimeter]\nrestricted_classes = [\"person\", \"car\"]\n[[perimeter.zone]]\nname = \"centre\"\npolygon = [[-20.0, -20.0], [20.0, -20.0], [20.0, 20.0], [-20.0, 20.0]]\n",
    );
    t
}

fn row(id: u32, x: f64, z: f64) -> TrackRow {
    TrackRow {
        id,
        class: "person".into(),
        depth_m: x.hypot(z),
        azimuth_deg: x.atan2(z).to_degrees(),
        speed_mps: 1.4,
        position_m: [x, z],
        velocity_mps: [1.4, 0.0],
        coasting: false,
        instance: None,
        zones: Vec::new(),
    }
}

/// An HTTP request to `addr`; the stream after the request was written.
fn request(addr: SocketAddr, head: &str, body: &str) -> Result<std::net::TcpStream, crate::Error> {
    let mut s = std::net::TcpStream::connect(addr)?;
    write!(
        s,
        "{head}\r\nHost: {addr}\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )?;
    Ok(s)
}

/// Runs the benchmark.
///
/// # Errors
/// No `nats-server`, or a server that cannot start.
pub fn run(sensors: usize, rate_hz: f64, seconds: f64) -> Result<SiteBench, crate::Error> {
    let exe = ["/usr/sbin/nats-server", "/usr/bin/nats-server"]
        .into_iter()
        .find(|p| std::path::Path::new(p).exists())
        .ok_or("bench site: nats-server not found (apt-get install nats-server)")?;
    if sensors == 0 || !(rate_hz > 0.0 && seconds > 0.0) {
        return Err("bench site: give --sensors ≥ 1, --rate-hz > 0 and --seconds > 0".into());
    }
    let dir = tempfile::tempdir()?;
    let port = free_port()?;
    let secret = format!(
        "{:x}",
        Instant::now().elapsed().as_nanos() ^ u128::from(std::process::id()) << 64
    );
    let conf = dir.path().join("nats.conf");
    std::fs::write(
        &conf,
        format!(
            "listen: 127.0.0.1:{port}\njetstream {{ store_dir: \"{}\" }}\nauthorization {{ users: [ {{ user: bench, password: \"{secret}\" }} ] }}\n",
            dir.path().join("store").display()
        ),
    )?;
    let mut server = std::process::Command::new(exe)
        .arg("-c")
        .arg(&conf)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()?;
    let result = (|| {
        let deadline = Instant::now() + Duration::from_secs(10);
        while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
            if Instant::now() > deadline {
                return Err(crate::Error::from("bench site: nats-server did not start"));
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let config = |sensor: &str| -> Result<NatsConfig, crate::Error> {
            let mut c = NatsConfig::new(&format!("nats://127.0.0.1:{port}"), "bench", sensor)?;
            c.login = Some(metamoran_operator::mqtt::MqttLogin::new(
                "bench",
                secret.clone(),
            ));
            Ok(c)
        };
        measure(sensors, rate_hz, seconds, &config)
    })();
    let _ = server.kill();
    let _ = server.wait();
    result
}

fn measure(
    sensors: usize,
    rate_hz: f64,
    seconds: f64,
    config: &dyn Fn(&str) -> Result<NatsConfig, crate::Error>,
) -> Result<SiteBench, crate::Error> {
    let site = metamoran_operator::site::SiteFile::parse(&site_toml(sensors))?;
    let password = "bench-operator";
    let users = metamoran_web::login::Users::parse(&format!(
        "bench:{}",
        metamoran_web::login::hash_password(password).map_err(|e| e.to_string())?
    ))?;
    let web = metamoran_web::start(metamoran_web::ServeOptions {
        site,
        users,
        feed: metamoran_web::Feed::Nats(config("serve")?),
        listen: "127.0.0.1:0".parse().map_err(|e| format!("{e}"))?,
        session_ttl: Duration::from_secs(3600),
        silence_s: 3600.0,
        bundles: None,
        tls: None,
    })
    .map_err(|e| e.to_string())?;
    let addr = web.addr();
    // The page: log in, then read the event stream; per sensor, when each frame first shows.
    let mut login = request(
        addr,
        "POST /login HTTP/1.1\r\nContent-Type: application/x-www-form-urlencoded\r\nConnection: close",
        &format!("user=bench&password={password}"),
    )?;
    let mut reply = String::new();
    login.read_to_string(&mut reply)?;
    let cookie = reply
        .lines()
        .find_map(|l| {
            l.to_ascii_lowercase()
                .starts_with("set-cookie:")
                .then(|| l[11..].trim().to_owned())
        })
        .and_then(|c| c.split(';').next().map(String::from))
        .ok_or("bench site: the login gave no session")?;
    let events = request(
        addr,
        &format!("GET /events HTTP/1.1\r\nCookie: {cookie}"),
        "",
    )?;
    let shown: Arc<Mutex<BTreeMap<(String, u32), Instant>>> = Arc::default();
    let reader = std::thread::spawn({
        let shown = shown.clone();
        move || {
            let mut last: BTreeMap<String, u32> = BTreeMap::new();
            for line in BufReader::new(events).lines() {
                let Ok(line) = line else { break };
                let Some(data) = line.strip_prefix("data: ") else {
                    continue;
                };
                let now = Instant::now();
                let Ok(state) = serde_json::from_str::<serde_json::Value>(data) else {
                    continue;
                };
                let mut shown = shown
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                for h in state["health"].as_array().into_iter().flatten() {
                    let (Some(id), Some(frame)) = (h["id"].as_str(), h["last_frame"].as_u64())
                    else {
                        continue;
                    };
                    let frame = frame as u32;
                    let from = last.get(id).map_or(0, |f| f + 1);
                    for f in from..=frame {
                        shown.entry((id.to_owned(), f)).or_insert(now);
                    }
                    last.insert(id.to_owned(), frame);
                }
            }
        }
    });
    let publishers: Vec<NatsPublisher> = (0..sensors)
        .map(|k| Ok(NatsPublisher::connect(&config(&format!("s{k}"))?)?))
        .collect::<Result<_, crate::Error>>()?;
    let frames = (seconds * rate_hz).round() as u32;
    let period = 1.0 / rate_hz;
    let mut sent: BTreeMap<(String, u32), Instant> = BTreeMap::new();
    let start = Instant::now();
    for f in 0..frames {
        let due = start + Duration::from_secs_f64(f64::from(f) * period);
        std::thread::sleep(due.saturating_duration_since(Instant::now()));
        let t = f64::from(f) * period;
        for (k, p) in publishers.iter().enumerate() {
            // Two people walking across each pole's view, 30 m out.
            let x = -10.0 + 1.4 * t % 20.0;
            let m = SensorTracks {
                frame: f,
                time_s: t,
                tracks: vec![row(1, x, 30.0), row(2, -x, 40.0)],
            };
            sent.insert((format!("s{k}"), f), Instant::now());
            p.publish("tracks", &serde_json::to_value(&m)?);
            if f % (rate_hz.round().max(1.0) as u32) == 0 {
                p.alert(&bench_alert(k, f, t));
            }
        }
    }
    let published_s = start.elapsed().as_secs_f64();
    let (mut stored, mut queued) = (0, 0);
    for p in publishers {
        let stats = p.close(metamoran_operator::nats::CLOSE_TIMEOUT)?;
        stored += stats.stored;
        queued += stats.alerts;
    }
    std::thread::sleep(Duration::from_millis(500));
    web.stop();
    let _ = reader.join();
    let shown = shown
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let mut latencies: Vec<f64> = Vec::with_capacity(sent.len());
    let mut unseen = 0;
    for (key, at) in &sent {
        match shown.get(key) {
            Some(seen) => latencies.push(seen.saturating_duration_since(*at).as_secs_f64() * 1e3),
            None => unseen += 1,
        }
    }
    latencies.sort_by(f64::total_cmp);
    let q = |p: f64| {
        latencies
            .get(((latencies.len() as f64 - 1.0) * p).round() as usize)
            .copied()
            .unwrap_or(f64::NAN)
    };
    let (p50, p99, max) = (
        q(0.5),
        q(0.99),
        latencies.last().copied().unwrap_or(f64::NAN),
    );
    Ok(SiteBench {
        sensors,
        rate_hz,
        seconds,
        track_messages: sent.len() as u64,
        track_messages_per_s: sent.len() as f64 / published_s,
        alerts_stored: stored,
        alerts_per_s: stored as f64 / published_s,
        alerts_lost: queued - stored,
        frames_unseen: unseen,
        latency_ms: [p50, p99, max],
        p99_over_period: p99 / (period * 1e3),
    })
}

/// A sensor's alert for the load (an `enter` of its track 1).
fn bench_alert(sensor: usize, frame: u32, t: f64) -> metamoran_operator::geofence::Alert {
    metamoran_operator::geofence::Alert {
        kind: metamoran_operator::geofence::AlertKind::Enter,
        zone: "centre".into(),
        track: sensor as u32,
        instance: None,
        class: "person".into(),
        depth_m: 30.0,
        azimuth_deg: 0.0,
        position_m: [0.0, 30.0],
        velocity_mps: [1.4, 0.0],
        closing_mps: None,
        inside_s: None,
        frame,
        time_s: t,
    }
}
