//! The telemetry link between the module and the host: messages ([`message`]), framing and
//! authentication ([`frame`], [`auth`]), the checking receiver ([`receiver`]) and bounded
//! queues ([`queue`]). Shared verbatim by the firmware and the host tool.
//!
//! ```text
//! host ── Downlink::{Config, Hint…, Frame} ──▶ module ── capture ──▶ pipeline
//! host ◀── Uplink::{Result…, Summary, Health, Fault} ── module
//! ```
//!
//! Each message travels in one frame: postcard payload, version, direction, counter and a
//! truncated HMAC-SHA-256 tag, COBS-encoded and delimited by a zero byte. Frames are tagged with
//! per-session keys a handshake derives from the device key and two fresh nonces
//! ([`session`]).

pub mod auth;
pub mod frame;
pub mod host;
pub mod message;
pub mod queue;
pub mod receiver;
pub mod session;

#[cfg(feature = "dev-key")]
pub use auth::DEV_KEY;
pub use auth::{KEY_LEN, Key, KeyError, TAG_LEN};
pub use frame::{EncodeError, MAX_WIRE, Sender, Stream};
pub use host::HostLink;
pub use message::{
    ALTERNATIVES, Alternative, CalibrationRow, Downlink, Fault, FrameSummary, Health, Hint,
    LinkStats, ObjectResult, Score, Uplink,
};
pub use queue::DropOldest;
pub use receiver::{Deframer, LinkError, Opened, Receiver};
pub use session::{DeviceKey, HandshakeDown, HandshakeUp, NONCE_LEN, Nonce, SessionKeys};

/// Protocol version: the first byte of every frame. Version 4: each object result carries
/// three candidates with a [`Score`] (half-dB height and the survival bit) each. Version 5:
/// the downlink's [`CalibrationRow`]s.
pub const VERSION: u8 = 5;
