//! `metamoran calibrate`: per-channel gain and frequency corrections from a corner-reflector
//! capture, written as a calibration file a bundle names in `[radar] calibration_file`.

use super::args::CaptureArgs;
use metamoran_bundle::calibration::{CalibrationFile, ChannelId, TiCalibration};
use metamoran_bundle::ti::Board;
use metamoran_process::calibrate::{CalibrateOptions, ChannelMeans, calibrate};
use std::path::PathBuf;

/// Calibrate a board's channels from a corner reflector on boresight (TI's procedure): per
/// (TX, RX) pair, a complex gain relative to the reference channel and a frequency (range-delay)
/// correction.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "The calibrated sample n of channel (t, r) is (re + j·im) · exp(j·2π·f·n/N) · x[n], \
                  t indexing tx_positions, r rx_positions, N = adc_samples.\n\nExamples:\n  \
                  metamoran simulate --preset corner --board 5 --seed 1 --out cal\n  \
                  metamoran calibrate cal/corner-board5-1-0000 --out board5.toml\n  \
                  metamoran calibrate cal/corner-board5-2-0000 --check board5.toml   (another capture of the board)\n  \
                  metamoran calibrate adc_data.bin --config cascade.mmwave.json --board mmwcas-rf-evm --target-m 5 --out cal.toml --json\n  \
                  metamoran calibrate --import-ti calibrateResults_high.mat --config cascade.mmwave.json --board mmwcas-rf-evm --out cal.toml"
)]
pub struct Args {
    /// The calibration capture: a bundle folder or a DCA1000 .bin (with --config). A bundle's
    /// own calibration_file is ignored: the capture is read as recorded.
    #[arg(required_unless_present = "import_ti")]
    capture: Option<PathBuf>,
    /// Import TI's own calibration instead (`calibrateResults*.mat` from the cascade's
    /// calibration_cascade flow: calibResult.RangeMat, PeakValMat and params), for the board
    /// --config describes.
    #[arg(long, value_name = "MAT", conflicts_with_all = ["capture", "check"], requires = "config")]
    import_ti: Option<PathBuf>,
    /// With --import-ti: the range-FFT interpolation RangeMat was measured with (TI's
    /// calibrationInterp).
    #[arg(long, default_value_t = 5.0, requires = "import_ti")]
    interp: f64,
    /// The capture's config (with --import-ti: the board the calibration is for; --board
    /// defaults to mmwcas-rf-evm there).
    #[command(flatten)]
    capture_args: CaptureArgs,
    /// The calibration file to write (TOML).
    #[arg(long, required_unless_present = "check", conflicts_with = "check")]
    out: Option<PathBuf>,
    /// Measure instead how well an existing calibration file makes this capture's array
    /// coherent at its reflector (applied as every reader applies it).
    #[arg(long, value_name = "CAL")]
    check: Option<PathBuf>,
    /// Where the reflector stands, m: search within ±1 m [default: the strongest reflector
    /// beyond 1 m].
    #[arg(long, value_name = "M")]
    target_m: Option<f64>,
    /// The reference channel, as TX,RX (indices into tx_positions and rx_positions).
    #[arg(long, value_name = "TX,RX", default_value = "0,0", value_parser = parse_channel)]
    reference: ChannelId,
    /// Print the calibration as JSON (`{"reference", "target_range_m", "channels"}`) instead
    /// of the summary.
    #[arg(long)]
    json: bool,
}

fn parse_channel(s: &str) -> Result<ChannelId, String> {
    let (t, r) = s
        .split_once(',')
        .ok_or_else(|| format!("\"{s}\": give TX,RX, e.g. 0,0"))?;
    let index = |v: &str| {
        v.trim()
            .parse::<usize>()
            .map_err(|e| format!("\"{v}\" in \"{s}\": {e}"))
    };
    Ok(ChannelId {
        tx: index(t)?,
        rx: index(r)?,
    })
}

/// Runs `metamoran calibrate`.
///
/// # Errors
/// A bad capture or config, no reflector, or an output that cannot be written.
pub fn run(args: &Args) -> super::Result {
    let board = args.capture_args.board;
    if let (Some(mat), Some(config)) = (&args.import_ti, &args.capture_args.config) {
        let radar = metamoran_bundle::capture::read_config(config, board.map(Into::into))?.radar;
        let board = board.map_or(Board::MmwcasRfEvm, Into::into);
        let file = TiCalibration::read(mat)?.to_file(mat, &radar, board, args.interp)?;
        let out = args.out.as_ref().ok_or("give --out FILE")?;
        metamoran_operator::outputs::write(out, file.to_toml().as_bytes())?;
        if args.json {
            return super::print_json(&file.report());
        }
        println!(
            "imported {} channels from {} (reference tx {} rx {}); wrote {}",
            file.channels.len(),
            mat.display(),
            file.reference.tx,
            file.reference.rx,
            out.display()
        );
        return Ok(());
    }
    let capture = args.capture.as_deref().unwrap_or(std::path::Path::new(""));
    let mut file = args.capture_args.open(capture)?;
    let means = ChannelMeans::read(&mut file, true)?;
    if let Some(check) = &args.check {
        let cal = CalibrationFile::read(check)?;
        let config = file.config().clone();
        file.calibrate(&cal.for_config(check, &config)?);
        let bin = means.reflector_bin(args.target_m)? as f64;
        let calibrated = ChannelMeans::read(&mut file, false)?;
        let report = Check {
            range_m: f64::from(config.bin_to_range(bin as f32, config.adc_samples as usize)),
            before: means.coherence(bin, None),
            after: calibrated.coherence(bin, None),
        };
        return super::print(&report, args.json);
    }
    let Some(out) = &args.out else {
        return Err("give --out FILE (or --check CAL)".into());
    };
    let options = CalibrateOptions {
        reference: args.reference,
        target_m: args.target_m,
    };
    let measured = calibrate(&means, options)?;
    metamoran_operator::outputs::write(out, measured.file.to_toml().as_bytes())?;
    if args.json {
        super::print_json(&measured.file.report())
    } else {
        print!("{measured}");
        println!("wrote        {}", out.display());
        Ok(())
    }
}

/// `calibrate --check`: the array coherence at a capture's reflector without and with a
/// calibration.
#[derive(Debug, serde::Serialize)]
struct Check {
    /// The reflector's range bin centre, m.
    range_m: f64,
    /// Coherence as recorded.
    before: f64,
    /// Coherence with the calibration applied.
    after: f64,
}

impl std::fmt::Display for Check {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "coherence at {:.2} m: {:.3} as recorded → {:.3} calibrated (|Σ Y| / Σ |Y|, ±1 bin)",
            self.range_m, self.before, self.after
        )
    }
}
