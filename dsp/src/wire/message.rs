//! What travels on the link, both ways: postcard-encoded enums whose integer fields are varints.
//!
//! Units are fixed on the wire so both ends agree to the bit: sines of azimuth in Q15
//! (`sin θ · 32767`, rounded), ranges in millimetres ([`sin_to_q15`], [`m_to_mm`]). The
//! pipeline converts its hints and reports to and from these messages (`ObjectHint::to_wire`,
//! `ObjectHint::from_wire`, `ObjectReport::to_wire`), and the host's in-process pipeline
//! quantizes through the same conversions, so in-process and on-module answers are identical.
//! This module knows nothing of the pipeline.

use crate::config::{MAX_RX, RadarConfig};
use crate::search::MAX_CONTOUR;
use heapless::Vec;
use serde::{Deserialize, Serialize};

/// Objects per frame the module accepts.
pub const MAX_OBJECTS: usize = 16;
/// Clutter directions per frame the host may name.
pub const MAX_CLUTTER: usize = 16;

/// `sin θ` as Q15 (saturating).
pub fn sin_to_q15(s: f32) -> i16 {
    libm::roundf(s.clamp(-1.0, 1.0) * 32767.0) as i16
}

/// Q15 back to `sin θ`.
pub fn q15_to_sin(q: i16) -> f32 {
    (q as f32 / 32767.0).clamp(-1.0, 1.0)
}

/// Metres to millimetres, rounded and saturated to `u32` (negative and NaN give 0).
pub fn m_to_mm(m: f32) -> u32 {
    if m.is_nan() || m <= 0.0 {
        0
    } else {
        libm::roundf((m * 1000.0).min(u32::MAX as f32)) as u32
    }
}

/// One contour point: direction and range behind the closest point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct WirePoint {
    /// `sin θ`, Q15.
    pub sin_az: i16,
    /// Range relative to the contour's closest point, mm (saturates at 65.535 m).
    pub rel_mm: u16,
}

/// Downlink: what the camera says about one object of a frame.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Hint {
    /// Frame the hint is for.
    pub frame: u32,
    /// Instance id.
    pub instance: u16,
    /// Class code (the host's segmentation class; opaque to the module).
    pub class: u8,
    /// `sin θ` of the mask's left and right edges, Q15.
    pub span: (i16, i16),
    /// Monocular range of the closest point, mm (0: unknown).
    pub prior_mm: u32,
    /// The ranges of the closest point the camera's other cues allow (the mask's apparent
    /// size), mm: near and far bound, each 0 where unknown.
    pub window_mm: (u32, u32),
    /// The contour, at most [`MAX_CONTOUR`] points.
    pub contour: Vec<WirePoint, MAX_CONTOUR>,
}

/// A strong object the host knows is clutter (not searched), by direction and class.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Clutter {
    /// `sin θ`, Q15.
    pub sin_az: i16,
    /// Class code.
    pub class: u8,
}

/// One TX's row of a channel calibration, in the form the module's range stage applies
/// (`range::calibration::AppliedCalibration`): per RX a Q15 gain (all rows share one scale) and
/// a per-sample phase step. A calibration is `of` rows, one per TX; the module applies it once
/// every row has arrived, and a new `Config` clears it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CalibrationRow {
    /// TX index (into `tx_positions`).
    pub tx: u8,
    /// Rows of the whole calibration: the configuration's TX count.
    pub of: u8,
    /// Per RX (into `rx_positions`): the gain (re, im), Q15.
    pub gains: Vec<(i16, i16), MAX_RX>,
    /// Per RX: the frequency correction, turns per sample × 2³² (wrapping: negative steps are
    /// near 2³²).
    pub steps: Vec<u32, MAX_RX>,
}

/// Downlink messages.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Downlink {
    /// The radar configuration; the module (re)builds its pipeline. Sent first.
    Config(RadarConfig),
    /// One object of the next frame.
    Hint(Hint),
    /// Process frame `frame` from the capture source with the hints received for it.
    Frame {
        /// Frame number.
        frame: u32,
        /// Hints sent for it (the module reports a mismatch as lost hints).
        objects: u8,
        /// Clutter the camera recognized (informational: SIC finds clutter in the radar data).
        clutter: Vec<Clutter, MAX_CLUTTER>,
    },
    /// Send the health counters now.
    Health,
    /// Stop: the module sends its health counters and halts.
    Stop,
    /// One TX's row of the channel calibration (after `Config`, before the frames).
    Calibration(CalibrationRow),
}

/// How well one depth candidate explains the data, in one byte: its score's height over the
/// search floor in half dB (7 bits, 0 … 63.5 dB, clamped) and whether it survives cancelling
/// the strongest direction outside the object's span at its range (bit 0; see
/// `search::survival`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Score(pub u8);

impl Score {
    /// The score of a candidate standing `over_floor_db` dB above the floor (NaN and negative
    /// values give 0), `survives` or not.
    pub fn new(over_floor_db: f32, survives: bool) -> Self {
        let half_db = if over_floor_db.is_nan() {
            0.0
        } else {
            libm::roundf(2.0 * over_floor_db).clamp(0.0, 127.0)
        };
        Self((half_db as u8) << 1 | u8::from(survives))
    }

    /// Height over the search floor, dB (half-dB steps).
    pub fn over_floor_db(self) -> f64 {
        f64::from(self.0 >> 1) / 2.0
    }

    /// Whether the candidate survives the cancellation of the direction outside the span.
    pub fn survives(self) -> bool {
        self.0 & 1 == 1
    }
}

/// Another explanation of an object's data than the reported depth: an offset from it and its
/// [`Score`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Alternative {
    /// Its depth minus the reported depth, cm (±327 m).
    pub offset_cm: i16,
    /// Its score (0: no alternative; an alternative's is at least 1).
    pub score: Score,
}

/// Alternatives reported per object: the search's other refined candidates.
pub const ALTERNATIVES: usize = 2;

/// Uplink: the module's answer for one object, inside its frame's [`Uplink::Results`] (which
/// carries the frame number once): at most 15 bytes on the wire for depths below 2 km.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ObjectResult {
    /// Instance id (the host knows the class and span it sent in the hint).
    pub instance: u16,
    /// Depth of the object's closest point, mm: the strongest candidate that survives (the
    /// strongest of all when none does).
    pub depth_mm: u32,
    /// Its score, whether or not it passes the module's own test (the frame's
    /// [`FrameSummary::detected`] counts those): the host's trust test decides, with the
    /// camera's evidence.
    pub score: Score,
    /// The search's other explanations, survivors first, then by score (see [`Alternative`]).
    pub others: [Alternative; ALTERNATIVES],
}

impl ObjectResult {
    /// Depth in metres.
    pub fn depth_m(&self) -> f64 {
        self.depth_mm as f64 / 1000.0
    }

    /// The alternatives there are: depth (m) and score of each, those in front of the radar
    /// (over 0 m) only. None when the answer has no depth (`depth_mm` 0: nothing found, a best
    /// candidate at or behind 0 m, which [`m_to_mm`] clamps, or one the host withdrew): their
    /// offsets are from a depth the answer no longer carries, and reading them from 0 m would
    /// invent depths.
    pub fn alternatives(&self) -> impl Iterator<Item = (f64, Score)> + '_ {
        let anchored = self.depth_mm > 0;
        self.others
            .iter()
            .filter(move |a| anchored && a.score.0 > 0)
            .map(|a| (self.depth_m() + f64::from(a.offset_cm) / 100.0, a.score))
            .filter(|&(depth_m, _)| depth_m > 0.0)
    }
}

/// Uplink: one frame's bookkeeping.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct FrameSummary {
    /// Frame number.
    pub frame: u32,
    /// Objects searched.
    pub objects: u8,
    /// Objects detected.
    pub detected: u8,
    /// Strong reflectors in the frame's peak list.
    pub peaks: u8,
    /// Block exponent of the frame's spectra.
    pub exponent: i8,
    /// Time the frame took on the module, µs (monotonic clock).
    pub busy_us: u32,
}

/// The link's receive counters (see [`super::receiver`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct LinkStats {
    /// Frames accepted.
    pub accepted: u32,
    /// Frames whose COBS, length or payload could not be decoded.
    pub malformed: u32,
    /// Frames of another protocol version.
    pub bad_version: u32,
    /// Frames whose tag did not verify (forged, corrupted, wrong key or direction).
    pub bad_tag: u32,
    /// Frames whose counter was already seen or too old to tell.
    pub replayed: u32,
    /// Counters skipped and not (yet) filled in by late frames.
    pub lost: u32,
    /// Frames that arrived after a later one.
    pub reordered: u32,
    /// Frames longer than the receive buffer.
    pub overflow: u32,
}

/// Uplink: the module's health counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Health {
    /// Frames processed.
    pub frames: u32,
    /// Capture errors (short read, wrong size).
    pub capture_errors: u32,
    /// Pipeline errors (configuration, search).
    pub pipeline_errors: u32,
    /// Protocol errors (message out of order, hint mismatch).
    pub protocol_errors: u32,
    /// Uplink messages dropped by the full send queue (oldest first).
    pub queue_dropped: u32,
    /// What the downlink receiver saw.
    pub link: LinkStats,
    /// Deepest stack use so far, bytes (stack painting; 0 where the board does not measure it).
    pub stack_bytes: u32,
}

/// What went wrong on the module, reported as it happens.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Fault {
    /// A frame arrived before any configuration.
    NoConfig,
    /// The configuration does not fit the module (arena, sizes) or is invalid.
    Config,
    /// The capture source failed (short read, device error).
    Capture,
    /// The pipeline failed on an object.
    Pipeline,
    /// A downlink frame was rejected (see [`LinkStats`]).
    Link,
    /// More hints than [`MAX_OBJECTS`], or hints of another frame.
    Hints,
    /// A frame behind the capture source, or further ahead of it than the module skips.
    Sequence,
    /// The nonce source failed: no session can be opened until it works.
    Entropy,
}

impl Fault {
    /// Every fault, in wire order.
    pub const ALL: [Fault; 8] = [
        Fault::NoConfig,
        Fault::Config,
        Fault::Capture,
        Fault::Pipeline,
        Fault::Link,
        Fault::Hints,
        Fault::Sequence,
        Fault::Entropy,
    ];
}

/// Uplink messages.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
// Without an allocator there is nothing to box into: the module queues messages by value in
// fixed capacity (each Results at most 16 × 28 bytes).
#[allow(clippy::large_enum_variant)]
pub enum Uplink {
    /// The session is open: the module's first message under the new session keys (its
    /// version and limits came in the handshake's `Hello`).
    Ready,
    /// A frame is done: its bookkeeping and the answer for each object, in hint order.
    Results {
        /// Frame number, counts, timing.
        summary: FrameSummary,
        /// One per hint searched.
        objects: Vec<ObjectResult, MAX_OBJECTS>,
    },
    /// Health counters.
    Health(Health),
    /// Something failed (counted in [`Health`] too). Faults of one kind are reported at most
    /// once per rate-limit interval; the others are counted into the next report.
    Fault {
        /// Frame concerned.
        frame: u32,
        /// What.
        fault: Fault,
        /// Faults of this kind since the previous report that were not reported each.
        repeats: u32,
    },
}
