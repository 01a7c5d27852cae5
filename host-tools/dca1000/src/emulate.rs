//! A DCA1000 stand-in for tests and benchmarks: sends a capture file's bytes as raw-mode data
//! packets, optionally losing, reordering and duplicating some (deterministically, from a
//! seed), or replays a real capture's packets ([`crate::pcap`]); and answers the configuration
//! commands the way the board does.

use crate::command::{Reply, parse_request};
use crate::packet::DataPacket;
use rand::{Rng, SeedableRng};
use std::io;
use std::net::{SocketAddr, UdpSocket};
use std::time::{Duration, Instant};

/// What the stand-in does to the packets, each a probability per packet.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Impairments {
    /// Not sent.
    pub loss: f64,
    /// Swapped with the next packet.
    pub reorder: f64,
    /// Sent twice.
    pub duplicate: f64,
    /// Seed of the draws.
    pub seed: u64,
}

/// What the stand-in sent.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sent {
    /// Packets of the stream.
    pub packets: u64,
    /// Datagrams sent (packets less lost plus duplicates).
    pub datagrams: u64,
    /// Packets not sent.
    pub lost: u64,
    /// Packets swapped with the next.
    pub reordered: u64,
    /// Packets sent twice.
    pub duplicated: u64,
    /// Bytes of samples sent.
    pub bytes: u64,
}

/// The order in which the packets of a `len`-byte stream cut in `payload`-byte packets go out,
/// as (packet index, copies), and the counts. Deterministic in `imp.seed`.
pub fn schedule(len: usize, payload: usize, imp: &Impairments) -> (Vec<(usize, u8)>, Sent) {
    let n = len.div_ceil(payload.max(1));
    let mut rng = rand_pcg::Pcg64::seed_from_u64(imp.seed);
    let mut order: Vec<usize> = (0..n).collect();
    let mut sent = Sent {
        packets: n as u64,
        ..Sent::default()
    };
    let mut i = 0;
    while i + 1 < n {
        if rng.random_bool(imp.reorder.clamp(0.0, 1.0)) {
            order.swap(i, i + 1);
            sent.reordered += 1;
            i += 2;
        } else {
            i += 1;
        }
    }
    let mut out = Vec::with_capacity(n);
    for k in order {
        if rng.random_bool(imp.loss.clamp(0.0, 1.0)) {
            sent.lost += 1;
            continue;
        }
        let copies = if rng.random_bool(imp.duplicate.clamp(0.0, 1.0)) {
            sent.duplicated += 1;
            2
        } else {
            1
        };
        out.push((k, copies));
    }
    (out, sent)
}

/// Sends `stream` to `to` from `from` as packets of `payload` bytes with `imp`, at most one
/// packet per `pace` (none: as fast as the socket takes them).
///
/// # Errors
/// The socket fails.
pub fn send(
    socket: &UdpSocket,
    to: SocketAddr,
    stream: &[u8],
    payload: usize,
    imp: &Impairments,
    pace: Option<Duration>,
) -> io::Result<Sent> {
    let payload = payload.max(1);
    let (order, mut sent) = schedule(stream.len(), payload, imp);
    let mut datagram = Vec::with_capacity(payload + 10);
    let begin = Instant::now();
    for (i, &(k, copies)) in order.iter().enumerate() {
        let at = k * payload;
        let chunk = &stream[at..(at + payload).min(stream.len())];
        DataPacket {
            seq: k as u32 + 1,
            offset: at as u64,
            payload: chunk,
        }
        .encode(&mut datagram);
        for _ in 0..copies {
            if let Some(p) = pace {
                let due = begin + p * i as u32;
                while Instant::now() < due {
                    std::hint::spin_loop();
                }
            }
            socket.send_to(&datagram, to)?;
            sent.datagrams += 1;
            sent.bytes += chunk.len() as u64;
        }
    }
    Ok(sent)
}

/// [`send`] from a fresh socket on `from` in its own thread: a board streaming while the
/// caller receives.
pub fn spawn(
    from: SocketAddr,
    to: SocketAddr,
    stream: Vec<u8>,
    payload: usize,
    imp: Impairments,
    pace: Option<Duration>,
) -> std::thread::JoinHandle<io::Result<Sent>> {
    std::thread::spawn(move || {
        let socket = UdpSocket::bind(from)?;
        send(&socket, to, &stream, payload, &imp, pace)
    })
}

/// Answers every command that arrives on `socket` with status 0 (success), as the board does,
/// until `until` returns true between commands (checked every `poll`); returns the commands
/// answered, in order.
///
/// # Errors
/// The socket fails.
pub fn answer_commands(
    socket: &UdpSocket,
    poll: Duration,
    until: impl Fn() -> bool,
) -> io::Result<Vec<crate::command::Command>> {
    socket.set_read_timeout(Some(poll))?;
    let mut buf = [0u8; 1500];
    let mut seen = Vec::new();
    while !until() {
        match socket.recv_from(&mut buf) {
            Ok((n, from)) => {
                if let Ok((command, _)) = parse_request(&buf[..n]) {
                    socket.send_to(&Reply { command, status: 0 }.to_bytes(), from)?;
                    seen.push(command);
                }
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                ) => {}
            Err(e) => return Err(e),
        }
    }
    Ok(seen)
}
