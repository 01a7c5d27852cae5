//! The module's loop: take configuration and hints from the link, frames from the capture
//! source, run the pipeline per object and send the results back.
//!
//! ```text
//! link ─▶ Deframer ─▶ Receiver ─▶ Downlink::Config ─▶ Edge::new
//!                                 Downlink::Hint   ─▶ hints of frame F
//!                                 Downlink::Frame  ─▶ capture ─▶ pipeline ─▶ Uplink queue ─▶ link
//! ```
//!
//! Everything here is generic over the hardware (capture source, `embedded-io` link, clock,
//! nonce source), so the same state machine runs on the module, under QEMU and in host tests
//! with mocks. Nothing in it panics: every failure becomes a counted [`Health`] entry and a
//! rate-limited [`Uplink::Fault`].
//!
//! The link opens a session first (`metamoran_dsp::wire::session`): at boot the module sends
//! a `Hello` with a fresh nonce from the board's TRNG, and takes session messages only after a
//! host's `Session` for that nonce, under the keys both nonces derive.

use crate::capture::CaptureSource;
use crate::clock::Monotonic;
use embedded_io::{Read, ReadReady, Write};
use heapless::Vec;
use metamoran_dsp::array::MAX_CHANNELS;
use metamoran_dsp::capture::{IqOrder, deinterleave_bytes};
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::pipeline::{Edge, ObjectHint};
use metamoran_dsp::range::calibration::{self, AppliedCalibration};
use metamoran_dsp::trig::Phase;
use metamoran_dsp::wire::message::MAX_OBJECTS;
use metamoran_dsp::wire::session::fresh_nonce;
use metamoran_dsp::wire::{
    CalibrationRow, Deframer, DeviceKey, Downlink, DropOldest, Fault, FrameSummary, HandshakeDown,
    HandshakeUp, Health, Hint, MAX_WIRE, Nonce, ObjectResult, Opened, Receiver, Sender, Stream,
    Uplink,
};
use rand_core::TryCryptoRng;

/// Longest chirp the module takes (samples).
pub const MAX_SAMPLES: usize = 1024;
/// Uplink messages waiting for the link at most; beyond, the oldest is dropped.
pub const QUEUE: usize = 40;
/// Firmware version in the `Hello` message (major · 10000 + minor · 100 + patch).
pub const FIRMWARE_VERSION: u32 = 200;
/// Frames the module skips forward at most to reach a requested one (the capture source only
/// goes forward); a request further ahead is a [`Fault::Sequence`], so one authentic message
/// cannot keep the loop reading for hours.
pub const MAX_SKIP: u64 = 64;
/// Least time between two reports of one fault kind (or two `Hello`s), µs: 2 bytes of garbage
/// no longer buy ~20 bytes of uplink each; the faults in between are counted into the next
/// report's `repeats` (and always into [`Health`]).
pub const REPORT_INTERVAL_US: u32 = 100_000;

/// Rate limit of one kind of report: when it was last sent and what was held back since.
#[derive(Clone, Copy, Debug, Default)]
struct Gate {
    last_us: Option<u32>,
    held: u32,
}

impl Gate {
    /// Whether a report may go out at `now_us`; if not, it is counted as held back.
    fn pass(&mut self, now_us: u32) -> bool {
        let open = self
            .last_us
            .is_none_or(|t| now_us.wrapping_sub(t) >= REPORT_INTERVAL_US);
        if open {
            self.last_us = Some(now_us);
        } else {
            self.held = self.held.saturating_add(1);
        }
        open
    }
}

/// A frame's summary (without its time), its results, and how many objects failed.
type FrameResults = (FrameSummary, Vec<ObjectResult, MAX_OBJECTS>, u32);

/// Words of the channel calibration's block coefficients: every channel of the largest board
/// (32 KiB).
pub const CALIBRATION_WORDS: usize = MAX_CHANNELS * calibration::BLOCKS;

/// The module's working memory besides the frame arena (about 68 KiB, half of it the
/// calibration table); put it in a static.
pub struct Scratch {
    bytes: [u8; 4 * MAX_SAMPLES],
    chirp: [CQ15; MAX_SAMPLES],
    row: [CQ15; MAX_SAMPLES],
    azimuth: [CQ15; 256],
    powers: [u64; 768],
    scores: [f32; MAX_SAMPLES],
    calibration: [u32; CALIBRATION_WORDS],
}

impl Scratch {
    /// Zeroed scratch.
    pub const fn new() -> Self {
        Self {
            bytes: [0; 4 * MAX_SAMPLES],
            chirp: [CQ15::from_raw(0, 0); MAX_SAMPLES],
            row: [CQ15::from_raw(0, 0); MAX_SAMPLES],
            azimuth: [CQ15::from_raw(0, 0); 256],
            powers: [0; 768],
            scores: [0.0; MAX_SAMPLES],
            calibration: [0; CALIBRATION_WORDS],
        }
    }
}

/// The channel calibration as it arrives: rows by TX until all have come, then the block
/// coefficients in [`Scratch`] with their headroom.
// One lives in the module's state, by value: there is no allocator to box the 2 KiB rows into.
#[allow(clippy::large_enum_variant)]
enum Calibrating {
    /// None sent since the configuration: frames are summed as recorded.
    Off,
    /// Rows received so far (a bit per TX) of a calibration of `of` rows.
    Partial {
        rows: u32,
        of: u8,
        calibration: AppliedCalibration,
    },
    /// Every row came: the table holds the coefficients for this headroom.
    On { headroom: u32 },
}

impl Default for Scratch {
    fn default() -> Self {
        Self::new()
    }
}

/// What one call of [`Module::poll`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Poll {
    /// Nothing to do.
    Idle,
    /// Handled at least one byte.
    Busy,
    /// The host sent `Stop`: the module sent its counters and should halt.
    Stopped,
}

/// The module: hardware, pipeline state and counters.
pub struct Module<'m, C, L, K, R> {
    capture: C,
    link: L,
    clock: K,
    rng: R,
    arena: &'m mut [u32],
    scratch: &'m mut Scratch,
    edge: Option<Edge>,
    calibrating: Calibrating,
    hints: Vec<ObjectHint, MAX_OBJECTS>,
    hints_frame: u32,
    /// Next frame the capture source will deliver (past `u32::MAX` after the last one).
    next_frame: u64,
    deframer: Deframer,
    device: DeviceKey,
    /// Takes handshake frames always, session frames once a session is open.
    receiver: Receiver,
    handshake: Sender,
    /// The session's uplink sender; `None` until the first session opens.
    sender: Option<Sender>,
    /// The nonce offered in the last `Hello`, until a `Session` for it arrives.
    pending: Option<Nonce>,
    queue: DropOldest<Uplink, QUEUE>,
    health: Health,
    /// One rate limit per [`Fault`] kind (wire order), then one for `Hello`.
    gates: [Gate; Fault::ALL.len() + 1],
    stack_gauge: Option<fn() -> u32>,
}

impl<'m, C, L, K, R> Module<'m, C, L, K, R>
where
    C: CaptureSource,
    L: Read + ReadReady + Write,
    K: Monotonic,
    R: TryCryptoRng,
{
    /// A module on this hardware with frame arena `arena`, provisioned with `device`, taking
    /// session nonces from `rng` (the board's TRNG). Sends its first `Hello`.
    pub fn new(
        capture: C,
        link: L,
        clock: K,
        rng: R,
        arena: &'m mut [u32],
        scratch: &'m mut Scratch,
        device: DeviceKey,
    ) -> Self {
        let handshake = device.handshake();
        let mut m = Self {
            capture,
            link,
            clock,
            rng,
            arena,
            scratch,
            edge: None,
            calibrating: Calibrating::Off,
            hints: Vec::new(),
            hints_frame: 0,
            next_frame: 0,
            deframer: Deframer::new(),
            receiver: Receiver::with_handshake(handshake.clone(), Stream::Downlink),
            handshake: Sender::new(handshake, Stream::UplinkHandshake),
            device,
            sender: None,
            pending: None,
            queue: DropOldest::new(),
            health: Health::default(),
            gates: [Gate::default(); Fault::ALL.len() + 1],
            stack_gauge: None,
        };
        m.hello();
        m
    }

    /// Offers the pending nonce (drawing one if there is none) in a `Hello`, at most once per
    /// [`REPORT_INTERVAL_US`].
    fn hello(&mut self) {
        if self.pending.is_none() {
            match fresh_nonce(&mut self.rng) {
                Ok(n) => self.pending = Some(n),
                Err(_) => return self.fail(0, Fault::Entropy),
            }
        }
        let now = self.clock.micros();
        let (Some(nonce), Some(gate)) = (self.pending, self.gates.last_mut()) else {
            return;
        };
        if !gate.pass(now) {
            return;
        }
        let hello = HandshakeUp::Hello {
            firmware: FIRMWARE_VERSION,
            arena_words: self.arena.len().min(u32::MAX as usize) as u32,
            nonce,
        };
        let mut out = [0u8; MAX_WIRE];
        if let Ok(n) = self.handshake.encode(&hello, &mut out) {
            // A refused write is retried by the host's next Sync.
            let _ = self.link.write_all(out.get(..n).unwrap_or(&[]));
        }
    }

    /// Opens the session of the pending nonce and the host's `host`: new keys both ways, the
    /// replay window and counters start over, what the old session had queued is dropped, and
    /// `Ready` goes out first. A `Session` for any other nonce (a recording) is a link fault.
    fn open_session(&mut self, module: Nonce, host: Nonce) {
        if self.pending != Some(module) {
            self.health.link.replayed = self.health.link.replayed.saturating_add(1);
            return self.fault(0, Fault::Link);
        }
        self.pending = None;
        let keys = self.device.session(&module, &host);
        self.receiver.install(keys.downlink);
        self.sender = Some(Sender::new(keys.uplink, Stream::Uplink));
        while self.queue.pop().is_some() {
            self.health.queue_dropped = self.health.queue_dropped.saturating_add(1);
        }
        self.hints.clear();
        crate::info!("session open");
        self.queue.push(Uplink::Ready);
    }

    /// Reports `gauge()` (deepest stack use, bytes) in every [`Health`].
    pub fn with_stack_gauge(mut self, gauge: fn() -> u32) -> Self {
        self.stack_gauge = Some(gauge);
        self
    }

    /// The counters.
    pub fn health(&self) -> Health {
        let mut link = self.receiver.stats();
        link.replayed = link.replayed.saturating_add(self.health.link.replayed);
        Health {
            queue_dropped: self
                .queue
                .dropped()
                .saturating_add(self.health.queue_dropped),
            link,
            stack_bytes: self.stack_gauge.map_or(0, |g| g()),
            ..self.health
        }
    }

    /// Whether a session is open.
    pub fn in_session(&self) -> bool {
        self.sender.is_some()
    }

    /// The link (host tests and the fuzz target feed and read a mock one).
    pub fn link_mut(&mut self) -> &mut L {
        &mut self.link
    }

    /// The hardware back (host tests inspect the mock link).
    pub fn release(self) -> (C, L, K) {
        (self.capture, self.link, self.clock)
    }

    /// Sends what is queued, then handles the bytes the link has ready (at most one message).
    pub fn poll(&mut self) -> Poll {
        self.flush();
        let mut state = Poll::Idle;
        let mut byte = [0u8; 1];
        while matches!(self.link.read_ready(), Ok(true)) {
            match self.link.read(&mut byte) {
                Ok(1) => state = Poll::Busy,
                _ => break,
            }
            let message = match self.deframer.push(byte[0]) {
                None => continue,
                Some(Ok(frame)) => self.receiver.open_any::<HandshakeDown, Downlink>(frame),
                Some(Err(e)) => {
                    self.receiver.count(e);
                    Err(e)
                }
            };
            match message {
                Ok(Opened::Session(m)) => {
                    if self.handle(m) {
                        self.flush();
                        return Poll::Stopped;
                    }
                }
                Ok(Opened::Handshake(HandshakeDown::Sync)) => self.hello(),
                Ok(Opened::Handshake(HandshakeDown::Session { module, host })) => {
                    self.open_session(module, host);
                }
                Err(_) => self.fault(self.hints_frame, Fault::Link),
            }
            break;
        }
        self.flush();
        state
    }

    /// Handles one message; true for `Stop`.
    fn handle(&mut self, message: Downlink) -> bool {
        match message {
            Downlink::Config(config) => {
                self.edge = match config.validate().ok().and(Edge::new(&config).ok()) {
                    Some(e) if e.arena_words() <= self.arena.len() && fits(&config) => {
                        crate::info!(
                            "configured: {=usize} elements, {=u16} samples, {=usize} rows per frame",
                            e.array().elements(),
                            e.samples(),
                            e.rows_per_frame()
                        );
                        Some(e)
                    }
                    _ => {
                        self.health.pipeline_errors += 1;
                        self.fault(0, Fault::Config);
                        None
                    }
                };
                self.next_frame = 0;
                self.hints.clear();
                self.calibrating = Calibrating::Off;
            }
            Downlink::Calibration(row) => self.calibration_row(&row),
            Downlink::Hint(h) => self.hint(&h),
            Downlink::Frame { frame, objects, .. } => {
                if self.hints_frame != frame {
                    // Hints of another frame do not describe this one.
                    self.hints.clear();
                }
                if self.hints.len() != objects as usize {
                    self.health.protocol_errors += 1;
                    self.fault(frame, Fault::Hints);
                }
                self.frame(frame);
                self.hints.clear();
            }
            Downlink::Health => self.queue.push(Uplink::Health(self.health())),
            Downlink::Stop => {
                self.queue.push(Uplink::Health(self.health()));
                return true;
            }
        }
        false
    }

    /// Takes one TX's row of the channel calibration; with the last one, fills the block
    /// coefficients. A row that does not fit the configuration discards the calibration (the
    /// frames then fail until a whole one arrives: they are never summed half calibrated).
    fn calibration_row(&mut self, row: &CalibrationRow) {
        let Some(edge) = self.edge.as_ref() else {
            self.health.protocol_errors += 1;
            return self.fault(0, Fault::NoConfig);
        };
        let (tx_count, rx_count) = (edge.tx_count(), edge.rx_count());
        let fits = usize::from(row.of) == tx_count
            && usize::from(row.tx) < tx_count
            && row.gains.len() == rx_count
            && row.steps.len() == rx_count;
        let state = core::mem::replace(&mut self.calibrating, Calibrating::Off);
        let (mut rows, mut calibration) = match state {
            Calibrating::Partial {
                rows,
                of,
                calibration,
            } if of == row.of => (rows, calibration),
            _ => match AppliedCalibration::identity(tx_count, rx_count) {
                Ok(c) => (0, c),
                Err(_) => {
                    self.health.pipeline_errors += 1;
                    return self.fault(0, Fault::Config);
                }
            },
        };
        let mut ok = fits;
        for (r, (&(re, im), &step)) in row.gains.iter().zip(&row.steps).enumerate() {
            ok &= calibration
                .set(usize::from(row.tx), r, CQ15::from_raw(re, im), Phase(step))
                .is_ok();
        }
        if !ok {
            self.health.protocol_errors += 1;
            self.calibrating = Calibrating::Partial {
                rows: 0,
                of: 0,
                calibration,
            };
            return self.fault(0, Fault::Config);
        }
        rows |= 1 << row.tx;
        if rows.count_ones() as usize != tx_count {
            self.calibrating = Calibrating::Partial {
                rows,
                of: row.of,
                calibration,
            };
            return;
        }
        match edge.calibrate(&calibration, &mut self.scratch.calibration) {
            Ok(c) => {
                crate::info!("calibrated: headroom {=u32} bits", c.headroom());
                self.calibrating = Calibrating::On {
                    headroom: c.headroom(),
                };
            }
            Err(_) => {
                self.health.pipeline_errors += 1;
                self.calibrating = Calibrating::Partial {
                    rows: 0,
                    of: 0,
                    calibration,
                };
                self.fault(0, Fault::Config);
            }
        }
    }

    fn hint(&mut self, h: &Hint) {
        if !self.hints.is_empty() && h.frame != self.hints_frame {
            // Hints of an older frame that never got its Frame message.
            self.hints.clear();
            self.health.protocol_errors += 1;
            self.fault(h.frame, Fault::Hints);
        }
        self.hints_frame = h.frame;
        if self.hints.push(ObjectHint::from_wire(h)).is_err() {
            self.health.protocol_errors += 1;
            self.fault(h.frame, Fault::Hints);
        }
    }

    /// Reads frame `frame` from the capture source, runs the pipeline on it and queues its
    /// results; a failure is counted and reported as a fault instead.
    fn frame(&mut self, frame: u32) {
        let start = self.clock.micros();
        let (mut summary, objects, failed) = match self.run_frame(frame) {
            Ok(done) => done,
            Err(fault) => return self.fail(frame, fault),
        };
        // Reported once the scratch is free (still before the frame's results).
        for _ in 0..failed {
            self.fail(frame, Fault::Pipeline);
        }
        self.health.frames += 1;
        summary.busy_us = self.clock.micros().wrapping_sub(start);
        crate::info!(
            "frame {=u32}: {=u8} of {=u8} objects detected, {=u8} peaks, {=u32} us",
            frame,
            summary.detected,
            summary.objects,
            summary.peaks,
            summary.busy_us
        );
        self.queue.push(Uplink::Results { summary, objects });
    }

    /// The frame's sums from the capture source (skipping frames the host did not ask for),
    /// the range stage, and the search for each hint: the frame's summary (without its time),
    /// the results and how many objects failed.
    fn run_frame(&mut self, frame: u32) -> Result<FrameResults, Fault> {
        let edge = self.edge.as_ref().ok_or(Fault::NoConfig)?;
        let wanted = u64::from(frame);
        if wanted < self.next_frame || wanted - self.next_frame > MAX_SKIP {
            // The capture source only goes forward, and only so far per request.
            return Err(Fault::Sequence);
        }
        let s = &mut *self.scratch;
        let n = usize::from(edge.samples());
        let rows = edge.rows_per_frame();
        let bytes = s.bytes.get_mut(..4 * n).ok_or(Fault::Config)?;
        let chirp = s.chirp.get_mut(..n).ok_or(Fault::Config)?;
        // Skip frames the host did not ask for.
        // At most MAX_SKIP frames (checked above).
        while self.next_frame < wanted {
            for _ in 0..rows {
                self.capture.read_exact(bytes).map_err(|_| Fault::Capture)?;
            }
            self.next_frame += 1;
        }
        self.next_frame = wanted + 1;
        // A calibration that is not whole is never applied, nor is it ignored.
        let coefficients = match &self.calibrating {
            Calibrating::Off => None,
            Calibrating::Partial { .. } => return Err(Fault::Config),
            Calibrating::On { headroom } => Some(
                edge.coefficients(&s.calibration, *headroom)
                    .map_err(|_| Fault::Config)?,
            ),
        };
        let mut sum = match &coefficients {
            None => edge.start(self.arena),
            Some(c) => edge.start_calibrated(self.arena, c),
        }
        .map_err(|_| Fault::Config)?;
        let rx = edge.rx_count();
        for row in 0..rows {
            let ok = self.capture.read_exact(bytes).is_ok()
                && deinterleave_bytes(bytes, IqOrder::Iiqq, chirp).is_ok();
            if !ok {
                return Err(Fault::Capture);
            }
            let (chirp_index, rx_index) = (row.checked_div(rx), row.checked_rem(rx));
            let pushed = match (chirp_index, rx_index, &coefficients) {
                (Some(c), Some(r), None) => edge.push(&mut sum, c, r, chirp).is_ok(),
                (Some(c), Some(r), Some(k)) => {
                    edge.push_calibrated(&mut sum, c, r, chirp, k).is_ok()
                }
                _ => false,
            };
            if !pushed {
                return Err(Fault::Pipeline);
            }
        }
        let mut scene = edge
            .finish(sum, &mut s.row, &mut s.azimuth, &mut s.powers)
            .map_err(|_| Fault::Pipeline)?;
        let m = edge.fft_len().min(MAX_SAMPLES);
        let mut summary = FrameSummary {
            frame,
            objects: self.hints.len() as u8,
            detected: 0,
            peaks: scene.peaks.len().min(255) as u8,
            exponent: scene.spectra.exponent().clamp(-128, 127) as i8,
            busy_us: 0,
        };
        let mut objects = Vec::new();
        let mut failed = 0u32;
        for hint in &self.hints {
            match edge.object(&mut scene, hint, s.scores.get_mut(..m).unwrap_or(&mut [])) {
                Ok(report) => {
                    summary.detected += report.detected() as u8;
                    let r = report.to_wire();
                    // Cannot overflow: at most MAX_OBJECTS hints.
                    let _ = objects.push(r);
                }
                Err(_) => failed += 1,
            }
        }
        Ok((summary, objects, failed))
    }

    /// Counts a failure in its health counter (protocol, capture or pipeline) and reports it.
    fn fail(&mut self, frame: u32, fault: Fault) {
        let h = &mut self.health;
        let count = match fault {
            Fault::NoConfig | Fault::Hints | Fault::Link | Fault::Sequence => {
                &mut h.protocol_errors
            }
            Fault::Capture => &mut h.capture_errors,
            Fault::Config | Fault::Pipeline | Fault::Entropy => &mut h.pipeline_errors,
        };
        *count = count.saturating_add(1);
        self.fault(frame, fault);
    }

    /// Reports a (counted) error: sent to the host as a `Fault` and logged, at most once per
    /// [`REPORT_INTERVAL_US`] per kind; the ones held back go into the next report's `repeats`.
    fn fault(&mut self, frame: u32, fault: Fault) {
        let now = self.clock.micros();
        let Some(gate) = self.gates.get_mut(fault as usize) else {
            return;
        };
        if !gate.pass(now) {
            return;
        }
        let repeats = core::mem::take(&mut gate.held);
        crate::warn!("fault at frame {=u32}: {=str}", frame, fault_name(fault));
        self.queue.push(Uplink::Fault {
            frame,
            fault,
            repeats,
        });
    }

    /// Sends every queued message; a link that refuses bytes, or no session yet, leaves the
    /// rest queued.
    fn flush(&mut self) {
        let mut out = [0u8; MAX_WIRE];
        let Some(sender) = self.sender.as_mut() else {
            return;
        };
        while let Some(msg) = self.queue.front() {
            let encoded = sender.encode(msg, &mut out);
            let Ok(len) = encoded else {
                self.health.protocol_errors += 1;
                crate::warn!("uplink message could not be encoded; dropped");
                let _ = self.queue.pop();
                continue;
            };
            if self.link.write_all(out.get(..len).unwrap_or(&[])).is_err() {
                // Keep the message; the receiver sees its counter skipped as a loss.
                return;
            }
            let _ = self.queue.pop();
        }
    }
}

/// What a fault means, for the log.
fn fault_name(fault: Fault) -> &'static str {
    match fault {
        Fault::NoConfig => "frame before any configuration",
        Fault::Config => "configuration rejected (invalid or too large for the module)",
        Fault::Capture => "capture failed (short read or device error)",
        Fault::Pipeline => "pipeline error",
        Fault::Link => "link frame rejected (see the link counters)",
        Fault::Hints => "hints do not match the frame",
        Fault::Sequence => "frame behind the capture or too far ahead of it",
        Fault::Entropy => "the nonce source failed",
    }
}

/// Whether `config` fits the module's scratch.
fn fits(config: &metamoran_dsp::config::RadarConfig) -> bool {
    // The range FFT pads `adc_samples` up to a power of two: bounding it bounds both.
    config.range_fft_len() <= MAX_SAMPLES
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::bench_scene;
    use crate::capture::SliceCapture;
    use crate::clock::StepClock;
    use crate::host_mock::{Line as MockLink, SeededNonces as TestRng};
    use metamoran_dsp::wire::{DEV_KEY, Fault, Health, HostLink, Key, LinkError};
    use std::vec;
    use std::vec::Vec as StdVec;

    /// The budget scene's frame as the radar board sends it (DCA1000 IIQQ bytes), `frames` times.
    fn capture(frames: usize) -> StdVec<u8> {
        let config = bench_scene::config();
        let mut chirp = vec![CQ15::from_raw(0, 0); bench_scene::N];
        let mut one = StdVec::new();
        for c in 0..config.chirps_per_frame() {
            for rx in 0..config.rx_count() {
                bench_scene::chirp(&config, c, rx, &mut chirp);
                for pair in chirp.chunks_exact(2) {
                    for v in [pair[0].re.0, pair[1].re.0, pair[0].im.0, pair[1].im.0] {
                        one.extend_from_slice(&v.to_le_bytes());
                    }
                }
            }
        }
        one.repeat(frames)
    }

    type TestModule<'a> = Module<'a, SliceCapture<'a>, MockLink, StepClock, TestRng>;

    /// The host's end, on the development key; `nonce` seeds its nonces.
    struct Host {
        link: HostLink,
        nonce: u8,
    }

    impl Host {
        fn new() -> Self {
            Self {
                link: HostLink::new(DeviceKey::new(DEV_KEY)),
                nonce: 0x40,
            }
        }
        fn frame(&mut self, msg: &Downlink) -> StdVec<u8> {
            let mut out = [0u8; MAX_WIRE];
            let n = self.link.encode(msg, &mut out).unwrap();
            out[..n].to_vec()
        }
        fn sync(&mut self) -> StdVec<u8> {
            let mut out = [0u8; MAX_WIRE];
            let n = self.link.sync(&mut out).unwrap();
            out[..n].to_vec()
        }
        /// Every frame of `bytes`, handshake or session.
        fn open_all(
            &mut self,
            bytes: &[u8],
        ) -> StdVec<Result<Opened<HandshakeUp, Uplink>, LinkError>> {
            let mut d: Deframer = Deframer::new();
            let mut out = StdVec::new();
            for &b in bytes {
                if let Some(Ok(f)) = d.push(b) {
                    out.push(self.link.open(f));
                }
            }
            out
        }
        /// The session messages of `bytes` (handshake frames left out).
        fn decode(&mut self, bytes: &[u8]) -> StdVec<Result<Uplink, LinkError>> {
            self.open_all(bytes)
                .into_iter()
                .filter_map(|r| match r {
                    Ok(Opened::Session(m)) => Some(Ok(m)),
                    Ok(Opened::Handshake(_)) => None,
                    Err(e) => Some(Err(e)),
                })
                .collect()
        }
        /// Pairs with `m` from the last `Hello` it sent (taking what it sent), and checks the
        /// session opens with `Ready`.
        fn pair(&mut self, m: &mut TestModule<'_>) {
            let sent = core::mem::take(&mut m.link.tx);
            let nonce = self
                .open_all(&sent)
                .into_iter()
                .filter_map(|r| match r {
                    Ok(Opened::Handshake(HandshakeUp::Hello { nonce, .. })) => Some(nonce),
                    _ => None,
                })
                .next_back()
                .expect("the module sent no Hello");
            self.nonce += 1;
            let mut out = [0u8; MAX_WIRE];
            let n = self.link.pair(nonce, [self.nonce; 16], &mut out).unwrap();
            send(m, &out[..n]);
            let sent = core::mem::take(&mut m.link.tx);
            assert_eq!(self.decode(&sent), [Ok(Uplink::Ready)]);
            assert!(m.in_session());
        }
    }

    fn run<C: CaptureSource>(module: &mut Module<'_, C, MockLink, StepClock, TestRng>) {
        for _ in 0..1_000_000 {
            if module.poll() != Poll::Busy {
                return;
            }
        }
        panic!("the module never went idle");
    }

    struct Rig {
        arena: StdVec<u32>,
        scratch: std::boxed::Box<Scratch>,
        bytes: StdVec<u8>,
    }

    impl Rig {
        fn new(frames: usize) -> Self {
            Self {
                arena: vec![0; bench_scene::ARENA_WORDS],
                scratch: std::boxed::Box::new(Scratch::new()),
                bytes: capture(frames),
            }
        }
        /// A module booted with nonce seed `boot`, not paired.
        fn boot(&mut self, link: MockLink, boot: u64) -> TestModule<'_> {
            Module::new(
                SliceCapture::new(&self.bytes),
                link,
                StepClock::new(10),
                TestRng(boot),
                &mut self.arena,
                &mut self.scratch,
                DeviceKey::new(DEV_KEY),
            )
        }
        /// A module paired with `host`.
        fn module(&mut self, link: MockLink, host: &mut Host) -> TestModule<'_> {
            let mut m = self.boot(link, 1);
            host.pair(&mut m);
            m
        }
    }

    /// A request for frame `frame` with no hints.
    fn go(frame: u32) -> Downlink {
        Downlink::Frame {
            frame,
            objects: 0,
            clutter: Vec::new(),
        }
    }

    fn send(m: &mut TestModule<'_>, bytes: &[u8]) {
        m.link.rx.extend(bytes.iter().copied());
        run(m);
    }

    #[test]
    fn a_frame_gives_the_pipelines_results() {
        let mut host = Host::new();
        let mut rig = Rig::new(1);
        let mut m = rig.module(MockLink::default(), &mut host);
        send(
            &mut m,
            &host.frame(&Downlink::Config(bench_scene::config())),
        );
        let hints = bench_scene::hints();
        for h in &hints {
            send(&mut m, &host.frame(&Downlink::Hint(h.to_wire(0))));
        }
        let go = Downlink::Frame {
            frame: 0,
            objects: 4,
            clutter: Vec::new(),
        };
        send(&mut m, &host.frame(&go));
        let up: StdVec<Uplink> = host
            .decode(&m.link.tx)
            .into_iter()
            .map(Result::unwrap)
            .collect();
        // The same frame through the pipeline directly.
        let expected = direct(None);
        let Uplink::Results { summary, objects } = &up[0] else {
            panic!("expected results, got {:?}", up[0]);
        };
        assert_eq!(&objects[..], &expected[..]);
        for (i, r) in objects.iter().enumerate() {
            assert!(r.score.over_floor_db() > 7.5, "object {i}: {r:?}");
            assert!(
                (r.depth_m() as f32 - bench_scene::truth_m(i)).abs() < 0.05,
                "{r:?}"
            );
        }
        assert_eq!(
            (summary.frame, summary.objects, summary.detected),
            (0, 4, 4)
        );
        assert_eq!(m.health().frames, 1);
    }

    /// The budget scene's results through the pipeline directly (not the module), calibrated
    /// by `calibration` as it is summed when given.
    fn direct(calibration: Option<&AppliedCalibration>) -> StdVec<ObjectResult> {
        let config = bench_scene::config();
        let edge = Edge::new(&config).unwrap();
        let mut table = vec![0u32; edge.calibration_words()];
        let k = calibration.map(|c| edge.calibrate(c, &mut table).unwrap());
        let mut arena = vec![0u32; edge.arena_words()];
        let mut sum = match &k {
            None => edge.start(&mut arena).unwrap(),
            Some(k) => edge.start_calibrated(&mut arena, k).unwrap(),
        };
        let mut chirp = vec![CQ15::from_raw(0, 0); bench_scene::N];
        for c in 0..config.chirps_per_frame() {
            for rx in 0..config.rx_count() {
                bench_scene::chirp(&config, c, rx, &mut chirp);
                match &k {
                    None => edge.push(&mut sum, c, rx, &chirp),
                    Some(k) => edge.push_calibrated(&mut sum, c, rx, &chirp, k),
                }
                .unwrap();
            }
        }
        let (mut row, mut az, mut pw) = (
            vec![CQ15::from_raw(0, 0); 512],
            [CQ15::from_raw(0, 0); 256],
            [0u64; 768],
        );
        let mut scene = edge.finish(sum, &mut row, &mut az, &mut pw).unwrap();
        let mut scores = vec![0.0f32; 512];
        bench_scene::hints()
            .iter()
            .map(|h| {
                let h = ObjectHint::from_wire(&h.to_wire(0));
                edge.object(&mut scene, &h, &mut scores).unwrap().to_wire()
            })
            .collect()
    }

    /// The rows of `cal` as the host sends them.
    fn rows(cal: &AppliedCalibration) -> StdVec<Downlink> {
        let (tx, rx) = cal.size();
        (0..tx)
            .map(|t| {
                let row = (0..rx).map(|r| cal.get(t, r).unwrap());
                Downlink::Calibration(CalibrationRow {
                    tx: t as u8,
                    of: tx as u8,
                    gains: row.clone().map(|(g, _)| (g.re.0, g.im.0)).collect(),
                    steps: row.map(|(_, p)| p.0).collect(),
                })
            })
            .collect()
    }

    /// The module's results of frame 0 after `before` (downlink messages).
    fn results_after(before: &[Downlink]) -> (StdVec<Uplink>, Health) {
        let mut host = Host::new();
        let mut rig = Rig::new(1);
        let mut m = rig.module(MockLink::default(), &mut host);
        for msg in before {
            send(&mut m, &host.frame(msg));
        }
        let hints = bench_scene::hints();
        for h in &hints {
            send(&mut m, &host.frame(&Downlink::Hint(h.to_wire(0))));
        }
        send(
            &mut m,
            &host.frame(&Downlink::Frame {
                frame: 0,
                objects: hints.len() as u8,
                clutter: Vec::new(),
            }),
        );
        let up = host
            .decode(&m.link.tx)
            .into_iter()
            .map(Result::unwrap)
            .collect();
        (up, m.health())
    }

    #[test]
    fn a_calibration_sent_over_the_link_is_applied_in_the_range_stage() {
        let config = bench_scene::config();
        let cal = bench_scene::calibration().unwrap();
        let mut msgs = vec![Downlink::Config(config.clone())];
        msgs.extend(rows(&cal));
        let (up, health) = results_after(&msgs);
        // The same frame through the calibrated pipeline directly.
        let expected = direct(Some(&cal));
        let Uplink::Results { objects, .. } = &up[0] else {
            panic!("expected results, got {:?}", up[0]);
        };
        assert_eq!(&objects[..], &expected[..]);
        assert_eq!(health.frames, 1);
        // Not the uncalibrated answer.
        let (plain, _) = results_after(&msgs[..1]);
        let Uplink::Results { objects: raw, .. } = &plain[0] else {
            panic!("{:?}", plain[0]);
        };
        assert_ne!(raw, objects, "the calibration changed nothing");
    }

    #[test]
    fn a_partial_calibration_fails_the_frames_until_it_is_whole_or_cleared() {
        let config = bench_scene::config();
        let all = rows(&bench_scene::calibration().unwrap());
        let mut msgs = vec![Downlink::Config(config.clone())];
        msgs.extend(all[..all.len() - 1].iter().cloned());
        let (up, health) = results_after(&msgs);
        assert!(
            up.iter().all(|u| !matches!(u, Uplink::Results { .. })),
            "{up:?}"
        );
        assert!(up.iter().any(|u| matches!(
            u,
            Uplink::Fault {
                fault: Fault::Config,
                ..
            }
        )));
        assert_eq!(health.frames, 0);
        // A row for another board's size discards the calibration.
        let Downlink::Calibration(mut bad) = all[0].clone() else {
            unreachable!()
        };
        bad.gains.pop();
        let mut wrong = vec![Downlink::Config(config.clone()), Downlink::Calibration(bad)];
        wrong.extend(all[1..].iter().cloned());
        let (up, health) = results_after(&wrong);
        assert!(
            up.iter().all(|u| !matches!(u, Uplink::Results { .. })),
            "{up:?}"
        );
        assert!(health.protocol_errors >= 1);
        // A new configuration clears it: the frame is summed as recorded.
        msgs.push(Downlink::Config(config));
        let (up, health) = results_after(&msgs);
        assert!(matches!(up[0], Uplink::Results { .. }), "{up:?}");
        assert_eq!(health.frames, 1);
    }

    fn faults(up: &[Result<Uplink, LinkError>]) -> StdVec<Fault> {
        up.iter()
            .filter_map(|u| match u {
                Ok(Uplink::Fault { fault, .. }) => Some(*fault),
                _ => None,
            })
            .collect()
    }

    fn health(up: &[Result<Uplink, LinkError>]) -> Health {
        up.iter()
            .rev()
            .find_map(|u| match u {
                Ok(Uplink::Health(h)) => Some(*h),
                _ => None,
            })
            .expect("no health message")
    }

    #[test]
    fn a_frame_before_any_configuration_is_a_counted_fault() {
        let mut host = Host::new();
        let mut rig = Rig::new(1);
        let mut m = rig.module(MockLink::default(), &mut host);
        let go = Downlink::Frame {
            frame: 0,
            objects: 0,
            clutter: Vec::new(),
        };
        send(&mut m, &host.frame(&go));
        send(&mut m, &host.frame(&Downlink::Health));
        let up = host.decode(&m.link.tx);
        assert_eq!(faults(&up), [Fault::NoConfig]);
        assert_eq!(health(&up).protocol_errors, 1);
    }

    #[test]
    fn frames_are_skipped_forward_and_a_short_capture_is_a_fault() {
        let mut host = Host::new();
        let mut rig = Rig::new(2);
        let mut m = rig.module(MockLink::default(), &mut host);
        send(
            &mut m,
            &host.frame(&Downlink::Config(bench_scene::config())),
        );
        send(&mut m, &host.frame(&go(1))); // skips frame 0
        send(&mut m, &host.frame(&go(0))); // cannot go back
        send(&mut m, &host.frame(&go(2))); // beyond the capture
        send(&mut m, &host.frame(&Downlink::Health));
        let up = host.decode(&m.link.tx);
        assert_eq!(faults(&up), [Fault::Sequence, Fault::Capture]);
        let h = health(&up);
        assert_eq!((h.frames, h.capture_errors, h.protocol_errors), (1, 1, 1));
    }

    #[test]
    fn garbage_forgeries_and_replays_are_counted_and_the_loop_goes_on() {
        let mut host = Host::new();
        let mut rig = Rig::new(1);
        let mut m = rig.module(MockLink::default(), &mut host);
        let cfg = host.frame(&Downlink::Config(bench_scene::config()));
        send(&mut m, &[0x13, 0x37, 0x00, 0x00]); // garbage frame
        send(&mut m, &vec![0x5A; 2 * MAX_WIRE]); // overlong
        send(&mut m, &[0]);
        let mut forged = cfg.clone();
        forged[3] ^= 0x40;
        send(&mut m, &forged);
        send(&mut m, &cfg);
        send(&mut m, &cfg); // replay
        let mut other = Sender::new(DeviceKey::new([9; 32]).handshake(), Stream::Downlink);
        let mut wrong = [0u8; MAX_WIRE];
        let n = other.encode(&Downlink::Stop, &mut wrong).unwrap();
        send(&mut m, &wrong[..n]); // wrong key: must not stop the module
        send(&mut m, &host.frame(&Downlink::Health));
        let up = host.decode(&m.link.tx);
        let h = health(&up);
        // The handshake's Session, the configuration and the health request.
        assert_eq!(h.link.accepted, 3, "{h:?}");
        assert_eq!(h.link.replayed, 1);
        assert_eq!(h.link.overflow, 1);
        assert!(h.link.bad_tag >= 2 && h.link.malformed >= 1, "{h:?}");
        assert!(faults(&up).iter().all(|f| *f == Fault::Link));
    }

    #[test]
    fn a_refusing_link_drops_the_oldest_uplink_messages_and_counts_them() {
        let mut host = Host::new();
        let mut rig = Rig::new(1);
        let mut m = rig.module(MockLink::default(), &mut host);
        m.link.refuse = true;
        for _ in 0..QUEUE + 10 {
            send(&mut m, &host.frame(&Downlink::Health));
        }
        m.link.refuse = false;
        send(&mut m, &host.frame(&Downlink::Stop));
        let up = host.decode(&m.link.tx);
        // The first Health answers were dropped; the newest survive, in order.
        let h = health(&up);
        assert_eq!(h.queue_dropped, 10, "{h:?}");
        assert_eq!(up.len(), QUEUE + 1);
        let _ = Key::new(&DEV_KEY);
    }

    /// Issue #18, item 1: after a module reboot every recorded frame of the old session is
    /// rejected both ways (before, counters restarted at 1 under one key and recordings of
    /// Config, Stop and "no detections" Results were accepted).
    #[test]
    fn a_reboot_makes_every_recorded_frame_useless() {
        let mut rig = Rig::new(2);
        let mut host = Host::new();
        let (config, stop, old_uplink) = {
            let mut m = rig.module(MockLink::default(), &mut host);
            let config = host.frame(&Downlink::Config(bench_scene::config()));
            send(&mut m, &config);
            send(&mut m, &host.frame(&Downlink::Health));
            let stop = host.frame(&Downlink::Stop);
            (config, stop, core::mem::take(&mut m.link.tx))
        };
        // The module reboots (another nonce) and pairs with a new host run.
        let mut host = Host::new();
        let mut m = rig.boot(MockLink::default(), 2);
        host.pair(&mut m);
        send(&mut m, &stop);
        send(&mut m, &config);
        assert!(m.in_session(), "a recorded Stop must not stop the module");
        send(
            &mut m,
            &host.frame(&Downlink::Frame {
                frame: 0,
                objects: 0,
                clutter: Vec::new(),
            }),
        );
        send(&mut m, &host.frame(&Downlink::Health));
        let up = host.decode(&m.link.tx);
        assert_eq!(faults(&up), [Fault::Link, Fault::NoConfig], "{up:?}");
        let h = health(&up);
        assert_eq!(h.link.bad_tag, 2, "{h:?}");
        // The old session's uplink (its Health, counter 2) is rejected by the new host.
        assert!(
            host.decode(&old_uplink)
                .iter()
                .all(|r| *r == Err(LinkError::Tag)),
            "old uplink frames must fail the tag"
        );
    }

    /// A recorded `Session` pairs nothing: the module takes a `Session` only for the nonce it
    /// offers now.
    #[test]
    fn a_replayed_session_message_cannot_pair_with_a_recording() {
        let mut rig = Rig::new(1);
        let recorded = {
            let mut m = rig.boot(MockLink::default(), 1);
            let mut host = Host::new();
            let sent = core::mem::take(&mut m.link.tx);
            let Some(Ok(Opened::Handshake(HandshakeUp::Hello { nonce, .. }))) =
                host.open_all(&sent).pop()
            else {
                panic!("no Hello");
            };
            let mut out = [0u8; MAX_WIRE];
            let n = host.link.pair(nonce, [7; 16], &mut out).unwrap();
            out[..n].to_vec()
        };
        let mut m = rig.boot(MockLink::default(), 2);
        send(&mut m, &recorded);
        assert!(!m.in_session());
        assert_eq!(m.health().link.replayed, 1);
        // The genuine host still pairs.
        Host::new().pair(&mut m);
    }

    /// Issue #18, item 1: when the host restarts, a `Sync` gets a new `Hello` and a new
    /// session; the old host's frames are then rejected.
    #[test]
    fn a_host_restart_resyncs_the_session() {
        let mut rig = Rig::new(1);
        let mut old = Host::new();
        let mut m = rig.module(MockLink::default(), &mut old);
        let late = old.frame(&Downlink::Stop);
        let mut new = Host::new();
        new.nonce = 0x90;
        // Past the Hello's rate limit (the boot Hello was just sent).
        m.clock = StepClock::new(2 * REPORT_INTERVAL_US);
        send(&mut m, &new.sync());
        new.pair(&mut m);
        send(&mut m, &late);
        assert!(m.in_session());
        send(&mut m, &new.frame(&Downlink::Health));
        let h = health(&new.decode(&m.link.tx));
        assert_eq!(h.link.bad_tag, 1, "{h:?}");
        // A replayed Sync re-sends the pending Hello, and the session keeps running.
        send(&mut m, &new.sync());
        m.link.tx.clear();
        send(&mut m, &new.frame(&Downlink::Health));
        assert!(matches!(
            new.decode(&m.link.tx)[..],
            [Ok(Uplink::Health(_))]
        ));
    }

    /// Issue #18, item 3: 1,000 two-byte garbage frames used to queue 1,000 faults (~20 bytes
    /// each); now one report per kind per interval, the rest counted into the next report.
    #[test]
    fn faults_are_rate_limited_and_aggregated() {
        let mut rig = Rig::new(1);
        let mut host = Host::new();
        let mut m = rig.module(MockLink::default(), &mut host);
        let garbage = [0x13u8, 0x00].repeat(1000);
        send(&mut m, &garbage);
        let uplink = m.link.tx.len();
        let up = host.decode(&core::mem::take(&mut m.link.tx));
        assert_eq!(faults(&up), [Fault::Link]);
        assert!(
            uplink < 64,
            "{uplink} uplink bytes for 2,000 bytes of garbage"
        );
        // After the interval the next report carries what was held back.
        m.clock = StepClock::new(2 * REPORT_INTERVAL_US);
        send(&mut m, &[0x13, 0x00]);
        send(&mut m, &host.frame(&Downlink::Health));
        let up = host.decode(&m.link.tx);
        let repeats: StdVec<u32> = up
            .iter()
            .filter_map(|u| match u {
                Ok(Uplink::Fault { repeats, .. }) => Some(*repeats),
                _ => None,
            })
            .collect();
        assert_eq!(repeats, [999]);
        assert_eq!(health(&up).link.malformed, 1001);
    }

    /// Issue #18, item 3: `frame + 1` wrapped at `u32::MAX` and the skip loop had no bound.
    #[test]
    fn the_last_frame_number_and_far_requests_are_sequence_faults() {
        let mut rig = Rig::new(2);
        let mut host = Host::new();
        let mut m = rig.module(MockLink::default(), &mut host);
        send(
            &mut m,
            &host.frame(&Downlink::Config(bench_scene::config())),
        );
        send(&mut m, &host.frame(&go(u32::MAX)));
        m.clock = StepClock::new(2 * REPORT_INTERVAL_US);
        send(&mut m, &host.frame(&go(MAX_SKIP as u32 + 1)));
        // Within the bound the module still skips forward and runs the frame.
        send(&mut m, &host.frame(&go(1)));
        send(&mut m, &host.frame(&Downlink::Health));
        let up = host.decode(&m.link.tx);
        assert_eq!(faults(&up), [Fault::Sequence, Fault::Sequence]);
        let h = health(&up);
        assert_eq!((h.frames, h.capture_errors), (1, 0), "{h:?}");
    }

    /// Configurations the module cannot hold are refused, each counted once (cargo-mutants:
    /// the arena and scratch guards could be dropped without a test noticing).
    #[test]
    fn configurations_beyond_the_arena_or_the_scratch_are_refused() {
        let mut rig = Rig::new(1);
        // An arena big enough for a 2048-bin search (a board with more RAM): the scratch
        // bound must still refuse chirps longer than it.
        rig.arena = vec![0; 140_000];
        let mut host = Host::new();
        let mut m = rig.module(MockLink::default(), &mut host);
        // Twice the budget frame's samples: valid, but its frame sums need twice the arena.
        let mut big = bench_scene::config();
        big.adc_samples = 1024;
        big.chirp_period_s = 120e-6;
        big.validate().unwrap();
        assert!(Edge::new(&big).unwrap().arena_words() > 140_000);
        // One element, one loop, 1040 samples: a small arena, but chirps longer than the
        // scratch (1024 samples).
        let mut long = bench_scene::config();
        long.adc_samples = 1040;
        long.chirps_per_tx = 1;
        long.chirp_period_s = 300e-6;
        long.slope_hz_per_s = 3e12;
        long.tx_positions = Vec::from_slice(&[0]).unwrap();
        long.rx_positions = Vec::from_slice(&[0]).unwrap();
        long.tx_order = Vec::from_slice(&[0]).unwrap();
        long.validate().unwrap();
        let words = Edge::new(&long).unwrap().arena_words();
        assert!(words <= 140_000, "{words}");
        // Every fault reported (one per rate-limit interval).
        m.clock = StepClock::new(2 * REPORT_INTERVAL_US);
        for config in [big, long] {
            send(&mut m, &host.frame(&Downlink::Config(config)));
        }
        send(&mut m, &host.frame(&Downlink::Health));
        let up = host.decode(&m.link.tx);
        assert_eq!(faults(&up), [Fault::Config, Fault::Config], "{up:?}");
        assert_eq!(health(&up).pipeline_errors, 2);
    }

    /// Hints that do not describe the requested frame, and more hints than the module holds,
    /// are each a counted protocol error.
    #[test]
    fn hint_mismatches_are_counted_once_each() {
        let mut rig = Rig::new(1);
        let mut host = Host::new();
        let mut m = rig.module(MockLink::default(), &mut host);
        send(
            &mut m,
            &host.frame(&Downlink::Config(bench_scene::config())),
        );
        m.clock = StepClock::new(2 * REPORT_INTERVAL_US);
        let hint = |frame| bench_scene::hints()[0].to_wire(frame);
        // A hint of frame 5, then one of frame 0 with no Frame for 5 in between: 1 error.
        send(&mut m, &host.frame(&Downlink::Hint(hint(5))));
        send(&mut m, &host.frame(&Downlink::Hint(hint(0))));
        // MAX_OBJECTS + 1 hints of frame 0 (one already sent): 1 error for the one too many.
        for _ in 0..MAX_OBJECTS {
            send(&mut m, &host.frame(&Downlink::Hint(hint(0))));
        }
        // A Frame that announces another number of hints than arrived: 1 error.
        send(
            &mut m,
            &host.frame(&Downlink::Frame {
                frame: 0,
                objects: 3,
                clutter: Vec::new(),
            }),
        );
        send(&mut m, &host.frame(&Downlink::Health));
        let h = health(&host.decode(&m.link.tx));
        assert_eq!((h.protocol_errors, h.frames), (3, 1), "{h:?}");
    }

    /// The skip bound's edge on a light radar with distinct frames: exactly `MAX_SKIP` ahead is
    /// read (and the next frame is the one after it), one more is a Sequence fault.
    #[test]
    fn the_skip_bound_is_exact() {
        use crate::workload::{
            TWO_REFLECTOR_N, noise_q15, two_reflector_config, two_reflector_row,
        };
        let config = two_reflector_config();
        let frames = MAX_SKIP as usize + 2;
        let mut bytes = StdVec::new();
        for f in 0..frames {
            for row in 0..16 {
                let mut noise = [CQ15::default(); TWO_REFLECTOR_N];
                noise_q15(
                    (f * 16 + row) as u32,
                    metamoran_dsp::fixed::Q15(300),
                    &mut noise,
                );
                let mut chirp = [CQ15::default(); TWO_REFLECTOR_N];
                two_reflector_row(row / 4, row % 4, &noise, &mut chirp);
                for pair in chirp.chunks_exact(2) {
                    for v in [pair[0].re.0, pair[1].re.0, pair[0].im.0, pair[1].im.0] {
                        bytes.extend_from_slice(&v.to_le_bytes());
                    }
                }
            }
        }
        let mut rig = Rig::new(0);
        rig.bytes = bytes;
        let mut host = Host::new();
        let mut m = rig.module(MockLink::default(), &mut host);
        send(&mut m, &host.frame(&Downlink::Config(config)));
        send(&mut m, &host.frame(&go(MAX_SKIP as u32))); // skips frames 0..MAX_SKIP
        send(&mut m, &host.frame(&go(MAX_SKIP as u32 + 1))); // the last frame, no skip
        m.clock = StepClock::new(2 * REPORT_INTERVAL_US);
        send(&mut m, &host.frame(&go(2 * MAX_SKIP as u32 + 3))); // MAX_SKIP + 1 ahead
        send(&mut m, &host.frame(&Downlink::Health));
        let up = host.decode(&m.link.tx);
        assert_eq!(faults(&up), [Fault::Sequence], "{up:?}");
        let h = health(&up);
        assert_eq!((h.frames, h.capture_errors), (2, 0), "{h:?}");
    }

    /// Health carries the stack gauge's reading.
    #[test]
    fn health_reports_the_stack_gauge() {
        let mut rig = Rig::new(1);
        let mut host = Host::new();
        let m = rig.module(MockLink::default(), &mut host);
        let m = m.with_stack_gauge(|| 4242);
        assert_eq!(m.health().stack_bytes, 4242);
    }
}
