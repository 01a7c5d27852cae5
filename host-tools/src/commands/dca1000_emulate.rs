//! `metamoran dca1000-emulate`: a DCA1000 stand-in sending a capture to an address.

use metamoran_dca1000::emulate::{Impairments, Sent, send};
use metamoran_dca1000::packet::{DATA_PORT, DEFAULT_PAYLOAD, MAX_PAYLOAD};
use std::fmt;
use std::net::{SocketAddr, UdpSocket};
use std::path::PathBuf;
use std::time::Duration;

/// Send a capture file as DCA1000 raw-mode packets (for testing a receiver without a board),
/// optionally losing, reordering and duplicating some; or replay a recorded session (.pcap).
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  metamoran dca1000-emulate adc_data.bin --to 127.0.0.1:4098\n  metamoran dca1000-emulate adc_data.bin --to 127.0.0.1:4098 --loss 0.01 --reorder 0.01 --duplicate 0.01 --seed 7\n  metamoran dca1000-emulate test_one_frame.pcap --to 127.0.0.1:4098"
)]
pub struct Args {
    /// A capture (.bin) to send, or a packet capture (.pcap) whose port-4098 packets to replay.
    file: PathBuf,
    /// Where to send: the receiver's address and port.
    #[arg(long)]
    to: SocketAddr,
    /// Sample bytes per packet.
    #[arg(long, default_value_t = DEFAULT_PAYLOAD)]
    payload: usize,
    /// Share of packets not sent.
    #[arg(long, default_value_t = 0.0)]
    loss: f64,
    /// Share of packets swapped with the next.
    #[arg(long, default_value_t = 0.0)]
    reorder: f64,
    /// Share of packets sent twice.
    #[arg(long, default_value_t = 0.0)]
    duplicate: f64,
    /// Seed of the impairments.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Sample rate to send at, Mbit/s (0: as fast as the socket takes them).
    #[arg(long, default_value_t = 0.0)]
    mbps: f64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// What was sent.
#[derive(Debug, serde::Serialize)]
pub struct Report {
    /// The counts.
    #[serde(flatten)]
    sent: SentJson,
}

#[derive(Debug, serde::Serialize)]
struct SentJson {
    packets: u64,
    datagrams: u64,
    lost: u64,
    reordered: u64,
    duplicated: u64,
    bytes: u64,
}

impl From<Sent> for SentJson {
    fn from(s: Sent) -> Self {
        Self {
            packets: s.packets,
            datagrams: s.datagrams,
            lost: s.lost,
            reordered: s.reordered,
            duplicated: s.duplicated,
            bytes: s.bytes,
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.sent;
        writeln!(
            f,
            "sent {} datagrams ({} bytes of samples) for {} packets: {} lost, {} reordered, {} duplicated",
            s.datagrams, s.bytes, s.packets, s.lost, s.reordered, s.duplicated
        )
    }
}

/// Runs `metamoran dca1000-emulate`.
///
/// # Errors
/// An unreadable file, bad options or a socket failure.
pub fn run(args: &Args) -> super::Result {
    for (flag, p) in [
        ("--loss", args.loss),
        ("--reorder", args.reorder),
        ("--duplicate", args.duplicate),
    ] {
        if !(0.0..=1.0).contains(&p) {
            return Err(format!("{flag} {p}: give a share from 0 to 1").into());
        }
    }
    if args.payload == 0 || args.payload > MAX_PAYLOAD {
        return Err(format!("--payload {}: give 1 to {MAX_PAYLOAD} bytes", args.payload).into());
    }
    let limit = metamoran_bundle::limits::MAX_FRAME_BYTES * 16;
    let bytes = metamoran_bundle::limits::read_bounded(&args.file, limit)?;
    let local: SocketAddr = if args.to.is_ipv4() {
        "0.0.0.0:0"
    } else {
        "[::]:0"
    }
    .parse()?;
    let socket = UdpSocket::bind(local).map_err(|e| format!("cannot open a socket: {e}"))?;
    let is_pcap = args.file.extension().is_some_and(|e| e == "pcap");
    let sent = if is_pcap {
        let data = metamoran_dca1000::pcap::udp_to_port(&bytes, DATA_PORT)
            .map_err(|e| format!("{}: {e}", args.file.display()))?;
        let mut s = Sent::default();
        for d in &data {
            socket.send_to(&d.payload, args.to)?;
            s.packets += 1;
            s.datagrams += 1;
            s.bytes += d.payload.len().saturating_sub(10) as u64;
        }
        s
    } else {
        let imp = Impairments {
            loss: args.loss,
            reorder: args.reorder,
            duplicate: args.duplicate,
            seed: args.seed,
        };
        let pace = (args.mbps > 0.0)
            .then(|| Duration::from_secs_f64(args.payload as f64 * 8.0 / (args.mbps * 1e6)));
        send(&socket, args.to, &bytes, args.payload, &imp, pace)?
    };
    super::print(&Report { sent: sent.into() }, args.json)
}
