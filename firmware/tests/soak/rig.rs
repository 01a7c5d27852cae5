//! The soak rig (issue #18, "Load"), shared by `tests/soak.rs` and `benches/soak.rs`: the module's loop on the host at full rate, paired with a
//! host over a link that loses, reorders and corrupts frames both ways, against the same run on
//! a clean link.
//!
//! Each frame the host sends one `Hint` and a `Frame`; the module reads the frame's rows from a
//! synthetic capture (a reflector at range bin 20.3 plus noise that changes every frame), runs
//! the pipeline and answers with `Results`. Every frame must be accounted for: processed (its
//! results arrived), or lost with a cause the rig can name (a damaged downlink message, a
//! damaged uplink frame, or a fault the module reported); and every frame whose messages
//! arrived intact must give exactly the clean run's results.

use firmware::capture::{CaptureSource, SourceError};
use firmware::clock::StepClock;
use firmware::host_mock::{Line, SeededNonces};
use firmware::module::{Module, Poll, Scratch};
use firmware::workload::{TWO_REFLECTOR_N, noise_q15, two_reflector_config, two_reflector_row};
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::fixed::{CQ15, Q15};
use metamoran_dsp::pipeline::ObjectHint;
use metamoran_dsp::search::Contour;
use metamoran_dsp::wire::{
    DEV_KEY, Deframer, DeviceKey, Downlink, Fault, HandshakeUp, Health, HostLink, LinkStats,
    MAX_WIRE, ObjectResult, Opened, Uplink,
};
use std::collections::{BTreeMap, BTreeSet};

/// Samples per chirp of the rig's radar.
const N: usize = TWO_REFLECTOR_N;

/// The rig's radar: 2 TX × 4 RX, 64 samples, 2 loops (16 rows of 256 bytes per frame).
pub fn config() -> RadarConfig {
    RadarConfig {
        frames: 0,
        ..two_reflector_config()
    }
}

/// Rows of one frame.
const ROWS: u64 = 16;

/// An endless capture of the two-reflector frame with noise that changes every frame: row r of
/// the stream belongs to frame r / 16, and its samples depend only on (frame, row), so a frame
/// reads the same whatever was skipped before it.
struct Synthetic {
    row: u64,
}

impl CaptureSource for Synthetic {
    fn read_exact(&mut self, buf: &mut [u8]) -> Result<(), SourceError> {
        let (frame, row) = (self.row / ROWS, self.row % ROWS);
        self.row += 1;
        let mut noise = [CQ15::default(); N];
        noise_q15((frame * 131 + row) as u32, Q15(300), &mut noise);
        let mut chirp = [CQ15::default(); N];
        two_reflector_row(row as usize / 4, row as usize % 4, &noise, &mut chirp);
        // DCA1000 order: I[2k], I[2k+1], Q[2k], Q[2k+1].
        let mut out = buf.chunks_exact_mut(2);
        for pair in chirp.chunks_exact(2) {
            for v in [pair[0].re.0, pair[1].re.0, pair[0].im.0, pair[1].im.0] {
                let Some(o) = out.next() else {
                    return Err(SourceError::Ended);
                };
                o.copy_from_slice(&v.to_le_bytes());
            }
        }
        Ok(())
    }
}

/// How the line misbehaves: each frame (message) is lost, corrupted (one byte flipped) or
/// swapped with the next one with these probabilities, independently both ways.
#[derive(Clone, Copy, Debug)]
pub struct Faults {
    /// Probability a frame is dropped.
    pub loss: f64,
    /// Probability a frame is swapped with the one after it.
    pub reorder: f64,
    /// Probability one byte of a frame is changed.
    pub corrupt: f64,
}

impl Faults {
    /// A clean line.
    pub const NONE: Self = Self {
        loss: 0.0,
        reorder: 0.0,
        corrupt: 0.0,
    };
}

/// Splits `bytes` into whole wire frames (each with its delimiter).
fn split_frames(bytes: &[u8]) -> Vec<Vec<u8>> {
    bytes
        .split_inclusive(|&b| b == 0)
        .map(<[u8]>::to_vec)
        .collect()
}

/// A small PCG for the fault draws.
struct Draw(u64);
impl Draw {
    fn unit(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Damages `frames` per `faults`; returns the bytes to deliver and whether each frame (by
/// index) arrived unchanged and in place.
fn damage(frames: Vec<Vec<u8>>, faults: Faults, draw: &mut Draw) -> (Vec<u8>, Vec<bool>) {
    let mut intact = vec![true; frames.len()];
    let mut order: Vec<usize> = (0..frames.len()).collect();
    let mut i = 0;
    while i + 1 < order.len() {
        if draw.unit() < faults.reorder {
            order.swap(i, i + 1);
            intact[order[i]] = false;
            intact[order[i + 1]] = false;
            i += 2;
        } else {
            i += 1;
        }
    }
    let mut out = Vec::new();
    for k in order {
        let mut f = frames[k].clone();
        if draw.unit() < faults.loss {
            intact[k] = false;
            continue;
        }
        if draw.unit() < faults.corrupt && f.len() > 1 {
            let at = (draw.unit() * (f.len() - 1) as f64) as usize;
            f[at] ^= 0x5A;
            intact[k] = false;
        }
        out.extend(f);
    }
    (out, intact)
}

/// What a soak run did.
#[derive(Clone, Debug, Default)]
pub struct SoakReport {
    /// Frames the host asked for.
    pub frames: u32,
    /// Frames whose results arrived.
    pub processed: u32,
    /// Of those, frames whose messages all arrived intact both ways.
    pub intact: u32,
    /// Frames lost for a damaged downlink message (hint or frame request).
    pub lost_downlink: u32,
    /// Frames lost for a damaged uplink results frame.
    pub lost_uplink: u32,
    /// Frames with results that differ from the clean run (each with a damaged hint).
    pub differ: u32,
    /// Frames lost without a cause the rig can name (must be 0).
    pub unexplained: u32,
    /// Processed frames whose messages were intact but whose results differ (must be 0).
    pub wrong: u32,
    /// The results of every processed frame, by frame.
    pub results: BTreeMap<u32, Vec<ObjectResult>>,
    /// The host's receive counters.
    pub host_link: LinkStats,
    /// The module's counters at the end.
    pub module: Health,
    /// Faults the module reported, by kind, with their repeats.
    pub faults: BTreeMap<String, u32>,
}

/// Runs `frames` frames over a line with `faults` (seeded by `seed`), comparing with `clean`
/// (the results of a clean run, if given). `progress` is called every 1,000 frames.
pub fn run(
    frames: u32,
    faults: Faults,
    seed: u64,
    clean: Option<&BTreeMap<u32, Vec<ObjectResult>>>,
    mut progress: impl FnMut(u32),
) -> SoakReport {
    let mut arena = vec![0u32; 16 * 1024];
    let mut scratch = Box::new(Scratch::new());
    let mut m = Module::new(
        Synthetic { row: 0 },
        Line::default(),
        StepClock::new(1_000),
        SeededNonces(seed),
        &mut arena,
        &mut scratch,
        DeviceKey::new(DEV_KEY),
    );
    let mut host = HostLink::new(DeviceKey::new(DEV_KEY));
    let mut deframer: Deframer = Deframer::new();
    let mut draw = Draw(seed);
    let mut buf = [0u8; MAX_WIRE];
    let mut report = SoakReport {
        frames,
        ..SoakReport::default()
    };
    let poll = |m: &mut Module<'_, Synthetic, Line, StepClock, SeededNonces>| {
        while m.poll() == Poll::Busy {}
    };
    // Pair and configure over a clean line (the rig soaks the frames, not the setup).
    poll(&mut m);
    let hello = std::mem::take(&mut m.link_mut().tx);
    let nonce = hello
        .iter()
        .find_map(|&b| match deframer.push(b) {
            Some(Ok(f)) => match host.open(f) {
                Ok(Opened::Handshake(HandshakeUp::Hello { nonce, .. })) => Some(nonce),
                _ => None,
            },
            _ => None,
        })
        .expect("Hello");
    let n = host.pair(nonce, [7; 16], &mut buf).unwrap();
    m.link_mut().rx.extend(&buf[..n]);
    let n = host.encode(&Downlink::Config(config()), &mut buf).unwrap();
    m.link_mut().rx.extend(&buf[..n]);
    poll(&mut m);
    m.link_mut().tx.clear();
    let hint = ObjectHint {
        id: 1,
        class: 1,
        span: (-0.04, 0.04),
        prior_m: 0.0,
        window_m: (0.0, 0.0),
        contour: Contour::new((0..4).map(|i| (-0.03 + 0.02 * i as f32, 5.0 + 0.05 * i as f32))),
    };
    let mut down_damaged = BTreeSet::new();
    let mut faulted = BTreeSet::new();
    let mut up_damaged = 0u32;
    for f in 0..frames {
        // Downlink: this frame's hint and request, through the line.
        let mut msgs = Vec::new();
        for msg in [
            Downlink::Hint(hint.to_wire(f)),
            Downlink::Frame {
                frame: f,
                objects: 1,
                clutter: heapless::Vec::new(),
            },
        ] {
            let n = host.encode(&msg, &mut buf).unwrap();
            msgs.push(buf[..n].to_vec());
        }
        let (bytes, intact) = damage(msgs, faults, &mut draw);
        if intact.iter().any(|&ok| !ok) {
            down_damaged.insert(f);
        }
        m.link_mut().rx.extend(bytes);
        poll(&mut m);
        // Uplink: whatever the module sent, through the line.
        let sent = std::mem::take(&mut m.link_mut().tx);
        let (bytes, intact) = damage(split_frames(&sent), faults, &mut draw);
        up_damaged += intact.iter().filter(|&&ok| !ok).count() as u32;
        for b in bytes {
            match deframer.push(b) {
                Some(Ok(frame)) => match host.open(frame) {
                    Ok(Opened::Session(Uplink::Results { summary, objects })) => {
                        report.results.insert(summary.frame, objects.to_vec());
                    }
                    Ok(Opened::Session(Uplink::Fault {
                        frame,
                        fault,
                        repeats,
                    })) => {
                        faulted.insert(frame);
                        *report.faults.entry(format!("{fault:?}")).or_default() += 1 + repeats;
                        let _: Fault = fault;
                    }
                    _ => {}
                },
                Some(Err(e)) => host.count(e),
                None => {}
            }
        }
        if (f + 1) % 1000 == 0 {
            progress(f + 1);
        }
    }
    // Account for every frame.
    for f in 0..frames {
        match report.results.get(&f) {
            Some(got) => {
                report.processed += 1;
                let same = clean.is_none_or(|c| c.get(&f) == Some(got));
                if !down_damaged.contains(&f) {
                    report.intact += 1;
                    if !same {
                        report.wrong += 1;
                    }
                } else if !same {
                    report.differ += 1;
                }
            }
            None if down_damaged.contains(&f) || faulted.contains(&f) => report.lost_downlink += 1,
            None => report.lost_uplink += 1,
        }
    }
    // Frames lost on the uplink cannot exceed the uplink frames damaged.
    report.unexplained = report.lost_uplink.saturating_sub(up_damaged);
    report.host_link = host.stats();
    report.module = m.health();
    report
}

/// A `/proc/self/status` figure in KiB (`VmHWM`: peak resident set; `VmRSS`: now).
pub fn status_kib(key: &str) -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with(key))
                .and_then(|l| l.split_whitespace().nth(1)?.parse().ok())
        })
        .unwrap_or(0)
}
