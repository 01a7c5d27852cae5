//! What the people who watch a perimeter get from a sensor: [`geofence`] turns each frame's
//! detections into zone alerts with hysteresis; [`outputs`] writes the run's files
//! (`results.json`, KITTI depth PNGs and PLY clouds through [`depth_image`], `recording.mcap`
//! through [`record`], inspection plots through [`plot`] and [`inspect`]); [`live`] draws the
//! operator view on a terminal; [`mqtt`] publishes objects, alerts and status to a broker;
//! [`tracking`] keeps objects' ids across frames (a tracker in the ground plane and its
//! CLEAR-MOT score).
//!
//! It sits above `metamoran-process` (it consumes its results) and below the `metamoran` binary.

pub mod alert_log;
pub mod depth_image;
mod error;
pub mod geofence;
pub mod inspect;
pub mod live;
pub mod mqtt;
pub mod nats;
pub mod outputs;
pub mod plot;
pub mod record;
pub mod site;
pub mod tracking;
pub mod watch;

pub use error::OperatorError;
