//! The durable alert log, `alerts.jsonl`: one JSON alert per line, each appended and synced to
//! disk before it is published anywhere (issue #18, item 10), so an alert a broker or a crash
//! loses is still on the sensor.

use crate::OperatorError;
use crate::geofence::Alert;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

/// An open alert log.
#[derive(Debug)]
pub struct AlertLog {
    path: PathBuf,
    file: File,
    written: u64,
}

impl AlertLog {
    /// Starts a new log at `path` (an earlier one there is replaced).
    ///
    /// # Errors
    /// [`OperatorError::Output`] naming the file.
    pub fn create(path: &Path) -> Result<Self, OperatorError> {
        let file = File::create(path).map_err(|e| OperatorError::output(path, "create", e))?;
        Ok(Self {
            path: path.to_owned(),
            file,
            written: 0,
        })
    }

    /// Appends `alert` as one line and waits until it is on disk (`fdatasync`).
    ///
    /// # Errors
    /// [`OperatorError::Output`] naming the file: the alert must not be published then.
    pub fn append(&mut self, alert: &Alert) -> Result<(), OperatorError> {
        let mut line =
            serde_json::to_vec(alert).map_err(|e| OperatorError::output(&self.path, "write", e))?;
        line.push(b'\n');
        self.file
            .write_all(&line)
            .and_then(|()| self.file.sync_data())
            .map_err(|e| OperatorError::output(&self.path, "write", e))?;
        self.written += 1;
        Ok(())
    }

    /// Alerts appended so far.
    pub fn written(&self) -> u64 {
        self.written
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geofence::AlertKind;

    #[test]
    fn each_alert_is_a_line_on_disk_as_soon_as_it_is_appended() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("alerts.jsonl");
        let mut log = AlertLog::create(&path).unwrap();
        let alert = |frame| Alert {
            kind: AlertKind::Enter,
            zone: "gate".into(),
            track: 3,
            instance: Some(2),
            class: "person".into(),
            depth_m: 12.5,
            azimuth_deg: -3.0,
            position_m: [-0.65, 12.48],
            velocity_mps: [1.4, 0.0],
            closing_mps: None,
            inside_s: None,
            frame,
            time_s: f64::from(frame) * 0.5,
        };
        for f in 0..3 {
            log.append(&alert(f)).unwrap();
            // Read back through another handle before the log is closed.
            let text = std::fs::read_to_string(&path).unwrap();
            assert_eq!(text.lines().count(), f as usize + 1);
            let last: serde_json::Value =
                serde_json::from_str(text.lines().last().unwrap()).unwrap();
            assert_eq!(last["frame"], f);
        }
        assert_eq!(log.written(), 3);
    }
}
