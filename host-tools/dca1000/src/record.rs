//! A live stream to the bytes of a `.bin`: every frame the receiver hands on is written as it
//! came, missing bytes zero, and the frames that are not whole are listed, so a recording of a
//! lossy stream is never mistaken for a clean one; or, for a consumer that processes the
//! frames, only the whole ones are written ([`Incomplete::Skip`]).

use crate::receive::{Counters, Receiver};
use std::io::{self, Write};
use std::time::{Duration, Instant};

/// What a recording holds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recording {
    /// Frames handed on by the receiver.
    pub frames: u64,
    /// Frames with missing bytes (zero-filled) or cut short, by number.
    pub incomplete: Vec<u64>,
    /// Bytes written.
    pub bytes: u64,
    /// From the first frame handed on to the last, s.
    pub seconds: f64,
    /// The receiver's counters.
    pub counters: Counters,
}

/// What to do with a frame that is not whole.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Incomplete {
    /// Write it zero-filled (a capture file keeps its frame numbering).
    ZeroFill,
    /// Leave it out (the frames go to processing, which must never take one for whole).
    Skip,
}

/// Records frames of `frame_bytes` from `rx` into `out` until the stream goes quiet for `idle`
/// (waiting up to `start` for it to begin) or `limit` frames are handed on.
///
/// # Errors
/// The socket or `out` fails.
pub fn record(
    rx: &mut Receiver,
    out: &mut impl Write,
    frame_bytes: usize,
    limit: Option<u64>,
    (start, idle): (Duration, Duration),
    incomplete: Incomplete,
) -> io::Result<Recording> {
    let mut r = Recording::default();
    let mut first = None;
    while limit.is_none_or(|n| r.frames < n) {
        let Some(frame) = rx.next_frame(start, idle)? else {
            break;
        };
        let t = *first.get_or_insert_with(Instant::now);
        let whole = frame.is_whole(frame_bytes);
        if !whole {
            r.incomplete.push(frame.index);
        }
        r.frames += 1;
        if whole || incomplete == Incomplete::ZeroFill {
            out.write_all(&frame.bytes)?;
            r.bytes += frame.bytes.len() as u64;
        }
        r.seconds = t.elapsed().as_secs_f64();
    }
    out.flush()?;
    r.counters = rx.counters();
    Ok(r)
}
