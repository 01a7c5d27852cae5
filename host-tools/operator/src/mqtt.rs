//! MQTT publishing for fleet use (rumqttc, MQTT 3.1.1): per frame the objects at QoS 0
//! (`metamoran/<sensor>/objects`, JSON, newest wins), alerts at QoS 1
//! (`metamoran/<sensor>/alerts`, every one delivered at least once), and a retained status
//! (`metamoran/<sensor>/status`): `online` while connected, `stopped` after a clean end, and
//! the broker's last will `offline` when the connection is lost without one.
//!
//! Publishing never blocks the sensor and survives the broker (issue #18, item 10):
//! - every QoS 1 message (alerts, status) waits in an outbox until the broker's PUBACK for it;
//!   the network loop reconnects with exponential backoff (0.1 s to 5 s) and, when the broker
//!   lost our session (a restart without persistence), publishes every unacknowledged one again,
//!   in order; frames go on meanwhile (objects, QoS 0, are dropped while disconnected);
//! - the session is persistent (`clean_session = false`), so a broker that kept it resends
//!   nothing twice: rumqttc retransmits the in-flight messages with their packet ids;
//! - alerts are on disk first ([`crate::alert_log`]): a broker that never comes back loses
//!   nothing, and [`Publisher::close`] says how many were not acknowledged.

use crate::OperatorError;
use crate::geofence::Alert;
use metamoran_process::FrameResult;
use rumqttc::{Client, Connection, Event, LastWill, MqttOptions, Packet, QoS};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, mpsc};
use std::thread::JoinHandle;
use std::time::Duration;

/// Where and as whom to publish.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MqttConfig {
    /// Broker host.
    pub host: String,
    /// Broker port.
    pub port: u16,
    /// Sensor id: the topic level under `metamoran/` and the MQTT client id.
    pub sensor: String,
    /// TLS to the broker (`None`: plain TCP, for a broker on loopback only).
    pub tls: Option<MqttTls>,
    /// Username and password for the broker.
    pub login: Option<MqttLogin>,
}

/// TLS to the broker: the CA that signs its certificate, and the client's own certificate
/// where the broker requires one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MqttTls {
    /// PEM file of the CA certificate(s) trusted for the broker.
    pub ca: PathBuf,
    /// PEM files of the client certificate chain and its private key.
    pub client: Option<(PathBuf, PathBuf)>,
}

/// A broker login. `Debug` never shows the password.
#[derive(Clone, PartialEq, Eq)]
pub struct MqttLogin {
    /// Username.
    pub username: String,
    password: String,
}

impl std::fmt::Debug for MqttLogin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "MqttLogin({}, ..)", self.username)
    }
}

impl MqttLogin {
    /// `username` with `password` (from a file or the environment, never the command line).
    pub fn new(username: &str, password: String) -> Self {
        Self {
            username: username.to_owned(),
            password,
        }
    }

    /// The password, for the client that logs in with it.
    pub(crate) fn password(&self) -> &str {
        &self.password
    }
}

fn security(what: &Path, problem: impl ToString) -> OperatorError {
    OperatorError::MqttSecurity {
        what: what.display().to_string(),
        problem: problem.to_string(),
    }
}

impl MqttTls {
    /// The rustls client configuration: the CA as the only root, TLS 1.2 and 1.3 (ring).
    ///
    /// # Errors
    /// [`OperatorError::MqttSecurity`] naming the unreadable or invalid file.
    pub fn client_config(&self) -> Result<rustls::ClientConfig, OperatorError> {
        use rustls_pki_types::pem::PemObject;
        use rustls_pki_types::{CertificateDer, PrivateKeyDer};
        let certs = |path: &Path| -> Result<Vec<CertificateDer<'static>>, OperatorError> {
            let certs = CertificateDer::pem_file_iter(path)
                .and_then(Iterator::collect::<Result<Vec<_>, _>>)
                .map_err(|e| security(path, format!("not a PEM certificate file ({e})")))?;
            if certs.is_empty() {
                return Err(security(path, "holds no certificate"));
            }
            Ok(certs)
        };
        let mut roots = rustls::RootCertStore::empty();
        for cert in certs(&self.ca)? {
            roots
                .add(cert)
                .map_err(|e| security(&self.ca, format!("not a usable CA certificate ({e})")))?;
        }
        let provider = Arc::new(rustls::crypto::ring::default_provider());
        let builder = rustls::ClientConfig::builder_with_provider(provider)
            .with_safe_default_protocol_versions()
            .map_err(|e| security(&self.ca, e))?
            .with_root_certificates(roots);
        match &self.client {
            None => Ok(builder.with_no_client_auth()),
            Some((cert, key)) => {
                let chain = certs(cert)?;
                let key = PrivateKeyDer::from_pem_file(key)
                    .map_err(|e| security(key, format!("not a PEM private key ({e})")))?;
                builder
                    .with_client_auth_cert(chain, key)
                    .map_err(|e| security(cert, format!("does not match its key ({e})")))
            }
        }
    }
}

impl MqttConfig {
    /// Parses `HOST:PORT` (port 1883 if omitted) for sensor `sensor`.
    ///
    /// # Errors
    /// [`OperatorError`] saying what form is expected.
    pub fn parse(broker: &str, sensor: &str) -> Result<Self, OperatorError> {
        let (host, port) = match broker.rsplit_once(':') {
            Some((h, p)) => (
                h,
                p.parse().map_err(|_| OperatorError::MqttAddress {
                    broker: broker.to_owned(),
                    problem: "the port must be a number (HOST:PORT)".to_owned(),
                })?,
            ),
            None => (broker, 1883),
        };
        if host.is_empty() || sensor.is_empty() || sensor.contains(['/', '+', '#']) {
            return Err(OperatorError::MqttAddress {
                broker: broker.to_owned(),
                problem: format!("sensor {sensor:?}: give HOST:PORT and a sensor id without / + #"),
            });
        }
        Ok(Self {
            host: host.to_owned(),
            port,
            sensor: sensor.to_owned(),
            tls: None,
            login: None,
        })
    }

    /// The client options for client id `client_id`: keep-alive 5 s, TLS and login as set.
    ///
    /// # Errors
    /// [`OperatorError::MqttSecurity`] if a TLS file is unusable.
    pub fn options(&self, client_id: &str) -> Result<MqttOptions, OperatorError> {
        let mut options = MqttOptions::new(client_id, &self.host, self.port);
        options.set_keep_alive(Duration::from_secs(5));
        if let Some(tls) = &self.tls {
            let config = tls.client_config()?;
            options.set_transport(rumqttc::Transport::tls_with_config(
                rumqttc::TlsConfiguration::Rustls(Arc::new(config)),
            ));
        }
        if let Some(login) = &self.login {
            options.set_credentials(login.username.clone(), login.password.clone());
        }
        Ok(options)
    }

    /// The topic `metamoran/<sensor>/<leaf>`.
    pub fn topic(&self, leaf: &str) -> String {
        format!("metamoran/{}/{leaf}", self.sensor)
    }
}

/// A QoS 1 message waiting for its PUBACK.
#[derive(Debug)]
struct Pending {
    topic: String,
    retain: bool,
    payload: Vec<u8>,
    /// Handed to the client in the current broker session.
    handed: bool,
    /// The packet id the client gave it (when it went out).
    pkid: Option<u16>,
}

/// The outbox shared by the publishing side and the network loop.
#[derive(Debug, Default)]
struct Outbox {
    pending: std::collections::VecDeque<Pending>,
    /// Messages ever queued, and acknowledged.
    queued: u64,
    acked: u64,
    connected: bool,
    reconnects: u32,
    last_error: Option<String>,
}

impl Outbox {
    /// Hands every message not yet handed in this session to `client`, in order, until its
    /// queue is full.
    fn hand(&mut self, client: &Client) {
        for p in self.pending.iter_mut().filter(|p| !p.handed) {
            let sent = client.try_publish(
                p.topic.clone(),
                QoS::AtLeastOnce,
                p.retain,
                p.payload.clone(),
            );
            if sent.is_err() {
                return;
            }
            p.handed = true;
        }
    }

    /// A QoS 1 publish went out with `pkid`: a retransmission if some message has it, else it
    /// is the oldest handed message without one (the client sends them in order).
    fn went_out(&mut self, pkid: u16) {
        if pkid == 0 || self.pending.iter().any(|p| p.pkid == Some(pkid)) {
            return;
        }
        if let Some(p) = self
            .pending
            .iter_mut()
            .find(|p| p.handed && p.pkid.is_none())
        {
            p.pkid = Some(pkid);
        }
    }

    /// The broker acknowledged `pkid`.
    fn acknowledged(&mut self, pkid: u16) {
        if let Some(i) = self.pending.iter().position(|p| p.pkid == Some(pkid)) {
            self.pending.remove(i);
            self.acked += 1;
        }
    }

    /// A new broker session that does not hold ours: whatever was handed is gone from the
    /// client; hand it again.
    fn session_lost(&mut self) {
        for p in &mut self.pending {
            p.handed = false;
            p.pkid = None;
        }
    }
}

/// A publisher; its network loop runs on a thread and reconnects on its own.
pub struct Publisher {
    client: Client,
    config: MqttConfig,
    stop: Arc<AtomicBool>,
    outbox: Arc<Mutex<Outbox>>,
    /// QoS 0 messages dropped because the client's queue was full (broker away).
    dropped: std::sync::atomic::AtomicU32,
    pump: Option<JoinHandle<()>>,
}

/// How long to wait for the broker's first CONNACK.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);
/// How long [`Publisher::close`] waits for the last acknowledgements.
pub const CLOSE_TIMEOUT: Duration = Duration::from_secs(30);
/// Longest wait between two reconnection attempts.
const MAX_BACKOFF: Duration = Duration::from_secs(5);

impl Publisher {
    /// Connects (persistent session, last will `offline` retained) and publishes `online`
    /// retained; returns once the broker has acknowledged it.
    ///
    /// # Errors
    /// [`OperatorError`] naming the broker when it does not accept the connection in 5 s.
    pub fn connect(config: &MqttConfig) -> Result<Self, OperatorError> {
        let mut options = config.options(&format!("metamoran-{}", config.sensor))?;
        options
            .set_clean_session(false)
            .set_last_will(LastWill::new(
                config.topic("status"),
                "offline",
                QoS::AtLeastOnce,
                true,
            ));
        let (client, connection) = Client::new(options, 64);
        let stop = Arc::new(AtomicBool::new(false));
        let outbox = Arc::new(Mutex::new(Outbox::default()));
        let (ready, connected) = mpsc::channel();
        let pump = std::thread::spawn({
            let (stop, outbox, client) = (stop.clone(), outbox.clone(), client.clone());
            move || pump(connection, &client, &stop, &outbox, ready)
        });
        let broker = format!("{}:{}", config.host, config.port);
        let first = connected.recv_timeout(CONNECT_TIMEOUT);
        let mut p = Self {
            client,
            config: config.clone(),
            stop,
            outbox,
            dropped: std::sync::atomic::AtomicU32::new(0),
            pump: Some(pump),
        };
        match first {
            Ok(Ok(())) => {}
            Ok(Err(problem)) => {
                p.halt();
                return Err(OperatorError::Broker { broker, problem });
            }
            Err(_) => {
                p.halt();
                return Err(OperatorError::Broker {
                    broker,
                    problem: "no answer in 5 s; is it running?".to_owned(),
                });
            }
        }
        p.reliable("status", true, b"online".to_vec());
        p.flush(CONNECT_TIMEOUT)?;
        Ok(p)
    }

    fn broker(&self) -> String {
        format!("{}:{}", self.config.host, self.config.port)
    }

    fn outbox(&self) -> std::sync::MutexGuard<'_, Outbox> {
        self.outbox
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Waits up to `timeout` until the broker has acknowledged every QoS 1 message so far.
    ///
    /// # Errors
    /// [`OperatorError`] naming the broker and how many are still unacknowledged.
    pub fn flush(&self, timeout: Duration) -> Result<(), OperatorError> {
        let deadline = std::time::Instant::now() + timeout;
        loop {
            let (left, error) = {
                let mut o = self.outbox();
                o.hand(&self.client);
                (o.pending.len(), o.last_error.clone())
            };
            if left == 0 {
                return Ok(());
            }
            if std::time::Instant::now() > deadline {
                return Err(OperatorError::Broker {
                    broker: self.broker(),
                    problem: format!(
                        "{left} alert/status message(s) unacknowledged after {timeout:?}{}; \
                         the alerts are in alerts.jsonl",
                        error.map_or(String::new(), |e| format!(" (last error: {e})"))
                    ),
                });
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// Queues a QoS 1 message: kept until the broker acknowledges it.
    fn reliable(&self, leaf: &str, retain: bool, payload: Vec<u8>) {
        let mut o = self.outbox();
        o.pending.push_back(Pending {
            topic: self.config.topic(leaf),
            retain,
            payload,
            handed: false,
            pkid: None,
        });
        o.queued += 1;
        o.hand(&self.client);
    }

    /// Publishes a frame's objects (QoS 0); dropped (and counted) while the broker is away.
    pub fn frame(&self, frame: &FrameResult) {
        let objects: Vec<_> = frame
            .objects
            .iter()
            .map(|o| {
                serde_json::json!({
                    "instance": o.instance, "class": o.class, "detected": o.detected,
                    "depth_m": o.depth_m, "azimuth_deg": o.azimuth_deg,
                    "confidence_db": o.confidence_db,
                })
            })
            .collect();
        let body = serde_json::json!({ "frame": frame.frame, "objects": objects });
        // Retry what waits first: alerts go before objects.
        self.outbox().hand(&self.client);
        let sent = self.client.try_publish(
            self.config.topic("objects"),
            QoS::AtMostOnce,
            false,
            body.to_string().into_bytes(),
        );
        if sent.is_err() {
            self.dropped.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Publishes an alert (QoS 1): queued until the broker acknowledges it, never blocking.
    pub fn alert(&self, alert: &Alert) {
        // An Alert is plain data: serializing it cannot fail.
        let body = serde_json::to_vec(alert).unwrap_or_default();
        self.reliable("alerts", false, body);
    }

    /// What the link did: messages queued and acknowledged, reconnections, objects dropped.
    pub fn stats(&self) -> PublishStats {
        let o = self.outbox();
        PublishStats {
            queued: o.queued,
            acked: o.acked,
            reconnects: o.reconnects,
            objects_dropped: self.dropped.load(Ordering::Relaxed),
            connected: o.connected,
        }
    }

    /// Publishes `stopped` retained and disconnects cleanly (no last will) once the broker has
    /// acknowledged every QoS 1 message (alerts, status), waiting up to [`CLOSE_TIMEOUT`].
    ///
    /// # Errors
    /// [`OperatorError`] if the broker does not acknowledge them in time.
    pub fn close(mut self) -> Result<PublishStats, OperatorError> {
        self.reliable("status", true, b"stopped".to_vec());
        let flushed = self.flush(CLOSE_TIMEOUT);
        let stats = self.stats();
        if flushed.is_err() {
            self.halt();
            return flushed.map(|()| stats);
        }
        let _ = self.client.disconnect();
        if let Some(p) = self.pump.take() {
            let _ = p.join();
        }
        Ok(stats)
    }

    /// Drops the connection without a DISCONNECT, as a crash or a cut cable would: the broker
    /// then publishes the last will.
    pub fn abort(mut self) {
        self.halt();
    }

    fn halt(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(p) = self.pump.take() {
            let _ = p.join();
        }
    }
}

/// A publisher's counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PublishStats {
    /// QoS 1 messages (alerts, status) queued.
    pub queued: u64,
    /// Of them, acknowledged by the broker.
    pub acked: u64,
    /// Reconnections after a lost connection.
    pub reconnects: u32,
    /// Objects messages (QoS 0) dropped while the broker was away.
    pub objects_dropped: u32,
    /// Whether the broker is connected now.
    pub connected: bool,
}

impl Drop for Publisher {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

/// The network loop: reports the first CONNACK (or the first error), tracks acknowledgements,
/// and reconnects with backoff after an error, until a clean disconnect or `stop`.
fn pump(
    mut connection: Connection,
    client: &Client,
    stop: &AtomicBool,
    outbox: &Mutex<Outbox>,
    ready: mpsc::Sender<Result<(), String>>,
) {
    let mut ready = Some(ready);
    let mut backoff = Duration::from_millis(100);
    let lock = || {
        outbox
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    };
    while !stop.load(Ordering::Relaxed) {
        match connection.recv_timeout(Duration::from_millis(50)) {
            Ok(Ok(Event::Incoming(Packet::ConnAck(ack)))) => {
                backoff = Duration::from_millis(100);
                let mut o = lock();
                if ready.take().is_some_and(|r| r.send(Ok(())).is_ok()) {
                    o.connected = true;
                    continue;
                }
                o.connected = true;
                o.reconnects += 1;
                if !ack.session_present {
                    o.session_lost();
                }
                o.hand(client);
            }
            Ok(Ok(Event::Outgoing(rumqttc::Outgoing::Publish(pkid)))) => lock().went_out(pkid),
            Ok(Ok(Event::Incoming(Packet::PubAck(ack)))) => {
                let mut o = lock();
                o.acknowledged(ack.pkid);
                o.hand(client);
            }
            Ok(Ok(Event::Outgoing(rumqttc::Outgoing::Disconnect))) => return,
            Ok(Ok(_)) | Err(rumqttc::RecvTimeoutError::Timeout) => {}
            Ok(Err(e)) => {
                if let Some(r) = ready.take() {
                    let _ = r.send(Err(e.to_string()));
                    return;
                }
                {
                    let mut o = lock();
                    o.connected = false;
                    o.last_error = Some(e.to_string());
                }
                // The next poll reconnects; wait first, longer each time.
                let until = std::time::Instant::now() + backoff;
                while std::time::Instant::now() < until && !stop.load(Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(20));
                }
                backoff = (backoff * 2).min(MAX_BACKOFF);
            }
            Err(rumqttc::RecvTimeoutError::Disconnected) => return,
        }
    }
}
