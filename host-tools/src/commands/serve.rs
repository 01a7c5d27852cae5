//! `metamoran serve` and `metamoran hash-password`: the operator's web view of a site.

use super::args::NatsServerArgs;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::Duration;

/// Serve the site's operator page: the plan with zones, sensors and coverage, live tracks with
/// trails, alerts to acknowledge, sensor health. Login required (argon2id hashes in a users
/// file); updates as server-sent events.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  metamoran hash-password < pw.txt | sed 's/^/alice:/' > users.txt\n  metamoran serve --site sites/site-1/site.toml --users users.txt --replay sites/site-1\n  metamoran serve --site site.toml --users users.txt --nats nats://127.0.0.1:4222 --bundles site-1 --listen 0.0.0.0:8443 --tls-cert cert.pem --tls-key key.pem"
)]
pub struct Args {
    /// The site file (sensors, plan, zones).
    #[arg(long = "site")]
    site_file: PathBuf,
    /// Users file: `user:argon2-hash` lines (metamoran hash-password makes a hash).
    #[arg(long)]
    users: PathBuf,
    /// Address to serve on (loopback by default; any other address needs --tls-cert).
    #[arg(long, default_value = "127.0.0.1:8080")]
    listen: SocketAddr,
    /// Serve HTTPS with this certificate chain (PEM, leaf first).
    #[arg(long, value_name = "PEM", requires = "tls_key")]
    tls_cert: Option<PathBuf>,
    /// The certificate's private key (PEM).
    #[arg(long, value_name = "PEM", requires = "tls_cert")]
    tls_key: Option<PathBuf>,
    /// Replay a simulated site folder (its bundles processed and tracked as the sensors would,
    /// then fed in real time, over and over) instead of subscribing to NATS.
    #[arg(long, value_name = "DIR", conflicts_with = "nats")]
    replay: Option<PathBuf>,
    /// The folder with each sensor's bundle (`DIR/<sensor>/`), for the selected track's
    /// range–azimuth map and fused depth image (`--replay DIR` implies it).
    #[arg(long, value_name = "DIR", conflicts_with = "replay")]
    bundles: Option<PathBuf>,
    /// The NATS server the sensors publish their tracks to (the site name is the site file's).
    #[command(flatten)]
    nats: NatsServerArgs,
    /// Minutes a login session lasts.
    #[arg(long, default_value_t = 60)]
    session_minutes: u64,
    /// Seconds without a message after which a sensor raises a `silent` alert.
    #[arg(long, default_value_t = 5.0)]
    silence_s: f64,
}

/// Runs `metamoran serve` until stopped.
///
/// # Errors
/// A bad site or users file, a folder that cannot be replayed, or a server that cannot start.
pub fn run(args: &Args) -> super::Result {
    let site = metamoran_operator::site::SiteFile::load(&args.site_file)?;
    let users = metamoran_web::login::Users::load(&args.users).map_err(|e| e.to_string())?;
    let feed = match (&args.replay, args.nats.config(&site.name, "serve")?) {
        (Some(dir), _) => {
            let (sensors, period_s) = metamoran::site::replay_messages(dir, &site)?;
            metamoran_web::replay_feed(sensors, period_s)
        }
        (None, Some(config)) => metamoran_web::Feed::Nats(config),
        (None, None) => return Err("metamoran serve: give --nats URL or --replay DIR".into()),
    };
    let server = metamoran_web::start(metamoran_web::ServeOptions {
        site,
        users,
        feed,
        listen: args.listen,
        session_ttl: Duration::from_secs(args.session_minutes.max(1) * 60),
        silence_s: args.silence_s,
        bundles: args.replay.clone().or_else(|| args.bundles.clone()),
        tls: args
            .tls_cert
            .clone()
            .zip(args.tls_key.clone())
            .map(|(cert, key)| metamoran_web::tls::TlsFiles { cert, key }),
    })
    .map_err(|e| e.to_string())?;
    // Scripts read this line for the address (port 0 picks a free one).
    let scheme = if args.tls_cert.is_some() {
        "https"
    } else {
        "http"
    };
    println!("serving {scheme}://{}/", server.addr());
    server.wait();
    Ok(())
}

/// Print an argon2id hash of the password read from standard input (its first line), for a
/// `serve --users` file.
#[derive(clap::Args, Debug)]
pub struct HashArgs {}

/// Runs `metamoran hash-password`.
///
/// # Errors
/// No password on standard input.
pub fn hash(_: &HashArgs) -> super::Result {
    let mut line = String::new();
    std::io::stdin()
        .read_line(&mut line)
        .map_err(|e| format!("standard input: {e}"))?;
    let password = line.trim_end_matches(['\n', '\r']);
    if password.is_empty() {
        return Err("metamoran hash-password: give the password on standard input".into());
    }
    println!(
        "{}",
        metamoran_web::login::hash_password(password).map_err(|e| e.to_string())?
    );
    Ok(())
}
