//! Detection: constant-false-alarm-rate thresholds (CA and OS, 1D and 2D) and sub-bin peak
//! interpolation.

mod cfar;
mod peak;

pub use cfar::{Boundary, Cfar, Cfar2d, CfarError, CfarKind, Detection};
pub use peak::{is_local_max, quadratic_offset};
