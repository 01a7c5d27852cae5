//! The operator's web view in a real browser (issue #20 part 4): Debian's headless Chromium
//! driven through chromedriver (WebDriver, `fantoccini`) against `metamoran serve` replaying a
//! simulated three-pole site. Log in, see the tracks move, receive an alert, acknowledge it,
//! select a track and get its fused depth image and range–azimuth map before and after SIC, and find the zone and a
//! track in the screenshot's pixels. Without the browser: the API
//! refuses requests without a session, and the sixth failed login in a minute is refused.

use fantoccini::{ClientBuilder, Locator};
use metamoran_e2e::{free_port, http, oracles_required, post_login, site_folder, status_of};
use metamoran_operator::site::SiteFile;
use metamoran_web::login::{Users, hash_password};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const PASSWORD: &str = "operator-test-password-51d2";

struct Driver(Child);

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Types `text` into the field with id `id`.
async fn type_into(c: &fantoccini::Client, id: &str, text: &str) {
    c.find(Locator::Id(id))
        .await
        .unwrap()
        .send_keys(text)
        .await
        .unwrap();
}

/// Logs in on the page shown.
async fn log_in(c: &fantoccini::Client, user: &str, password: &str) {
    type_into(c, "user", user).await;
    type_into(c, "password", password).await;
    c.find(Locator::Id("submit"))
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
}

#[test]
fn an_operator_logs_in_sees_tracks_move_and_acknowledges_an_alert() {
    let Some(driver_exe) = ["/usr/bin/chromedriver", "/usr/lib/chromium/chromedriver"]
        .into_iter()
        .find(|p| std::path::Path::new(p).exists())
    else {
        assert!(
            !oracles_required(),
            "chromium and chromium-driver are required (apt-get install -y chromium chromium-driver)"
        );
        eprintln!("SKIPPED: chromedriver not installed");
        return;
    };
    let out = tempfile::tempdir().unwrap();
    let dir = site_folder(out.path());
    let file = SiteFile::load(&dir.join("site.toml")).unwrap();
    let (sensors, period_s) = metamoran::site::replay_messages(&dir, &file).unwrap();
    let users = Users::parse(&format!("operator:{}", hash_password(PASSWORD).unwrap())).unwrap();
    let server = metamoran_web::start(metamoran_web::ServeOptions {
        site: file,
        users,
        feed: metamoran_web::replay_feed(sensors, period_s),
        listen: "127.0.0.1:0".parse().unwrap(),
        session_ttl: Duration::from_secs(600),
        silence_s: 60.0,
        bundles: Some(dir.clone()),
        tls: None,
    })
    .unwrap();
    let addr = server.addr();

    // Without a session the API and the event stream are refused.
    for path in ["/api/state", "/api/plan", "/events"] {
        let code = status_of(&http(addr, &format!("GET {path} HTTP/1.1"), ""));
        assert_eq!(code, 401, "{path}");
    }

    let port = free_port();
    let _driver = Driver(
        Command::new(driver_exe)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let deadline = Instant::now() + Duration::from_secs(20);
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(Instant::now() < deadline, "chromedriver did not start");
        std::thread::sleep(Duration::from_millis(50));
    }
    let profile = tempfile::tempdir().unwrap();
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let screenshot = runtime.block_on(async {
        let mut caps = serde_json::Map::new();
        caps.insert(
            "goog:chromeOptions".into(),
            serde_json::json!({
                "binary": "/usr/bin/chromium",
                "args": [
                    "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                    "--disable-background-networking", "--disable-component-update",
                    "--disable-sync", "--no-first-run", "--disable-quic", "--window-size=1400,900",
                    format!("--user-data-dir={}", profile.path().display()),
                ],
            }),
        );
        let c = ClientBuilder::new(hyper_util::client::legacy::connect::HttpConnector::new())
            .capabilities(caps)
            .connect(&format!("http://127.0.0.1:{port}"))
            .await
            .expect("a WebDriver session in headless Chromium");
        c.goto(&format!("http://{addr}/")).await.unwrap();
        // A wrong password is refused on the page.
        log_in(&c, "operator", "wrong").await;
        // The click returns before the answer page is there: wait for it.
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            let page = c.source().await.unwrap();
            if page.contains("wrong user or password") {
                break;
            }
            assert!(Instant::now() < deadline, "{page}");
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
        log_in(&c, "operator", PASSWORD).await;
        // The plan: three sensors and the zone; then tracks.
        c.wait()
            .at_most(Duration::from_secs(20))
            .for_element(Locator::Css("circle.track"))
            .await
            .expect("tracks on the plan");
        assert_eq!(
            c.find_all(Locator::Css("circle.sensor"))
                .await
                .unwrap()
                .len(),
            3
        );
        assert_eq!(
            c.find_all(Locator::Css("polygon.zone"))
                .await
                .unwrap()
                .len(),
            1
        );
        let zone_label = c.find(Locator::Css("text.zone-label")).await.unwrap();
        assert_eq!(zone_label.text().await.unwrap(), "yard");
        // A track moves: the same id somewhere else a second and a half later.
        let id = c
            .execute(
                "const e = document.querySelector('circle.track.person'); return e ? e.getAttribute('data-track') : null;",
                vec![],
            )
            .await
            .unwrap()
            .as_str()
            .expect("a person track")
            .to_owned();
        // The page redraws on every update, so an element can go stale between two reads:
        // read again.
        let at = |c: fantoccini::Client, id: String| async move {
            for _ in 0..20 {
                let read = async {
                    let e = c
                        .find(Locator::Css(&format!("circle.track[data-track='{id}']")))
                        .await
                        .ok()?;
                    let x: f64 = e.attr("cx").await.ok()??.parse().ok()?;
                    let y: f64 = e.attr("cy").await.ok()??.parse().ok()?;
                    Some((x, y))
                };
                if let Some(p) = read.await {
                    return Some(p);
                }
                tokio::time::sleep(Duration::from_millis(50)).await;
            }
            None
        };
        let p0 = at(c.clone(), id.clone()).await.unwrap();
        tokio::time::sleep(Duration::from_millis(1500)).await;
        if let Some(p1) = at(c.clone(), id.clone()).await {
            let moved = (p1.0 - p0.0).hypot(p1.1 - p0.1);
            assert!(moved > 0.5, "track {id} moved {moved} m");
        }
        // An alert arrives; the operator acknowledges it; the page says by whom. (A new alert
        // redraws the list, so a click can meet a stale button: find it again.)
        c.wait()
            .at_most(Duration::from_secs(30))
            .for_element(Locator::Css("#alerts li button.ack"))
            .await
            .expect("an alert to acknowledge");
        let mut clicked = false;
        for _ in 0..20 {
            if let Ok(b) = c.find(Locator::Css("#alerts li button.ack")).await
                && b.click().await.is_ok()
            {
                clicked = true;
                break;
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
        assert!(clicked, "the acknowledge button could not be clicked");
        let deadline = Instant::now() + Duration::from_secs(10);
        let text = loop {
            let read = c
                .execute(
                    "const e = document.querySelector('#alerts li.acked'); return e ? e.textContent : null;",
                    vec![],
                )
                .await
                .unwrap();
            if let Some(t) = read.as_str() {
                break t.to_owned();
            }
            assert!(Instant::now() < deadline, "no alert was acknowledged");
            tokio::time::sleep(Duration::from_millis(100)).await;
        };
        assert!(text.contains("acknowledged by operator"), "{text}");
        assert!(text.contains("yard"), "{text}");
        // Selecting a track shows its range–azimuth map before and after SIC from a sensor's
        // bundle (the inspection plot, 1400 × 700).
        c.execute(
            "const e = document.querySelector('circle.track.person'); e.dispatchEvent(new MouseEvent('click', { bubbles: true })); return e.getAttribute('data-track');",
            vec![],
        )
        .await
        .unwrap();
        let deadline = Instant::now() + Duration::from_secs(60);
        let width = loop {
            let w = c
                .execute(
                    "const i = document.getElementById('track-plot'); return i.complete ? i.naturalWidth : 0;",
                    vec![],
                )
                .await
                .unwrap()
                .as_u64()
                .unwrap_or(0);
            if w > 0 {
                break w;
            }
            assert!(Instant::now() < deadline, "the track's plot never loaded");
            tokio::time::sleep(Duration::from_millis(200)).await;
        };
        assert_eq!(width, 1400);
        // And the fused depth image of that frame (the camera's 640 × 360 with margins, a
        // title and a scale), the track's object in colour: counted in the page's canvas.
        let deadline = Instant::now() + Duration::from_secs(60);
        let (width, coloured) = loop {
            let read = c
                .execute(
                    "const i = document.getElementById('track-depth');
                     if (!i.complete || i.naturalWidth === 0) return null;
                     const c = document.createElement('canvas');
                     c.width = i.naturalWidth; c.height = i.naturalHeight;
                     const g = c.getContext('2d'); g.drawImage(i, 0, 0);
                     const d = g.getImageData(16, 36, 640, 360).data;
                     let n = 0;
                     for (let k = 0; k < d.length; k += 4) {
                       const hi = Math.max(d[k], d[k + 1], d[k + 2]), lo = Math.min(d[k], d[k + 1], d[k + 2]);
                       if (hi - lo > 30) n++;
                     }
                     return [i.naturalWidth, n];",
                    vec![],
                )
                .await
                .unwrap();
            if let Some([w, n]) = read.as_array().map(Vec::as_slice) {
                break (w.as_u64().unwrap(), n.as_u64().unwrap());
            }
            assert!(Instant::now() < deadline, "the track's depth image never loaded");
            tokio::time::sleep(Duration::from_millis(200)).await;
        };
        assert_eq!(width, 640 + 2 * 16);
        // Only the picked-out object is drawn in colour (the others grey, the box and label
        // white, the background dark grey), each of its points as a 3 × 3 block: at least one
        // block. How many depends on the frame the track was last seen in (a far person has a
        // handful of points), so the count is not pinned; a drawing that greys or drops the
        // selected object leaves none.
        assert!(coloured >= 9, "{coloured} coloured pixels of the picked-out object");
        let shot = c.screenshot().await.unwrap();
        c.close().await.unwrap();
        shot
    });
    // The screenshot (PNG) shows the zone's border and a person track in their colours.
    let decoder = png::Decoder::new(std::io::Cursor::new(&screenshot));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0u8; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let near = |px: &[u8], rgb: [u8; 3]| {
        px.iter()
            .zip(rgb)
            .all(|(&a, b)| (i16::from(a) - i16::from(b)).abs() <= 40)
    };
    let (mut zone, mut person) = (0, 0);
    for px in buf[..info.buffer_size()].chunks_exact(channels) {
        zone += usize::from(near(px, [0xff, 0x52, 0x52]));
        person += usize::from(near(px, [0x00, 0xe6, 0x76]));
    }
    assert!(zone > 100, "{zone} zone-border pixels");
    assert!(person > 30, "{person} person-track pixels");
    let keep = std::env::var_os("METAMORAN_SCREENSHOT").map_or_else(
        || out.path().join("site-view.png"),
        std::path::PathBuf::from,
    );
    std::fs::write(&keep, &screenshot).unwrap();
    eprintln!(
        "screenshot: {} ({zone} zone, {person} person pixels)",
        keep.display()
    );

    // Logins are limited per address: after 5 failures in a minute the next is refused even
    // with the right password. (The browser's two attempts above count too.)
    let mut codes = Vec::new();
    for _ in 0..5 {
        codes.push(status_of(&post_login(addr, "user=operator&password=nope")));
    }
    codes.push(status_of(&post_login(
        addr,
        &format!("user=operator&password={PASSWORD}"),
    )));
    assert!(codes.contains(&401), "{codes:?}");
    assert_eq!(codes.last(), Some(&429), "{codes:?}");
    // A request body beyond the bound is refused.
    let big = "x".repeat(metamoran_web::MAX_BODY_BYTES + 1);
    assert_eq!(status_of(&post_login(addr, &big)), 413);
    server.stop();
}

/// One HTTP/1.1 exchange over TLS with a client that trusts only `ca` (PEM); the reply.
fn https(addr: std::net::SocketAddr, ca: &str, head: &str, body: &str) -> String {
    use rustls::pki_types::pem::PemObject;
    use std::io::{Read, Write};
    let mut roots = rustls::RootCertStore::empty();
    for cert in rustls::pki_types::CertificateDer::pem_slice_iter(ca.as_bytes()) {
        roots.add(cert.unwrap()).unwrap();
    }
    let config = rustls::ClientConfig::builder_with_provider(std::sync::Arc::new(
        rustls::crypto::ring::default_provider(),
    ))
    .with_safe_default_protocol_versions()
    .unwrap()
    .with_root_certificates(roots)
    .with_no_client_auth();
    let name = rustls::pki_types::ServerName::try_from("localhost").unwrap();
    let conn = rustls::ClientConnection::new(std::sync::Arc::new(config), name).unwrap();
    let tcp = std::net::TcpStream::connect(addr).unwrap();
    let mut tls = rustls::StreamOwned::new(conn, tcp);
    write!(
        tls,
        "{head}\r\nHost: localhost\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut reply = Vec::new();
    let _ = tls.read_to_end(&mut reply);
    String::from_utf8_lossy(&reply).into_owned()
}

#[test]
fn the_page_is_served_over_https_and_plain_http_only_on_loopback() {
    let out = tempfile::tempdir().unwrap();
    // The simulated site's plan; no sensor is replayed (the state is what is checked).
    let file = SiteFile::parse(&metamoran_sim::site::site_toml("site-tls")).unwrap();
    let users = Users::parse(&format!("operator:{}", hash_password(PASSWORD).unwrap())).unwrap();
    let made = rcgen::generate_simple_self_signed(vec!["localhost".to_owned()]).unwrap();
    let (cert, key) = (out.path().join("cert.pem"), out.path().join("key.pem"));
    std::fs::write(&cert, made.cert.pem()).unwrap();
    std::fs::write(&key, made.key_pair.serialize_pem()).unwrap();
    let options =
        |listen: &str, tls: Option<metamoran_web::tls::TlsFiles>| metamoran_web::ServeOptions {
            site: file.clone(),
            users: users.clone(),
            feed: metamoran_web::replay_feed(Vec::new(), 0.25),
            listen: listen.parse().unwrap(),
            session_ttl: Duration::from_secs(600),
            silence_s: 60.0,
            bundles: None,
            tls,
        };
    let files = metamoran_web::tls::TlsFiles {
        cert: cert.clone(),
        key: key.clone(),
    };
    let server = metamoran_web::start(options("127.0.0.1:0", Some(files.clone()))).unwrap();
    let addr = server.addr();
    // Logging in over HTTPS gives a session cookie browsers send only over HTTPS.
    let reply = https(
        addr,
        &made.cert.pem(),
        "POST /login HTTP/1.1\r\nContent-Type: application/x-www-form-urlencoded",
        &format!("user=operator&password={PASSWORD}"),
    );
    assert_eq!(status_of(&reply), 303, "{reply}");
    let cookie_line = reply
        .lines()
        .find(|l| l.to_ascii_lowercase().starts_with("set-cookie:"))
        .unwrap_or_else(|| panic!("{reply}"));
    assert!(cookie_line.contains("; Secure"), "{cookie_line}");
    let cookie = cookie_line
        .split_once(':')
        .and_then(|(_, v)| v.trim().split(';').next())
        .unwrap();
    let state = https(
        addr,
        &made.cert.pem(),
        &format!("GET /api/state HTTP/1.1\r\nCookie: {cookie}"),
        "",
    );
    assert_eq!(status_of(&state), 200, "{state}");
    assert!(state.contains("\"tracks\""), "{state}");
    // Plain HTTP to the HTTPS port gets no HTTP answer (the server may close the connection
    // before the request is even written).
    let plain = {
        use std::io::{Read, Write};
        let mut s = std::net::TcpStream::connect(addr).unwrap();
        let _ = s.write_all(b"GET / HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n");
        let mut reply = Vec::new();
        let _ = s.read_to_end(&mut reply);
        String::from_utf8_lossy(&reply).into_owned()
    };
    assert!(!plain.contains("HTTP/1.1 "), "{plain}");
    server.stop();
    // Plain HTTP is refused on an address other hosts reach; a bad key file is named.
    let refused = metamoran_web::start(options("0.0.0.0:0", None))
        .err()
        .unwrap();
    assert!(
        refused.to_string().contains("not a loopback address"),
        "{refused}"
    );
    std::fs::write(&key, "not a key").unwrap();
    let bad = metamoran_web::start(options("127.0.0.1:0", Some(files)))
        .err()
        .unwrap();
    assert!(bad.to_string().contains("key.pem"), "{bad}");
}
