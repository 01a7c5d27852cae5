//! Live data from a TI DCA1000EVM capture card in raw mode, where a capture file would
//! otherwise come from: the board streams a radar's samples over Ethernet as UDP packets
//! ([`packet`]) and takes its configuration commands on another port ([`command`]); the host
//! reassembles frames from the packets by their byte counts ([`assemble`]), on a socket
//! ([`receive`]), and writes them as a capture file ([`record`]); [`control`] configures and
//! starts the board. [`emulate`] stands in for the board and [`pcap`] reads recorded sessions.
//!
//! ```text
//! board ──UDP 4098──▶ Receiver ─▶ Assembler ─▶ Frame (whole, or zero-filled and flagged) ─▶ .bin / pipeline
//! host  ──UDP 4096──▶ board (connect, configure FPGA, start/stop record) ◀── replies
//! ```

pub mod assemble;
pub mod command;
pub mod control;
pub mod emulate;
pub mod packet;
pub mod pcap;
pub mod receive;
pub mod record;

pub use assemble::{Assembler, Frame, Stats};
pub use receive::{Counters, Receiver};
