//! Doppler: FFT over the loops of each (channel, range bin), after optional static clutter
//! removal, and the non-coherent range–Doppler map.

mod column;
mod map;

pub use column::{DopplerError, DopplerOptions, doppler_column};
pub use map::{magnitude, range_doppler_map, range_doppler_rows, range_doppler_rows_keeping};
