//! The site stream against a real server: Debian's `nats-server` with JetStream on file storage,
//! started by each test on a free loopback port with a user/password login (issue #20 part 3).
//! The server is killed and restarted while the demo runs, and no alert may be lost or doubled;
//! a station that connects afterwards replays every alert in order; clients without the login,
//! or with a wrong password, are refused.

use metamoran::demo::{DemoEdge, DemoOptions, run};
use metamoran_e2e::{
    free_port, http, oracles_required, post_login, site_folder, status_of, wait_for_lines,
};
use metamoran_operator::mqtt::MqttLogin;
use metamoran_operator::nats::{NatsConfig, NatsPublisher, replay};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The sensor's and the station's passwords (test-only; a site's come from files).
const SENSOR_PASSWORD: &str = "sensor-test-password-7f3a";
const STATION_PASSWORD: &str = "station-test-password-c91e";

struct Server {
    child: Child,
    port: u16,
    config: PathBuf,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn nats_server() -> Option<PathBuf> {
    ["/usr/sbin/nats-server", "/usr/bin/nats-server"]
        .into_iter()
        .map(PathBuf::from)
        .find(|p| p.exists())
}

/// A server config in `dir`: loopback `port`, JetStream stored in `dir/store`, two users.
fn write_config(dir: &Path, port: u16) -> PathBuf {
    let path = dir.join("nats.conf");
    std::fs::write(
        &path,
        format!(
            "listen: 127.0.0.1:{port}\n\
             jetstream {{ store_dir: \"{}\" }}\n\
             authorization {{ users: [\n  \
               {{ user: gate, password: \"{SENSOR_PASSWORD}\" }}\n  \
               {{ user: station, password: \"{STATION_PASSWORD}\" }}\n] }}\n",
            dir.join("store").display()
        ),
    )
    .unwrap();
    path
}

/// Starts the server on `config` and waits until it accepts connections.
fn start(exe: &Path, config: &Path, port: u16) -> Server {
    let child = Command::new(exe)
        .args(["-c".as_ref(), config.as_os_str()])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(10);
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(Instant::now() < deadline, "nats-server did not start");
        std::thread::sleep(Duration::from_millis(50));
    }
    Server {
        child,
        port,
        config: config.to_owned(),
    }
}

fn login(user: &str, password: &str) -> Option<MqttLogin> {
    Some(MqttLogin::new(user, password.to_owned()))
}

fn config(port: u16, sensor: &str, who: Option<MqttLogin>) -> NatsConfig {
    let mut c = NatsConfig::new(&format!("nats://127.0.0.1:{port}"), "yard", sensor).unwrap();
    c.login = who;
    c
}

#[test]
fn alerts_survive_a_server_restart_and_a_late_station_replays_them_in_order() {
    let Some((exe, _state, server)) = with_server() else {
        return;
    };
    let port = server.port;
    let out = tempfile::tempdir().unwrap();
    let log = out.path().join("alerts.jsonl");
    let sensor = config(port, "gate", login("gate", SENSOR_PASSWORD));
    let demo = std::thread::spawn({
        let (dir, sensor) = (out.path().to_owned(), sensor.clone());
        move || {
            run(
                &dir,
                &DemoOptions {
                    edge: DemoEdge::InProcess,
                    nats: Some(sensor),
                    realtime: true,
                    ..DemoOptions::default()
                },
            )
        }
    });
    // Down after the first alert, back (same store) after the second was raised.
    wait_for_lines(&log, 1);
    let (config_path, port) = (server.config.clone(), server.port);
    drop(server);
    wait_for_lines(&log, 2);
    std::thread::sleep(Duration::from_millis(500));
    let server = start(&exe, &config_path, port);
    let report = demo
        .join()
        .unwrap()
        .expect("the run must survive the server");
    assert_eq!(report.frames, 22);
    let words = report.nats.clone().unwrap_or_default();
    assert!(words.contains("stored in JetStream"), "{words}");
    let expected: Vec<String> = report
        .alerts
        .iter()
        .map(|a| serde_json::to_string(a).unwrap())
        .collect();
    assert!(expected.len() >= 3, "{expected:?}");
    assert_eq!(wait_for_lines(&log, expected.len()), expected);

    // A station that was never connected replays the stream: every alert once, in order.
    let station = config(port, "station", login("station", STATION_PASSWORD));
    let stored = replay(&station, 1000).unwrap();
    let got: Vec<&str> = stored.iter().map(|s| s.json.as_str()).collect();
    assert_eq!(got, expected, "every alert once, in order");
    assert!(stored.iter().all(|s| s.sensor == "gate"));
    let sequences: Vec<u64> = stored.iter().map(|s| s.sequence).collect();
    assert_eq!(sequences, (1..=expected.len() as u64).collect::<Vec<_>>());

    // The server kept them on file: after another restart they are all still there.
    drop(server);
    let _server = start(&exe, &config_path, port);
    assert_eq!(replay(&station, 1000).unwrap().len(), expected.len());
}

#[test]
fn clients_without_the_login_are_refused() {
    let Some((_, _state, _server)) = with_server() else {
        return;
    };
    let port = _server.port;
    for (who, what) in [
        (None, "no login"),
        (login("gate", "not-the-password"), "a wrong password"),
        (login("intruder", SENSOR_PASSWORD), "an unknown user"),
    ] {
        let e = NatsPublisher::connect(&config(port, "gate", who.clone()))
            .err()
            .unwrap_or_else(|| panic!("a sensor with {what} connected"));
        assert!(e.to_string().contains("cannot connect"), "{what}: {e}");
        let e = replay(&config(port, "station", who), 10).unwrap_err();
        assert!(e.to_string().contains("cannot connect"), "{what}: {e}");
    }
    // The right login gets in, and creates the stream.
    let p = NatsPublisher::connect(&config(port, "gate", login("gate", SENSOR_PASSWORD))).unwrap();
    p.close(Duration::from_secs(5)).unwrap();
    assert!(
        replay(
            &config(port, "station", login("station", STATION_PASSWORD)),
            10
        )
        .unwrap()
        .is_empty()
    );
}

/// Logs in to the web view at `addr`; the session cookie.
fn web_login(addr: std::net::SocketAddr, user: &str, password: &str) -> String {
    let reply = post_login(addr, &format!("user={user}&password={password}"));
    reply
        .lines()
        .find_map(|l| {
            l.strip_prefix("set-cookie: ")
                .or_else(|| l.strip_prefix("Set-Cookie: "))
        })
        .and_then(|c| c.split(';').next())
        .unwrap_or_else(|| panic!("no session cookie: {reply}"))
        .to_owned()
}

/// `GET path` with `cookie`; the body.
fn web_get(addr: std::net::SocketAddr, path: &str, cookie: &str) -> String {
    let reply = http(
        addr,
        &format!("GET {path} HTTP/1.1\r\nCookie: {cookie}"),
        "",
    );
    reply
        .split_once("\r\n\r\n")
        .map(|(_, b)| b.to_owned())
        .unwrap_or_default()
}

/// A server on a free port with its state in a new folder, or `None` (skipped, unless the
/// oracles are required) without nats-server.
fn with_server() -> Option<(PathBuf, tempfile::TempDir, Server)> {
    let Some(exe) = nats_server() else {
        assert!(
            !oracles_required(),
            "nats-server is required (apt-get install -y nats-server)"
        );
        eprintln!("SKIPPED: nats-server not installed");
        return None;
    };
    let state = tempfile::tempdir().unwrap();
    let port = free_port();
    let server = start(&exe, &write_config(state.path(), port), port);
    Some((exe, state, server))
}

/// The deployment's path (issue #20 parts 2–4): three poles publish their tracks to
/// nats-server, the site process (`serve --nats`) fuses them, evaluates the zone once, stores
/// its alerts in the stream with the sensors that saw each object, and the page's state shows
/// the site tracks and every sensor's health.
#[test]
fn the_site_process_fuses_the_poles_tracks_from_nats() {
    let Some((_, _state, _server)) = with_server() else {
        return;
    };
    let port = _server.port;
    let out = tempfile::tempdir().unwrap();
    let dir = site_folder(out.path());
    let file = metamoran_operator::site::SiteFile::load(&dir.join("site.toml")).unwrap();
    let site_name = file.name.clone();
    let serve_config = config(port, "serve", login("station", STATION_PASSWORD));
    let mut serve_config = serve_config;
    serve_config.site.clone_from(&site_name);
    let password = "web-test-password-0b7c";
    let users = metamoran_web::login::Users::parse(&format!(
        "operator:{}",
        metamoran_web::login::hash_password(password).unwrap()
    ))
    .unwrap();
    let web = metamoran_web::start(metamoran_web::ServeOptions {
        site: file,
        users,
        feed: metamoran_web::Feed::Nats(serve_config),
        listen: "127.0.0.1:0".parse().unwrap(),
        session_ttl: Duration::from_secs(600),
        silence_s: 60.0,
        // The poles' recordings, for the selected track's pictures.
        bundles: Some(dir.clone()),
        tls: None,
    })
    .unwrap();
    let addr = web.addr();
    // Bad input first: a malformed message from a known pole and one from a sensor the site
    // does not have. Both are refused and counted; neither stops the site process.
    for (sensor, body) in [
        (
            "pole-a",
            serde_json::json!({ "frame": 0, "time_s": "soon" }),
        ),
        (
            "intruder",
            serde_json::json!({ "frame": 0, "time_s": 0.0, "tracks": [] }),
        ),
    ] {
        let mut c = config(port, sensor, login("gate", SENSOR_PASSWORD));
        c.site.clone_from(&site_name);
        let p = NatsPublisher::connect(&c).unwrap();
        p.publish("tracks", &body);
        p.close(Duration::from_secs(5)).unwrap();
    }
    // The poles, live: one lap of 40 frames at 4 Hz.
    let sent = metamoran::site::publish_sensors(
        &dir,
        &|site, sensor| {
            let mut c = config(port, sensor, login("gate", SENSOR_PASSWORD));
            c.site = site.to_owned();
            Ok(c)
        },
        1,
    )
    .unwrap();
    assert_eq!(sent, 3 * 40);
    std::thread::sleep(Duration::from_millis(500));
    let cookie = web_login(addr, "operator", password);
    let body = web_get(addr, "/api/state", &cookie);
    let state: serde_json::Value =
        serde_json::from_str(&body).unwrap_or_else(|e| panic!("{e}: {body}"));
    for h in state["health"].as_array().unwrap() {
        assert_eq!(h["accepted"], 40, "{h}");
        let refused = if h["id"] == "pole-a" { 1 } else { 0 };
        assert_eq!(h["rejected"], refused, "{h}");
    }
    assert_eq!(state["unknown_messages"], 1, "{state}");
    let tracks = state["tracks"].as_array().unwrap();
    assert!((2..=4).contains(&tracks.len()), "{tracks:?}");
    // Each live track's pictures are drawn from the pole's recording of the frame a pole last
    // detected it in.
    for picture in ["depth", "range-azimuth"] {
        let path = format!("/api/track/{}/{picture}.png", tracks[0]["id"]);
        let reply = http(
            addr,
            &format!("GET {path} HTTP/1.1\r\nCookie: {cookie}"),
            "",
        );
        let head: String = reply.chars().take(300).collect();
        assert_eq!(status_of(&reply), 200, "{path}: {head}");
        assert!(reply.contains("content-type: image/png"), "{path}");
        assert!(
            reply.contains("\r\n\r\n\u{fffd}PNG\r\n"),
            "{path}: not a PNG"
        );
    }
    // The site's alerts are in the stream, each with the sensors that saw the object; the two
    // people's entries into the yard were seen by two poles or more.
    let mut station = config(port, "station", login("station", STATION_PASSWORD));
    station.site = site_name;
    let stored = replay(&station, 1000).unwrap();
    let site_alerts: Vec<serde_json::Value> = stored
        .iter()
        .filter(|s| s.sensor == "site")
        .map(|s| serde_json::from_str(&s.json).unwrap())
        .collect();
    let enters: Vec<_> = site_alerts
        .iter()
        .filter(|a| a["kind"] == "enter" && a["sensors"].as_array().unwrap().len() >= 2)
        .collect();
    assert_eq!(enters.len(), 2, "{site_alerts:?}");
    web.stop();
}

/// nats-server with TLS (a certificate made for the run): a sensor that trusts it publishes an
/// alert and a station replays it over TLS; a client that does not trust the certificate, and
/// one that will not use TLS, are refused.
#[test]
fn the_stream_runs_over_tls_with_a_trusted_certificate_only() {
    let Some(exe) = nats_server() else {
        assert!(
            !oracles_required(),
            "nats-server is required (apt-get install -y nats-server)"
        );
        eprintln!("SKIPPED: nats-server not installed");
        return;
    };
    let state = tempfile::tempdir().unwrap();
    let port = free_port();
    let made = rcgen::generate_simple_self_signed(vec!["127.0.0.1".to_owned()]).unwrap();
    let (cert, key) = (state.path().join("cert.pem"), state.path().join("key.pem"));
    std::fs::write(&cert, made.cert.pem()).unwrap();
    std::fs::write(&key, made.key_pair.serialize_pem()).unwrap();
    let conf = write_config(state.path(), port);
    let mut text = std::fs::read_to_string(&conf).unwrap();
    text.push_str(&format!(
        "tls {{ cert_file: \"{}\", key_file: \"{}\" }}\n",
        cert.display(),
        key.display()
    ));
    std::fs::write(&conf, text).unwrap();
    let _server = start(&exe, &conf, port);
    let secure = |sensor: &str, who| {
        let mut c = config(port, sensor, who);
        c.ca = Some(cert.clone());
        c
    };
    let p = NatsPublisher::connect(&secure("gate", login("gate", SENSOR_PASSWORD))).unwrap();
    let alert = serde_json::json!({ "kind": "enter", "zone": "yard", "track": 7, "frame": 3 });
    // Published on the alert subject, which the stream stores.
    p.publish("alerts", &alert);
    p.close(Duration::from_secs(5)).unwrap();
    let stored = replay(&secure("station", login("station", STATION_PASSWORD)), 10).unwrap();
    assert_eq!(stored.len(), 1, "{stored:?}");
    assert!(stored[0].json.contains("\"track\":7"), "{stored:?}");
    // Without the certificate among its roots (plain or TLS), a client gets nowhere.
    let e = NatsPublisher::connect(&config(port, "gate", login("gate", SENSOR_PASSWORD)))
        .err()
        .expect("a client without the server's certificate connected");
    assert!(e.to_string().contains("cannot connect"), "{e}");
    let other = rcgen::generate_simple_self_signed(vec!["127.0.0.1".to_owned()]).unwrap();
    let stranger = state.path().join("other.pem");
    std::fs::write(&stranger, other.cert.pem()).unwrap();
    let mut wrong = config(port, "gate", login("gate", SENSOR_PASSWORD));
    wrong.ca = Some(stranger);
    let e = NatsPublisher::connect(&wrong)
        .err()
        .expect("a client trusting another certificate connected");
    assert!(e.to_string().contains("cannot connect"), "{e}");
}
