//! Capture: raw ADC words from the DCA1000 (or the module's SPI) → complex Q15 samples.

mod dca1000;

pub use dca1000::{CaptureError, IqOrder, deinterleave_bytes};
