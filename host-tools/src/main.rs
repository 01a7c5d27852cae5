//! `metamoran`: the command-line front of the host tools.

use clap::{Parser, Subcommand, ValueEnum};
use dsp::capture::IqOrder;
use host_tools::bundle::{Bundle, OpenOptions, RadarFile};
use host_tools::capture::{open_bare, parse_radar_config};
use host_tools::summary::summarize;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Metamoran: mmWave radar + camera depth imaging.
#[derive(Parser)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Camera models that compute a bundle's products from `camera/F_image.png`.
#[derive(clap::Args, Debug)]
struct ModelArgs {
    /// ONNX semantic segmenter: input [1,3,H,W] RGB 0..1, output [1,C,H,W] class scores,
    /// labels in its metadata 'labels' or MODEL.labels; replaces F_mask.png and
    /// F_instances.json (connected regions of each class). Needs a build with --features onnx.
    #[arg(long, value_name = "MODEL.onnx")]
    segmenter: Option<PathBuf>,
    /// ONNX monocular depth network: input [1,3,H,W] RGB 0..1, output [1,1,H,W] metres along
    /// z; replaces F_depth.png. Needs a build with --features onnx.
    #[arg(long, value_name = "MODEL.onnx")]
    depth_model: Option<PathBuf>,
}

impl ModelArgs {
    /// Bundle options with these models loaded.
    fn options(&self, iq_order: IqOrder) -> Result<OpenOptions, String> {
        Ok(OpenOptions {
            iq_order,
            camera_models: host_tools::bundle::CameraModels::load(
                self.segmenter.as_deref(),
                self.depth_model.as_deref(),
            )?,
        })
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum IqArg {
    /// I[2k], I[2k+1], Q[2k], Q[2k+1] (the bundle format's order)
    Iiqq,
    /// Q[2k], Q[2k+1], I[2k], I[2k+1] (devices with adcbufCfg sample swap)
    Qqii,
}

impl From<IqArg> for IqOrder {
    fn from(a: IqArg) -> Self {
        match a {
            IqArg::Iiqq => IqOrder::Iiqq,
            IqArg::Qqii => IqOrder::Qqii,
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Summarize a scene bundle or a bare DCA1000 capture: range-profile peaks and moving targets.
    ///
    /// Example: metamoran summarize capture.bin --config radar.toml
    #[command(
        after_help = "Examples:\n  metamoran summarize scenes/parking-lot-07\n  metamoran summarize adc_data.bin --config radar.toml --iq-order qqii --json"
    )]
    Summarize {
        /// A bundle folder (with scene.toml) or a DCA1000 .bin file.
        path: PathBuf,
        /// Radar config TOML (a `[radar]` table as in scene.toml) for a bare .bin.
        #[arg(long)]
        config: Option<PathBuf>,
        /// I/Q order of the samples.
        #[arg(long, value_enum, default_value = "iiqq")]
        iq_order: IqArg,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Estimate each object of interest's depth in every frame of a scene bundle (cli.md).
    #[command(
        after_help = "Examples:\n  metamoran process scenes/parking-lot-1-0000 --mode naive --json\n  metamoran process scenes/parking-lot-1-0000 --mode monocular --json\n  metamoran process scenes/parking-lot-1-0000 --mode metamoran --edge qemu --json\n  metamoran process site-07 --segmenter seg.onnx --depth-model depth.onnx --json   (needs --features onnx)"
    )]
    Process {
        /// The bundle folder.
        bundle: PathBuf,
        /// Method.
        #[arg(long, value_enum, default_value = "metamoran")]
        mode: host_tools::process::Mode,
        /// I/Q order of radar.bin.
        #[arg(long, value_enum, default_value = "iiqq")]
        iq_order: IqArg,
        /// Where the module's share of `--mode metamoran` runs: in this process, or the firmware
        /// under QEMU over the authenticated telemetry link (same JSON).
        #[arg(long, value_enum, default_value = "in-process")]
        edge: host_tools::process::EdgeKind,
        /// Link key for `--edge qemu`: 64 hex digits (default: the development key the firmware
        /// is built with unless METAMORAN_LINK_KEY was set at its build).
        #[arg(long, env = "METAMORAN_LINK_KEY", hide_env_values = true)]
        link_key: Option<String>,
        /// With `--edge qemu`: write the module's defmt log (binary frames) to this file; read it
        /// with `defmt-print -e firmware/target/thumbv7em-none-eabihf/release/edge < FILE`.
        #[arg(long, value_name = "FILE")]
        edge_log: Option<PathBuf>,
        /// Also write the engineer's products into this folder: results.json, per frame the
        /// fused depth image (depth_F.png, 16-bit KITTI: m × 256, 0 = none) and point cloud
        /// (points_F.ply), and with --mode metamoran the range–azimuth maps before/after SIC
        /// and P(d) plots per object (as `inspect`).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        #[command(flatten)]
        models: ModelArgs,
        /// Print the JSON document (cli.md) instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Plots of what the radar saw for each object of one frame: the range–azimuth map before
    /// and after SIC (span, cancelled reflectors and chosen depth marked) and the score P(d).
    #[command(
        after_help = "Examples:\n  metamoran inspect demo-out/scene --out inspect-out\n  metamoran inspect scenes/parking-lot-1-0000 --frame 2 --json"
    )]
    Inspect {
        /// The bundle folder.
        bundle: PathBuf,
        /// Frame to inspect.
        #[arg(long, default_value_t = 0)]
        frame: u32,
        /// Output folder for the PNG plots.
        #[arg(long, default_value = "inspect-out")]
        out: PathBuf,
        /// I/Q order of radar.bin.
        #[arg(long, value_enum, default_value = "iiqq")]
        iq_order: IqArg,
        #[command(flatten)]
        models: ModelArgs,
        /// Print JSON instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// Doppler odometry of a moving-platform bundle (`simulate --preset drive`): per frame the
    /// radar's velocity by RANSAC over its point cloud, the vehicle's speed and yaw rate
    /// (Ackermann, radar 3.7 m ahead of the rear axle), and the error against the truth.
    #[command(
        after_help = "Example:\n  metamoran simulate --preset drive --seed 3 --count 1 --out drives\n  metamoran odometry drives/drive-3-0000"
    )]
    Odometry {
        /// The bundle folder.
        bundle: PathBuf,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Dense radar map of a moving-platform bundle (the second paper): odometry, the last
    /// frame's submap, its completion by IP-Basic and by the 3D-RadarHR network, each depth
    /// image's MAE/RMSE against the lidar truth, and the network's frame rate. Writes the depth
    /// images (16-bit KITTI PNG, 320 × 80: frame, submap, ip_basic, network, lidar) and point
    /// clouds (PLY: submap.ply, network.ply) into --out. The network needs a build with
    /// --features onnx.
    #[command(
        after_help = "Example:\n  cargo build --release -p metamoran --features onnx\n  metamoran simulate --preset drive --seed 3 --count 1 --out drives\n  metamoran map drives/drive-3-0000 --out drive-map --json"
    )]
    Map {
        /// The bundle folder.
        bundle: PathBuf,
        /// Output folder for the depth images and point clouds.
        #[arg(long, default_value = "map-out")]
        out: PathBuf,
        /// A 3D-RadarHR ONNX model (contract: vision crate docs) instead of the shipped one.
        #[arg(long, value_name = "MODEL.onnx")]
        model: Option<PathBuf>,
        /// Skip the network (its figures are null); works without the onnx feature.
        #[arg(long, conflicts_with = "model")]
        no_network: bool,
        /// Also write every frame's submap and lidar depth images as training pairs
        /// (OUT/pairs/submap_FFFFFF.png, OUT/pairs/lidar_FFFFFF.png) for train/radarhr.py.
        #[arg(long)]
        training_pairs: bool,
        /// Print the figures as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Evaluate methods on every bundle in a folder against its truth (Table-I-like report).
    #[command(
        after_help = "Example:\n  metamoran simulate --preset parking-lot --seed 11 --out eval --count 60\n  metamoran eval eval --modes naive,monocular"
    )]
    Eval {
        /// Folder of bundle folders.
        dir: PathBuf,
        /// Methods to evaluate.
        #[arg(
            long,
            value_enum,
            value_delimiter = ',',
            default_value = "naive,monocular"
        )]
        modes: Vec<host_tools::process::Mode>,
        /// Print JSON instead of tables.
        #[arg(long)]
        json: bool,
    },
    /// Simulate scene bundles (bundle.md): FMCW radar samples, camera mask and monocular depth, truth.
    #[command(
        after_help = "Examples:\n  metamoran simulate --preset parking-lot --seed 1 --out scenes --count 60\n  metamoran simulate --preset moving --radar xwr18xx --seed 7 --out scenes\n  metamoran simulate --preset perimeter --count 1 --out scenes   (22 frames, the demo's scene)\n  metamoran simulate --preset drive --seed 3 --count 2 --out drives   (moving platform, elevation, lidar truth)"
    )]
    Simulate {
        /// Scene preset.
        #[arg(long, value_enum)]
        preset: host_tools::sim::layout::Preset,
        /// Run seed (the same seed gives the same scenes).
        #[arg(long)]
        seed: u64,
        /// Output folder; scenes go to OUT/<preset>-<seed>-<index>.
        #[arg(long)]
        out: PathBuf,
        /// Number of scenes.
        #[arg(long, default_value_t = 1)]
        count: u64,
        /// Simulated radar board.
        #[arg(long, value_enum, default_value = "cascade")]
        radar: host_tools::sim::radar::RadarKind,
    },
    /// The whole system on a built-in scene, no hardware: simulated radar frames into the module
    /// (firmware under QEMU, or in-process where QEMU is absent), telemetry back, camera fusion,
    /// perimeter alerts, operator view; outputs in one folder.
    #[command(
        after_help = "Examples:\n  metamoran demo\n  metamoran demo --out /tmp/demo --edge in-process\n  metamoran demo --perimeter site.toml --json\n  metamoran demo --mqtt localhost:1883 --sensor gate-east\n  metamoran demo --no-live > operator.txt"
    )]
    Demo {
        /// Output folder (results.json, depth_0.png, points_0.ply, alerts.jsonl, operator.txt, …).
        #[arg(long, default_value = "demo-out")]
        out: PathBuf,
        /// Where the module runs.
        #[arg(long, value_enum, default_value = "auto")]
        edge: host_tools::demo::DemoEdge,
        /// Perimeter TOML (zones, restricted classes, confidence, hysteresis); default: built in.
        #[arg(long)]
        perimeter: Option<PathBuf>,
        /// Also publish to this MQTT broker (HOST:PORT): objects at QoS 0, alerts at QoS 1,
        /// retained status with a last will, under metamoran/<sensor>/.
        #[arg(long, value_name = "HOST:PORT")]
        mqtt: Option<String>,
        /// Sensor id for the MQTT topics and client id.
        #[arg(long, default_value = "demo")]
        sensor: String,
        /// Print JSON instead of the operator view.
        #[arg(long)]
        json: bool,
        /// No live terminal view while frames arrive (it is on when stdout is a terminal and
        /// --json is not given); the final operator view is printed either way.
        #[arg(long)]
        no_live: bool,
    },
    /// Summarize the built-in real TI capture (OpenRadar doppler_example_1) with the module's DSP.
    #[command(
        name = "demo-capture",
        after_help = "Example:\n  metamoran demo-capture"
    )]
    DemoCapture {
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Benchmarks, reported as ratios against baselines measured in the same run.
    Bench {
        #[command(subcommand)]
        what: BenchCommand,
    },
}

#[derive(Subcommand)]
enum BenchCommand {
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
    },
    /// Depth search on a cascade-86, 512-sample frame: coarse-to-fine vs brute force (MACs, time).
    #[command(after_help = "Example:\n  metamoran bench search --json")]
    Search {
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// The module's budgets on the release firmware: flash, RAM, stack, instructions per
    /// cascade-86 frame with 4 objects under QEMU -icount, telemetry bytes.
    #[command(after_help = "Example:\n  metamoran bench m7 --json")]
    M7 {
        /// Print JSON.
        #[arg(long)]
        json: bool,
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

/// The built-in demo capture: OpenRadar's two-target Doppler example, with its config.
const DEMO_CAPTURE: &str = "data/real/openradar_doppler_example_1/adc_data.bin";
const DEMO_CONFIG: &str = include_str!("../../tests/data/real/openradar_doppler_example_1.toml");

/// Opens a bare capture (with `config`) or the radar file of a bundle folder (checking the bundle).
fn open_capture(path: &Path, config: Option<&Path>, order: IqOrder) -> Result<RadarFile, String> {
    if !path.exists() {
        return Err(format!(
            "{}: no such file or folder; give a bundle folder or a DCA1000 .bin",
            path.display()
        ));
    }
    match config {
        Some(cfg) => open_bare(path, cfg, order).map_err(|e| e.to_string()),
        None if path.is_dir() => {
            let bundle = Bundle::open(path, OpenOptions::iq(order)).map_err(|e| e.to_string())?;
            RadarFile::open(&bundle.scene.adc_file, bundle.scene.radar.clone(), order)
                .map_err(|e| e.to_string())
        }
        None => Err(format!(
            "{}: a bare capture needs its radar config: add --config radar.toml (a [radar] table as in scene.toml)",
            path.display()
        )),
    }
}

fn print<T: serde::Serialize + std::fmt::Display>(value: &T, json: bool) -> Result<(), String> {
    if json {
        print_json(value)
    } else {
        print!("{value}");
        Ok(())
    }
}

fn print_json<T: serde::Serialize>(value: &T) -> Result<(), String> {
    println!(
        "{}",
        serde_json::to_string_pretty(value).map_err(|e| e.to_string())?
    );
    Ok(())
}

/// `x` with `decimals`, or "—".
fn figure(x: Option<f64>, decimals: usize) -> String {
    x.map_or("—".to_owned(), |x| format!("{x:.decimals$}"))
}

/// `metamoran map`: see the command's help.
fn map(
    bundle: &std::path::Path,
    out: &std::path::Path,
    model: Option<&std::path::Path>,
    no_network: bool,
    training_pairs: bool,
    json: bool,
) -> Result<(), String> {
    use host_tools::map::{cylinder, depth, lidar, network::Network, report};
    let network = (!no_network).then(|| Network::load(model)).transpose()?;
    let complete = network.as_ref().map(|n| move |r: &[f32]| n.complete(r));
    let (report, odometry, images) = report::run(
        bundle,
        &host_tools::sim::drive::MOUNT,
        complete.as_ref().map(|c| c as depth::Completion),
    )?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: cannot create ({e})", out.display()))?;
    let png = |name: &str, img: &cylinder::DepthImage| {
        host_tools::depth_image::write_png16(
            &out.join(name),
            cylinder::WIDTH as u32,
            cylinder::HEIGHT as u32,
            &img.kitti(),
        )
    };
    if let Some(im) = &images {
        png("frame.png", &im.frame)?;
        png("submap.png", &im.submap)?;
        png("ip_basic.png", &im.ip_basic)?;
        lidar::write(&out.join("submap.ply"), &im.submap_points)?;
        if let Some(n) = &im.network {
            png("network.png", n)?;
            lidar::write(&out.join("network.ply"), &n.points())?;
        }
        if let Some(l) = &im.lidar {
            png("lidar.png", l)?;
        }
    }
    if training_pairs {
        let pairs = out.join("pairs");
        std::fs::create_dir_all(&pairs)
            .map_err(|e| format!("{}: cannot create ({e})", pairs.display()))?;
        for (k, submap, truth) in depth::training_pairs(bundle, &odometry)? {
            png(&format!("pairs/submap_{k:06}.png"), &submap)?;
            png(&format!("pairs/lidar_{k:06}.png"), &truth)?;
        }
    }
    if json {
        return print_json(&report);
    }
    println!(
        "ego-velocity error {} m/s over {} frames; density growth factor {}",
        figure(report.ego_velocity_error_mps, 3),
        odometry.frames.len(),
        figure(report.density_growth_factor, 1)
    );
    if let (Some(m), Some(r)) = (report.mae_m, report.rmse_m) {
        println!("depth image vs lidar   MAE m   RMSE m");
        for (name, a, b) in [
            ("radar frame", m.frame, r.frame),
            ("radar submap", m.submap, r.submap),
            ("IP-Basic", m.ip_basic, r.ip_basic),
            ("3D-RadarHR", m.network, r.network),
        ] {
            println!("{name:<20}  {:>6}   {:>6}", figure(a, 2), figure(b, 2));
        }
    }
    println!(
        "network {} Hz; images and point clouds in {}",
        figure(report.network_fps, 1),
        out.display()
    );
    Ok(())
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        Command::Summarize {
            path,
            config,
            iq_order,
            json,
        } => {
            let mut file = open_capture(&path, config.as_deref(), iq_order.into())?;
            print(&summarize(&mut file).map_err(|e| e.to_string())?, json)
        }
        Command::Process {
            bundle,
            mode,
            iq_order,
            edge,
            link_key,
            edge_log,
            out: products,
            models,
            json,
        } => {
            let options = models.options(iq_order.into())?;
            let key = match link_key {
                Some(hex) => {
                    dsp::wire::Key::from_hex(&hex).map_err(|e| format!("--link-key: {e}"))?
                }
                None => dsp::wire::Key::new(&dsp::wire::DEV_KEY),
            };
            let (out, log) =
                host_tools::process::process_logged(&bundle, mode, options.clone(), edge, key)?;
            if let Some(path) = edge_log {
                let bytes = log.map(|l| l.defmt).ok_or(
                    "--edge-log: only the module under QEMU (--mode metamoran --edge qemu) logs",
                )?;
                std::fs::write(&path, bytes)
                    .map_err(|e| format!("--edge-log {}: {e}", path.display()))?;
            }
            if let Some(dir) = products {
                let files = host_tools::process::write_products(&dir, &bundle, options, &out)?;
                eprintln!("wrote {} files to {}", files.len(), dir.display());
            }
            if json {
                println!(
                    "{}",
                    serde_json::to_string(&out).map_err(|e| e.to_string())?
                );
            } else {
                for f in &out.frames {
                    for o in &f.objects {
                        let depth = o
                            .depth_m
                            .map_or("not detected".to_owned(), |d| format!("{d:.3} m"));
                        let az = o
                            .azimuth_deg
                            .map_or(String::new(), |a| format!(" at {a:+.1}°"));
                        println!(
                            "frame {} {:<7} #{:<3} {depth}{az} ({} points)",
                            f.frame,
                            o.class,
                            o.instance,
                            o.points.len()
                        );
                    }
                }
            }
            Ok(())
        }
        Command::Inspect {
            bundle,
            frame,
            out,
            iq_order,
            models,
            json,
        } => print(
            &host_tools::inspect::run(&bundle, frame, &out, models.options(iq_order.into())?)?,
            json,
        ),
        Command::Odometry { bundle, json } => {
            let o = host_tools::map::odometry::run(&bundle, &host_tools::sim::drive::MOUNT)?;
            if json {
                return print_json(&o);
            }
            println!(
                "frame  points  static  v_x m/s  v_z m/s  speed m/s  yaw rate rad/s  error m/s"
            );
            for f in &o.frames {
                println!(
                    "{:>5}  {:>6}  {:>6}  {:>7}  {:>7}  {:>9}  {:>14}  {:>9}",
                    f.frame,
                    f.points,
                    f.inliers,
                    figure(f.velocity_mps.map(|v| v[0]), 3),
                    figure(f.velocity_mps.map(|v| v[1]), 3),
                    figure(f.speed_mps, 3),
                    figure(f.yaw_rate_rps, 3),
                    figure(f.error_mps, 3)
                );
            }
            println!(
                "mean ego-velocity error {} m/s; integrated position error at the last frame {} m",
                figure(o.ego_velocity_error_mps, 3),
                figure(o.final_position_error_m, 3)
            );
            Ok(())
        }
        Command::Map {
            bundle,
            out,
            model,
            no_network,
            training_pairs,
            json,
        } => map(
            &bundle,
            &out,
            model.as_deref(),
            no_network,
            training_pairs,
            json,
        ),
        Command::Eval { dir, modes, json } => {
            let (report, _) = host_tools::eval::run(&dir, &modes, !json)?;
            print(&report, json)?;
            if report.failed.is_empty() {
                Ok(())
            } else {
                Err(format!(
                    "{} bundle(s) failed; see above",
                    report.failed.len()
                ))
            }
        }
        Command::Simulate {
            preset,
            seed,
            out,
            count,
            radar,
        } => {
            let dirs = host_tools::sim::simulate(preset, radar, seed, count, &out, true)?;
            eprintln!("wrote {} bundle(s) to {}", dirs.len(), out.display());
            Ok(())
        }
        Command::Demo {
            out,
            edge,
            perimeter,
            mqtt,
            sensor,
            json,
            no_live,
        } => {
            let mqtt = mqtt
                .map(|b| host_tools::mqtt::MqttConfig::parse(&b, &sensor))
                .transpose()?;
            let live = !json && !no_live && std::io::IsTerminal::is_terminal(&std::io::stdout());
            print(
                &host_tools::demo::run(&out, edge, perimeter.as_deref(), mqtt.as_ref(), live)?,
                json,
            )
        }
        Command::DemoCapture { json } => {
            let capture = host_tools::shared_dir().join(DEMO_CAPTURE);
            if !capture.exists() {
                return Err(format!(
                    "{}: the demo capture is missing; clone the repository beside shared/ or set METAMORAN_SHARED",
                    capture.display()
                ));
            }
            let config = parse_radar_config(Path::new("built-in demo config"), DEMO_CONFIG)
                .map_err(|e| e.to_string())?;
            let mut file =
                RadarFile::open(&capture, config, IqOrder::Iiqq).map_err(|e| e.to_string())?;
            if !json {
                println!(
                    "Demo: OpenRadar doppler_example_1 (real IWR1642-class capture, 2 TX × 4 RX, 128 loops)\n"
                );
            }
            print(&summarize(&mut file).map_err(|e| e.to_string())?, json)
        }
        Command::Bench {
            what: BenchCommand::Fft { json, sizes },
        } => {
            if let Some(&bad) = sizes.iter().find(|&&n| !dsp::fft::is_supported_len(n)) {
                return Err(format!("--sizes {bad}: use powers of two from 16 to 2048"));
            }
            print(&host_tools::bench::fft::run(&sizes, true), json)
        }
        Command::Bench {
            what: BenchCommand::M7 { json },
        } => print(&host_tools::bench::budget::run()?, json),
        Command::Bench {
            what: BenchCommand::FftM7 { json },
        } => print(&host_tools::bench::m7::run()?, json),
        Command::Bench {
            what: BenchCommand::Search { json },
        } => print(&host_tools::bench::search::run()?, json),
        Command::Bench {
            what: BenchCommand::Network { json },
        } => print(&host_tools::bench::network::run()?, json),
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
