//! Radar point clouds (dense radar mapping, Sec. 3.1): every CFAR detection of the
//! range–Doppler map becomes one or more points with x, y, z, radial velocity and a relative
//! RCS, their azimuth from an FFT over the array's base row and their elevation from the phase
//! between an elevated row and the base row.
//!
//! * [`geometry`]: where each virtual channel sits, in azimuth and elevation;
//! * [`angles`]: the directions present in one range–Doppler cell;
//! * [`cloud`]: the points of a frame, from the range cube.

pub mod angles;
pub mod cloud;
pub mod geometry;

pub use angles::{Direction, cell_directions};
pub use cloud::{
    CloudOptions, CubeSpectra, DopplerSpectra, Peaks, PointsError, RadarPoint, Screen,
    frame_points, spectrum_f32,
};
pub use geometry::{ArrayGeometry, GeometryError};
