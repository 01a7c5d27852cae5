//! The receiving end: splits the byte stream at zero bytes, checks each frame (COBS, version,
//! direction, tag, counter) and decodes its message, counting every rejection.
//!
//! Replays are rejected with a sliding window over the sender's counter, as in IPsec's
//! anti-replay check (RFC 4303 §3.4.3): counters above the highest seen advance the window
//! (the skipped ones count as lost until they arrive); counters inside the window are accepted
//! once (a reordered frame, which also un-counts a loss); counters below it are rejected as
//! too old to tell from a replay. The tag is checked before the counter, so forged frames
//! cannot move the window.

use super::VERSION;
use super::auth::{Key, TAG_LEN};
use super::frame::{HEADER_LEN, MAX_RAW, MAX_WIRE, Stream};
use super::message::LinkStats;
use core::fmt;
use serde::Deserialize;

/// Counters the replay window remembers below the highest one.
pub const WINDOW: u32 = 64;

/// Why a frame was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum LinkError {
    /// Not valid COBS, or shorter than a header and a tag.
    Malformed,
    /// Longer than [`MAX_WIRE`] bytes before its delimiter.
    Overflow,
    /// Another protocol version.
    Version(u8),
    /// Tag mismatch: corrupted, forged, wrong key, or a frame of the other direction.
    Tag,
    /// Counter already accepted.
    Replay(u32),
    /// Counter more than [`WINDOW`] below the highest accepted.
    Stale(u32),
    /// Authentic frame whose payload is not a valid message (a sender bug).
    Payload,
}

impl core::error::Error for LinkError {}

impl fmt::Display for LinkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Malformed => write!(
                f,
                "malformed frame (COBS or length): check the wiring and baud rate"
            ),
            Self::Overflow => write!(
                f,
                "frame longer than {MAX_WIRE} bytes: is the peer speaking this protocol?"
            ),
            Self::Version(v) => write!(
                f,
                "protocol version {v}, expected {VERSION}: update the firmware or the host tool"
            ),
            Self::Tag => write!(
                f,
                "authentication tag mismatch: check that both ends use the same link key"
            ),
            Self::Replay(c) => write!(
                f,
                "counter {c} was already received: replayed frame rejected"
            ),
            Self::Stale(c) => write!(
                f,
                "counter {c} is older than the replay window: frame rejected"
            ),
            Self::Payload => write!(
                f,
                "authentic frame with an undecodable message: the peer's protocol differs"
            ),
        }
    }
}

/// Splits a byte stream into frames at zero bytes. Holds at most `N` bytes of one frame;
/// longer ones are dropped whole and reported once at their delimiter.
#[derive(Debug)]
pub struct Deframer<const N: usize = MAX_WIRE> {
    buf: heapless::Vec<u8, N>,
    overflowed: bool,
    complete: bool,
}

impl<const N: usize> Default for Deframer<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Deframer<N> {
    /// An empty deframer.
    pub const fn new() -> Self {
        Self {
            buf: heapless::Vec::new(),
            overflowed: false,
            complete: false,
        }
    }

    /// Takes one byte; at a delimiter returns the frame before it (COBS-encoded, without the
    /// delimiter) or [`LinkError::Overflow`]. Empty frames are skipped. O(1).
    pub fn push(&mut self, byte: u8) -> Option<Result<&mut [u8], LinkError>> {
        if self.complete {
            self.buf.clear();
            self.complete = false;
        }
        if byte != 0 {
            if self.buf.push(byte).is_err() {
                self.overflowed = true;
            }
            return None;
        }
        self.complete = true;
        if core::mem::take(&mut self.overflowed) {
            return Some(Err(LinkError::Overflow));
        }
        if self.buf.is_empty() {
            return None;
        }
        Some(Ok(self.buf.as_mut_slice()))
    }
}

/// A frame [`Receiver::open_any`] accepted: a handshake message or a session message.
#[derive(Clone, Debug, PartialEq)]
pub enum Opened<H, M> {
    /// On the handshake stream, under the handshake key.
    Handshake(H),
    /// On the session stream, under the session key and inside the replay window.
    Session(M),
}

/// Checks and decodes frames of one direction; keeps the replay window and the counters.
#[derive(Debug)]
pub struct Receiver {
    /// Tags the session frames; `None` before the first session.
    key: Option<Key>,
    /// Tags the handshake frames, if this receiver takes them.
    handshake: Option<Key>,
    stream: Stream,
    highest: u32,
    /// Bit i: counter `highest − i` was accepted.
    seen: u64,
    stats: LinkStats,
}

impl Receiver {
    /// A receiver of `stream` frames under session key `key`, expecting the sender's counter to
    /// start at 1; it takes no handshake frames.
    pub fn new(key: Key, stream: Stream) -> Self {
        Self {
            key: Some(key),
            handshake: None,
            stream,
            highest: 0,
            seen: 1, // counter 0 is never sent: treat it as seen
            stats: LinkStats::default(),
        }
    }

    /// A receiver of `stream` that takes handshake frames under `handshake` and no session
    /// frames until [`Receiver::install`].
    pub fn with_handshake(handshake: Key, stream: Stream) -> Self {
        Self {
            key: None,
            handshake: Some(handshake),
            stream,
            highest: 0,
            seen: 1,
            stats: LinkStats::default(),
        }
    }

    /// Starts a new session under `key`: the replay window starts over (the sender's counter
    /// restarts at 1); frames of the previous session now fail the tag.
    pub fn install(&mut self, key: Key) {
        self.key = Some(key);
        self.highest = 0;
        self.seen = 1;
    }

    /// The counters so far.
    pub fn stats(&self) -> LinkStats {
        self.stats
    }

    /// Counts a rejection the caller saw before [`Receiver::open`] (e.g. a deframer overflow).
    pub fn count(&mut self, error: LinkError) {
        let s = &mut self.stats;
        let c = match error {
            LinkError::Malformed | LinkError::Payload => &mut s.malformed,
            LinkError::Overflow => &mut s.overflow,
            LinkError::Version(_) => &mut s.bad_version,
            LinkError::Tag => &mut s.bad_tag,
            LinkError::Replay(_) | LinkError::Stale(_) => &mut s.replayed,
        };
        *c = c.saturating_add(1);
    }

    /// Checks the COBS-encoded session `frame` (decoded in place) and returns its message.
    /// Every rejection is counted; a handshake frame is rejected as [`LinkError::Tag`]. O(len).
    ///
    /// # Errors
    /// [`LinkError`] naming the first check that failed.
    pub fn open<'b, M: Deserialize<'b>>(&mut self, frame: &'b mut [u8]) -> Result<M, LinkError> {
        match self.open_any::<Never, M>(frame)? {
            Opened::Session(m) => Ok(m),
            Opened::Handshake(never) => match never {},
        }
    }

    /// Checks the COBS-encoded `frame` (decoded in place): a handshake message `H` on the
    /// handshake stream, or a session message `M`. Every rejection is counted. O(len).
    ///
    /// # Errors
    /// [`LinkError`] naming the first check that failed; a session frame before any session
    /// fails the tag.
    pub fn open_any<'b, H: Deserialize<'b>, M: Deserialize<'b>>(
        &mut self,
        frame: &'b mut [u8],
    ) -> Result<Opened<H, M>, LinkError> {
        let r = self.check(frame);
        if let Err(e) = r {
            self.count(e);
        }
        r
    }

    fn check<'b, H: Deserialize<'b>, M: Deserialize<'b>>(
        &mut self,
        frame: &'b mut [u8],
    ) -> Result<Opened<H, M>, LinkError> {
        if frame.len() > MAX_WIRE {
            return Err(LinkError::Overflow);
        }
        let n = cobs_decode_in_place(frame).ok_or(LinkError::Malformed)?;
        let raw = frame.get(..n).ok_or(LinkError::Malformed)?;
        if !(HEADER_LEN + TAG_LEN..=MAX_RAW).contains(&n) {
            return Err(LinkError::Malformed);
        }
        let (body, tag) = raw.split_at(n - TAG_LEN);
        let (header, payload) = body.split_at(HEADER_LEN);
        if header[0] != VERSION {
            return Err(LinkError::Version(header[0]));
        }
        let handshake = header[1] == self.stream.handshake() as u8;
        let key = if handshake {
            self.handshake.as_ref()
        } else if header[1] == self.stream as u8 {
            self.key.as_ref()
        } else {
            None
        };
        if !key.is_some_and(|k| k.verify(body, tag)) {
            return Err(LinkError::Tag);
        }
        let opened = if handshake {
            // Fresh by its nonces (see `session`): no counter check.
            decode(payload).map(Opened::Handshake)
        } else {
            let counter = u32::from_le_bytes([header[2], header[3], header[4], header[5]]);
            self.admit(counter)?;
            decode(payload).map(Opened::Session)
        }?;
        self.stats.accepted = self.stats.accepted.saturating_add(1);
        Ok(opened)
    }

    /// The replay window (see the module docs).
    fn admit(&mut self, counter: u32) -> Result<(), LinkError> {
        let s = &mut self.stats;
        if counter > self.highest {
            let ahead = counter - self.highest;
            s.lost = s.lost.saturating_add(ahead - 1);
            // `| 1` and `^ 1` agree here (the shift clears bit 0): cargo-mutants' one
            // equivalent mutant in this file.
            self.seen = if ahead >= 64 { 0 } else { self.seen << ahead } | 1;
            self.highest = counter;
            return Ok(());
        }
        let behind = self.highest - counter;
        if behind >= WINDOW {
            return Err(LinkError::Stale(counter));
        }
        let bit = 1u64 << behind;
        if self.seen & bit != 0 {
            return Err(LinkError::Replay(counter));
        }
        self.seen |= bit;
        s.reordered = s.reordered.saturating_add(1);
        s.lost = s.lost.saturating_sub(1);
        Ok(())
    }
}
/// A whole postcard message of `payload`.
fn decode<'b, T: Deserialize<'b>>(payload: &'b [u8]) -> Result<T, LinkError> {
    match postcard::take_from_bytes::<T>(payload) {
        Ok((msg, [])) => Ok(msg),
        _ => Err(LinkError::Payload),
    }
}

/// No handshake message: what [`Receiver::open`] takes on the handshake stream.
#[derive(Debug)]
enum Never {}

impl<'de> Deserialize<'de> for Never {
    fn deserialize<D: serde::Deserializer<'de>>(_: D) -> Result<Self, D::Error> {
        Err(serde::de::Error::custom("no handshake message expected"))
    }
}

/// Decodes a COBS frame (delimiter removed) in place; returns the decoded length, or `None` for
/// a zero byte inside the frame or a code that runs past its end (the `cobs` crate's verdicts on
/// every frame the deframer can deliver). The decoded bytes never
/// overtake the encoded ones (`write ≤ read`), so one buffer serves both. Written here rather
/// than taken from the `cobs` crate (which encodes for us) because its decoder links a slice
/// panic into the firmware's loop; O(len), only checked accesses.
fn cobs_decode_in_place(buf: &mut [u8]) -> Option<usize> {
    let (mut read, mut write) = (0usize, 0usize);
    while let Some(&code) = buf.get(read) {
        if code == 0 {
            return None;
        }
        read += 1;
        for _ in 1..code {
            let byte = *buf.get(read)?;
            if byte == 0 {
                return None;
            }
            *buf.get_mut(write)? = byte;
            write += 1;
            read += 1;
        }
        if code != 0xFF && read < buf.len() {
            *buf.get_mut(write)? = 0;
            write += 1;
        }
    }
    Some(write)
}

#[cfg(test)]
mod tests {
    use super::cobs_decode_in_place;

    /// Agrees with the `cobs` crate's decoder on valid frames (round trips) and on garbage.
    #[test]
    fn cobs_decoder_matches_the_crate() {
        let mut x = 99u64;
        let mut next = || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 33) as u32
        };
        for round in 0..20_000 {
            let len = next() as usize % 600;
            let zeros = 1 + round % 5;
            let data: std::vec::Vec<u8> = (0..len)
                .map(|_| {
                    if next() % zeros as u32 == 0 {
                        0
                    } else {
                        next() as u8
                    }
                })
                .collect();
            // Valid frames decode to the data.
            let mut enc = std::vec![0u8; cobs::max_encoding_length(len)];
            let n = cobs::encode(&data, &mut enc);
            enc.truncate(n);
            let mut mine = enc.clone();
            assert_eq!(cobs_decode_in_place(&mut mine), Some(len), "round {round}");
            assert_eq!(&mine[..len], &data[..]);
            // Arbitrary bytes as the deframer delivers them (no zero, not empty; ours also
            // rejects an interior zero, where the crate stops): the same verdict and bytes.
            let garbage: std::vec::Vec<u8> = data.iter().map(|&b| b.max(1)).collect();
            if garbage.is_empty() {
                continue;
            }
            let (mut a, mut b) = (garbage.clone(), garbage.clone());
            let theirs = cobs::decode_in_place(&mut a).ok();
            let ours = cobs_decode_in_place(&mut b);
            assert_eq!(ours, theirs, "round {round}: {garbage:?}");
            if let Some(n) = ours {
                assert_eq!(a[..n], b[..n]);
            }
        }
    }
}
