//! `metamoran bench dca1000`: the receiver's sustained loopback throughput against the DCA1000's
//! practical maximum (about 700 Mbit/s of samples), with the loss and the receiving thread's CPU
//! share at each rate. The emulator paces packets by spinning on one core; the receiver runs on
//! the other.

use metamoran_dca1000::Receiver;
use metamoran_dca1000::emulate::{Impairments, spawn};
use metamoran_dca1000::packet::DEFAULT_PAYLOAD;
use serde::Serialize;
use std::fmt;
use std::time::{Duration, Instant};

/// The DCA1000EVM's practical sample rate over its gigabit link, Mbit/s.
pub const LINE_RATE_MBPS: f64 = 700.0;
/// Frame size of the stream: the xWR18xx `.cfg` of the real capture (16 loops × 2 TX × 4 RX ×
/// 256 samples × 4 bytes).
pub const FRAME_BYTES: usize = 131_072;

/// One rate's figures.
#[derive(Clone, Debug, Serialize)]
pub struct Rate {
    /// Rate asked of the emulator, Mbit/s (0: as fast as it can send).
    pub asked_mbps: f64,
    /// Samples received whole, Mbit/s of wall time.
    pub received_mbps: f64,
    /// Received rate over the DCA1000's line rate.
    pub vs_line_rate: f64,
    /// Packets sent and lost.
    pub packets: u64,
    /// Packets lost.
    pub lost: u64,
    /// Frames not whole.
    pub incomplete_frames: u64,
    /// The receiving thread's CPU time over the wall time (1 = one core busy).
    pub receiver_cpu: f64,
}

/// The benchmark's report.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Bytes sent per rate.
    pub bytes: usize,
    /// The rates.
    pub rates: Vec<Rate>,
    /// How it was measured.
    pub method: &'static str,
}

/// The calling thread's CPU time (user + system), s, from `/proc/thread-self/stat` (clock ticks
/// of 10 ms: USER_HZ is 100 on Linux); 0 where that is not readable.
fn thread_cpu_s() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/thread-self/stat") else {
        return 0.0;
    };
    // Fields after the command name in parentheses: utime is the 12th, stime the 13th.
    let after = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
    let fields: Vec<&str> = after.split_whitespace().collect();
    let tick = |i: usize| {
        fields
            .get(i)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (tick(11) + tick(12)) / 100.0
}

fn one_rate(stream: &[u8], mbps: f64) -> Result<Rate, crate::Error> {
    let mut rx = Receiver::bind(
        "127.0.0.1:0".parse()?,
        FRAME_BYTES,
        Some([127, 0, 0, 1].into()),
    )?;
    let to = rx.local_addr()?;
    let pace =
        (mbps > 0.0).then(|| Duration::from_secs_f64(DEFAULT_PAYLOAD as f64 * 8.0 / (mbps * 1e6)));
    // The receiver is bound: what arrives before it reads waits in its socket buffer.
    let from = "127.0.0.1:0".parse()?;
    let sender = spawn(
        from,
        to,
        stream.to_vec(),
        DEFAULT_PAYLOAD,
        Impairments::default(),
        pace,
    );
    let (cpu0, mut first, mut last) = (thread_cpu_s(), None, Instant::now());
    let mut whole_bytes = 0u64;
    while let Some(f) = rx.next_frame(Duration::from_secs(5), Duration::from_millis(300))? {
        first.get_or_insert_with(Instant::now);
        last = Instant::now();
        if f.is_whole(FRAME_BYTES) {
            whole_bytes += f.bytes.len() as u64;
        }
    }
    let cpu = thread_cpu_s() - cpu0;
    let sent = sender
        .join()
        .map_err(|_| "the emulator thread panicked")??;
    let wall = first.map_or(0.0, |t| (last - t).as_secs_f64()).max(1e-9);
    let c = rx.counters();
    let received_mbps = whole_bytes as f64 * 8.0 / wall / 1e6;
    Ok(Rate {
        asked_mbps: mbps,
        received_mbps,
        vs_line_rate: received_mbps / LINE_RATE_MBPS,
        packets: sent.packets,
        lost: sent.packets - c.assembly.packets,
        incomplete_frames: c.assembly.incomplete_frames,
        // The idle wait that ends the stream is not part of the wall time, nor (sleeping) of
        // the CPU time.
        receiver_cpu: cpu / wall,
    })
}

/// Sends `mbytes` MB at 100, 350 and 700 Mbit/s and unpaced to a receiver on loopback.
///
/// # Errors
/// A socket failure.
pub fn run(mbytes: usize) -> Result<Report, crate::Error> {
    let bytes = (mbytes << 20) / FRAME_BYTES * FRAME_BYTES;
    let stream: Vec<u8> = (0..bytes).map(|i| (i * 31 + i / 4099) as u8).collect();
    let mut rates = Vec::new();
    for mbps in [100.0, 350.0, LINE_RATE_MBPS, 0.0] {
        rates.push(one_rate(&stream, mbps)?);
    }
    Ok(Report {
        bytes,
        rates,
        method: "metamoran-dca1000 emulator -> Receiver on 127.0.0.1, 1456-byte packets, 131072-byte frames, 32 MiB socket buffer asked; CPU from /proc/thread-self/stat",
    })
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "DCA1000 receiver on loopback, {} MB per rate ({})",
            self.bytes >> 20,
            self.method
        )?;
        writeln!(
            f,
            "  asked Mbit/s  received Mbit/s  vs 700 Mbit/s  lost/packets  incomplete frames  receiver CPU"
        )?;
        for r in &self.rates {
            let asked = if r.asked_mbps > 0.0 {
                format!("{:.0}", r.asked_mbps)
            } else {
                "max".into()
            };
            writeln!(
                f,
                "  {asked:>12}  {:>15.0}  {:>12.2}×  {:>6}/{:<6}  {:>17}  {:>11.0}%",
                r.received_mbps,
                r.vs_line_rate,
                r.lost,
                r.packets,
                r.incomplete_frames,
                100.0 * r.receiver_cpu
            )?;
        }
        Ok(())
    }
}
