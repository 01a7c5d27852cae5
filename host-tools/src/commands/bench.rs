//! `metamoran bench`: benchmarks, reported as ratios against baselines measured in the same run.

use super::args::Locations;
use metamoran::bench;
use metamoran_map::network::Board;

/// Benchmarks, reported as ratios against baselines measured in the same run.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    what: What,
}

/// `bench network --board`: which board's drive scenes.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum BenchBoard {
    /// The xWR1843-like board.
    Small,
    /// The 4D imaging board.
    Imaging,
}

/// The benchmarks.
#[derive(clap::Subcommand, Debug)]
enum What {
    /// FFT speed on this host and SQNR at -12/-40 dBFS: ours (Q15, Q31) vs microfft, rustfft, CMSIS-DSP.
    #[command(after_help = "Example:\n  metamoran bench fft --json")]
    Fft {
        /// Print JSON.
        #[arg(long)]
        json: bool,
        /// FFT lengths.
        #[arg(long, value_delimiter = ',', default_value = "256,1024")]
        sizes: Vec<usize>,
    },
    /// 3D-RadarHR's time per drive submap against IP-Basic's, and the map path's frame rate
    /// (needs a build with --features onnx).
    #[command(
        after_help = "Example:\n  cargo run --release -p metamoran --features onnx -- bench network"
    )]
    Network {
        /// Print JSON.
        #[arg(long)]
        json: bool,
        /// The board whose drive scenes are mapped: `small` (xWR1843-like) or `imaging` (the
        /// 4D board: 192 channels per frame, its own network).
        #[arg(long, value_enum, default_value_t = BenchBoard::Small)]
        board: BenchBoard,
        /// Which earlier points the submaps keep: the board's own rule (`auto`), `all` or
        /// `seen-again` (what the check costs, in the same run).
        #[arg(long, value_enum, default_value_t = super::map::KeepArg::Auto)]
        keep: super::map::KeepArg,
        /// Which detections become points: the board's own rule (`auto`), `map` or
        /// `direction` (what each costs, in the same run).
        #[arg(long, value_enum, default_value_t = super::map::PeaksArg::Auto)]
        peaks: super::map::PeaksArg,
        /// Whether the detector's screen applies: the board's own rule (`auto`), `on` or `off`
        /// (what it costs, in the same run).
        #[arg(long, value_enum, default_value_t = super::map::Switch::Auto)]
        screen: super::map::Switch,
    },
    /// Depth search on a cascade-86, 512-sample frame: coarse-to-fine vs brute force (MACs, time).
    #[command(after_help = "Example:\n  metamoran bench search --json")]
    Search {
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// The DCA1000 receiver's sustained loopback throughput at 100, 350, 700 Mbit/s and
    /// unpaced, against the board's ~700 Mbit/s: loss and the receiving thread's CPU share.
    #[command(after_help = "Example:\n  metamoran bench dca1000 --json")]
    Dca1000 {
        /// Print JSON.
        #[arg(long)]
        json: bool,
        /// Megabytes sent per rate.
        #[arg(long, default_value_t = 256)]
        mbytes: usize,
    },
    /// The module's budgets on the release firmware: flash, RAM, stack, instructions per
    /// cascade-86 frame with 4 objects under QEMU -icount, telemetry bytes.
    #[command(after_help = "Example:\n  metamoran bench m7 --json")]
    M7 {
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// The site stream under load: N sensors' tracks (and an alert a second each) through one
    /// nats-server (started here on loopback) to one site process; messages per second and the
    /// frame → page latency against the frame period.
    #[command(
        after_help = "Example:\n  metamoran bench site --sensors 50 --rate-hz 10 --seconds 10"
    )]
    Site {
        /// Print JSON.
        #[arg(long)]
        json: bool,
        /// Simulated sensors.
        #[arg(long, default_value_t = 50)]
        sensors: usize,
        /// Frames per second per sensor.
        #[arg(long, default_value_t = 10.0)]
        rate_hz: f64,
        /// Seconds of publishing.
        #[arg(long, default_value_t = 10.0)]
        seconds: f64,
    },
    /// FFT instruction counts on the Cortex-M7 under QEMU (-icount), vs CMSIS-DSP's published counts.
    #[command(
        name = "fft-m7",
        after_help = "Example:\n  metamoran bench fft-m7 --json"
    )]
    FftM7 {
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
}

/// Runs `metamoran bench …`.
///
/// # Errors
/// A bad size, a missing firmware, QEMU or model, or a failed measurement.
pub fn run(args: &Args, locations: &Locations) -> super::Result {
    match &args.what {
        What::Fft { json, sizes } => {
            if let Some(&bad) = sizes
                .iter()
                .find(|&&n| !metamoran_dsp::fft::is_supported_len(n))
            {
                return Err(format!("--sizes {bad}: use powers of two from 16 to 2048").into());
            }
            super::print(&bench::fft::run(sizes, true), *json)
        }
        What::M7 { json } => super::print(&bench::budget::run(&locations.firmware()?)?, *json),
        What::FftM7 { json } => super::print(&bench::m7::run(&locations.firmware()?)?, *json),
        What::Search { json } => super::print(&bench::search::run()?, *json),
        What::Dca1000 { json, mbytes } => super::print(&bench::dca1000::run(*mbytes)?, *json),
        What::Network {
            json,
            board,
            keep,
            peaks,
            screen,
        } => {
            let board = match board {
                BenchBoard::Small => Board::Small,
                BenchBoard::Imaging => Board::Imaging,
            };
            let auto = board.submap_options();
            let options = metamoran_map::depth::SubmapOptions {
                keep: keep.rule(auto.keep),
                peaks: peaks.rule(auto.peaks),
                screen: screen.rule(auto.screen, metamoran_map::cloud::DIRECTION_SCREEN),
                ..auto
            };
            super::print(&bench::network::run(board, options)?, *json)
        }
        What::Site {
            json,
            sensors,
            rate_hz,
            seconds,
        } => super::print(&bench::site::run(*sensors, *rate_hz, *seconds)?, *json),
    }
}
