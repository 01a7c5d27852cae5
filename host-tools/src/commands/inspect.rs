//! `metamoran inspect`: plots of what the radar saw for each object of one frame.

use super::args::BundleArgs;
use std::path::PathBuf;

/// Plots of what the radar saw for each object of one frame: the range–azimuth map before
/// and after SIC (span, cancelled reflectors and chosen depth marked) and the score P(d).
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  metamoran inspect demo-out/scene --out inspect-out\n  metamoran inspect scenes/parking-lot-1-0000 --frame 2 --json"
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
    /// Print JSON instead of a summary.
    #[arg(long)]
    json: bool,
}

/// Runs `metamoran inspect`.
///
/// # Errors
/// A bad bundle or model, a frame out of range, or plots that cannot be written.
pub fn run(args: &Args) -> super::Result {
    let report = metamoran_operator::inspect::run(
        &args.bundle,
        args.frame,
        &args.out,
        args.read.options()?,
    )?;
    super::print(&report, args.json)
}
