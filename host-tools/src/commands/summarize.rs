//! `metamoran summarize`: range-profile peaks and moving targets of a bundle or a bare capture.

use super::args::IqArg;
use metamoran_bundle::capture::open_bare;
use metamoran_bundle::{Bundle, OpenOptions, RadarFile};
use metamoran_dsp::capture::IqOrder;
use metamoran_process::summary::summarize;
use std::path::{Path, PathBuf};

/// Summarize a scene bundle or a bare DCA1000 capture: range-profile peaks and moving targets.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  metamoran summarize scenes/parking-lot-07\n  metamoran summarize adc_data.bin --config radar.toml --iq-order qqii --json"
)]
pub struct Args {
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
}

/// Runs `metamoran summarize`.
///
/// # Errors
/// A missing or bad capture, config or bundle.
pub fn run(args: &Args) -> super::Result {
    let mut file = open_capture(&args.path, args.config.as_deref(), args.iq_order.into())?;
    super::print(&summarize(&mut file)?, args.json)
}

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
