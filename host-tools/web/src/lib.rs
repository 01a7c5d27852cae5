//! `metamoran serve`: the operator's web view of a site (issue #20 part 4), the end of the
//! data flow. The server runs the site fusion on the sensors' track messages (from NATS, or a
//! simulated site replayed in real time), and serves one page: the plan with zones, sensors and
//! their coverage, live tracks with trails, the alerts to acknowledge, sensor health. Updates go
//! to the page as server-sent events.
//!
//! ```text
//! NATS metamoran.<site>.*.tracks ─┐
//!   (or a replayed site)          ├▶ Live (site fusion, trails, alerts, health) ─▶ SSE ─▶ page
//!                                 └─ acknowledgements ◀── POST /api/ack ◀──────────────── page
//! ```
//!
//! Security: every route but the login needs a session (a random 256-bit token in an
//! `HttpOnly`, `SameSite=Strict` cookie, expiring); passwords are checked against argon2id
//! hashes from a file; login attempts are limited per address; request bodies are bounded;
//! the page builds every string it shows with `textContent`, and the only server-rendered
//! string (the site name) is escaped. HTTPS with `--tls-cert`/`--tls-key` ([`tls`], rustls;
//! session cookies are then `Secure`); without them only a loopback address is served, for the
//! site's TLS proxy in front.

pub mod live;
pub mod login;
mod pictures;
pub mod tls;

use axum::extract::{ConnectInfo, DefaultBodyLimit, Form, State};
use axum::http::{HeaderMap, StatusCode, header};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{Html, IntoResponse, Redirect, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use live::Live;
use login::{Sessions, Users};
use metamoran_operator::nats::NatsConfig;
use metamoran_operator::site::{SensorTracks, Site, SiteConfig, SiteFile, SiteMessages};
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// What went wrong starting the server.
#[derive(Debug, thiserror::Error)]
pub enum WebError {
    /// The users file is unreadable or malformed.
    #[error("{path}: {problem}")]
    Users {
        /// The file.
        path: String,
        /// The line and what is wrong.
        problem: String,
    },
    /// The address cannot be listened on.
    #[error("--listen {addr}: {problem}")]
    Listen {
        /// The address.
        addr: SocketAddr,
        /// Why.
        problem: String,
    },
    /// The NATS server cannot be used.
    #[error(transparent)]
    Nats(#[from] metamoran_operator::OperatorError),
    /// A TLS certificate or key file cannot be read or used.
    #[error("{path}: {problem}")]
    Tls {
        /// The file.
        path: String,
        /// What is wrong with it.
        problem: String,
    },
    /// Plain HTTP asked for on an address other hosts can reach.
    #[error(
        "--listen {0}: not a loopback address; serve over TLS (--tls-cert FILE --tls-key FILE) or listen on loopback behind the site's TLS proxy"
    )]
    PlainHttp(SocketAddr),
}

/// Where the sensors' messages come from.
#[derive(Clone, Debug)]
pub enum Feed {
    /// Subscribe to `metamoran.<site>.*.tracks` on this server; acknowledgements go to the
    /// site's alert stream (`metamoran.<site>.operator.acks`).
    Nats(NatsConfig),
    /// Each sensor's messages, replayed at `period_s` per frame, over and over (a simulated
    /// site: `metamoran simulate --preset site`).
    Replay {
        /// Sensor id and its messages, frame by frame.
        sensors: SiteMessages,
        /// Seconds per frame.
        period_s: f64,
    },
}

/// How to serve.
#[derive(Clone, Debug)]
pub struct ServeOptions {
    /// The site.
    pub site: SiteFile,
    /// Who may log in.
    pub users: Users,
    /// The sensors' messages.
    pub feed: Feed,
    /// Address to listen on (port 0: any free port).
    pub listen: SocketAddr,
    /// How long a session lasts.
    pub session_ttl: Duration,
    /// Seconds without a message after which a sensor raises a `silent` alert.
    pub silence_s: f64,
    /// The folder with each sensor's bundle (`DIR/<sensor>/`), for the selected track's
    /// pictures; without it the page shows none.
    pub bundles: Option<std::path::PathBuf>,
    /// Serve HTTPS with this certificate and key; without it only a loopback address is
    /// served (plain HTTP, for a TLS proxy in front).
    pub tls: Option<tls::TlsFiles>,
}

/// Largest request body, bytes (a login form or an acknowledgement).
pub const MAX_BODY_BYTES: usize = 8 * 1024;
/// Largest sensor message taken from NATS, bytes.
pub const MAX_MESSAGE_BYTES: usize = 256 * 1024;

struct App {
    live: Mutex<Live>,
    sessions: Mutex<Sessions>,
    users: Users,
    plan: serde_json::Value,
    title: String,
    ttl: Duration,
    changed: tokio::sync::watch::Sender<u64>,
    acks: Option<(async_nats::jetstream::Context, String)>,
    /// The sensors' bundles, for the selected track's pictures.
    bundles: Option<pictures::Bundles>,
    /// Whether the page is served over TLS (session cookies are then `Secure`).
    secure: bool,
}

type Shared = Arc<App>;

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// `&`, `<`, `>`, `"` and `'` as HTML entities.
pub fn escape_html(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// The plan the page draws: extent, sensors with coverage, zones.
fn plan(site: &SiteFile) -> serde_json::Value {
    serde_json::json!({
        "name": site.name,
        "extent": site.extent,
        "sensors": site.sensors.iter().map(|s| serde_json::json!({
            "id": s.id, "position": s.position, "heading_deg": s.heading_deg,
            "range_m": s.range_m, "fov_deg": s.fov_deg,
        })).collect::<Vec<_>>(),
        "zones": site.perimeter.zones.iter().map(|z| serde_json::json!({
            "name": z.name, "polygon": z.polygon,
        })).collect::<Vec<_>>(),
    })
}

/// A running server.
pub struct Server {
    addr: SocketAddr,
    runtime: tokio::runtime::Runtime,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
}

impl Server {
    /// The address it listens on.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Serves until the process is stopped.
    pub fn wait(self) {
        self.runtime.block_on(std::future::pending::<()>());
    }

    /// Stops serving.
    pub fn stop(mut self) {
        if let Some(s) = self.stop.take() {
            let _ = s.send(());
        }
        self.runtime.shutdown_timeout(Duration::from_secs(2));
    }
}

fn now_unix_s() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// Starts the server and its feed on their own runtime; returns once it listens.
///
/// # Errors
/// [`WebError`] if the address cannot be bound or the NATS server cannot be used.
pub fn start(options: ServeOptions) -> Result<Server, WebError> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| WebError::Listen {
            addr: options.listen,
            problem: e.to_string(),
        })?;
    let ServeOptions {
        site,
        users,
        feed,
        listen,
        session_ttl,
        silence_s,
        bundles,
        tls,
    } = options;
    let acceptor = match &tls {
        Some(files) => Some(tls::acceptor(files)?),
        None if !tls::is_loopback(&listen) => return Err(WebError::PlainHttp(listen)),
        None => None,
    };
    let (changed, _) = tokio::sync::watch::channel(0u64);
    let nats = match &feed {
        Feed::Nats(config) => Some(runtime.block_on(connect(config))?),
        Feed::Replay { .. } => None,
    };
    // The JetStream context spawns its task on the runtime it is made in.
    let _in_runtime = runtime.enter();
    let app = Arc::new(App {
        plan: plan(&site),
        title: escape_html(&site.name),
        live: Mutex::new(Live::new(
            Site::new(site.clone(), SiteConfig::default()),
            silence_s,
        )),
        sessions: Mutex::new(Sessions::default()),
        users,
        ttl: session_ttl,
        changed,
        bundles: bundles.map(pictures::Bundles::new),
        secure: acceptor.is_some(),
        acks: nats.as_ref().map(|(client, config)| {
            (
                async_nats::jetstream::new(client.clone()),
                format!("metamoran.{}.operator.acks", config.site),
            )
        }),
    });
    let listener = runtime
        .block_on(tokio::net::TcpListener::bind(listen))
        .map_err(|e| WebError::Listen {
            addr: listen,
            problem: e.to_string(),
        })?;
    let addr = listener.local_addr().map_err(|e| WebError::Listen {
        addr: listen,
        problem: e.to_string(),
    })?;
    match (feed, nats) {
        (
            Feed::Replay {
                sensors, period_s, ..
            },
            _,
        ) => {
            runtime.spawn(replay(app.clone(), sensors, period_s));
        }
        (Feed::Nats(_), Some((client, config))) => {
            runtime.spawn(subscribe(app.clone(), client, config));
        }
        (Feed::Nats(_), None) => {}
    }
    runtime.spawn(watch_silence(app.clone()));
    let router = Router::new()
        .route("/", get(index))
        .route("/login", post(do_login))
        .route("/logout", post(do_logout))
        .route("/api/plan", get(api_plan))
        .route("/api/state", get(api_state))
        .route("/api/ack", post(api_ack))
        .route("/api/track/{id}/{picture}", get(pictures::track_picture))
        .route("/events", get(events))
        .layer(DefaultBodyLimit::max(MAX_BODY_BYTES))
        .with_state(app);
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    match acceptor {
        Some(acceptor) => {
            runtime.spawn(tls::serve(listener, acceptor, router, stopped));
        }
        None => {
            runtime.spawn(async move {
                let serve = axum::serve(
                    listener,
                    router.into_make_service_with_connect_info::<SocketAddr>(),
                )
                .with_graceful_shutdown(async {
                    let _ = stopped.await;
                });
                let _ = serve.await;
            });
        }
    }
    Ok(Server {
        addr,
        runtime,
        stop: Some(stop),
    })
}

async fn connect(
    config: &NatsConfig,
) -> Result<(async_nats::Client, NatsConfig), metamoran_operator::OperatorError> {
    // The publisher's connection logic, through a sensor-less handle.
    let client = metamoran_operator::nats::connect_client(config, "metamoran-serve").await?;
    Ok((client, config.clone()))
}

fn notify(app: &App, version: u64) {
    app.changed.send_replace(version);
}

async fn replay(app: Shared, sensors: SiteMessages, period_s: f64) {
    let frames = sensors.iter().map(|s| s.1.len()).max().unwrap_or(0);
    if frames == 0 || !(period_s.is_finite() && period_s > 0.0) {
        return;
    }
    let mut tick = tokio::time::interval(Duration::from_secs_f64(period_s));
    let cycle_s = frames as f64 * period_s;
    for lap in 0u32.. {
        for f in 0..frames {
            tick.tick().await;
            let version = {
                let mut live = lock(&app.live);
                for (id, messages) in &sensors {
                    if let Some(m) = messages.get(f) {
                        // Each lap goes on in frame number and time, as a live sensor would.
                        let m = SensorTracks {
                            frame: m.frame + lap * frames as u32,
                            time_s: m.time_s + f64::from(lap) * cycle_s,
                            tracks: m.tracks.clone(),
                        };
                        live.ingest(id, &m, Instant::now());
                    }
                }
                live.version
            };
            notify(&app, version);
        }
    }
}

async fn subscribe(app: Shared, client: async_nats::Client, config: NatsConfig) {
    use tokio_stream::StreamExt;
    let subject = format!("metamoran.{}.*.tracks", config.site);
    let Ok(mut sub) = client.subscribe(subject).await else {
        return;
    };
    while let Some(m) = sub.next().await {
        let sensor = m.subject.split('.').nth(2).unwrap_or("").to_owned();
        let (version, alerts) = {
            let mut live = lock(&app.live);
            let parsed = if m.payload.len() > MAX_MESSAGE_BYTES {
                Err(format!(
                    "{} bytes; at most {MAX_MESSAGE_BYTES}",
                    m.payload.len()
                ))
            } else {
                serde_json::from_slice::<SensorTracks>(&m.payload)
                    .map_err(|e| format!("not a tracks message ({e})"))
            };
            let alerts = match parsed {
                Ok(tracks) => live.ingest(&sensor, &tracks, Instant::now()),
                Err(problem) => {
                    live.refuse(&sensor, problem);
                    Vec::new()
                }
            };
            (live.version, alerts)
        };
        // The site's own alerts (zones evaluated once, with the sensors that saw each object)
        // go into the stream, stored before the page shows them.
        if let Some((js, _)) = &app.acks {
            let subject = format!("metamoran.{}.site.alerts", config.site);
            for a in &alerts {
                let body = serde_json::to_vec(a).unwrap_or_default();
                if let Ok(ack) = js.publish(subject.clone(), body.into()).await {
                    let _ = ack.await;
                }
            }
        }
        notify(&app, version);
    }
}

async fn watch_silence(app: Shared) {
    let mut tick = tokio::time::interval(Duration::from_millis(500));
    loop {
        tick.tick().await;
        let raised = {
            let mut live = lock(&app.live);
            live.check_silence(Instant::now()).then_some(live.version)
        };
        if let Some(v) = raised {
            notify(&app, v);
        }
    }
}

/// The user of the request's session cookie.
fn session_user(app: &App, headers: &HeaderMap) -> Option<String> {
    let cookies = headers.get(header::COOKIE)?.to_str().ok()?;
    let token = cookies
        .split(';')
        .filter_map(|c| c.trim().strip_prefix("mm_session="))
        .next()?;
    lock(&app.sessions)
        .user(token, Instant::now())
        .map(String::from)
}

fn unauthorized() -> Response {
    (StatusCode::UNAUTHORIZED, "log in first").into_response()
}

const PAGE: &str = include_str!("page.html");
const LOGIN: &str = include_str!("login.html");

fn login_page(app: &App, message: &str) -> Html<String> {
    Html(
        LOGIN
            .replace("{{title}}", &app.title)
            .replace("{{message}}", &escape_html(message)),
    )
}

async fn index(State(app): State<Shared>, headers: HeaderMap) -> Response {
    match session_user(&app, &headers) {
        Some(user) => Html(
            PAGE.replace("{{title}}", &app.title)
                .replace("{{user}}", &escape_html(&user)),
        )
        .into_response(),
        None => login_page(&app, "").into_response(),
    }
}

#[derive(serde::Deserialize)]
struct LoginForm {
    user: String,
    password: String,
}

async fn do_login(
    State(app): State<Shared>,
    ConnectInfo(peer): ConnectInfo<SocketAddr>,
    Form(form): Form<LoginForm>,
) -> Response {
    if !lock(&app.sessions).attempt(peer.ip(), Instant::now()) {
        return (
            StatusCode::TOO_MANY_REQUESTS,
            login_page(&app, "too many attempts; wait a minute"),
        )
            .into_response();
    }
    let users = app.users.clone();
    let (user, password) = (form.user, form.password);
    let checked =
        tokio::task::spawn_blocking(move || users.verify(&user, &password).then_some(user))
            .await
            .ok()
            .flatten();
    let Some(user) = checked else {
        return (
            StatusCode::UNAUTHORIZED,
            login_page(&app, "wrong user or password"),
        )
            .into_response();
    };
    let token = lock(&app.sessions).open(&user, app.ttl, Instant::now());
    let cookie = format!(
        "mm_session={token}; HttpOnly; SameSite=Strict; Path=/; Max-Age={}{}",
        app.ttl.as_secs(),
        if app.secure { "; Secure" } else { "" }
    );
    ([(header::SET_COOKIE, cookie)], Redirect::to("/")).into_response()
}

async fn do_logout(State(app): State<Shared>, headers: HeaderMap) -> Response {
    if let Some(token) = headers
        .get(header::COOKIE)
        .and_then(|c| c.to_str().ok())
        .and_then(|c| {
            c.split(';')
                .find_map(|c| c.trim().strip_prefix("mm_session="))
        })
    {
        lock(&app.sessions).close(token);
    }
    Redirect::to("/").into_response()
}

async fn api_plan(State(app): State<Shared>, headers: HeaderMap) -> Response {
    if session_user(&app, &headers).is_none() {
        return unauthorized();
    }
    Json(app.plan.clone()).into_response()
}

async fn api_state(State(app): State<Shared>, headers: HeaderMap) -> Response {
    if session_user(&app, &headers).is_none() {
        return unauthorized();
    }
    Json(lock(&app.live).snapshot(Instant::now())).into_response()
}

#[derive(serde::Deserialize)]
struct AckRequest {
    id: u64,
}

async fn api_ack(
    State(app): State<Shared>,
    headers: HeaderMap,
    Json(req): Json<AckRequest>,
) -> Response {
    let Some(user) = session_user(&app, &headers) else {
        return unauthorized();
    };
    let (entry, version) = {
        let mut live = lock(&app.live);
        (live.acknowledge(req.id, &user, now_unix_s()), live.version)
    };
    let Some(entry) = entry else {
        return (StatusCode::NOT_FOUND, "no such alert").into_response();
    };
    // Recorded in the site's alert stream before the page hears it was taken.
    if let Some((js, subject)) = &app.acks {
        let body = serde_json::to_vec(&entry).unwrap_or_default();
        let stored = match js.publish(subject.clone(), body.into()).await {
            Ok(ack) => ack.await.is_ok(),
            Err(_) => false,
        };
        if !stored {
            return (
                StatusCode::SERVICE_UNAVAILABLE,
                "the acknowledgement could not be stored in the stream; try again",
            )
                .into_response();
        }
    }
    notify(&app, version);
    Json(entry).into_response()
}

async fn events(State(app): State<Shared>, headers: HeaderMap) -> Response {
    if session_user(&app, &headers).is_none() {
        return unauthorized();
    }
    let rx = app.changed.subscribe();
    let stream = tokio_stream::wrappers::WatchStream::new(rx);
    let app2 = app.clone();
    let events = tokio_stream::StreamExt::map(stream, move |_| {
        let state = lock(&app2.live).snapshot(Instant::now());
        Ok::<_, std::convert::Infallible>(Event::default().data(state.to_string()))
    });
    Sse::new(events)
        .keep_alive(KeepAlive::default())
        .into_response()
}

/// `serve`'s replay feed for a simulated site folder: each sensor's messages from
/// `sensor_tracks` (the caller processes the bundles).
pub fn replay_feed(sensors: SiteMessages, period_s: f64) -> Feed {
    Feed::Replay { sensors, period_s }
}

#[cfg(test)]
mod tests {
    use super::escape_html;

    #[test]
    fn escaping_leaves_no_markup() {
        assert_eq!(
            escape_html(r#"<script>alert("x")</script> & 'y'"#),
            "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt; &amp; &#39;y&#39;"
        );
    }
}
