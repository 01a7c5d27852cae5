//! Detection: constant-false-alarm-rate thresholds (CA and OS, 1D and 2D), a map's noise floor
//! and sub-bin peak interpolation.

mod cfar;
mod floor;
mod peak;

pub use cfar::{Boundary, Cfar, Cfar2d, CfarError, CfarKind, Detection};
pub use floor::{FLOOR_BUCKETS, median_floor};
pub use peak::{is_local_max, quadratic_offset};
