//! Range: windowed, zero-padded FFT of each (chirp, RX) row, streaming as rows arrive, into a
//! caller-owned [`RangeCube`].

pub mod calibration;
mod cube;
pub mod frame_sum;
mod processor;
mod static_sum;

pub use cube::RangeCube;
pub use frame_sum::{FrameSum, Spectra};
pub use processor::{RangeError, RangeProcessor};
pub use static_sum::StaticSum;
