//! The site stream on NATS JetStream (issue #20 part 3): each sensor publishes its confirmed
//! tracks and its health on core NATS, newest wins, and its alerts into a JetStream stream with
//! file storage, so an operator station that was offline replays what it missed.
//!
//! ```text
//! metamoran.<site>.<sensor>.tracks   core NATS, one message per frame (JSON)
//! metamoran.<site>.<sensor>.health   core NATS, one message per frame (JSON)
//! metamoran.<site>.<sensor>.alerts   JetStream stream `metamoran-<site>-alerts`, file storage
//! ```
//!
//! An alert counts as delivered only when the server's JetStream acknowledgement says it is
//! stored. Until then it waits, in order, and is sent again with backoff (0.1 s to 2 s) across
//! server restarts; its `Nats-Msg-Id` (sensor, run, sequence) lets the stream's duplicate window
//! drop the copies a lost acknowledgement causes. Alerts are on disk first
//! ([`crate::alert_log`]), so a server that never comes back loses nothing either, and
//! [`NatsPublisher::close`] says how many were not stored.
//!
//! The client is `async-nats` on a one-worker tokio runtime; the sensor's frame loop never
//! waits on the network.

use crate::OperatorError;
use crate::geofence::Alert;
use crate::mqtt::MqttLogin;
use async_nats::jetstream;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

/// Where and as whom to publish.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NatsConfig {
    /// Server URL (`nats://HOST:PORT`, or `tls://HOST:PORT`).
    pub url: String,
    /// Site name: the subject level under `metamoran.`.
    pub site: String,
    /// Sensor id: the subject level under the site.
    pub sensor: String,
    /// User and password (from a file or the environment, never the command line).
    pub login: Option<MqttLogin>,
    /// PEM file of the CA that signs the server's certificate: TLS is then required.
    pub ca: Option<PathBuf>,
}

/// Whether `name` can be one subject token (a site or sensor id): ASCII letters, digits, `-`
/// and `_`, 1 to 64 of them.
pub fn is_token(name: &str) -> bool {
    !name.is_empty()
        && name.len() <= 64
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_')
}

impl NatsConfig {
    /// The server at `url` for sensor `sensor` of site `site`.
    ///
    /// # Errors
    /// [`OperatorError::NatsAddress`] for a URL that is not `nats://` or `tls://`, or a site or
    /// sensor that is not one subject token.
    pub fn new(url: &str, site: &str, sensor: &str) -> Result<Self, OperatorError> {
        let bad = |problem: String| OperatorError::NatsAddress {
            url: url.to_owned(),
            problem,
        };
        let rest = url
            .strip_prefix("nats://")
            .or_else(|| url.strip_prefix("tls://"))
            .ok_or_else(|| bad("give nats://HOST:PORT or tls://HOST:PORT".into()))?;
        if rest.is_empty() || rest.contains(['/', '@', ' ']) {
            return Err(bad(
                "give nats://HOST:PORT (the login comes from --nats-user and a file)".into(),
            ));
        }
        for (what, name) in [("site", site), ("sensor", sensor)] {
            if !is_token(name) {
                return Err(bad(format!(
                    "{what} {name:?}: use 1–64 letters, digits, - or _ (it is a subject token)"
                )));
            }
        }
        Ok(Self {
            url: url.to_owned(),
            site: site.to_owned(),
            sensor: sensor.to_owned(),
            login: None,
            ca: None,
        })
    }

    /// `metamoran.<site>.<sensor>.<leaf>`.
    pub fn subject(&self, leaf: &str) -> String {
        format!("metamoran.{}.{}.{leaf}", self.site, self.sensor)
    }

    /// The site's alert stream: `metamoran-<site>-alerts`.
    pub fn stream(&self) -> String {
        format!("metamoran-{}-alerts", self.site)
    }

    fn error(&self, problem: impl std::fmt::Display) -> OperatorError {
        OperatorError::Nats {
            url: self.url.clone(),
            problem: problem.to_string(),
        }
    }

    /// Connects (5 s to answer; reconnects forever afterwards).
    async fn connect(&self, name: &str) -> Result<async_nats::Client, OperatorError> {
        let mut options = async_nats::ConnectOptions::new()
            .name(name)
            .connection_timeout(Duration::from_secs(5))
            .max_reconnects(None)
            .reconnect_delay_callback(|attempt| {
                Duration::from_millis(100 << attempt.min(4)).min(Duration::from_secs(2))
            });
        if let Some(login) = &self.login {
            options =
                options.user_and_password(login.username.clone(), login.password().to_owned());
        }
        if let Some(ca) = &self.ca {
            options = options.add_root_certificates(ca.clone()).require_tls(true);
        }
        options.connect(self.url.as_str()).await.map_err(|e| {
            self.error(format!(
                "cannot connect ({e}); is it running, and are the user and password right?"
            ))
        })
    }

    /// The alert stream, created when missing: every sensor's alerts of the site and the
    /// operators' acknowledgements (`metamoran.<site>.operator.acks`), on file, kept 30 days,
    /// duplicates within 2 minutes dropped.
    async fn alert_stream(
        &self,
        js: &jetstream::Context,
    ) -> Result<jetstream::stream::Stream, OperatorError> {
        js.get_or_create_stream(jetstream::stream::Config {
            name: self.stream(),
            subjects: vec![
                format!("metamoran.{}.*.alerts", self.site),
                format!("metamoran.{}.*.acks", self.site),
            ],
            storage: jetstream::stream::StorageType::File,
            max_age: Duration::from_secs(30 * 24 * 3600),
            duplicate_window: Duration::from_secs(120),
            ..Default::default()
        })
        .await
        .map_err(|e| {
            self.error(format!(
                "cannot open the alert stream {} ({e}); is JetStream on (nats-server -js)?",
                self.stream()
            ))
        })
    }
}

/// A client of `config`'s server named `name`, with the site's alert stream opened (created
/// when missing): what the site's web view uses to subscribe and to record acknowledgements.
///
/// # Errors
/// [`OperatorError::Nats`] as [`NatsPublisher::connect`].
pub async fn connect_client(
    config: &NatsConfig,
    name: &str,
) -> Result<async_nats::Client, OperatorError> {
    let client = config.connect(name).await?;
    config.alert_stream(&jetstream::new(client.clone())).await?;
    Ok(client)
}

/// What a publisher did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NatsStats {
    /// Alerts queued.
    pub alerts: u64,
    /// Alerts the server acknowledged as stored.
    pub stored: u64,
    /// Sends that failed or were not acknowledged, and were retried.
    pub retries: u64,
    /// Track and health messages the client could not take.
    pub dropped: u64,
}

#[derive(Debug, Default)]
struct Counters {
    alerts: AtomicU64,
    stored: AtomicU64,
    retries: AtomicU64,
    dropped: AtomicU64,
}

/// A sensor's publisher.
pub struct NatsPublisher {
    config: NatsConfig,
    runtime: tokio::runtime::Runtime,
    client: async_nats::Client,
    alerts: Option<tokio::sync::mpsc::UnboundedSender<(String, Vec<u8>)>>,
    worker: Option<tokio::task::JoinHandle<()>>,
    counters: Arc<Counters>,
    /// This run's part of every alert's message id.
    run: String,
}

/// How long [`NatsPublisher::close`] waits for the last acknowledgements.
pub const CLOSE_TIMEOUT: Duration = Duration::from_secs(30);

/// Sends one alert until the stream acknowledges it as stored.
async fn store(
    js: &jetstream::Context,
    subject: &str,
    id: &str,
    payload: &[u8],
    counters: &Counters,
) {
    let mut backoff = Duration::from_millis(100);
    loop {
        let message = jetstream::message::PublishMessage::build()
            .payload(payload.to_vec().into())
            .message_id(id);
        let sent = js.send_publish(subject.to_owned(), message).await;
        if let Ok(ack) = sent
            && ack.await.is_ok()
        {
            counters.stored.fetch_add(1, Ordering::Relaxed);
            return;
        }
        counters.retries.fetch_add(1, Ordering::Relaxed);
        tokio::time::sleep(backoff).await;
        backoff = (backoff * 2).min(Duration::from_secs(2));
    }
}

impl NatsPublisher {
    /// Connects, opens (or creates) the site's alert stream and starts the alert sender.
    ///
    /// # Errors
    /// [`OperatorError::Nats`] when the server does not accept the connection in 5 s, refuses
    /// the login, or has no JetStream.
    pub fn connect(config: &NatsConfig) -> Result<Self, OperatorError> {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .enable_all()
            .build()
            .map_err(|e| config.error(format!("cannot start the client's runtime ({e})")))?;
        let name = format!("metamoran-{}-{}", config.site, config.sensor);
        let (client, js) = runtime.block_on(async {
            let client = config.connect(&name).await?;
            let mut js = jetstream::new(client.clone());
            js.set_timeout(Duration::from_secs(2));
            config.alert_stream(&js).await?;
            Ok::<_, OperatorError>((client, js))
        })?;
        let counters = Arc::new(Counters::default());
        let (tx, mut rx) = tokio::sync::mpsc::unbounded_channel::<(String, Vec<u8>)>();
        let worker = runtime.spawn({
            let (counters, subject) = (counters.clone(), config.subject("alerts"));
            async move {
                while let Some((id, payload)) = rx.recv().await {
                    store(&js, &subject, &id, &payload, &counters).await;
                }
            }
        });
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        Ok(Self {
            config: config.clone(),
            runtime,
            client,
            alerts: Some(tx),
            worker: Some(worker),
            counters,
            run: format!("{}-{nanos:x}-{:x}", config.sensor, std::process::id()),
        })
    }

    /// Queues `alert` for the stream (it is stored in order, however long the server is away).
    pub fn alert(&self, alert: &Alert) {
        let Ok(payload) = serde_json::to_vec(alert) else {
            return;
        };
        let n = self.counters.alerts.fetch_add(1, Ordering::Relaxed);
        if let Some(tx) = &self.alerts {
            // The receiver lives until close.
            let _ = tx.send((format!("{}-{n}", self.run), payload));
        }
    }

    /// Publishes `body` (JSON) on `metamoran.<site>.<sensor>.<leaf>`, core NATS: dropped,
    /// and counted, when the client cannot take it.
    pub fn publish(&self, leaf: &str, body: &serde_json::Value) {
        let Ok(payload) = serde_json::to_vec(body) else {
            return;
        };
        let (client, subject) = (self.client.clone(), self.config.subject(leaf));
        let counters = self.counters.clone();
        self.runtime.spawn(async move {
            if client.publish(subject, payload.into()).await.is_err() {
                counters.dropped.fetch_add(1, Ordering::Relaxed);
            }
        });
    }

    /// What was sent so far.
    pub fn stats(&self) -> NatsStats {
        let c = &self.counters;
        NatsStats {
            alerts: c.alerts.load(Ordering::Relaxed),
            stored: c.stored.load(Ordering::Relaxed),
            retries: c.retries.load(Ordering::Relaxed),
            dropped: c.dropped.load(Ordering::Relaxed),
        }
    }

    /// Waits up to `timeout` for every queued alert to be stored, flushes the rest, and
    /// disconnects.
    ///
    /// # Errors
    /// [`OperatorError::Nats`] saying how many alerts were not stored (they are in
    /// `alerts.jsonl`).
    pub fn close(mut self, timeout: Duration) -> Result<NatsStats, OperatorError> {
        drop(self.alerts.take());
        let worker = self.worker.take();
        let client = self.client.clone();
        let stored = self.runtime.block_on(async move {
            let done = match worker {
                Some(w) => tokio::time::timeout(timeout, w).await.is_ok(),
                None => true,
            };
            let _ = tokio::time::timeout(Duration::from_secs(2), client.flush()).await;
            done
        });
        let stats = self.stats();
        if stored && stats.stored == stats.alerts {
            Ok(stats)
        } else {
            Err(self.config.error(format!(
                "{} of {} alert(s) not stored after {timeout:?}; they are in alerts.jsonl",
                stats.alerts - stats.stored,
                stats.alerts
            )))
        }
    }
}

/// One alert (or acknowledgement) as the stream holds it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StoredAlert {
    /// Stream sequence number (1, 2, … in the order the server stored them).
    pub sequence: u64,
    /// The sensor that published it (its subject's third token; `operator` for an
    /// acknowledgement).
    pub sensor: String,
    /// The alert, JSON as published.
    pub json: String,
}

/// Reads the site's whole alert stream, in order: what an operator station that was offline
/// replays. At most `limit` alerts.
///
/// # Errors
/// [`OperatorError::Nats`] when the server cannot be reached, refuses the login, or the site has
/// no alert stream yet.
pub fn replay(config: &NatsConfig, limit: usize) -> Result<Vec<StoredAlert>, OperatorError> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|e| config.error(format!("cannot start the client's runtime ({e})")))?;
    runtime.block_on(async {
        let client = config.connect("metamoran-replay").await?;
        let js = jetstream::new(client);
        let mut stream = js.get_stream(config.stream()).await.map_err(|e| {
            config.error(format!(
                "no alert stream {} ({e}): has a sensor of site {} published yet?",
                config.stream(),
                config.site
            ))
        })?;
        let state = stream
            .info()
            .await
            .map_err(|e| config.error(format!("cannot read {} ({e})", config.stream())))?
            .state
            .clone();
        let mut out = Vec::new();
        if state.messages == 0 {
            return Ok(out);
        }
        for sequence in state.first_sequence..=state.last_sequence {
            if out.len() >= limit {
                break;
            }
            let m = stream.get_raw_message(sequence).await.map_err(|e| {
                config.error(format!("{} message {sequence}: {e}", config.stream()))
            })?;
            out.push(StoredAlert {
                sequence,
                sensor: m.subject.split('.').nth(2).unwrap_or("").to_owned(),
                json: String::from_utf8_lossy(&m.payload).into_owned(),
            });
        }
        Ok(out)
    })
}
