//! `metamoran site`: a whole multi-pole site in one process.

use std::path::PathBuf;

/// Run a site: every pole's bundle processed and tracked as its sensor would, fused into site
/// tracks on the plan, zones evaluated once, alerts with the sensors that saw each object.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  metamoran simulate --preset site --seed 1 --out sites && metamoran site sites/site-1\n  metamoran site sites/site-1 --json"
)]
pub struct Args {
    /// The site folder: site.toml and one bundle folder per sensor id.
    dir: PathBuf,
    /// Print JSON instead of the report.
    #[arg(long)]
    json: bool,
}

/// Runs `metamoran site`.
///
/// # Errors
/// A bad site file or bundle.
pub fn run(args: &Args) -> super::Result {
    super::print(&metamoran::site::run(&args.dir)?, args.json)
}
