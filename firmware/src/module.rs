//! The module's loop: take configuration and hints from the link, frames from the capture
//! source, run the pipeline per object and send the results back.
//!
//! ```text
//! link ─▶ Deframer ─▶ Receiver ─▶ Downlink::Config ─▶ Edge::new
//!                                 Downlink::Hint   ─▶ hints of frame F
//!                                 Downlink::Frame  ─▶ capture ─▶ pipeline ─▶ Uplink queue ─▶ link
//! ```
//!
//! Everything here is generic over the hardware (capture source, `embedded-io` link, clock), so
//! the same state machine runs on the module, under QEMU and in host tests with mocks. Nothing
//! in it panics: every failure becomes a counted [`Health`] entry and an [`Uplink::Fault`].

use crate::capture::CaptureSource;
use crate::clock::Monotonic;
use embedded_io::{Read, ReadReady, Write};
use heapless::Vec;
use metamoran_dsp::capture::{IqOrder, deinterleave_bytes};
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::pipeline::{Edge, ObjectHint};
use metamoran_dsp::wire::message::MAX_OBJECTS;
use metamoran_dsp::wire::{
    Deframer, Downlink, DropOldest, Fault, FrameSummary, Health, Hint, Key, MAX_WIRE, ObjectResult,
    Receiver, Sender, Stream, Uplink,
};

/// Longest chirp the module takes (samples).
pub const MAX_SAMPLES: usize = 1024;
/// Uplink messages waiting for the link at most; beyond, the oldest is dropped.
pub const QUEUE: usize = 40;
/// Firmware version in the `Hello` message (major · 10000 + minor · 100 + patch).
pub const FIRMWARE_VERSION: u32 = 100;

/// A frame's summary (without its time), its results, and how many objects failed.
type FrameResults = (FrameSummary, Vec<ObjectResult, MAX_OBJECTS>, u32);

/// The module's working memory besides the frame arena (about 36 KiB); put it in a static.
pub struct Scratch {
    bytes: [u8; 4 * MAX_SAMPLES],
    chirp: [CQ15; MAX_SAMPLES],
    row: [CQ15; MAX_SAMPLES],
    azimuth: [CQ15; 256],
    powers: [u64; 768],
    scores: [f32; MAX_SAMPLES],
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
        }
    }
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
pub struct Module<'m, C, L, K> {
    capture: C,
    link: L,
    clock: K,
    arena: &'m mut [u32],
    scratch: &'m mut Scratch,
    edge: Option<Edge>,
    hints: Vec<ObjectHint, MAX_OBJECTS>,
    hints_frame: u32,
    /// Next frame the capture source will deliver.
    next_frame: u32,
    deframer: Deframer,
    receiver: Receiver,
    sender: Sender,
    queue: DropOldest<Uplink, QUEUE>,
    health: Health,
    stack_gauge: Option<fn() -> u32>,
}

impl<'m, C: CaptureSource, L: Read + ReadReady + Write, K: Monotonic> Module<'m, C, L, K> {
    /// A module on this hardware with frame arena `arena`, under link key `key`. Queues the
    /// `Hello` message.
    pub fn new(
        capture: C,
        link: L,
        clock: K,
        arena: &'m mut [u32],
        scratch: &'m mut Scratch,
        key: Key,
    ) -> Self {
        let arena_words = arena.len().min(u32::MAX as usize) as u32;
        let mut m = Self {
            capture,
            link,
            clock,
            arena,
            scratch,
            edge: None,
            hints: Vec::new(),
            hints_frame: 0,
            next_frame: 0,
            deframer: Deframer::new(),
            receiver: Receiver::new(key.clone(), Stream::Downlink),
            sender: Sender::new(key, Stream::Uplink),
            queue: DropOldest::new(),
            health: Health::default(),
            stack_gauge: None,
        };
        m.queue.push(Uplink::Hello {
            firmware: FIRMWARE_VERSION,
            arena_words,
        });
        m
    }

    /// Reports `gauge()` (deepest stack use, bytes) in every [`Health`].
    pub fn with_stack_gauge(mut self, gauge: fn() -> u32) -> Self {
        self.stack_gauge = Some(gauge);
        self
    }

    /// The counters.
    pub fn health(&self) -> Health {
        Health {
            queue_dropped: self.queue.dropped(),
            link: self.receiver.stats(),
            stack_bytes: self.stack_gauge.map_or(0, |g| g()),
            ..self.health
        }
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
                Some(Ok(frame)) => self.receiver.open::<Downlink>(frame),
                Some(Err(e)) => {
                    self.receiver.count(e);
                    Err(e)
                }
            };
            match message {
                Ok(m) => {
                    if self.handle(m) {
                        self.flush();
                        return Poll::Stopped;
                    }
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
            }
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
        if frame < self.next_frame {
            // The capture source only goes forward.
            return Err(Fault::Capture);
        }
        let s = &mut *self.scratch;
        let n = usize::from(edge.samples());
        let rows = edge.rows_per_frame();
        let bytes = s.bytes.get_mut(..4 * n).ok_or(Fault::Config)?;
        let chirp = s.chirp.get_mut(..n).ok_or(Fault::Config)?;
        // Skip frames the host did not ask for.
        while self.next_frame < frame {
            for _ in 0..rows {
                self.capture.read_exact(bytes).map_err(|_| Fault::Capture)?;
            }
            self.next_frame += 1;
        }
        self.next_frame = frame + 1;
        let mut sum = edge.start(self.arena).map_err(|_| Fault::Config)?;
        let rx = edge.rx_count();
        for row in 0..rows {
            let ok = self.capture.read_exact(bytes).is_ok()
                && deinterleave_bytes(bytes, IqOrder::Iiqq, chirp).is_ok();
            if !ok {
                return Err(Fault::Capture);
            }
            let (chirp_index, rx_index) = (row.checked_div(rx), row.checked_rem(rx));
            let pushed = match (chirp_index, rx_index) {
                (Some(c), Some(r)) => edge.push(&mut sum, c, r, chirp).is_ok(),
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
                    let r = report.to_wire(hint);
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
        match fault {
            Fault::NoConfig | Fault::Hints | Fault::Link => h.protocol_errors += 1,
            Fault::Capture => h.capture_errors += 1,
            Fault::Config | Fault::Pipeline => h.pipeline_errors += 1,
        }
        self.fault(frame, fault);
    }

    /// Reports a (counted) error: logged now, sent to the host as a `Fault`.
    fn fault(&mut self, frame: u32, fault: Fault) {
        crate::warn!("fault at frame {=u32}: {=str}", frame, fault_name(fault));
        self.queue.push(Uplink::Fault { frame, fault });
    }

    /// Sends every queued message; a link that refuses bytes leaves the rest queued.
    fn flush(&mut self) {
        let mut out = [0u8; MAX_WIRE];
        while let Some(msg) = self.queue.front() {
            let encoded = self.sender.encode(msg, &mut out);
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
    }
}

/// Whether `config` fits the module's scratch.
fn fits(config: &metamoran_dsp::config::RadarConfig) -> bool {
    (config.adc_samples as usize) <= MAX_SAMPLES && config.range_fft_len() <= MAX_SAMPLES
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::bench_scene;
    use crate::capture::SliceCapture;
    use crate::clock::StepClock;
    use metamoran_dsp::wire::{DEV_KEY, Fault, Health, LinkError};
    use std::collections::VecDeque;
    use std::vec;
    use std::vec::Vec as StdVec;

    /// A link whose receive side the test fills and whose send side it reads.
    #[derive(Default)]
    struct MockLink {
        rx: VecDeque<u8>,
        tx: StdVec<u8>,
        refuse: bool,
    }

    impl embedded_io::ErrorType for MockLink {
        type Error = embedded_io::ErrorKind;
    }
    impl ReadReady for MockLink {
        fn read_ready(&mut self) -> Result<bool, Self::Error> {
            Ok(!self.rx.is_empty())
        }
    }
    impl Read for MockLink {
        fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
            match (self.rx.pop_front(), buf.first_mut()) {
                (Some(b), Some(out)) => {
                    *out = b;
                    Ok(1)
                }
                _ => Ok(0),
            }
        }
    }
    impl Write for MockLink {
        fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
            if self.refuse {
                return Err(embedded_io::ErrorKind::Other);
            }
            self.tx.extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> Result<(), Self::Error> {
            Ok(())
        }
    }

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

    struct Host {
        tx: Sender,
        rx: Receiver,
    }

    impl Host {
        fn new() -> Self {
            Self {
                tx: Sender::new(Key::new(&DEV_KEY), Stream::Downlink),
                rx: Receiver::new(Key::new(&DEV_KEY), Stream::Uplink),
            }
        }
        fn frame(&mut self, msg: &Downlink) -> StdVec<u8> {
            let mut out = [0u8; MAX_WIRE];
            let n = self.tx.encode(msg, &mut out).unwrap();
            out[..n].to_vec()
        }
        fn decode(&mut self, bytes: &[u8]) -> StdVec<Result<Uplink, LinkError>> {
            let mut d: Deframer = Deframer::new();
            let mut out = StdVec::new();
            for &b in bytes {
                if let Some(Ok(f)) = d.push(b) {
                    out.push(self.rx.open::<Uplink>(f));
                }
            }
            out
        }
    }

    fn run<C: CaptureSource>(module: &mut Module<'_, C, MockLink, StepClock>) {
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
        fn module(&mut self, link: MockLink) -> Module<'_, SliceCapture<'_>, MockLink, StepClock> {
            Module::new(
                SliceCapture::new(&self.bytes),
                link,
                StepClock::new(10),
                &mut self.arena,
                &mut self.scratch,
                Key::new(&DEV_KEY),
            )
        }
    }

    fn send(m: &mut Module<'_, SliceCapture<'_>, MockLink, StepClock>, bytes: &[u8]) {
        m.link.rx.extend(bytes.iter().copied());
        run(m);
    }

    #[test]
    fn a_frame_gives_the_pipelines_results() {
        let mut host = Host::new();
        let mut rig = Rig::new(1);
        let mut m = rig.module(MockLink::default());
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
        assert!(matches!(up[0], Uplink::Hello { .. }));
        // The same frame through the pipeline directly.
        let config = bench_scene::config();
        let edge = Edge::new(&config).unwrap();
        let mut arena = vec![0u32; edge.arena_words()];
        let mut sum = edge.start(&mut arena).unwrap();
        let mut chirp = vec![CQ15::from_raw(0, 0); bench_scene::N];
        for c in 0..config.chirps_per_frame() {
            for rx in 0..config.rx_count() {
                bench_scene::chirp(&config, c, rx, &mut chirp);
                edge.push(&mut sum, c, rx, &chirp).unwrap();
            }
        }
        let (mut row, mut az, mut pw) = (
            vec![CQ15::from_raw(0, 0); 512],
            [CQ15::from_raw(0, 0); 256],
            [0u64; 768],
        );
        let mut scene = edge.finish(sum, &mut row, &mut az, &mut pw).unwrap();
        let mut scores = vec![0.0f32; 512];
        let expected: StdVec<ObjectResult> = hints
            .iter()
            .map(|h| {
                let h = ObjectHint::from_wire(&h.to_wire(0));
                let r = edge.object(&mut scene, &h, &mut scores).unwrap();
                r.to_wire(&h)
            })
            .collect();
        let Uplink::Results { summary, objects } = &up[1] else {
            panic!("expected results, got {:?}", up[1]);
        };
        assert_eq!(&objects[..], &expected[..]);
        for (i, r) in objects.iter().enumerate() {
            assert!(r.confidence_db() > 7.5, "object {i}: {r:?}");
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
        let mut m = rig.module(MockLink::default());
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
        let mut m = rig.module(MockLink::default());
        send(
            &mut m,
            &host.frame(&Downlink::Config(bench_scene::config())),
        );
        let go = |frame| Downlink::Frame {
            frame,
            objects: 0,
            clutter: Vec::new(),
        };
        send(&mut m, &host.frame(&go(1))); // skips frame 0
        send(&mut m, &host.frame(&go(0))); // cannot go back
        send(&mut m, &host.frame(&go(2))); // beyond the capture
        send(&mut m, &host.frame(&Downlink::Health));
        let up = host.decode(&m.link.tx);
        assert_eq!(faults(&up), [Fault::Capture, Fault::Capture]);
        let h = health(&up);
        assert_eq!((h.frames, h.capture_errors), (1, 2));
    }

    #[test]
    fn garbage_forgeries_and_replays_are_counted_and_the_loop_goes_on() {
        let mut host = Host::new();
        let mut rig = Rig::new(1);
        let mut m = rig.module(MockLink::default());
        let cfg = host.frame(&Downlink::Config(bench_scene::config()));
        send(&mut m, &[0x13, 0x37, 0x00, 0x00]); // garbage frame
        send(&mut m, &vec![0x5A; 2 * MAX_WIRE]); // overlong
        send(&mut m, &[0]);
        let mut forged = cfg.clone();
        forged[3] ^= 0x40;
        send(&mut m, &forged);
        send(&mut m, &cfg);
        send(&mut m, &cfg); // replay
        let mut other = Sender::new(Key::new(&[9; 32]), Stream::Downlink);
        let mut wrong = [0u8; MAX_WIRE];
        let n = other.encode(&Downlink::Stop, &mut wrong).unwrap();
        send(&mut m, &wrong[..n]); // wrong key: must not stop the module
        send(&mut m, &host.frame(&Downlink::Health));
        let up = host.decode(&m.link.tx);
        let h = health(&up);
        assert_eq!(h.link.accepted, 2, "{h:?}");
        assert_eq!(h.link.replayed, 1);
        assert_eq!(h.link.overflow, 1);
        assert!(h.link.bad_tag >= 2 && h.link.malformed >= 1, "{h:?}");
        assert!(faults(&up).iter().all(|f| *f == Fault::Link));
    }

    #[test]
    fn a_refusing_link_drops_the_oldest_uplink_messages_and_counts_them() {
        let mut host = Host::new();
        let mut rig = Rig::new(1);
        let mut m = rig.module(MockLink {
            refuse: true,
            ..Default::default()
        });
        for _ in 0..QUEUE + 10 {
            send(&mut m, &host.frame(&Downlink::Health));
        }
        m.link.refuse = false;
        send(&mut m, &host.frame(&Downlink::Stop));
        let up = host.decode(&m.link.tx);
        // Hello and the first Health answers were dropped; the newest survive, in order.
        assert!(!up.iter().any(|u| matches!(u, Ok(Uplink::Hello { .. }))));
        let h = health(&up);
        assert_eq!(h.queue_dropped, 11, "{h:?}");
        assert_eq!(up.len(), QUEUE + 1);
    }
}
