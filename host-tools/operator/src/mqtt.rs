//! MQTT publishing for fleet use (rumqttc, MQTT 3.1.1): per frame the objects at QoS 0
//! (`metamoran/<sensor>/objects`, JSON, newest wins), alerts at QoS 1
//! (`metamoran/<sensor>/alerts`, every one delivered at least once), and a retained status
//! (`metamoran/<sensor>/status`): `online` while connected, `stopped` after a clean end, and
//! the broker's last will `offline` when the connection is lost without one.

use crate::OperatorError;
use crate::geofence::Alert;
use metamoran_process::FrameResult;
use rumqttc::{Client, Connection, Event, LastWill, MqttOptions, Packet, QoS};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::mpsc;
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
        })
    }

    /// The topic `metamoran/<sensor>/<leaf>`.
    pub fn topic(&self, leaf: &str) -> String {
        format!("metamoran/{}/{leaf}", self.sensor)
    }
}

/// A connected publisher; its network loop runs on a thread.
pub struct Publisher {
    client: Client,
    config: MqttConfig,
    stop: Arc<AtomicBool>,
    /// QoS 1 messages published, and acknowledged by the broker.
    sent: AtomicU32,
    acked: Arc<AtomicU32>,
    pump: Option<JoinHandle<()>>,
}

/// How long to wait for the broker's CONNACK.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);

impl Publisher {
    /// Connects (clean session, last will `offline` retained) and publishes `online` retained;
    /// returns once the broker has acknowledged it.
    ///
    /// # Errors
    /// [`OperatorError`] naming the broker when it does not accept the connection in 5 s.
    pub fn connect(config: &MqttConfig) -> Result<Self, OperatorError> {
        let mut options = MqttOptions::new(
            format!("metamoran-{}", config.sensor),
            &config.host,
            config.port,
        );
        options
            .set_keep_alive(Duration::from_secs(5))
            .set_clean_session(true)
            .set_last_will(LastWill::new(
                config.topic("status"),
                "offline",
                QoS::AtLeastOnce,
                true,
            ));
        let (client, connection) = Client::new(options, 64);
        let stop = Arc::new(AtomicBool::new(false));
        let acked = Arc::new(AtomicU32::new(0));
        let (ready, connected) = mpsc::channel();
        let pump = std::thread::spawn({
            let (stop, acked) = (stop.clone(), acked.clone());
            move || pump(connection, &stop, &acked, ready)
        });
        let broker = format!("{}:{}", config.host, config.port);
        match connected.recv_timeout(CONNECT_TIMEOUT) {
            Ok(Ok(())) => {}
            Ok(Err(problem)) => return Err(OperatorError::Broker { broker, problem }),
            Err(_) => {
                return Err(OperatorError::Broker {
                    broker,
                    problem: "no answer in 5 s; is it running?".to_owned(),
                });
            }
        }
        let p = Self {
            client,
            config: config.clone(),
            stop,
            sent: AtomicU32::new(0),
            acked,
            pump: Some(pump),
        };
        p.send("status", QoS::AtLeastOnce, true, b"online".to_vec())?;
        p.flush()?;
        Ok(p)
    }

    /// Waits until the broker has acknowledged every QoS 1 message published so far.
    ///
    /// # Errors
    /// [`OperatorError`] naming the broker if that takes more than 5 s.
    pub fn flush(&self) -> Result<(), OperatorError> {
        let deadline = std::time::Instant::now() + CONNECT_TIMEOUT;
        while self.acked.load(Ordering::Relaxed) < self.sent.load(Ordering::Relaxed) {
            if std::time::Instant::now() > deadline {
                return Err(OperatorError::Broker {
                    broker: format!("{}:{}", self.config.host, self.config.port),
                    problem: format!(
                        "{} of {} alerts/status messages unacknowledged after 5 s",
                        self.sent.load(Ordering::Relaxed) - self.acked.load(Ordering::Relaxed),
                        self.sent.load(Ordering::Relaxed)
                    ),
                });
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        Ok(())
    }

    fn send(
        &self,
        leaf: &str,
        qos: QoS,
        retain: bool,
        payload: Vec<u8>,
    ) -> Result<(), OperatorError> {
        if qos == QoS::AtLeastOnce {
            self.sent.fetch_add(1, Ordering::Relaxed);
        }
        self.client
            .publish(self.config.topic(leaf), qos, retain, payload)
            .map_err(|e| OperatorError::Publish {
                topic: self.config.topic(leaf),
                reason: e.to_string(),
            })
    }

    /// Publishes a frame's objects (QoS 0).
    ///
    /// # Errors
    /// [`OperatorError`] if the publisher is closed.
    pub fn frame(&self, frame: &FrameResult) -> Result<(), OperatorError> {
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
        self.send(
            "objects",
            QoS::AtMostOnce,
            false,
            body.to_string().into_bytes(),
        )
    }

    /// Publishes an alert (QoS 1).
    ///
    /// # Errors
    /// [`OperatorError`] if the publisher is closed.
    pub fn alert(&self, alert: &Alert) -> Result<(), OperatorError> {
        let body = serde_json::to_vec(alert).map_err(|e| OperatorError::Publish {
            topic: self.config.topic("alerts"),
            reason: e.to_string(),
        })?;
        self.send("alerts", QoS::AtLeastOnce, false, body)
    }

    /// Publishes `stopped` retained and disconnects cleanly (no last will) once the broker has
    /// acknowledged every QoS 1 message (alerts, status).
    ///
    /// # Errors
    /// [`OperatorError`] if the broker does not acknowledge them within 5 s.
    pub fn close(mut self) -> Result<(), OperatorError> {
        self.send("status", QoS::AtLeastOnce, true, b"stopped".to_vec())?;
        self.flush()?;
        self.client
            .disconnect()
            .map_err(|e| OperatorError::Publish {
                topic: self.config.topic("status"),
                reason: format!("disconnect: {e}"),
            })?;
        if let Some(p) = self.pump.take() {
            let _ = p.join();
        }
        Ok(())
    }

    /// Drops the connection without a DISCONNECT, as a crash or a cut cable would: the broker
    /// then publishes the last will.
    pub fn abort(mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(p) = self.pump.take() {
            let _ = p.join();
        }
    }
}

impl Drop for Publisher {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

/// The network loop: reports the CONNACK (or the first error) and counts PUBACKs, until a
/// clean disconnect, an error, or `stop`.
fn pump(
    mut connection: Connection,
    stop: &AtomicBool,
    acked: &AtomicU32,
    ready: mpsc::Sender<Result<(), String>>,
) {
    let mut ready = Some(ready);
    while !stop.load(Ordering::Relaxed) {
        match connection.recv_timeout(Duration::from_millis(50)) {
            Ok(Ok(Event::Incoming(Packet::ConnAck(_)))) => {
                if let Some(r) = ready.take() {
                    let _ = r.send(Ok(()));
                }
            }
            Ok(Ok(Event::Incoming(Packet::PubAck(_)))) => {
                acked.fetch_add(1, Ordering::Relaxed);
            }
            Ok(Ok(Event::Outgoing(rumqttc::Outgoing::Disconnect))) => return,
            Ok(Ok(_)) | Err(rumqttc::RecvTimeoutError::Timeout) => {}
            Ok(Err(e)) => {
                if let Some(r) = ready.take() {
                    let _ = r.send(Err(e.to_string()));
                }
                return;
            }
            Err(rumqttc::RecvTimeoutError::Disconnected) => return,
        }
    }
}
