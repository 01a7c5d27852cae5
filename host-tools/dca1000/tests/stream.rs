//! The receiver against the emulator on loopback, and a real DCA1000 session (issue #19).

use metamoran_dca1000::command::{Command, Reply};
use metamoran_dca1000::emulate::{Impairments, schedule, send, spawn};
use metamoran_dca1000::packet::{DATA_PORT, DEFAULT_PAYLOAD};
use metamoran_dca1000::{Frame, Receiver, pcap};
use std::net::{SocketAddr, UdpSocket};
use std::path::PathBuf;
use std::time::Duration;

const FRAME: usize = 32_768;
/// Where the emulated board sends from.
const LOCAL: &str = "127.0.0.1:0";
/// One packet every 20 µs.
const PACE: Option<Duration> = Some(Duration::from_micros(20));

/// Ten frames of distinct bytes.
fn stream() -> Vec<u8> {
    (0..10 * FRAME).map(|i| (i * 31 + i / 977) as u8).collect()
}

/// Sends `stream` with `imp` to a fresh receiver and returns every frame and its counters.
fn through_loopback(
    stream: &[u8],
    imp: Impairments,
) -> (
    Vec<Frame>,
    metamoran_dca1000::Counters,
    metamoran_dca1000::emulate::Sent,
) {
    let mut rx = Receiver::bind(
        "127.0.0.1:0".parse().unwrap(),
        FRAME,
        Some([127, 0, 0, 1].into()),
    )
    .unwrap();
    let to = rx.local_addr().unwrap();
    // ~580 Mbit/s: below the DCA1000's practical rate, so the kernel keeps every datagram.
    let sender = spawn(
        LOCAL.parse().unwrap(),
        to,
        stream.to_vec(),
        DEFAULT_PAYLOAD,
        imp,
        PACE,
    );
    let mut frames = Vec::new();
    while let Some(f) = rx
        .next_frame(Duration::from_secs(5), Duration::from_millis(300))
        .unwrap()
    {
        frames.push(f);
    }
    (frames, rx.counters(), sender.join().unwrap().unwrap())
}

#[test]
fn a_clean_stream_arrives_bit_identical() {
    let s = stream();
    let (frames, c, sent) = through_loopback(&s, Impairments::default());
    assert_eq!(frames.len(), 10);
    for f in &frames {
        let at = f.index as usize * FRAME;
        assert!(f.is_whole(FRAME), "frame {}", f.index);
        assert_eq!(f.bytes, s[at..at + FRAME], "frame {}", f.index);
    }
    assert_eq!(c.assembly.packets, sent.packets);
    assert_eq!(
        (c.assembly.lost(), c.assembly.duplicates, c.short, c.foreign),
        (0, 0, 0, 0)
    );
}

#[test]
fn loss_reordering_and_duplicates_are_counted_and_only_lost_frames_are_incomplete() {
    let s = stream();
    let imp = Impairments {
        loss: 0.02,
        reorder: 0.03,
        duplicate: 0.02,
        seed: 19,
    };
    let (frames, c, sent) = through_loopback(&s, imp);
    assert!(
        sent.lost > 0 && sent.reordered > 0 && sent.duplicated > 0,
        "{sent:?}"
    );
    // The frames a lost packet touches, from the emulator's own schedule.
    let (order, _) = schedule(s.len(), DEFAULT_PAYLOAD, &imp);
    let n = s.len().div_ceil(DEFAULT_PAYLOAD);
    let mut arrived = vec![false; n];
    for (k, _) in order {
        arrived[k] = true;
    }
    let mut hit = std::collections::BTreeSet::new();
    for k in (0..n).filter(|&k| !arrived[k]) {
        let (a, b) = (
            k * DEFAULT_PAYLOAD,
            ((k + 1) * DEFAULT_PAYLOAD).min(s.len()) - 1,
        );
        hit.extend([(a / FRAME) as u64, (b / FRAME) as u64]);
    }
    assert_eq!(frames.len(), 10);
    for f in &frames {
        let at = f.index as usize * FRAME;
        if hit.contains(&f.index) {
            assert!(
                f.missing > 0 && !f.is_whole(FRAME),
                "frame {} should be flagged",
                f.index
            );
        } else {
            assert!(f.is_whole(FRAME), "frame {}", f.index);
            assert_eq!(f.bytes, s[at..at + FRAME], "frame {}", f.index);
        }
    }
    assert_eq!(c.assembly.duplicates, sent.duplicated);
    assert_eq!(c.assembly.incomplete_frames, hit.len() as u64);
    // Losses at the very start or end of the stream lie outside the sequence range seen.
    let inside = (1..n - 1).filter(|&k| !arrived[k]).count() as u64;
    assert!(
        c.assembly.lost() >= inside && c.assembly.lost() <= sent.lost,
        "{c:?} {sent:?}"
    );
}

#[test]
fn foreign_and_short_datagrams_are_dropped_and_counted() {
    let mut rx = Receiver::bind(
        "127.0.0.1:0".parse().unwrap(),
        FRAME,
        Some([127, 0, 0, 1].into()),
    )
    .unwrap();
    let to = rx.local_addr().unwrap();
    let board = UdpSocket::bind("127.0.0.1:0").unwrap();
    let other = UdpSocket::bind("127.0.0.2:0").unwrap();
    let s: Vec<u8> = (0..FRAME).map(|i| i as u8).collect();
    other
        .send_to(&[1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 9, 9], to)
        .unwrap();
    board.send_to(&[1, 2, 3], to).unwrap();
    send(
        &board,
        to,
        &s,
        DEFAULT_PAYLOAD,
        &Impairments::default(),
        Some(Duration::from_micros(20)),
    )
    .unwrap();
    let f = rx
        .next_frame(Duration::from_secs(5), Duration::from_millis(300))
        .unwrap()
        .unwrap();
    assert!(f.is_whole(FRAME) && f.bytes == s);
    let c = rx.counters();
    assert_eq!((c.foreign, c.short), (1, 1));
}

fn real(file: &str) -> PathBuf {
    let shared = std::env::var_os("METAMORAN_SHARED").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared"),
        PathBuf::from,
    );
    shared
        .join("data/real/mmwave_capture_std_one_frame")
        .join(file)
}

/// The genuine capture (mmwave-capture-std's `test_one_frame.pcap`): its port-4098 packets sent
/// again, as recorded, through the receiver give the folder's `adc_data.bin`; its port-4096
/// packets are the board's replies.
#[test]
fn a_real_dca1000_session_replayed_gives_its_adc_data() {
    let bytes = std::fs::read(real("test_one_frame.pcap")).expect("shared/ beside the repository");
    let data = pcap::udp_to_port(&bytes, DATA_PORT).unwrap();
    assert_eq!(data.len(), 12);
    let board = data[0].from;
    // The .cfg's frame: 16 loops × 2 TX × 4 RX × 256 samples × 4 bytes.
    let mut rx = Receiver::bind(
        "127.0.0.1:0".parse().unwrap(),
        131_072,
        Some([127, 0, 0, 1].into()),
    )
    .unwrap();
    let to: SocketAddr = rx.local_addr().unwrap();
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    for d in &data {
        assert_eq!(d.from, board);
        socket.send_to(&d.payload, to).unwrap();
    }
    let mut recorded = Vec::new();
    while let Some(f) = rx
        .next_frame(Duration::from_secs(5), Duration::from_millis(300))
        .unwrap()
    {
        recorded.extend_from_slice(&f.bytes);
        assert_eq!(f.missing, 0);
    }
    assert_eq!(recorded, std::fs::read(real("adc_data.bin")).unwrap());
    assert_eq!(rx.counters().assembly.lost(), 0);
    // The replies: connect, reset FPGA, configure FPGA, packet config, start record, then the
    // board's own status at the end.
    let replies: Vec<Reply> = pcap::udp_to_port(&bytes, 4096)
        .unwrap()
        .iter()
        .map(|d| Reply::parse(&d.payload).unwrap())
        .collect();
    let commands: Vec<Command> = replies.iter().map(|r| r.command).collect();
    assert_eq!(
        commands,
        [
            Command::Connect,
            Command::ResetFpga,
            Command::ConfigFpga,
            Command::ConfigPacket,
            Command::StartRecord,
            Command::AsyncStatus
        ]
    );
    assert!(replies[..5].iter().all(|r| r.status == 0));
    assert!(pcap::udp_to_port(b"not a pcap", DATA_PORT).is_err());
}

/// A recording of the test stream with the (emulated) board under control: the result and
/// the commands the board answered, in order.
fn controlled(
    out: &mut impl std::io::Write,
) -> (
    Result<metamoran_dca1000::record::Recording, metamoran_dca1000::record::ControlledError>,
    Vec<Command>,
) {
    use metamoran_dca1000::control::Board;
    use metamoran_dca1000::emulate::answer_commands;
    use metamoran_dca1000::record::{Incomplete, record_controlled};
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};

    let config = UdpSocket::bind("127.0.0.1:0").unwrap();
    let board = Board::at(
        config.local_addr().unwrap(),
        "127.0.0.1:0".parse().unwrap(),
        Duration::from_secs(2),
    )
    .unwrap();
    let done = Arc::new(AtomicBool::new(false));
    let stop = done.clone();
    let answering = std::thread::spawn(move || {
        answer_commands(&config, Duration::from_millis(20), || {
            stop.load(Ordering::SeqCst)
        })
        .unwrap()
    });
    let mut rx = Receiver::bind(
        "127.0.0.1:0".parse().unwrap(),
        FRAME,
        Some([127, 0, 0, 1].into()),
    )
    .unwrap();
    let to = rx.local_addr().unwrap();
    let s = stream();
    let sender = spawn(
        LOCAL.parse().unwrap(),
        to,
        s.clone(),
        DEFAULT_PAYLOAD,
        Impairments::default(),
        PACE,
    );
    let timeouts = (Duration::from_secs(5), Duration::from_millis(300));
    let rec = record_controlled(
        &board,
        &mut rx,
        out,
        FRAME,
        Some(7),
        timeouts,
        Incomplete::ZeroFill,
    );
    sender.join().unwrap().unwrap();
    done.store(true, Ordering::SeqCst);
    (rec, answering.join().unwrap())
}

/// Every command of a recording, in TI's order.
const STARTED_AND_STOPPED: [Command; 6] = [
    Command::Connect,
    Command::ResetFpga,
    Command::ConfigFpga,
    Command::ConfigPacket,
    Command::StartRecord,
    Command::StopRecord,
];

/// The host configures and starts the (emulated) board over its config port, records the
/// stream into a `.bin` and stops it: the recording is the file, every command answered in
/// TI's order.
#[test]
fn a_controlled_recording_is_the_file() {
    let mut bin = Vec::new();
    let (rec, commands) = controlled(&mut bin);
    let rec = rec.unwrap();
    assert_eq!(commands, STARTED_AND_STOPPED);
    assert_eq!((rec.frames, rec.incomplete.len()), (7, 0));
    assert_eq!(bin, stream()[..7 * FRAME]);
}

/// An output that fails mid-recording (a full disk) ends it with that error, and the board is
/// still told to stop: it does not go on streaming into the network.
#[test]
fn a_failed_recording_still_stops_the_board() {
    struct Full(usize);
    impl std::io::Write for Full {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.0 < buf.len() {
                return Err(std::io::ErrorKind::StorageFull.into());
            }
            self.0 -= buf.len();
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let (rec, commands) = controlled(&mut Full(2 * FRAME));
    let err = rec.unwrap_err();
    assert!(
        matches!(&err, metamoran_dca1000::record::ControlledError::Io(e)
            if e.kind() == std::io::ErrorKind::StorageFull),
        "{err:?}"
    );
    assert_eq!(commands, STARTED_AND_STOPPED);
}
