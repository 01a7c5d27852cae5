//! Recording to MCAP, the log format Foxglove Studio and ROS 2 tools open: per frame the
//! objects (`/metamoran/objects`) and the fused point cloud (`/metamoran/points`, Foxglove's
//! `PointCloud` schema, so it renders in a 3D panel), and the perimeter alerts
//! (`/metamoran/alerts`). Every message is JSON with a JSON Schema; log time is the frame time.

use crate::OperatorError;
use crate::geofence::Alert;
use base64::Engine;
use metamoran_process::FrameResult;
use serde_json::json;
use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Topic of the per-frame object list.
pub const OBJECTS_TOPIC: &str = "/metamoran/objects";
/// Topic of the fused point clouds.
pub const POINTS_TOPIC: &str = "/metamoran/points";
/// Topic of the perimeter alerts.
pub const ALERTS_TOPIC: &str = "/metamoran/alerts";

/// Bytes per point of the point cloud: x, y, z, instance as little-endian `f32`.
pub const POINT_STRIDE: usize = 16;

const OBJECTS_SCHEMA: &str = r#"{"type":"object","properties":{"frame":{"type":"integer"},"objects":{"type":"array","items":{"type":"object","properties":{"instance":{"type":"integer"},"class":{"type":"string"},"detected":{"type":"boolean"},"depth_m":{"type":["number","null"]},"azimuth_deg":{"type":["number","null"]},"confidence_db":{"type":["number","null"]},"points":{"type":"integer"}}}}}}"#;
const ALERT_SCHEMA: &str = r#"{"type":"object","properties":{"kind":{"type":"string"},"zone":{"type":"string"},"track":{"type":"integer"},"instance":{"type":["integer","null"]},"class":{"type":"string"},"depth_m":{"type":"number"},"azimuth_deg":{"type":"number"},"position_m":{"type":"array","items":{"type":"number"}},"velocity_mps":{"type":"array","items":{"type":"number"}},"closing_mps":{"type":"number"},"inside_s":{"type":"number"},"frame":{"type":"integer"},"time_s":{"type":"number"}}}"#;
const POINT_CLOUD_SCHEMA: &str = r#"{"title":"foxglove.PointCloud","type":"object","properties":{"timestamp":{"type":"object","properties":{"sec":{"type":"integer"},"nsec":{"type":"integer"}}},"frame_id":{"type":"string"},"pose":{"type":"object"},"point_stride":{"type":"integer"},"fields":{"type":"array","items":{"type":"object","properties":{"name":{"type":"string"},"offset":{"type":"integer"},"type":{"type":"integer"}}}},"data":{"type":"string","contentEncoding":"base64"}}}"#;

/// An open MCAP recording.
pub struct Recorder {
    writer: mcap::Writer<BufWriter<std::fs::File>>,
    path: PathBuf,
    objects: u16,
    points: u16,
    alerts: u16,
    sequence: u32,
}

impl Recorder {
    /// Creates (or replaces) the recording at `path`.
    ///
    /// # Errors
    /// [`OperatorError::Output`] naming the file.
    pub fn create(path: &Path) -> Result<Self, OperatorError> {
        let e = |x: &dyn std::fmt::Display| OperatorError::output(path, "record", x);
        let file = std::fs::File::create(path).map_err(|x| e(&x))?;
        let mut writer = mcap::Writer::new(BufWriter::new(file)).map_err(|x| e(&x))?;
        let mut channel = |schema: &str, body: &str, topic: &str| -> Result<u16, OperatorError> {
            let id = writer
                .add_schema(schema, "jsonschema", body.as_bytes())
                .map_err(|x| e(&x))?;
            writer
                .add_channel(id, topic, "json", &BTreeMap::new())
                .map_err(|x| e(&x))
        };
        let objects = channel("metamoran.Objects", OBJECTS_SCHEMA, OBJECTS_TOPIC)?;
        let points = channel("foxglove.PointCloud", POINT_CLOUD_SCHEMA, POINTS_TOPIC)?;
        let alerts = channel("metamoran.Alert", ALERT_SCHEMA, ALERTS_TOPIC)?;
        Ok(Self {
            writer,
            path: path.to_owned(),
            objects,
            points,
            alerts,
            sequence: 0,
        })
    }

    fn write(
        &mut self,
        channel: u16,
        time_s: f64,
        value: &serde_json::Value,
    ) -> Result<(), OperatorError> {
        let nanos = (time_s.max(0.0) * 1e9).round() as u64;
        self.sequence += 1;
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: self.sequence,
            log_time: nanos,
            publish_time: nanos,
        };
        let data = serde_json::to_vec(value)
            .map_err(|x| OperatorError::output(&self.path, "record", x))?;
        self.writer
            .write_to_known_channel(&header, &data)
            .map_err(|x| OperatorError::output(&self.path, "record", x))
    }

    /// Records one frame's objects and its point cloud at `time_s` (s from the start).
    ///
    /// # Errors
    /// [`OperatorError::Output`] naming the file.
    pub fn frame(&mut self, time_s: f64, frame: &FrameResult) -> Result<(), OperatorError> {
        let objects: Vec<_> = frame
            .objects
            .iter()
            .map(|o| {
                json!({
                    "instance": o.instance,
                    "class": o.class,
                    "detected": o.detected,
                    "depth_m": o.depth_m,
                    "azimuth_deg": o.azimuth_deg,
                    "confidence_db": o.confidence_db,
                    "points": o.points.len(),
                })
            })
            .collect();
        let value = json!({ "frame": frame.frame, "objects": objects });
        self.write(self.objects, time_s, &value)?;
        let mut data = Vec::new();
        for o in &frame.objects {
            for p in &o.points {
                for v in [p[0] as f32, p[1] as f32, p[2] as f32, o.instance as f32] {
                    data.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
        let field =
            |name: &str, offset: usize| json!({ "name": name, "offset": offset, "type": 7 });
        let cloud = json!({
            "timestamp": { "sec": time_s.floor() as u64, "nsec": (time_s.fract() * 1e9).round() as u64 },
            "frame_id": "radar",
            "pose": { "position": { "x": 0.0, "y": 0.0, "z": 0.0 },
                      "orientation": { "x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0 } },
            "point_stride": POINT_STRIDE,
            "fields": [field("x", 0), field("y", 4), field("z", 8), field("instance", 12)],
            "data": base64::engine::general_purpose::STANDARD.encode(&data),
        });
        self.write(self.points, time_s, &cloud)
    }

    /// Records an alert at its own time.
    ///
    /// # Errors
    /// [`OperatorError::Output`] naming the file.
    pub fn alert(&mut self, alert: &Alert) -> Result<(), OperatorError> {
        let value = serde_json::to_value(alert)
            .map_err(|x| OperatorError::output(&self.path, "record", x))?;
        self.write(self.alerts, alert.time_s, &value)
    }

    /// Writes the summary and index and closes the file.
    ///
    /// # Errors
    /// [`OperatorError::Output`] naming the file.
    pub fn finish(mut self) -> Result<(), OperatorError> {
        self.writer
            .finish()
            .map(|_| ())
            .map_err(|x| OperatorError::output(&self.path, "finish the recording", x))
    }
}

/// Records `frames` (frame `f` at `f · period_s`) and `alerts` into `path`.
///
/// # Errors
/// [`OperatorError::Output`] naming the file.
pub fn record(
    path: &Path,
    frames: &[FrameResult],
    period_s: f64,
    alerts: &[Alert],
) -> Result<(), OperatorError> {
    let mut r = Recorder::create(path)?;
    for f in frames {
        r.frame(f.frame as f64 * period_s, f)?;
    }
    for a in alerts {
        r.alert(a)?;
    }
    r.finish()
}
