//! Ego-motion from Doppler (dense radar mapping, Sec. 3.2): static reflectors seen from a moving
//! radar have radial velocities on a cosine of their azimuth. A RANSAC fit of that relation
//! ([`velocity`]) gives the radar's own velocity while movers fall out as outliers, and the
//! Ackermann relation ([`ackermann`]) turns it into the vehicle's forward speed and yaw rate,
//! which the host integrates into odometry for submaps. Where the radial velocities fold (a
//! board of many TDM slots), [`unfold`] finds the velocity to unfold them with first.
//!
//! Frame: the radar frame of the rest of the crate (x right, y down, z forward); the platform
//! moves in the x–z plane.

pub mod ackermann;
pub mod unfold;
pub mod velocity;

pub use ackermann::{Mount, VehicleMotion};
pub use unfold::{UnfoldGrid, search as unfold_search};
pub use velocity::{DopplerDetection, EgoError, EgoVelocity, Ransac, estimate};
