//! `metamoran summarize`: range-profile peaks and moving targets of a bundle or a bare capture.

use super::args::{CaptureArgs, LinkArgs};
use metamoran_process::summary::summarize;
use std::path::PathBuf;

/// Summarize a scene bundle or a bare DCA1000 capture: range-profile peaks and moving targets.
#[derive(clap::Args, Debug)]
#[command(
    mut_arg("dca1000", |a| a
        .requires("config")
        .conflicts_with("path")
        .help("Summarize a live DCA1000 stream instead: this host's address and data port the board sends to (the frames are recorded to a temporary file first; needs --config)")),
    after_help = "Examples:\n  metamoran summarize scenes/parking-lot-07\n  metamoran summarize adc_data.bin --config radar.toml --iq-order qqii --json\n  metamoran summarize adc_data.bin --config xwr18xx_profile.cfg --board xwr18xx-boost"
)]
pub struct Args {
    /// A bundle folder (with scene.toml) or a DCA1000 .bin file (none with --dca1000).
    #[arg(required_unless_present = "dca1000")]
    path: Option<PathBuf>,
    #[command(flatten)]
    link: LinkArgs,
    /// With --dca1000: frames to take.
    #[arg(long, requires = "dca1000")]
    frames: Option<u64>,
    #[command(flatten)]
    capture: CaptureArgs,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

/// Runs `metamoran summarize`.
///
/// # Errors
/// A missing or bad capture, config or bundle.
pub fn run(args: &Args) -> super::Result {
    // A live stream is recorded first, through `record`'s code.
    let live = match args.link.dca1000 {
        Some(addr) => {
            let stream = super::record::StreamArgs {
                link: args.link.clone(),
                config: args.capture.config.clone(),
                board: args.capture.board,
                frames: args.frames,
            };
            let mut tmp = tempfile::NamedTempFile::new()?;
            // Frames that are not whole are left out: they are never processed as frames.
            let skip = metamoran_dca1000::record::Incomplete::Skip;
            let rec = stream.record(&mut std::io::BufWriter::new(tmp.as_file_mut()), skip)?;
            eprint!("{}", super::record::Report::new(tmp.path(), &rec));
            if rec.bytes == 0 {
                return Err(format!("no whole frame arrived on {addr}").into());
            }
            Some(tmp)
        }
        None => None,
    };
    let path = live.as_ref().map_or_else(
        || args.path.clone().unwrap_or_default(),
        |t| t.path().to_owned(),
    );
    let mut file = args.capture.open(&path)?;
    if let Some((have, frame)) = file.loops_of_frame() {
        eprintln!(
            "note: {} holds {have} of a frame's {frame} loops (a capture cut short); read as one frame of {have}",
            path.display()
        );
    }
    super::print(&summarize(&mut file)?, args.json)
}
