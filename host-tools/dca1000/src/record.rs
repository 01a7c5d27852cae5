//! A live stream to the bytes of a `.bin`: every frame the receiver hands on is written as it
//! came, missing bytes zero, and the frames that are not whole are listed, so a recording of a
//! lossy stream is never mistaken for a clean one; or, for a consumer that processes the
//! frames, only the whole ones are written ([`Incomplete::Skip`]).

use crate::control::{Board, ControlError};
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
    /// The address the receiver listened on (`None` if the OS could not say).
    pub local: Option<std::net::SocketAddr>,
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
    r.local = rx.local_addr().ok();
    Ok(r)
}

/// Why a recording with the board under control failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ControlledError {
    /// The board did not start or stop as asked.
    #[error(transparent)]
    Control(#[from] ControlError),
    /// The socket or the output failed (the board was told to stop all the same).
    #[error(transparent)]
    Io(#[from] io::Error),
}

/// [`record`] between `board`'s start and its stop. The board is stopped however the recording
/// ends, so a socket or output failure does not leave it streaming into the network.
///
/// # Errors
/// The board does not start; else the recording's error; else the stop's.
pub fn record_controlled(
    board: &Board,
    rx: &mut Receiver,
    out: &mut impl Write,
    frame_bytes: usize,
    limit: Option<u64>,
    timeouts: (Duration, Duration),
    incomplete: Incomplete,
) -> Result<Recording, ControlledError> {
    board.start()?;
    let recorded = record(rx, out, frame_bytes, limit, timeouts, incomplete);
    let stopped = board.stop();
    let rec = recorded?;
    stopped?;
    Ok(rec)
}
