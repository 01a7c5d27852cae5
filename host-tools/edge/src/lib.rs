//! The Metamoran module as the host's peer: [`qemu`] builds the firmware and runs it under
//! `qemu-system-arm` (machine `mps2-an500`, a Cortex-M7); [`link`] speaks the authenticated
//! telemetry protocol (`metamoran_dsp::wire`) to the module running there.
//!
//! It depends only on `dsp` (the wire format and the radar config): processing crates call it,
//! it calls none of them.

mod error;
pub mod keys;
pub mod link;
pub mod qemu;

pub use error::EdgeError;
