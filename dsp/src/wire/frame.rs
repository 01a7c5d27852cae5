//! The envelope around every message: header, postcard payload, tag, all COBS-encoded and
//! ended by a zero byte.
//!
//! ```text
//! raw  = version:u8 ‖ stream:u8 ‖ counter:u32 LE ‖ payload (postcard) ‖ tag (TAG_LEN bytes)
//! wire = COBS(raw) ‖ 0x00
//! tag  = HMAC-SHA-256(key, version ‖ stream ‖ counter ‖ payload)[..TAG_LEN]
//! ```
//!
//! The counter is the sender's, starting at 1 in each session and increasing by one per frame;
//! the receiver uses it against replays and to detect loss and reordering (handshake frames are
//! fresh by their nonces instead). The stream byte keeps an uplink frame from being reflected
//! back as a downlink one, and a handshake frame from passing as a session one.

use super::VERSION;
use super::auth::{Key, TAG_LEN};
use core::fmt;
use serde::Serialize;

/// Header bytes before the payload.
pub const HEADER_LEN: usize = 6;
/// Largest payload (postcard bytes) of one frame.
pub const MAX_PAYLOAD: usize = 384;
/// Largest raw (decoded) frame.
pub const MAX_RAW: usize = HEADER_LEN + MAX_PAYLOAD + TAG_LEN;
/// Largest frame on the wire, COBS overhead and delimiter included.
pub const MAX_WIRE: usize = cobs::max_encoding_length(MAX_RAW) + 1;

/// Direction and kind of a frame: session frames of each direction, and the handshake frames
/// that open sessions ([`super::session`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Stream {
    /// Module to host, in a session.
    Uplink = 0x55,
    /// Host to module, in a session.
    Downlink = 0xD1,
    /// Module to host, handshake.
    UplinkHandshake = 0x5A,
    /// Host to module, handshake.
    DownlinkHandshake = 0xDA,
}

impl Stream {
    /// The handshake stream of the same direction.
    pub fn handshake(self) -> Self {
        match self {
            Self::Uplink | Self::UplinkHandshake => Self::UplinkHandshake,
            Self::Downlink | Self::DownlinkHandshake => Self::DownlinkHandshake,
        }
    }
}

/// Why a message could not be framed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum EncodeError {
    /// The message does not fit [`MAX_PAYLOAD`] bytes.
    TooLarge,
    /// The output buffer is smaller than [`MAX_WIRE`].
    Buffer,
    /// The counter reached `u32::MAX`: open a new session.
    CounterExhausted,
    /// No session is open yet: pair first.
    NoSession,
}

impl core::error::Error for EncodeError {}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooLarge => write!(
                f,
                "the message exceeds {MAX_PAYLOAD} bytes: send fewer items"
            ),
            Self::Buffer => write!(f, "the frame buffer must hold {MAX_WIRE} bytes"),
            Self::CounterExhausted => {
                write!(
                    f,
                    "the link counter is exhausted: open a new session (handshake)"
                )
            }
            Self::NoSession => write!(f, "no session is open: pair with the module first"),
        }
    }
}

/// Frames messages of one direction: owns the key and the counter.
#[derive(Debug)]
pub struct Sender {
    key: Key,
    stream: Stream,
    counter: u32,
}

impl Sender {
    /// A sender on `stream` whose first frame carries counter 1.
    pub fn new(key: Key, stream: Stream) -> Self {
        Self {
            key,
            stream,
            counter: 0,
        }
    }

    /// Counter of the last frame sent (0: none yet).
    pub fn counter(&self) -> u32 {
        self.counter
    }

    /// Frames `msg` into `out` (at least [`MAX_WIRE`] bytes); returns the bytes to send,
    /// delimiter included. O(size).
    ///
    /// # Errors
    /// [`EncodeError`] if the message is too large, `out` too small or the counter exhausted.
    pub fn encode<M: Serialize>(&mut self, msg: &M, out: &mut [u8]) -> Result<usize, EncodeError> {
        let counter = self
            .counter
            .checked_add(1)
            .ok_or(EncodeError::CounterExhausted)?;
        let mut raw = [0u8; MAX_RAW];
        raw[0] = VERSION;
        raw[1] = self.stream as u8;
        raw[2..HEADER_LEN].copy_from_slice(&counter.to_le_bytes());
        let payload = postcard::to_slice(msg, &mut raw[HEADER_LEN..HEADER_LEN + MAX_PAYLOAD])
            .map_err(|_| EncodeError::TooLarge)?
            .len();
        let body = HEADER_LEN + payload;
        let tag = self.key.tag(raw.get(..body).ok_or(EncodeError::TooLarge)?);
        let sealed = raw.get_mut(..body + TAG_LEN).ok_or(EncodeError::TooLarge)?;
        for (o, &t) in sealed.iter_mut().skip(body).zip(&tag) {
            *o = t;
        }
        let n = cobs::try_encode(sealed, out).map_err(|_| EncodeError::Buffer)?;
        *out.get_mut(n).ok_or(EncodeError::Buffer)? = 0;
        self.counter = counter;
        Ok(n + 1)
    }
}
