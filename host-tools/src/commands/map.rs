//! `metamoran map`: the dense radar map of a moving-platform bundle and its figures.

use super::odometry::figure;
use metamoran_dsp::points::Peaks;
use metamoran_map::network::{Board, CompletionNetwork};
use metamoran_map::report::MapReport;
use metamoran_map::submap::Keep;
use metamoran_map::{cylinder, depth, ip_basic, report};
use std::fmt;
use std::path::{Path, PathBuf};

/// Dense radar map of a moving-platform bundle (the second paper): odometry, the last
/// frame's submap, its completion by IP-Basic and by the 3D-RadarHR network, each depth
/// image's MAE/RMSE against the lidar truth, and the network's frame rate. Writes the depth
/// images (16-bit KITTI PNG, 320 × 80: frame, submap, ip_basic, network, lidar) and point
/// clouds (PLY: submap.ply, network.ply) into --out. The network needs a build with
/// --features onnx.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Example:\n  cargo build --release -p metamoran --features onnx\n  metamoran simulate --preset drive --seed 3 --count 1 --out drives\n  metamoran map drives/drive-3-0000 --out drive-map --json"
)]
pub struct Args {
    /// The bundle folder.
    bundle: PathBuf,
    /// Output folder for the depth images and point clouds.
    #[arg(long, default_value = "map-out")]
    out: PathBuf,
    /// A 3D-RadarHR ONNX model (contract: vision crate docs) instead of the one shipped for the
    /// bundle's board (the small board's, or the 4D imaging board's for an array with three or
    /// more elevation rows).
    #[arg(long, value_name = "MODEL.onnx")]
    model: Option<PathBuf>,
    /// Skip the network (its figures are null); works without the onnx feature.
    #[arg(long, conflicts_with = "model")]
    no_network: bool,
    /// Also write every frame's submap and lidar depth images as training pairs
    /// (OUT/pairs/submap_FFFFFF.png, OUT/pairs/lidar_FFFFFF.png) for train/radarhr.py, with
    /// the submap's IP-Basic completion (OUT/pairs/ip_basic_FFFFFF.png), a guided model's
    /// second input.
    #[arg(long)]
    training_pairs: bool,
    /// Whether to cut the frame's and the submap's depth images to what is visible before
    /// completion: drop a pixel when one within ±6 columns and ±4 rows is nearer by 1 m + 5 %
    /// (the imaging board's beam; a wall seen past a pole from earlier poses). `auto` cuts on
    /// the imaging board, whose shipped network was trained so, and not on the small board;
    /// `--visibility` alone is `on`.
    #[arg(long, value_enum, default_value_t = Switch::Auto, num_args = 0..=1, default_missing_value = "on")]
    visibility: Switch,
    /// Which earlier frames' points the submap keeps: `all`, or `seen-again`, only those within
    /// 0.5 m of one of the last frame's points (a consistency check across frames: what has
    /// since been hidden, or was a ghost, stays out). `auto` is what the board's shipped
    /// network was trained on.
    #[arg(long, value_enum, default_value_t = KeepArg::Auto)]
    keep: KeepArg,
    /// Which detections become points: `map`, the range–Doppler map's local maxima, or
    /// `direction`, every detected cell with each direction kept where its own beam peaks in
    /// range and Doppler (weaker reflectors beside stronger ones in other directions are found
    /// too: denser frames, see the README). `auto` is what the board's shipped network was
    /// trained on.
    #[arg(long, value_enum, default_value_t = PeaksArg::Auto)]
    peaks: PeaksArg,
    /// Whether the detector also tests the cells the CFAR misses that are louder than their
    /// neighbourhood's mean, within 40 dB of the strongest cell and 6 dB over the map's median,
    /// its noise (with `--peaks direction`, which keeps only each direction's own peak: denser
    /// frames and submaps, see the README's "the direction rule's screen"). `auto` is what the board's shipped network was trained
    /// on; `--screen` alone is `on`.
    #[arg(long, value_enum, default_value_t = Switch::Auto, num_args = 0..=1, default_missing_value = "on")]
    screen: Switch,
    /// Print the figures as JSON.
    #[arg(long)]
    json: bool,
}

/// An option that is `auto` (what the board's shipped network was trained with), `on` or `off`:
/// `map --visibility` (whether the depth images are cut to what is visible) and `--screen`
/// (whether the detector's screen applies).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Switch {
    /// As the board's shipped network was trained.
    Auto,
    /// Always.
    On,
    /// Never.
    Off,
}

impl Switch {
    /// `value` where on, none where off, `auto` where auto.
    pub fn rule<T>(self, auto: Option<T>, value: T) -> Option<T> {
        match self {
            Self::Auto => auto,
            Self::On => Some(value),
            Self::Off => None,
        }
    }
}

/// `map --keep`: which earlier points the submap keeps.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum KeepArg {
    /// What the board's shipped network was trained on.
    Auto,
    /// Every static point of every frame.
    All,
    /// Only those the last frame sees again within 0.5 m.
    SeenAgain,
}

impl KeepArg {
    /// The rule, with `auto` the board's.
    pub fn rule(self, auto: Keep) -> Keep {
        match self {
            Self::Auto => auto,
            Self::All => Keep::All,
            Self::SeenAgain => Keep::SEEN_AGAIN,
        }
    }
}

/// `map --peaks`: which detections become points.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum PeaksArg {
    /// What the board's shipped network was trained on.
    Auto,
    /// Local maxima of the range–Doppler map.
    Map,
    /// Each direction's own peak in range and Doppler.
    Direction,
}

impl PeaksArg {
    /// The rule, with `auto` the board's.
    pub fn rule(self, auto: Peaks) -> Peaks {
        match self {
            Self::Auto => auto,
            Self::Map => Peaks::RangeDoppler,
            Self::Direction => Peaks::Direction,
        }
    }
}

/// Runs `metamoran map`.
///
/// # Errors
/// A bad bundle or model, or images that cannot be written.
pub fn run(args: &Args) -> super::Result {
    let board = Board::of(&args.bundle)?;
    let network = (!args.no_network)
        .then(|| CompletionNetwork::load(args.model.as_deref(), board))
        .transpose()?;
    let complete = network.as_ref().map(|n| move |r: &[f32]| n.complete(r));
    let auto = board.submap_options();
    let options = depth::SubmapOptions {
        visibility: args
            .visibility
            .rule(auto.visibility, cylinder::Visibility::IMAGING_BEAM),
        keep: args.keep.rule(auto.keep),
        peaks: args.peaks.rule(auto.peaks),
        screen: args
            .screen
            .rule(auto.screen, metamoran_map::cloud::DIRECTION_SCREEN),
    };
    let (report, odometry, images) = report::run_with(
        &args.bundle,
        &metamoran_sim::drive::MOUNT,
        complete.as_ref().map(|c| c as depth::Completion),
        &options,
    )?;
    let out = &args.out;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: cannot create ({e})", out.display()))?;
    if let Some(im) = &images {
        png(out, "frame.png", &im.frame)?;
        png(out, "submap.png", &im.submap)?;
        png(out, "ip_basic.png", &im.ip_basic)?;
        metamoran_bundle::lidar::write(&out.join("submap.ply"), &im.submap_points)?;
        if let Some(n) = &im.network {
            png(out, "network.png", n)?;
            metamoran_bundle::lidar::write(&out.join("network.ply"), &n.points())?;
        }
        if let Some(l) = &im.lidar {
            png(out, "lidar.png", l)?;
        }
    }
    if args.training_pairs {
        let pairs = out.join("pairs");
        std::fs::create_dir_all(&pairs)
            .map_err(|e| format!("{}: cannot create ({e})", pairs.display()))?;
        for (k, submap, truth) in depth::training_pairs(&args.bundle, &odometry, &options)? {
            let guide = cylinder::DepthImage {
                range_m: ip_basic::complete(&submap.range_m),
            };
            png(out, &format!("pairs/submap_{k:06}.png"), &submap)?;
            png(out, &format!("pairs/ip_basic_{k:06}.png"), &guide)?;
            png(out, &format!("pairs/lidar_{k:06}.png"), &truth)?;
        }
    }
    if args.json {
        return super::print_json(&report);
    }
    print!(
        "{}",
        Figures {
            report: &report,
            frames: odometry.frames.len(),
            out,
        }
    );
    Ok(())
}

/// Writes `img` as `out/name`, a 16-bit KITTI PNG.
fn png(
    out: &Path,
    name: &str,
    img: &cylinder::DepthImage,
) -> Result<(), metamoran_operator::OperatorError> {
    metamoran_operator::depth_image::write_png16(
        &out.join(name),
        cylinder::WIDTH as u32,
        cylinder::HEIGHT as u32,
        &img.kitti(),
    )
}

/// The map's figures as text.
struct Figures<'a> {
    report: &'a MapReport,
    frames: usize,
    out: &'a Path,
}

impl fmt::Display for Figures<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = self.report;
        writeln!(
            f,
            "ego-velocity error {} m/s over {} frames; density growth factor {} (submap), {} \
             (network)",
            figure(r.ego_velocity_error_mps, 3),
            self.frames,
            figure(r.density_growth_factor, 1),
            figure(r.network_density_growth_factor, 1)
        )?;
        if let (Some(m), Some(e), Some(p)) = (r.mae_m, r.rmse_m, r.point_accuracy_m) {
            writeln!(
                f,
                "depth image vs lidar   MAE m   RMSE m   point accuracy m   (MAE, RMSE over the pixels both fill)"
            )?;
            for (name, a, b, c) in [
                ("radar frame", m.frame, e.frame, p.frame),
                ("radar submap", m.submap, e.submap, p.submap),
                ("IP-Basic", m.ip_basic, e.ip_basic, p.ip_basic),
                ("3D-RadarHR", m.network, e.network, p.network),
            ] {
                writeln!(
                    f,
                    "{name:<20}  {:>6}   {:>6}   {:>6}",
                    figure(a, 2),
                    figure(b, 2),
                    figure(c, 2)
                )?;
            }
        }
        for (pixels, e) in [
            ("every lidar pixel (empty = 0 m)", r.lidar_pixels),
            ("the image's own pixels", r.own_pixels),
        ] {
            if let Some(e) = e {
                let m = e.mae_m;
                let s = e.rmse_m;
                writeln!(
                    f,
                    "MAE / RMSE m over {pixels}: frame {} / {}, submap {} / {}, IP-Basic {} / {}, \
                     3D-RadarHR {} / {}",
                    figure(m.frame, 2),
                    figure(s.frame, 2),
                    figure(m.submap, 2),
                    figure(s.submap, 2),
                    figure(m.ip_basic, 2),
                    figure(s.ip_basic, 2),
                    figure(m.network, 2),
                    figure(s.network, 2)
                )?;
            }
        }
        writeln!(
            f,
            "network {} Hz; images and point clouds in {}",
            figure(r.network_fps, 1),
            self.out.display()
        )
    }
}
