//! `metamoran demo-capture`: the built-in real TI capture summarized with the module's DSP.

use super::args::Locations;
use metamoran_bundle::RadarFile;
use metamoran_bundle::capture::parse_radar_config;
use metamoran_dsp::capture::IqOrder;
use metamoran_process::summary::summarize;
use std::path::Path;

/// The built-in demo capture: OpenRadar's two-target Doppler example, in the shared data.
const CAPTURE: &str = "data/real/openradar_doppler_example_1/adc_data.bin";
/// Its radar configuration (written for it; shipped in the binary).
const CONFIG: &str = include_str!("../../data/openradar_doppler_example_1.toml");

/// Summarize the built-in real TI capture (OpenRadar doppler_example_1) with the module's DSP.
#[derive(clap::Args, Debug)]
#[command(after_help = "Example:\n  metamoran demo-capture")]
pub struct Args {
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

/// Runs `metamoran demo-capture`.
///
/// # Errors
/// The shared data folder or the capture is missing.
pub fn run(args: &Args, locations: &Locations) -> super::Result {
    let capture = locations.shared()?.join(CAPTURE);
    if !capture.exists() {
        return Err(format!(
            "{}: the demo capture is missing; clone the repository beside shared/ or give --shared DIR",
            capture.display()
        )
        .into());
    }
    let config = parse_radar_config(Path::new("built-in demo config"), CONFIG)?;
    let mut file = RadarFile::open(&capture, config, IqOrder::Iiqq)?;
    if !args.json {
        println!(
            "Demo: OpenRadar doppler_example_1 (real IWR1642-class capture, 2 TX × 4 RX, 128 loops)\n"
        );
    }
    super::print(&summarize(&mut file)?, args.json)
}
