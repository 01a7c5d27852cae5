//! The telemetry link: round trips, authentication, replay window, loss and reordering
//! accounting, message sizes, and a fuzz run of both decoders on ≥ 1 M random and mutated frames.

use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::pipeline::ObjectHint;
use metamoran_dsp::search::Contour;
use metamoran_dsp::wire::frame::MAX_PAYLOAD;
use metamoran_dsp::wire::message::{Alternative, Clutter, MAX_CLUTTER, MAX_OBJECTS, Score};
use metamoran_dsp::wire::{
    Deframer, Downlink, FrameSummary, Health, Hint, Key, LinkError, LinkStats, MAX_WIRE,
    ObjectResult, Receiver, Sender, Stream, Uplink,
};

const KEY: [u8; 32] = [7; 32];

fn link(stream: Stream) -> (Sender, Receiver) {
    (
        Sender::new(Key::new(&KEY), stream),
        Receiver::new(Key::new(&KEY), stream),
    )
}

fn encode<M: serde::Serialize>(tx: &mut Sender, msg: &M) -> Vec<u8> {
    let mut out = [0u8; MAX_WIRE];
    let n = tx.encode(msg, &mut out).unwrap();
    out[..n].to_vec()
}

/// Feeds `bytes` through a deframer and receiver; returns what each frame gave.
fn receive<M: for<'b> serde::Deserialize<'b>>(
    rx: &mut Receiver,
    bytes: &[u8],
) -> Vec<Result<M, LinkError>> {
    let mut d: Deframer = Deframer::new();
    let mut got = Vec::new();
    for &b in bytes {
        match d.push(b) {
            Some(Ok(frame)) => got.push(rx.open::<M>(frame)),
            Some(Err(e)) => {
                rx.count(e);
                got.push(Err(e));
            }
            None => {}
        }
    }
    got
}

/// The largest configuration the module takes: the 12 × 16 cascade.
fn cascade() -> RadarConfig {
    use metamoran_dsp::config::boards::{CASCADE_RX, CASCADE_TX};
    RadarConfig {
        start_frequency_hz: 77.0e9,
        slope_hz_per_s: 30.0e12,
        sample_rate_hz: 10.0e6,
        adc_samples: 512,
        chirp_period_s: 59.2e-6,
        chirps_per_tx: 2,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: heapless::Vec::from_slice(&CASCADE_TX).unwrap(),
        rx_positions: heapless::Vec::from_slice(&CASCADE_RX).unwrap(),
        tx_order: (0..CASCADE_TX.len() as u8).collect(),
    }
}

fn result(frame: u32, instance: u16) -> Uplink {
    let r = ObjectResult {
        instance,
        depth_mm: 41_250,
        score: Score(77),
        others: [
            Alternative {
                offset_cm: -1_185,
                score: Score(70),
            },
            Alternative::default(),
        ],
    };
    Uplink::Results {
        summary: FrameSummary {
            frame,
            objects: 1,
            detected: 1,
            ..Default::default()
        },
        objects: heapless::Vec::from_slice(&[r]).unwrap(),
    }
}

fn full_hint() -> Hint {
    let contour = Contour::new((0..64).map(|i| (-0.5 + 0.0125 * i as f32, 40.0 + 0.05 * i as f32)));
    let hint = ObjectHint {
        id: 65_000,
        class: 9,
        span: (-0.5, 0.3),
        prior_m: 1234.5,
        window_m: (0.0, 0.0),
        contour,
    };
    hint.to_wire(u32::MAX)
}

#[test]
fn messages_round_trip_and_frames_have_no_zero_inside() {
    let (mut tx, mut rx) = link(Stream::Uplink);
    let msgs = vec![
        Uplink::Ready,
        result(1, 2),
        Uplink::Fault {
            frame: 3,
            fault: metamoran_dsp::wire::Fault::Capture,
            repeats: 4,
        },
        Uplink::Health(Health {
            frames: 9,
            link: LinkStats {
                lost: 2,
                ..Default::default()
            },
            ..Default::default()
        }),
    ];
    let mut bytes = Vec::new();
    for m in &msgs {
        let f = encode(&mut tx, m);
        assert_eq!(
            f.iter().filter(|&&b| b == 0).count(),
            1,
            "one delimiter per frame"
        );
        assert_eq!(*f.last().unwrap(), 0);
        bytes.extend(f);
    }
    let got: Vec<Uplink> = receive(&mut rx, &bytes)
        .into_iter()
        .map(Result::unwrap)
        .collect();
    assert_eq!(got, msgs);
    assert_eq!(rx.stats().accepted, msgs.len() as u32);
    assert_eq!(rx.stats().lost, 0);
}

#[test]
fn the_largest_downlink_messages_fit_a_frame() {
    let (mut tx, mut rx) = link(Stream::Downlink);
    let hint = Downlink::Hint(full_hint());
    let mut cfg = cascade();
    cfg.frames = u32::MAX;
    let go = Downlink::Frame {
        frame: u32::MAX,
        objects: 255,
        clutter: (0..MAX_CLUTTER)
            .map(|i| Clutter {
                sin_az: -32767 + i as i16,
                class: 255,
            })
            .collect(),
    };
    // A 16-RX calibration row with every varint at its longest.
    let row = Downlink::Calibration(metamoran_dsp::wire::CalibrationRow {
        tx: 255,
        of: 255,
        gains: (0..16).map(|_| (i16::MIN, i16::MIN)).collect(),
        steps: (0..16).map(|_| u32::MAX).collect(),
    });
    for m in [hint, Downlink::Config(cfg), go, row] {
        let f = encode(&mut tx, &m);
        assert!(f.len() <= MAX_WIRE);
        let got: Vec<Downlink> = receive(&mut rx, &f)
            .into_iter()
            .map(Result::unwrap)
            .collect();
        assert_eq!(got, vec![m]);
    }
}

#[test]
fn a_result_takes_at_most_16_bytes_on_the_wire() {
    // Worst case the docs promise: the id at its maximum, depth just below 2 km,
    // both alternatives as far away as an offset goes.
    let far = Alternative {
        offset_cm: i16::MIN,
        score: Score(u8::MAX),
    };
    let r = ObjectResult {
        instance: u16::MAX,
        depth_mm: 2_097_151,
        score: Score(u8::MAX),
        others: [far, far],
    };
    let alone = postcard::to_allocvec(&r).unwrap();
    assert!(alone.len() <= 15, "{} bytes", alone.len());
    // Marginal wire bytes of each object in a frame's results (COBS adds at most one byte
    // per 254).
    let frame_of = |n: usize| {
        let (mut tx, _) = link(Stream::Uplink);
        let msg = Uplink::Results {
            summary: FrameSummary {
                frame: 1 << 20,
                objects: n as u8,
                ..Default::default()
            },
            objects: (0..n).map(|_| r).collect(),
        };
        encode(&mut tx, &msg).len()
    };
    let (empty, full) = (frame_of(0), frame_of(MAX_OBJECTS));
    let per_object = (full - empty) as f64 / MAX_OBJECTS as f64;
    assert!(per_object <= 16.0, "{per_object} bytes per object");
    assert!(full <= MAX_WIRE);
}

#[test]
fn quantized_hints_survive_the_wire_exactly() {
    let h = full_hint();
    let back = ObjectHint::from_wire(&h).to_wire(h.frame);
    assert_eq!(back, h, "quantize(dequantize(x)) must be x");
    assert_eq!(h.contour.len(), 32);
}

#[test]
fn tampered_frames_fail_the_tag_and_count() {
    let (mut tx, mut rx) = link(Stream::Uplink);
    let f = encode(&mut tx, &result(1, 1));
    // Flip each bit of the COBS body in turn (not the delimiter).
    let mut rejected = 0;
    for i in 0..f.len() - 1 {
        for bit in 0..8 {
            let mut g = f.clone();
            g[i] ^= 1 << bit;
            let got = receive::<Uplink>(&mut rx, &g);
            assert!(
                got.iter().all(Result::is_err),
                "byte {i} bit {bit} accepted"
            );
            rejected += got.len();
        }
    }
    let s = rx.stats();
    assert_eq!(s.accepted, 0);
    assert!(rejected > 0);
    assert_eq!(
        s.malformed + s.bad_version + s.bad_tag + s.overflow + s.replayed,
        rejected as u32
    );
    assert!(s.bad_tag > 0);
    // The original still goes through: nothing above moved the replay window.
    assert!(receive::<Uplink>(&mut rx, &f)[0].is_ok());
}

#[test]
fn wrong_key_and_reflected_frames_are_rejected() {
    let mut other = Sender::new(Key::new(&[8; 32]), Stream::Uplink);
    let mut rx = Receiver::new(Key::new(&KEY), Stream::Uplink);
    assert_eq!(
        receive::<Uplink>(&mut rx, &encode(&mut other, &result(1, 1)))[0],
        Err(LinkError::Tag)
    );
    // A downlink frame under the right key replayed towards the host.
    let mut down = Sender::new(Key::new(&KEY), Stream::Downlink);
    assert_eq!(
        receive::<Uplink>(&mut rx, &encode(&mut down, &Downlink::Stop))[0],
        Err(LinkError::Tag)
    );
    assert_eq!(rx.stats().bad_tag, 2);
}

#[test]
fn replays_loss_and_reordering_are_counted() {
    let (mut tx, mut rx) = link(Stream::Uplink);
    let frames: Vec<Vec<u8>> = (1..=100).map(|i| encode(&mut tx, &result(i, 0))).collect();
    // Deliver 1..=10, skip 11 and 12, deliver 13..=20, then 12 late, then 5 again.
    let mut order: Vec<usize> = (0..10).collect();
    order.extend(12..20);
    order.push(11);
    order.push(4);
    let got: Vec<_> = order
        .iter()
        .flat_map(|&i| receive::<Uplink>(&mut rx, &frames[i]))
        .collect();
    assert_eq!(got.last(), Some(&Err(LinkError::Replay(5))));
    let s = rx.stats();
    assert_eq!((s.accepted, s.lost, s.reordered, s.replayed), (19, 1, 1, 1));
    // Jump far ahead: everything older than the window is stale, not accepted.
    assert!(receive::<Uplink>(&mut rx, &frames[99])[0].is_ok());
    assert_eq!(
        receive::<Uplink>(&mut rx, &frames[20])[0],
        Err(LinkError::Stale(21))
    );
    assert_eq!(rx.stats().lost, 1 + 79);
}

/// The window's edges, exactly (issue #18: `behind >= WINDOW` → `behind > WINDOW` and a
/// 16-frame window both survived the tests): a counter 63 behind the highest is still taken
/// once, 64 behind is stale, and a window of 64 remembers each of its 64 counters.
#[test]
fn the_replay_window_is_exactly_64_counters() {
    use metamoran_dsp::wire::receiver::WINDOW;
    assert_eq!(WINDOW, 64);
    let (mut tx, mut rx) = link(Stream::Uplink);
    let frames: Vec<Vec<u8>> = (1..=200).map(|i| encode(&mut tx, &result(i, 0))).collect();
    // Deliver 100 first: everything from 37 (63 behind) up is in the window.
    assert!(receive::<Uplink>(&mut rx, &frames[99])[0].is_ok());
    for counter in (37..100).rev() {
        let got = receive::<Uplink>(&mut rx, &frames[counter as usize - 1]);
        assert!(
            got[0].is_ok(),
            "counter {counter} ({} behind): {got:?}",
            100 - counter
        );
    }
    assert_eq!(
        receive::<Uplink>(&mut rx, &frames[35])[0],
        Err(LinkError::Stale(36)),
        "64 behind is outside the window"
    );
    // Every one of the 64 is now remembered: each replays.
    for counter in 37..=100 {
        assert_eq!(
            receive::<Uplink>(&mut rx, &frames[counter as usize - 1])[0],
            Err(LinkError::Replay(counter))
        );
    }
    // Advancing to 164 puts 100 exactly 64 behind (stale); 163, skipped, is taken late.
    assert!(receive::<Uplink>(&mut rx, &frames[163])[0].is_ok());
    assert_eq!(
        receive::<Uplink>(&mut rx, &frames[99])[0],
        Err(LinkError::Stale(100))
    );
    assert!(
        receive::<Uplink>(&mut rx, &frames[162])[0].is_ok(),
        "163 is 1 behind 164, unseen"
    );
    assert_eq!(rx.stats().lost, 164 - 1 - 64 - 1);
}

#[test]
fn overlong_frames_are_dropped_whole_and_the_stream_recovers() {
    let (mut tx, mut rx) = link(Stream::Uplink);
    let mut bytes = vec![0x11u8; 3 * MAX_WIRE];
    bytes.push(0);
    bytes.extend(encode(&mut tx, &result(1, 1)));
    let got = receive::<Uplink>(&mut rx, &bytes);
    assert_eq!(got.len(), 2);
    assert_eq!(got[0], Err(LinkError::Overflow));
    assert_eq!(got[1], Ok(result(1, 1)));
    assert_eq!(rx.stats().overflow, 1);
}

#[test]
fn oversized_messages_are_refused_by_the_sender() {
    let (mut tx, _) = link(Stream::Uplink);
    #[derive(serde::Serialize)]
    struct Big(#[serde(with = "serde_bytes_like")] Vec<u8>);
    mod serde_bytes_like {
        pub fn serialize<S: serde::Serializer>(v: &[u8], s: S) -> Result<S::Ok, S::Error> {
            s.serialize_bytes(v)
        }
    }
    let mut out = [0u8; MAX_WIRE];
    assert!(tx.encode(&Big(vec![1; MAX_PAYLOAD]), &mut out).is_err());
    assert_eq!(
        tx.counter(),
        0,
        "a refused message must not use up a counter"
    );
    assert!(tx.encode(&Big(vec![1; MAX_PAYLOAD - 3]), &mut out).is_ok());
    assert_eq!(tx.counter(), 1, "the first frame sent carries counter 1");
}

/// The frame size constants are their closed forms (cargo-mutants: `+` → `*` in them
/// survived, since larger buffers pass every round trip).
#[test]
fn frame_sizes_are_their_closed_forms() {
    use metamoran_dsp::wire::TAG_LEN;
    use metamoran_dsp::wire::frame::{HEADER_LEN, MAX_RAW};
    assert_eq!((HEADER_LEN, MAX_PAYLOAD, TAG_LEN), (6, 384, 8));
    assert_eq!(MAX_RAW, 6 + 384 + 8);
    // COBS adds one byte per 254 (rounded up), then the delimiter.
    assert_eq!(MAX_WIRE, MAX_RAW + MAX_RAW.div_ceil(254) + 1);
}

/// A slice longer than any frame is an overflow; one of exactly `MAX_WIRE` bytes (longer than
/// an encoded frame, but not by the length check) is malformed.
#[test]
fn the_receiver_bounds_frame_length_exactly() {
    let (_, mut rx) = link(Stream::Uplink);
    let mut at_limit = vec![1u8; MAX_WIRE];
    assert_eq!(rx.open::<Uplink>(&mut at_limit), Err(LinkError::Malformed));
    let mut over = vec![1u8; MAX_WIRE + 1];
    assert_eq!(rx.open::<Uplink>(&mut over), Err(LinkError::Overflow));
    assert_eq!((rx.stats().malformed, rx.stats().overflow), (1, 1));
}

/// What users read: every error says what happened and what to do, and no key is ever
/// printed by `Debug`.
#[test]
fn errors_say_what_to_do_and_keys_stay_secret() {
    use metamoran_dsp::wire::{DeviceKey, EncodeError, KeyError};
    let texts = [
        (KeyError::Hex.to_string(), "64 hexadecimal digits"),
        (EncodeError::TooLarge.to_string(), "send fewer items"),
        (EncodeError::Buffer.to_string(), "must hold"),
        (EncodeError::CounterExhausted.to_string(), "new session"),
        (EncodeError::NoSession.to_string(), "pair"),
        (LinkError::Malformed.to_string(), "baud rate"),
        (LinkError::Overflow.to_string(), "protocol"),
        (LinkError::Version(9).to_string(), "version 9"),
        (LinkError::Tag.to_string(), "same link key"),
        (LinkError::Replay(7).to_string(), "counter 7"),
        (
            LinkError::Stale(5).to_string(),
            "older than the replay window",
        ),
        (LinkError::Payload.to_string(), "protocol differs"),
    ];
    for (text, needle) in texts {
        assert!(text.contains(needle), "{text:?} lacks {needle:?}");
    }
    assert_eq!(format!("{:?}", Key::new(&KEY)), "Key(..)");
    assert_eq!(format!("{:?}", DeviceKey::new(KEY)), "DeviceKey(..)");
}

/// The host end counts what it rejects, including what the deframer rejected before it.
#[test]
fn the_host_end_counts_rejections() {
    use metamoran_dsp::wire::{DeviceKey, HostLink};
    let mut host = HostLink::new(DeviceKey::new(KEY));
    let mut junk = [0x13u8, 0x37, 0x01];
    assert!(host.open(&mut junk).is_err());
    host.count(LinkError::Overflow);
    let s = host.stats();
    assert_eq!(
        (s.malformed + s.bad_tag, s.overflow, s.accepted),
        (1, 1, 0),
        "{s:?}"
    );
}

/// xorshift64*: a fast deterministic generator for the fuzz run.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Mutates `f` the way a noisy line or an attacker would: bit flips, byte overwrites,
/// truncation, insertion, or a whole random frame.
fn mutate(rng: &mut Rng, f: &mut Vec<u8>) {
    match rng.below(6) {
        0 => {
            let i = rng.below(f.len());
            f[i] ^= 1 << rng.below(8);
        }
        1 => {
            let i = rng.below(f.len());
            f[i] = rng.next() as u8;
        }
        2 => f.truncate(rng.below(f.len() + 1)),
        3 => {
            let i = rng.below(f.len() + 1);
            f.insert(i, rng.next() as u8);
        }
        4 => {
            let n = rng.below(2 * MAX_WIRE);
            *f = (0..n).map(|_| rng.next() as u8).collect();
        }
        _ => {} // unchanged: a replay
    }
}

/// Frames whose tag is valid but whose payload is random: what a buggy peer sends. These reach
/// the postcard decoder, which the tag otherwise shields.
fn signed_garbage(rng: &mut Rng, tx: &mut Sender) -> Vec<u8> {
    // A tuple of bytes serializes without a length prefix: the payload is exactly these bytes.
    let n = rng.below(64);
    let bytes: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
    let mut out = [0u8; MAX_WIRE];
    let len = tx.encode(&RawTuple(&bytes), &mut out).unwrap();
    out[..len].to_vec()
}

struct RawTuple<'a>(&'a [u8]);
impl serde::Serialize for RawTuple<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        let mut t = s.serialize_tuple(self.0.len())?;
        for b in self.0 {
            t.serialize_element(b)?;
        }
        t.end()
    }
}

fn fuzz<M: for<'b> serde::Deserialize<'b> + serde::Serialize>(
    stream: Stream,
    seeds: &[M],
    iterations: usize,
) -> LinkStats {
    let (mut tx, mut rx) = link(stream);
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ stream as u64);
    let mut d: Deframer = Deframer::new();
    let (mut frames, mut bytes_in) = (0usize, 0usize);
    let mut valid = Vec::new();
    while frames < iterations {
        let mut f = match rng.below(8) {
            0 => signed_garbage(&mut rng, &mut tx),
            1 | 2 if !valid.is_empty() => {
                let v: &Vec<u8> = &valid[rng.below(valid.len())];
                v.clone() // replay of an earlier genuine frame
            }
            _ => {
                let f = encode(&mut tx, &seeds[rng.below(seeds.len())]);
                if valid.len() < 256 {
                    valid.push(f.clone());
                }
                f
            }
        };
        if rng.below(4) != 0 {
            mutate(&mut rng, &mut f);
        }
        bytes_in += f.len();
        for b in f {
            match d.push(b) {
                Some(Ok(frame)) => {
                    frames += 1;
                    let _ = rx.open::<M>(frame);
                }
                Some(Err(e)) => {
                    frames += 1;
                    rx.count(e);
                }
                None => {}
            }
        }
    }
    assert!(bytes_in > iterations);
    rx.stats()
}

#[test]
fn fuzz_both_decoders_a_million_frames() {
    let n = 500_000;
    let up = fuzz(
        Stream::Uplink,
        &[
            result(7, 1),
            Uplink::Health(Health::default()),
            Uplink::Ready,
        ],
        n,
    );
    let down = fuzz(
        Stream::Downlink,
        &[
            Downlink::Hint(full_hint()),
            Downlink::Config(cascade()),
            Downlink::Stop,
        ],
        n,
    );
    for s in [up, down] {
        let rejected = s.malformed + s.bad_version + s.bad_tag + s.replayed + s.overflow;
        // Every frame was either accepted or counted as rejected.
        assert!(s.accepted + rejected >= n as u32, "{s:?}");
        assert!(
            s.accepted > 0 && s.bad_tag > 0 && s.replayed > 0 && s.malformed > 0,
            "{s:?}"
        );
    }
}

/// Sessions (issue #18, item 1): a session receiver takes no handshake frames, a handshake
/// receiver no session frames before a session is installed, and installing a new session
/// rejects every frame of the old one while its counters start over at 1.
#[test]
fn sessions_separate_keys_streams_and_counters() {
    use metamoran_dsp::wire::{DeviceKey, HandshakeDown, HostLink, Opened};
    let device = DeviceKey::new([3; 32]);
    let mut host = HostLink::new(device.clone());
    let mut module = Receiver::with_handshake(device.handshake(), Stream::Downlink);
    let mut buf = [0u8; MAX_WIRE];
    let deliver = |rx: &mut Receiver, bytes: &[u8]| {
        let mut d: Deframer = Deframer::new();
        let mut frame = None;
        for &b in bytes {
            if let Some(Ok(f)) = d.push(b) {
                frame = Some(rx.open_any::<HandshakeDown, Downlink>(f));
            }
        }
        frame.expect("one frame")
    };
    // Before pairing the host cannot frame a session message.
    assert!(host.encode(&Downlink::Health, &mut buf).is_err());
    let n = host.sync(&mut buf).unwrap();
    assert_eq!(
        deliver(&mut module, &buf[..n]),
        Ok(Opened::Handshake(HandshakeDown::Sync))
    );
    // Session 1.
    let (m1, h1) = ([1; 16], [2; 16]);
    let n = host.pair(m1, h1, &mut buf).unwrap();
    assert!(matches!(
        deliver(&mut module, &buf[..n]),
        Ok(Opened::Handshake(HandshakeDown::Session { .. }))
    ));
    let n = host.encode(&Downlink::Health, &mut buf).unwrap();
    let old = buf[..n].to_vec();
    assert_eq!(
        deliver(&mut module, &old),
        Err(LinkError::Tag),
        "no session yet"
    );
    module.install(device.session(&m1, &h1).downlink);
    assert_eq!(
        deliver(&mut module, &old),
        Ok(Opened::Session(Downlink::Health))
    );
    assert_eq!(deliver(&mut module, &old), Err(LinkError::Replay(1)));
    // Session 2: the old frame fails the tag; the new one's counter 1 is fresh.
    let (m2, h2) = ([4; 16], [5; 16]);
    let _ = host.pair(m2, h2, &mut buf).unwrap();
    module.install(device.session(&m2, &h2).downlink);
    assert_eq!(deliver(&mut module, &old), Err(LinkError::Tag));
    let n = host.encode(&Downlink::Stop, &mut buf).unwrap();
    assert_eq!(
        deliver(&mut module, &buf[..n]),
        Ok(Opened::Session(Downlink::Stop))
    );
    // A plain session receiver rejects handshake frames.
    let (_, mut plain) = link(Stream::Downlink);
    let n = host.sync(&mut buf).unwrap();
    assert_eq!(
        receive::<Downlink>(&mut plain, &buf[..n]),
        [Err(LinkError::Tag)]
    );
}

#[test]
fn a_score_holds_half_decibels_and_the_survival_bit() {
    let s = Score::new(20.3, true);
    assert_eq!((s.over_floor_db(), s.survives()), (20.5, true));
    assert_eq!(Score::new(20.2, false).over_floor_db(), 20.0);
    assert!(!Score::new(20.2, false).survives());
    // Clamped to 0 … 63.5 dB; NaN and negative heights are 0.
    assert_eq!(Score::new(100.0, true).over_floor_db(), 63.5);
    assert_eq!(Score::new(-3.0, false), Score(0));
    assert_eq!(Score::new(f32::NAN, true), Score(1));
    // One byte on the wire.
    assert_eq!(
        postcard::to_allocvec(&Score::new(63.5, true)).unwrap(),
        [255]
    );
}

#[test]
fn alternatives_need_a_reported_depth_and_lie_in_front() {
    let alt = |offset_cm: i16| Alternative {
        offset_cm,
        score: Score::new(20.0, true),
    };
    let mut r = ObjectResult {
        instance: 3,
        depth_mm: 40_000,
        score: Score::new(30.0, true),
        others: [alt(-1_250), alt(-4_500)],
    };
    // 40 m − 12.5 m; 40 m − 45 m would be behind the radar and is not an alternative.
    let depths: Vec<f64> = r.alternatives().map(|(d, _)| d).collect();
    assert_eq!(depths, [27.5]);
    // A best candidate behind 0 m is clamped to 0 mm: the offsets lost their reference.
    r.depth_mm = 0;
    assert_eq!(r.alternatives().count(), 0);
}
