//! One sensor's fusion stage end to end: each frame's estimates become detections (placed,
//! trusted and confident enough for the perimeter), the [`Tracker`] keeps them as tracks, and
//! the [`Geofence`] runs the zone rules on the confirmed ones.
//!
//! ```text
//! ObjectEstimate ─▶ Detection (detected, placed, ≥ min_confidence_db) ─▶ Tracker ─▶ Geofence ─▶ Alert
//! ```
//!
//! Nothing here reads the camera's instance ids except to say, in an alert, which of this
//! frame's objects the track took: a segmenter that renumbers its instances every frame gives
//! the same tracks and alerts.

use crate::geofence::{Alert, Geofence, Perimeter, Sighting};
use crate::tracking::{Detection, Track, TrackError, Tracker, TrackerConfig};
use metamoran_process::ObjectEstimate;

/// The tracker and the zone rules of one sensor.
#[derive(Clone, Debug)]
pub struct Watch {
    tracker: Tracker,
    fence: Geofence,
}

impl Watch {
    /// No tracks yet, every zone empty.
    pub fn new(perimeter: Perimeter, config: TrackerConfig) -> Self {
        Self {
            tracker: Tracker::new(config),
            fence: Geofence::new(perimeter),
        }
    }

    /// The zone rules.
    pub fn perimeter(&self) -> &Perimeter {
        self.fence.perimeter()
    }

    /// Folds in one frame's estimates at `time_s` and returns the alerts it raises.
    /// O(objects² + tracks × zones × vertices).
    ///
    /// # Errors
    /// [`TrackError::Time`] if `time_s` is before the previous frame's (nothing changes).
    pub fn frame(
        &mut self,
        frame: u32,
        time_s: f64,
        objects: &[ObjectEstimate],
    ) -> Result<Vec<Alert>, TrackError> {
        let least = self.fence.perimeter().min_confidence_db;
        let (instances, detections): (Vec<u16>, Vec<Detection>) = objects
            .iter()
            .filter(|o| o.confidence_db.is_none_or(|c| c >= least))
            .filter_map(|o| Detection::from_estimate(o).map(|d| (o.instance, d)))
            .unzip();
        self.tracker.update(time_s, &detections)?;
        let sightings: Vec<Sighting> = self
            .tracker
            .confirmed()
            .map(|t| Sighting::of(t, t.detection.and_then(|j| instances.get(j).copied())))
            .collect();
        Ok(self.fence.update(frame, time_s, &sightings))
    }

    /// The confirmed tracks, oldest id first.
    pub fn tracks(&self) -> impl Iterator<Item = &Track> {
        self.tracker.confirmed()
    }

    /// Names of the zones `track` is in now.
    pub fn zones_of(&self, track: u32) -> Vec<&str> {
        self.fence.zones_of(track)
    }
}
