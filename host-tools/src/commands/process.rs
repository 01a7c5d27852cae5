//! `metamoran process`: each object of interest's depth in every frame of a bundle (cli.md).

use super::args::{BundleArgs, LinkArgs, Locations, ModeArg};
use metamoran_process::{ProcessOptions, ProcessOutput, Runner, process_streamed};
use std::fmt;
use std::path::PathBuf;

/// Where the module's share of `--mode metamoran` runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum EdgeArg {
    /// The `dsp` pipeline called in this process.
    InProcess,
    /// The firmware under QEMU, over the authenticated telemetry link.
    Qemu,
}

/// Estimate each object of interest's depth in every frame of a scene bundle (cli.md).
#[derive(clap::Args, Debug)]
#[command(
    mut_arg("dca1000", |a| a.help(
        "Take the radar samples from a live DCA1000 stream arriving at ADDR (this host's \
         address and data port) instead of the bundle's adc_file: the bundle's frame count of \
         frames of its [radar] table are recorded first; the camera products come from the \
         bundle; a frame that does not arrive whole is skipped and reported"
    )),
    after_help = "Examples:\n  metamoran process scenes/parking-lot-1-0000 --mode naive --json\n  metamoran process scenes/parking-lot-1-0000 --mode monocular --json\n  metamoran process scenes/parking-lot-1-0000 --mode metamoran --edge qemu --json\n  metamoran process site-07 --dca1000 192.168.33.30:4098 --json   (radar from the board, camera from the bundle)\n  metamoran process site-07 --segmenter seg.onnx --depth-model depth.onnx --json   (needs --features onnx)"
)]
pub struct Args {
    /// The bundle folder.
    bundle: PathBuf,
    /// Method.
    #[arg(long, value_enum, default_value = "metamoran")]
    mode: ModeArg,
    #[command(flatten)]
    read: BundleArgs,
    /// A live stream in place of the bundle's radar capture.
    #[command(flatten)]
    live: LinkArgs,
    /// Where the module's share of `--mode metamoran` runs: in this process, or the firmware
    /// under QEMU over the authenticated telemetry link (same JSON).
    #[arg(long, value_enum, default_value = "in-process")]
    edge: EdgeArg,
    /// The module's device key file for `--edge qemu` (from `metamoran provision`; the
    /// firmware is built with it). Default: the checkout's QEMU module key,
    /// firmware/target/qemu-link.key, provisioned on first use. Keys never go on the command
    /// line.
    #[arg(long, env = "METAMORAN_LINK_KEY_FILE", value_name = "FILE")]
    link_key_file: Option<PathBuf>,
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
    /// Print the JSON document (cli.md) instead of a table.
    #[arg(long)]
    json: bool,
}

/// Runs `metamoran process`.
///
/// # Errors
/// A bad bundle, model, key or output folder, or a module that cannot run.
pub fn run(args: &Args, locations: &Locations) -> super::Result {
    let mut open = args.read.options()?;
    let live = args.live.capture_for(&args.bundle)?;
    open.capture = live.as_ref().map(|l| l.capture.clone());
    let runner = match args.edge {
        EdgeArg::InProcess => Runner::InProcess,
        EdgeArg::Qemu => Runner::Qemu {
            firmware: locations.firmware()?,
            key_file: match &args.link_key_file {
                Some(path) => path.clone(),
                None => metamoran_edge::keys::checkout_key(&locations.firmware()?)?,
            },
        },
    };
    let options = ProcessOptions {
        mode: args.mode.into(),
        open,
        runner,
    };
    if let Some(dir) = &args.out {
        // Before any work: a folder that cannot be made fails the run while nothing is lost.
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("--out {}: cannot create the folder ({e})", dir.display()))?;
    }
    let (out, log) = process_streamed(&args.bundle, &options, |_| Ok(()))?;
    // The results first: if a product cannot be written, they are already out.
    if args.json {
        println!("{}", serde_json::to_string(&out)?);
    } else {
        print!("{}", Table(&out));
    }
    if let Some(path) = &args.edge_log {
        let bytes = log
            .map(|l| l.defmt)
            .ok_or("--edge-log: only the module under QEMU (--mode metamoran --edge qemu) logs")?;
        std::fs::write(path, bytes).map_err(|e| format!("--edge-log {}: {e}", path.display()))?;
    }
    if let Some(dir) = &args.out {
        let files =
            metamoran_operator::outputs::write_products(dir, &args.bundle, options.open, &out)?;
        eprintln!("wrote {} files to {}", files.len(), dir.display());
    }
    match out.faults() {
        Some(faults) => Err(format!(
            "{faults}\nthe other frames were processed and written; fix or drop the bad frames"
        )
        .into()),
        None => Ok(()),
    }
}

/// The estimates as lines of text, one object a line.
struct Table<'a>(&'a ProcessOutput);

impl fmt::Display for Table<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for frame in &self.0.frames {
            if let Some(e) = &frame.error {
                writeln!(f, "frame {} skipped: {e}", frame.frame)?;
            }
            for o in &frame.objects {
                let depth = o
                    .depth_m
                    .map_or("not detected".to_owned(), |d| format!("{d:.3} m"));
                let az = o
                    .azimuth_deg
                    .map_or(String::new(), |a| format!(" at {a:+.1}°"));
                writeln!(
                    f,
                    "frame {} {:<7} #{:<3} {depth}{az} ({} points)",
                    frame.frame,
                    o.class,
                    o.instance,
                    o.points.len()
                )?;
            }
        }
        Ok(())
    }
}
