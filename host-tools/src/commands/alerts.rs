//! `metamoran alerts`: what an operator station that was offline replays, the site's whole
//! JetStream alert stream in the order the server stored it.

use super::args::NatsArgs;
use serde::Serialize;
use std::fmt;

/// Replay a site's alerts from its NATS JetStream stream, oldest first.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  metamoran alerts --nats nats://127.0.0.1:4222 --site yard\n  METAMORAN_NATS_PASSWORD=… metamoran alerts --nats tls://hq:4222 --nats-ca ca.pem --nats-user station --site yard --json"
)]
pub struct Args {
    /// The server, site and login (`--nats` is required here).
    #[command(flatten)]
    nats: NatsArgs,
    /// At most this many alerts.
    #[arg(long, default_value_t = 100_000)]
    limit: usize,
    /// Print JSON (one object per alert, as published) instead of the table.
    #[arg(long)]
    json: bool,
}

/// The replayed alerts.
#[derive(Debug, Serialize)]
struct Replay {
    stream: String,
    alerts: Vec<Stored>,
}

#[derive(Debug, Serialize)]
struct Stored {
    sequence: u64,
    sensor: String,
    alert: serde_json::Value,
}

impl fmt::Display for Replay {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}: {} alert(s)", self.stream, self.alerts.len())?;
        for s in &self.alerts {
            let a = &s.alert;
            let word = |k: &str| a[k].as_str().unwrap_or("?").to_owned();
            writeln!(
                f,
                "{:>6}  {:<10} t={:>6.1} s  {:<8} {:<7} track {:<4} {} at {:.2} m",
                s.sequence,
                s.sensor,
                a["time_s"].as_f64().unwrap_or(f64::NAN),
                word("kind"),
                word("class"),
                a["track"],
                word("zone"),
                a["depth_m"].as_f64().unwrap_or(f64::NAN)
            )?;
        }
        Ok(())
    }
}

/// Runs `metamoran alerts`.
///
/// # Errors
/// No `--nats`, or the server cannot be read.
pub fn run(args: &Args) -> super::Result {
    let config = args
        .nats
        .config("replay")?
        .ok_or("metamoran alerts: give --nats URL (and --site)")?;
    let stored = metamoran_operator::nats::replay(&config, args.limit)?;
    let replay = Replay {
        stream: config.stream(),
        alerts: stored
            .into_iter()
            .map(|s| Stored {
                sequence: s.sequence,
                sensor: s.sensor,
                alert: serde_json::from_str(&s.json).unwrap_or(serde_json::Value::String(s.json)),
            })
            .collect(),
    };
    super::print(&replay, args.json)
}
