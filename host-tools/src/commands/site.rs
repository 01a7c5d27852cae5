//! `metamoran site`: a whole multi-pole site in one process.

use std::path::PathBuf;

/// Run a site: every pole's bundle processed and tracked as its sensor would, fused into site
/// tracks on the plan, zones evaluated once, alerts with the sensors that saw each object.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  metamoran simulate --preset site --seed 1 --out sites && metamoran site sites/site-1\n  metamoran site sites/site-1 --json\n  metamoran site sites/site-1 --nats nats://127.0.0.1:4222 --laps 0   (the poles, live, for serve --nats)"
)]
pub struct Args {
    /// The site folder: site.toml and one bundle folder per sensor id.
    dir: PathBuf,
    /// Print JSON instead of the report.
    #[arg(long)]
    json: bool,
    /// Be the site's sensors instead: publish each pole's tracks and health to this NATS server
    /// at the frame rate (the site process is `metamoran serve --nats`).
    #[command(flatten)]
    nats: super::args::NatsServerArgs,
    /// With --nats: how many times to play the site (0: until stopped).
    #[arg(long, default_value_t = 1, requires = "nats")]
    laps: u32,
}

/// Runs `metamoran site`.
///
/// # Errors
/// A bad site file or bundle.
pub fn run(args: &Args) -> super::Result {
    if args.nats.nats.is_some() {
        let server = |site: &str, sensor: &str| {
            args.nats
                .config(site, sensor)?
                .ok_or_else(|| metamoran::Error::from("--nats"))
        };
        let sent = metamoran::site::publish_sensors(&args.dir, &server, args.laps)?;
        eprintln!("published {sent} sensor message(s)");
        return Ok(());
    }
    super::print(&metamoran::site::run(&args.dir)?, args.json)
}
