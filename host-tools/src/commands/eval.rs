//! `metamoran eval`: methods against the truth on every bundle of a folder.

use super::args::ModeArg;
use std::path::PathBuf;

/// Evaluate methods on every bundle in a folder against its truth (Table-I-like report).
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Example:\n  metamoran simulate --preset parking-lot --seed 11 --out eval --count 60\n  metamoran eval eval --modes naive,monocular"
)]
pub struct Args {
    /// Folder of bundle folders.
    dir: PathBuf,
    /// Methods to evaluate.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "naive,monocular"
    )]
    modes: Vec<ModeArg>,
    /// Print JSON instead of tables.
    #[arg(long)]
    json: bool,
    /// Also write every object's sample (error, confidence, the trust test's evidence) to this
    /// JSON file (its folder is created): the input of `scripts/calibrate-trust.py`.
    #[arg(long, value_name = "FILE")]
    samples: Option<PathBuf>,
}

/// Runs `metamoran eval`.
///
/// # Errors
/// No bundle in the folder, or bundles that failed (listed in the report).
pub fn run(args: &Args) -> super::Result {
    let modes: Vec<_> = args.modes.iter().map(|&m| m.into()).collect();
    let bundles = metamoran_process::eval::bundles_in(&args.dir)?.len() as u64;
    let bar = super::progress::bar(bundles, "bundles", !args.json);
    bar.set_message("evaluating");
    let (report, samples) = metamoran_process::eval::run(&args.dir, &modes, &|| bar.inc(1))?;
    bar.finish_and_clear();
    if let Some(path) = &args.samples {
        let text = serde_json::to_string(&samples)?;
        let cannot =
            |e: std::io::Error| format!("cannot write the samples to {}: {e}", path.display());
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(cannot)?;
        }
        std::fs::write(path, text).map_err(cannot)?;
    }
    super::print(&report, args.json)?;
    if report.failed.is_empty() {
        Ok(())
    } else {
        Err(format!("{} bundle(s) failed; see above", report.failed.len()).into())
    }
}
