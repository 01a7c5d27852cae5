//! `metamoran record`: a live DCA1000 stream to a `.bin` capture.

use super::args::{BoardArg, LinkArgs};
use metamoran_bundle::capture::read_config;
use metamoran_dca1000::record::{Incomplete, Recording};
use std::fmt;
use std::path::{Path, PathBuf};

/// Record a live DCA1000EVM raw-mode stream into a capture file (the usual DCA1000 .bin): frames
/// reassembled by byte count, lost bytes zero-filled and the incomplete frames listed.
#[derive(clap::Args, Debug)]
#[command(
    mut_arg("dca1000", |a| a.required(true).help(
        "This host's address and data port the board sends its samples to \
         (192.168.33.30:4098 on TI's default setup)"
    )),
    mut_arg("config", |a| a.required(true)),
    after_help = "Examples:\n  metamoran record --dca1000 192.168.33.30:4098 --config profile.cfg --out capture.bin\n  metamoran record --dca1000 192.168.33.30:4098 --config profile.cfg --from 192.168.33.180 --control --frames 100 --out capture.bin"
)]
pub struct Args {
    #[command(flatten)]
    pub stream: StreamArgs,
    /// The capture file to write (replaced only once the recording is done).
    #[arg(long)]
    pub out: PathBuf,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Where a live stream comes from and how long it lasts (shared by `record` and `summarize`).
#[derive(clap::Args, Debug)]
pub struct StreamArgs {
    #[command(flatten)]
    pub link: LinkArgs,
    /// The radar config (TOML, mmWave SDK .cfg or mmWave Studio .mmwave.json): the frame size.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// The TI board a .cfg or .mmwave.json configures.
    #[arg(long, value_enum)]
    pub board: Option<BoardArg>,
    /// Stop after this many frames.
    #[arg(long, requires = "dca1000")]
    pub frames: Option<u64>,
}

impl StreamArgs {
    /// Records the stream into `out`, doing `incomplete` with frames that are not whole; the
    /// frame size from the config.
    ///
    /// # Errors
    /// No --dca1000 or --config, a bad config, a socket or control failure, or `out` failing.
    pub fn record(
        &self,
        out: &mut impl std::io::Write,
        incomplete: Incomplete,
    ) -> Result<Recording, metamoran::Error> {
        let (Some(link), Some(config)) = (self.link.link()?, &self.config) else {
            return Err("a live stream needs --dca1000 ADDR and --config".into());
        };
        let config = read_config(config, self.board.map(Into::into))?;
        let frame_bytes = config.radar.samples_per_frame() * 4;
        link.record(frame_bytes, self.frames, out, incomplete)
    }
}

/// What was recorded.
#[derive(Debug, serde::Serialize)]
pub struct Report {
    /// The file written.
    pub out: PathBuf,
    /// Frames written.
    pub frames: u64,
    /// Frames with missing bytes (zero-filled) or cut short.
    pub incomplete_frames: Vec<u64>,
    /// Bytes written.
    pub bytes: u64,
    /// Sample rate of the stream, Mbit/s.
    pub mbit_per_s: f64,
    /// Packets taken.
    pub packets: u64,
    /// Packets lost.
    pub lost: u64,
    /// Packets reordered.
    pub reordered: u64,
    /// Duplicates dropped.
    pub duplicates: u64,
    /// Packets for frames already written, dropped.
    pub late: u64,
    /// Datagrams from another address, dropped.
    pub foreign: u64,
    /// Datagrams too short to be packets, dropped.
    pub short: u64,
}

impl Report {
    /// The report of `rec` written to `out`.
    pub fn new(out: &Path, rec: &Recording) -> Self {
        let a = rec.counters.assembly;
        Self {
            out: out.to_owned(),
            frames: rec.frames,
            incomplete_frames: rec.incomplete.clone(),
            bytes: rec.bytes,
            mbit_per_s: if rec.seconds > 0.0 {
                rec.bytes as f64 * 8.0 / rec.seconds / 1e6
            } else {
                0.0
            },
            packets: a.packets,
            lost: a.lost(),
            reordered: a.reordered,
            duplicates: a.duplicates,
            late: a.late,
            foreign: rec.counters.foreign,
            short: rec.counters.short,
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{}: {} frames, {} bytes, {:.1} Mbit/s",
            self.out.display(),
            self.frames,
            self.bytes,
            self.mbit_per_s
        )?;
        if self.incomplete_frames.is_empty() {
            writeln!(f, "  every frame whole")?;
        } else {
            writeln!(
                f,
                "  {} frames incomplete (zero-filled): {:?}",
                self.incomplete_frames.len(),
                self.incomplete_frames
            )?;
        }
        writeln!(
            f,
            "  packets {}: lost {}, reordered {}, duplicates {}, late {}; dropped: {} foreign, {} short",
            self.packets,
            self.lost,
            self.reordered,
            self.duplicates,
            self.late,
            self.foreign,
            self.short
        )
    }
}

/// Runs `metamoran record`.
///
/// # Errors
/// A bad config, address or output folder, or a failed stream.
pub fn run(args: &Args) -> super::Result {
    let dir = args
        .out
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let mut tmp = tempfile::NamedTempFile::new_in(dir)
        .map_err(|e| format!("{}: cannot write there ({e})", dir.display()))?;
    let rec = {
        let mut w = std::io::BufWriter::new(tmp.as_file_mut());
        args.stream.record(&mut w, Incomplete::ZeroFill)?
    };
    if rec.frames == 0 {
        return Err(format!(
            "no frame arrived on {} within {} s",
            args.stream
                .link
                .dca1000
                .map_or_else(String::new, |a| a.to_string()),
            args.stream.link.start_s
        )
        .into());
    }
    tmp.persist(&args.out)
        .map_err(|e| format!("{}: cannot write it ({e})", args.out.display()))?;
    super::print(&Report::new(&args.out, &rec), args.json)
}
