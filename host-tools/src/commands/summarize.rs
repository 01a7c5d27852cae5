//! `metamoran summarize`: range-profile peaks and moving targets of a bundle or a bare capture.

use super::args::{BoardArg, IqArg};
use metamoran_bundle::capture::open_bare;
use metamoran_bundle::{Bundle, OpenOptions, RadarFile};
use metamoran_dsp::capture::IqOrder;
use metamoran_process::summary::summarize;
use std::path::{Path, PathBuf};

/// Summarize a scene bundle or a bare DCA1000 capture: range-profile peaks and moving targets.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  metamoran summarize scenes/parking-lot-07\n  metamoran summarize adc_data.bin --config radar.toml --iq-order qqii --json\n  metamoran summarize adc_data.bin --config xwr18xx_profile.cfg --board xwr18xx-boost"
)]
pub struct Args {
    /// A bundle folder (with scene.toml) or a DCA1000 .bin file (none with --dca1000).
    #[arg(required_unless_present = "dca1000")]
    path: Option<PathBuf>,
    /// Summarize a live DCA1000 stream instead: this host's address and data port the board
    /// sends to (the frames are recorded to a temporary file first; needs --config).
    #[arg(
        long,
        value_name = "ADDR",
        requires = "config",
        conflicts_with = "path"
    )]
    dca1000: Option<std::net::SocketAddr>,
    /// With --dca1000: frames to take.
    #[arg(long, requires = "dca1000")]
    frames: Option<u64>,
    /// Radar config of a bare .bin: a TOML `[radar]` table as in scene.toml, an mmWave SDK .cfg
    /// or an mmWave Studio .mmwave.json.
    #[arg(long)]
    config: Option<PathBuf>,
    /// The TI board a .cfg or .mmwave.json configures (its antenna layout).
    #[arg(long, value_enum)]
    board: Option<BoardArg>,
    /// I/Q order of the samples [default: what a TI config sets, else iiqq].
    #[arg(long, value_enum)]
    iq_order: Option<IqArg>,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

/// Runs `metamoran summarize`.
///
/// # Errors
/// A missing or bad capture, config or bundle.
pub fn run(args: &Args) -> super::Result {
    let order = args.iq_order.map(IqOrder::from);
    // A live stream is recorded first, through `record`'s code.
    let live = match (args.dca1000, &args.config) {
        (Some(addr), Some(config)) => {
            let stream = super::record::StreamArgs {
                dca1000: addr,
                config: config.clone(),
                board: args.board,
                from: None,
                control: false,
                frames: args.frames,
                start_s: 10.0,
                idle_s: 1.0,
            };
            let mut tmp = tempfile::NamedTempFile::new()?;
            // Frames that are not whole are left out: they are never processed as frames.
            let skip = metamoran_dca1000::record::Incomplete::Skip;
            let rec = stream.record(&mut std::io::BufWriter::new(tmp.as_file_mut()), skip)?;
            eprint!("{}", super::record::Report::new(tmp.path(), &rec));
            if rec.bytes == 0 {
                return Err(format!("no whole frame arrived on {addr}").into());
            }
            Some(tmp)
        }
        _ => None,
    };
    let path = live.as_ref().map_or_else(
        || args.path.clone().unwrap_or_default(),
        |t| t.path().to_owned(),
    );
    let mut file = open_capture(&path, args.config.as_deref(), order, args.board)?;
    if let Some((have, frame)) = file.loops_of_frame() {
        eprintln!(
            "note: {} holds {have} of a frame's {frame} loops (a capture cut short); read as one frame of {have}",
            path.display()
        );
    }
    super::print(&summarize(&mut file)?, args.json)
}

/// Opens a bare capture (with `config`) or the radar file of a bundle folder (checking the bundle).
fn open_capture(
    path: &Path,
    config: Option<&Path>,
    order: Option<IqOrder>,
    board: Option<BoardArg>,
) -> Result<RadarFile, String> {
    if !path.exists() {
        return Err(format!(
            "{}: no such file or folder; give a bundle folder or a DCA1000 .bin",
            path.display()
        ));
    }
    match config {
        Some(cfg) => open_bare(path, cfg, order, board.map(Into::into)).map_err(|e| e.to_string()),
        None if path.is_dir() => {
            let order = order.unwrap_or_default();
            let bundle = Bundle::open(path, OpenOptions::iq(order)).map_err(|e| e.to_string())?;
            RadarFile::open_layout(
                &bundle.scene.adc_file,
                bundle.scene.radar.clone(),
                order,
                bundle.scene.layout,
            )
            .map_err(|e| e.to_string())
        }
        None => Err(format!(
            "{}: a bare capture needs its radar config: add --config radar.toml (a [radar] table as in scene.toml), an mmWave SDK .cfg or an mmWave Studio .mmwave.json",
            path.display()
        )),
    }
}
