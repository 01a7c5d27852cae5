//! `metamoran inspect`: plots of what the radar saw for each object of one frame.

use super::args::{BundleArgs, LinkArgs};
use std::path::PathBuf;

/// Plots of what the radar saw for each object of one frame: the range–azimuth map before
/// and after SIC (span, cancelled reflectors and chosen depth marked) and the score P(d).
#[derive(clap::Args, Debug)]
#[command(
    mut_arg("dca1000", |a| a.help(
        "Take the radar samples from a live DCA1000 stream arriving at ADDR (this host's \
         address and data port) instead of the bundle's adc_file: the bundle's frames are \
         recorded first; the camera products come from the bundle"
    )),
    after_help = "Examples:\n  metamoran inspect demo-out/scene --out inspect-out\n  metamoran inspect scenes/parking-lot-1-0000 --frame 2 --json\n  metamoran inspect site-07 --dca1000 192.168.33.30:4098   (radar from the board, camera from the bundle)"
)]
pub struct Args {
    /// The bundle folder.
    bundle: PathBuf,
    /// Frame to inspect.
    #[arg(long, default_value_t = 0)]
    frame: u32,
    /// Output folder for the PNG plots.
    #[arg(long, default_value = "inspect-out")]
    out: PathBuf,
    #[command(flatten)]
    read: BundleArgs,
    /// A live stream in place of the bundle's radar capture.
    #[command(flatten)]
    live: LinkArgs,
    /// Print JSON instead of a summary.
    #[arg(long)]
    json: bool,
}

/// Runs `metamoran inspect`.
///
/// # Errors
/// A bad bundle or model, a frame out of range, or plots that cannot be written.
pub fn run(args: &Args) -> super::Result {
    let mut open = args.read.options()?;
    let live = args.live.capture_for(&args.bundle)?;
    open.capture = live.as_ref().map(|l| l.capture.clone());
    let report = metamoran_operator::inspect::run(&args.bundle, args.frame, &args.out, open)?;
    super::print(&report, args.json)
}
