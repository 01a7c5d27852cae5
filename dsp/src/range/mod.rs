//! Range: windowed, zero-padded FFT of each (chirp, RX) row, streaming as rows arrive, into a
//! caller-owned [`RangeCube`].

mod cube;
mod processor;

pub use cube::RangeCube;
pub use processor::{RangeError, RangeProcessor};
