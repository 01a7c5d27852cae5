//! MQTT against a real broker: Debian's mosquitto, started by the test on a free loopback port.
//! The demo's objects and alerts must arrive (objects QoS 0, alerts QoS 1, equal to the demo's
//! own report), the status must be retained (`stopped` after a clean end, seen by a subscriber
//! that connects afterwards), and a publisher that drops its connection without a DISCONNECT
//! must leave the broker's last will, `offline`, retained.

use metamoran::demo::{DemoEdge, DemoOptions, run};
use metamoran_e2e::{oracles_required, wait_for_lines};
use metamoran_operator::mqtt::{MqttConfig, MqttLogin, MqttTls, Publisher};
use rumqttc::{Client, Event, MqttOptions, Packet, QoS};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

struct Broker(Child, u16);

impl Drop for Broker {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn start_broker() -> Option<Broker> {
    let exe = ["/usr/sbin/mosquitto", "/usr/bin/mosquitto"]
        .into_iter()
        .find(|p| std::path::Path::new(p).exists())?;
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let child = Command::new(exe)
        .args(["-p", &port.to_string()])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .ok()?;
    let deadline = Instant::now() + Duration::from_secs(5);
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(Instant::now() < deadline, "mosquitto did not start");
        std::thread::sleep(Duration::from_millis(50));
    }
    Some(Broker(child, port))
}

/// Subscribes to `metamoran/#` and returns (topic, payload, retain) of everything received
/// until `quiet` passes without a message (or `limit`).
fn listen(port: u16, id: &str, during: impl FnOnce()) -> Vec<(String, String, bool)> {
    let (client, mut connection) = Client::new(MqttOptions::new(id, "127.0.0.1", port), 64);
    client.subscribe("metamoran/#", QoS::AtLeastOnce).unwrap();
    // Wait for the SUBACK before anything is published.
    loop {
        if let Ok(Ok(Event::Incoming(Packet::SubAck(_)))) =
            connection.recv_timeout(Duration::from_secs(5))
        {
            break;
        }
    }
    during();
    let mut got = Vec::new();
    while let Ok(Ok(event)) = connection.recv_timeout(Duration::from_millis(700)) {
        if let Event::Incoming(Packet::Publish(p)) = event {
            got.push((
                p.topic.clone(),
                String::from_utf8_lossy(&p.payload).into_owned(),
                p.retain,
            ));
        }
    }
    got
}

#[test]
fn demo_publishes_objects_alerts_status_and_last_will() {
    let Some(broker) = start_broker() else {
        assert!(
            !oracles_required(),
            "mosquitto is required (apt-get install -y mosquitto)"
        );
        eprintln!("SKIPPED: mosquitto not installed");
        return;
    };
    let port = broker.1;
    let dir = tempfile::tempdir().unwrap();
    let config = MqttConfig::parse(&format!("127.0.0.1:{port}"), "gate").unwrap();
    let mut report = None;
    let live = listen(port, "watcher", || {
        report = Some(
            run(
                dir.path(),
                &DemoOptions {
                    edge: DemoEdge::InProcess,
                    mqtt: Some(config.clone()),
                    ..DemoOptions::default()
                },
            )
            .unwrap(),
        );
    });
    let report = report.unwrap();
    let on = |topic: &str| -> Vec<&(String, String, bool)> {
        live.iter().filter(|m| m.0 == topic).collect()
    };
    // Objects: one message per frame, in order; the last holds results.json's last depths.
    let objects = on("metamoran/gate/objects");
    assert_eq!(objects.len(), report.frames, "{live:?}");
    let frames: Vec<u64> = objects
        .iter()
        .map(|m| {
            serde_json::from_str::<serde_json::Value>(&m.1).unwrap()["frame"]
                .as_u64()
                .unwrap()
        })
        .collect();
    assert_eq!(frames, (0..report.frames as u64).collect::<Vec<_>>());
    let body: serde_json::Value = serde_json::from_str(&objects[objects.len() - 1].1).unwrap();
    let depths: Vec<Option<f64>> = body["objects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["depth_m"].as_f64())
        .collect();
    let results: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("results.json")).unwrap()).unwrap();
    let last = &results["frames"][report.frames - 1]["objects"];
    let want: Vec<Option<f64>> = last
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["depth_m"].as_f64())
        .collect();
    assert!(!want.is_empty());
    assert_eq!(depths, want);
    // Alerts: every one, in order, byte for byte (parsing the floats back is not exact).
    let alerts: Vec<&str> = on("metamoran/gate/alerts")
        .iter()
        .map(|m| m.1.as_str())
        .collect();
    assert!(!report.alerts.is_empty());
    let expected: Vec<String> = report
        .alerts
        .iter()
        .map(|a| serde_json::to_string(a).unwrap())
        .collect();
    assert_eq!(alerts, expected);
    let status: Vec<&str> = on("metamoran/gate/status")
        .iter()
        .map(|m| m.1.as_str())
        .collect();
    assert_eq!(status, ["online", "stopped"]);

    // A late subscriber gets the retained status of a clean end.
    let late = listen(port, "late", || {});
    assert!(
        late.contains(&("metamoran/gate/status".into(), "stopped".into(), true)),
        "{late:?}"
    );

    // A lost connection: the broker publishes the last will, retained.
    let lost = MqttConfig::parse(&format!("127.0.0.1:{port}"), "mast").unwrap();
    let seen = listen(port, "watcher2", || {
        Publisher::connect(&lost).unwrap().abort();
    });
    let status: Vec<&str> = seen
        .iter()
        .filter(|m| m.0 == "metamoran/mast/status")
        .map(|m| m.1.as_str())
        .collect();
    assert_eq!(status, ["online", "offline"], "{seen:?}");
    let late = listen(port, "late2", || {});
    assert!(late.contains(&("metamoran/mast/status".into(), "offline".into(), true)));

    // A broker that is not there is a clear error, not a hang.
    drop(broker);
    let gone = MqttConfig::parse(&format!("127.0.0.1:{port}"), "gate").unwrap();
    let err = Publisher::connect(&gone).err().unwrap().to_string();
    assert!(err.contains(&format!("127.0.0.1:{port}")), "{err}");
}

/// mosquitto with a config file: persistence in `dir` (saved when it stops), on `port`.
fn start_persistent_broker(dir: &std::path::Path, port: u16) -> Broker {
    let conf = dir.join("mosquitto.conf");
    // As root, mosquitto would switch to user `mosquitto`, who cannot write the test's folder.
    let me = Command::new("id").arg("-un").output().unwrap().stdout;
    std::fs::write(
        &conf,
        format!(
            "listener {port} 127.0.0.1\nallow_anonymous true\npersistence true\n\
             persistence_location {}/\nuser {}\n",
            dir.display(),
            String::from_utf8_lossy(&me).trim()
        ),
    )
    .unwrap();
    let child = Command::new("mosquitto")
        .arg("-c")
        .arg(&conf)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(5);
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(Instant::now() < deadline, "mosquitto did not start");
        std::thread::sleep(Duration::from_millis(20));
    }
    Broker(child, port)
}

/// Stops the broker as a service manager would (SIGTERM: it saves its state and exits).
fn stop_broker(mut broker: Broker) {
    let pid = broker.0.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-TERM", &pid])
            .status()
            .unwrap()
            .success()
    );
    let _ = broker.0.wait();
}

/// Issue #18, item 10: the broker goes down after the first alert and comes back after the
/// second was raised. The sensor keeps processing (every frame), writes each alert to
/// alerts.jsonl before publishing it, reconnects, and a subscriber with a persistent session
/// that was offline throughout receives every alert exactly once, in order. (Before, the first
/// publish after the loss failed the run and every result was discarded.)
#[test]
fn alerts_survive_a_broker_restart() {
    if Command::new("mosquitto").arg("-h").output().is_err() {
        assert!(!oracles_required(), "mosquitto is required");
        return;
    }
    let state = tempfile::tempdir().unwrap();
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let broker = start_persistent_broker(state.path(), port);
    // The operator's station: a persistent session, subscribed, then offline.
    let station = || {
        let mut o = MqttOptions::new("station", "127.0.0.1", port);
        o.set_clean_session(false);
        Client::new(o, 64)
    };
    {
        let (client, mut connection) = station();
        client
            .subscribe("metamoran/gate/alerts", QoS::AtLeastOnce)
            .unwrap();
        while !matches!(
            connection.recv_timeout(Duration::from_secs(5)),
            Ok(Ok(Event::Incoming(Packet::SubAck(_))))
        ) {}
        client.disconnect().unwrap();
        while connection.recv_timeout(Duration::from_millis(200)).is_ok() {}
    }
    let out = tempfile::tempdir().unwrap();
    let log = out.path().join("alerts.jsonl");
    let config = MqttConfig::parse(&format!("127.0.0.1:{port}"), "gate").unwrap();
    let demo = std::thread::spawn({
        let dir = out.path().to_owned();
        move || {
            run(
                &dir,
                &DemoOptions {
                    edge: DemoEdge::InProcess,
                    mqtt: Some(config),
                    realtime: true,
                    ..DemoOptions::default()
                },
            )
        }
    });
    wait_for_lines(&log, 1);
    stop_broker(broker);
    wait_for_lines(&log, 2);
    std::thread::sleep(Duration::from_millis(500));
    let broker = start_persistent_broker(state.path(), port);
    let report = demo
        .join()
        .unwrap()
        .expect("the run must survive the broker");
    assert_eq!(report.frames, 22);
    assert!(
        report
            .mqtt
            .as_deref()
            .unwrap_or("")
            .contains("reconnection")
    );
    let logged = wait_for_lines(&log, report.alerts.len());
    let expected: Vec<String> = report
        .alerts
        .iter()
        .map(|a| serde_json::to_string(a).unwrap())
        .collect();
    assert_eq!(logged, expected);
    assert!(expected.len() >= 3, "{expected:?}");

    let (_client, mut connection) = station();
    let mut got = Vec::new();
    while let Ok(Ok(event)) = connection.recv_timeout(Duration::from_millis(1500)) {
        if let Event::Incoming(Packet::Publish(p)) = event {
            got.push(String::from_utf8_lossy(&p.payload).into_owned());
        }
    }
    assert_eq!(got, expected, "every alert once, in order");
    drop(broker);
}

/// Runs `openssl args…` in `dir`.
fn openssl(dir: &std::path::Path, args: &[&str]) {
    let out = Command::new("openssl")
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "openssl {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A CA, a broker certificate for 127.0.0.1 and client certificates for `clients`, all P-256.
fn certificates(dir: &std::path::Path, clients: &[&str]) {
    let ec = [
        "-newkey",
        "ec",
        "-pkeyopt",
        "ec_paramgen_curve:prime256v1",
        "-nodes",
    ];
    openssl(
        dir,
        &[
            &["req", "-x509"][..],
            &ec,
            &[
                "-keyout",
                "ca.key",
                "-out",
                "ca.pem",
                "-days",
                "1",
                "-subj",
                "/CN=metamoran test CA",
            ],
        ]
        .concat(),
    );
    std::fs::write(dir.join("server.ext"), "subjectAltName=IP:127.0.0.1\n").unwrap();
    std::fs::write(dir.join("client.ext"), "extendedKeyUsage=clientAuth\n").unwrap();
    for (name, ext) in
        std::iter::once(("server", "server.ext")).chain(clients.iter().map(|c| (*c, "client.ext")))
    {
        let (key, csr, pem) = (
            format!("{name}.key"),
            format!("{name}.csr"),
            format!("{name}.pem"),
        );
        openssl(
            dir,
            &[
                &["req"][..],
                &ec,
                &[
                    "-keyout",
                    &key,
                    "-out",
                    &csr,
                    "-subj",
                    &format!("/CN={name}"),
                ],
            ]
            .concat(),
        );
        openssl(
            dir,
            &[
                "x509",
                "-req",
                "-in",
                &csr,
                "-CA",
                "ca.pem",
                "-CAkey",
                "ca.key",
                "-CAcreateserial",
                "-out",
                &pem,
                "-days",
                "1",
                "-extfile",
                ext,
            ],
        );
    }
}

/// Connects with `config`'s TLS and login as `id`: `Some` once the broker accepted (CONNACK
/// success), `None` if it refused or the TLS handshake failed.
fn connect_as(config: &MqttConfig, id: &str) -> Option<(Client, rumqttc::Connection)> {
    let (client, mut connection) = Client::new(config.options(id).unwrap(), 64);
    let deadline = Instant::now() + Duration::from_secs(5);
    while Instant::now() < deadline {
        match connection.recv_timeout(Duration::from_millis(200)) {
            Ok(Ok(Event::Incoming(Packet::ConnAck(ack)))) => {
                return (ack.code == rumqttc::ConnectReturnCode::Success)
                    .then_some((client, connection));
            }
            Ok(Err(_)) => return None,
            _ => {}
        }
    }
    None
}

/// Issue #18, item 11: mosquitto with TLS, client certificates, passwords and an ACL. The
/// sensor publishes over TLS with its certificate and login; the operator station reads; a
/// client without TLS, without a certificate or without a login cannot connect, and one with
/// a login the ACL gives nothing can neither read the sensor's alerts nor inject its own.
#[test]
fn tls_credentials_and_acl_keep_out_everyone_else() {
    if Command::new("mosquitto").arg("-h").output().is_err()
        || Command::new("openssl").arg("version").output().is_err()
    {
        assert!(!oracles_required(), "mosquitto and openssl are required");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    certificates(d, &["gate", "station", "intruder"]);
    let passwd = d.join("passwd");
    for (i, user) in ["gate", "station", "intruder"].iter().enumerate() {
        let mut args = vec!["-b"];
        if i == 0 {
            args.push("-c");
        }
        let pw = format!("{user}-secret");
        args.extend([passwd.to_str().unwrap(), user, &pw]);
        assert!(
            Command::new("mosquitto_passwd")
                .args(&args)
                .status()
                .unwrap()
                .success()
        );
    }
    std::fs::write(
        d.join("acl"),
        "user gate\ntopic write metamoran/gate/#\n\nuser station\ntopic read metamoran/gate/#\n",
    )
    .unwrap();
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let me = Command::new("id").arg("-un").output().unwrap().stdout;
    let p = |f: &str| d.join(f).display().to_string();
    std::fs::write(
        d.join("mosquitto.conf"),
        format!(
            "listener {port} 127.0.0.1\ncafile {}\ncertfile {}\nkeyfile {}\nrequire_certificate true\n\
             allow_anonymous false\npassword_file {}\nacl_file {}\nuser {}\n",
            p("ca.pem"), p("server.pem"), p("server.key"), p("passwd"), p("acl"),
            String::from_utf8_lossy(&me).trim()
        ),
    )
    .unwrap();
    let child = Command::new("mosquitto")
        .arg("-c")
        .arg(d.join("mosquitto.conf"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let _broker = Broker(child, port);
    let deadline = Instant::now() + Duration::from_secs(5);
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(Instant::now() < deadline, "mosquitto did not start");
        std::thread::sleep(Duration::from_millis(20));
    }
    let as_user = |user: &str, cert: bool, login: bool| {
        let mut c = MqttConfig::parse(&format!("127.0.0.1:{port}"), user).unwrap();
        c.tls = Some(MqttTls {
            ca: d.join("ca.pem"),
            client: cert.then(|| (d.join(format!("{user}.pem")), d.join(format!("{user}.key")))),
        });
        c.login = login.then(|| MqttLogin::new(user, format!("{user}-secret")));
        c
    };
    // Kept out: no TLS at all, TLS without a certificate, a certificate without a login.
    let mut plain = MqttConfig::parse(&format!("127.0.0.1:{port}"), "station").unwrap();
    plain.login = Some(MqttLogin::new("station", "station-secret".into()));
    assert!(
        connect_as(&plain, "plain").is_none(),
        "plain TCP must not connect"
    );
    assert!(connect_as(&as_user("station", false, true), "nocert").is_none());
    assert!(connect_as(&as_user("station", true, false), "nologin").is_none());
    let mut wrong = as_user("station", true, true);
    wrong.login = Some(MqttLogin::new("station", "guess".into()));
    assert!(connect_as(&wrong, "wrongpw").is_none());

    // The station reads the sensor's topics; the intruder (a valid login) is given nothing.
    let (station, mut station_rx) = connect_as(&as_user("station", true, true), "station").unwrap();
    station
        .subscribe("metamoran/gate/#", QoS::AtLeastOnce)
        .unwrap();
    while !matches!(
        station_rx.recv_timeout(Duration::from_secs(5)),
        Ok(Ok(Event::Incoming(Packet::SubAck(_))))
    ) {}
    // The station listens on its own thread until the sensor's `stopped` status.
    let station_thread = std::thread::spawn(move || {
        let _station = station;
        let mut seen = Vec::new();
        while let Ok(Ok(e)) = station_rx.recv_timeout(Duration::from_secs(60)) {
            if let Event::Incoming(Packet::Publish(p)) = e {
                let m = (
                    p.topic.clone(),
                    String::from_utf8_lossy(&p.payload).into_owned(),
                );
                let done = m.0 == "metamoran/gate/status" && m.1 == "stopped";
                seen.push(m);
                if done {
                    break;
                }
            }
        }
        seen
    });
    let (intruder, mut intruder_rx) =
        connect_as(&as_user("intruder", true, true), "intruder").unwrap();
    intruder.subscribe("metamoran/#", QoS::AtLeastOnce).unwrap();
    // mosquitto grants a wildcard subscription and filters each delivery through the ACL:
    // what matters is that nothing arrives (checked below).
    while !matches!(
        intruder_rx.recv_timeout(Duration::from_secs(5)),
        Ok(Ok(Event::Incoming(Packet::SubAck(_))))
    ) {}
    // A forged alert: the broker acknowledges it (MQTT 3.1.1 cannot refuse a publish) and
    // drops it.
    intruder
        .publish(
            "metamoran/gate/alerts",
            QoS::AtLeastOnce,
            false,
            b"{\"kind\":\"exit\",\"forged\":true}".to_vec(),
        )
        .unwrap();
    while !matches!(
        intruder_rx.recv_timeout(Duration::from_secs(5)),
        Ok(Ok(Event::Incoming(Packet::PubAck(_))))
    ) {}
    // The intruder keeps listening (and its connection alive) while the sensor runs.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let intruder_thread = std::thread::spawn({
        let stop = stop.clone();
        move || {
            let _intruder = intruder;
            let (mut got, mut connected) = (0, true);
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                match intruder_rx.recv_timeout(Duration::from_millis(100)) {
                    Ok(Ok(Event::Incoming(Packet::Publish(_)))) => got += 1,
                    Ok(Err(_)) => connected = false,
                    _ => {}
                }
            }
            (got, connected)
        }
    });
    let out = tempfile::tempdir().unwrap();
    let report = run(
        out.path(),
        &DemoOptions {
            edge: DemoEdge::InProcess,
            mqtt: Some(as_user("gate", true, true)),
            ..DemoOptions::default()
        },
    )
    .unwrap();
    let seen = station_thread.join().unwrap();
    let alerts: Vec<&str> = seen
        .iter()
        .filter(|m| m.0 == "metamoran/gate/alerts")
        .map(|m| m.1.as_str())
        .collect();
    let expected: Vec<String> = report
        .alerts
        .iter()
        .map(|a| serde_json::to_string(a).unwrap())
        .collect();
    assert_eq!(
        alerts, expected,
        "the station gets the sensor's alerts and no forged one"
    );
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    let (intruder_got, intruder_connected) = intruder_thread.join().unwrap();
    assert!(
        intruder_connected,
        "the intruder stayed connected throughout"
    );
    assert_eq!(intruder_got, 0, "the intruder must read nothing");
}
