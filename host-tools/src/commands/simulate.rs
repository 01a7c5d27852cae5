//! `metamoran simulate`: scene bundles from the simulator.

use super::args::{PresetArg, RadarArg};
use std::path::PathBuf;

/// Simulate scene bundles (bundle.md): FMCW radar samples, camera mask and monocular depth, truth.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  metamoran simulate --preset parking-lot --seed 1 --out scenes --count 60\n  metamoran simulate --preset moving --radar xwr18xx --seed 7 --out scenes\n  metamoran simulate --preset parking-lot --radar xwr18xx --hard --seed 9 --out hard\n  metamoran simulate --preset perimeter --count 1 --out scenes   (22 frames, the demo's scene)\n  metamoran simulate --preset drive --seed 3 --count 2 --out drives   (moving platform, elevation, lidar truth)\n  metamoran simulate --preset drive --radar imaging --seed 3 --out drives   (the same street seen by the 4D imaging board)\n  metamoran simulate --preset tunnel --radar imaging --seed 1 --out drives   (also: parking-area, garage)\n  metamoran simulate --preset corner --board 5 --seed 1 --out cal   (a calibration capture of board 5)\n  metamoran simulate --preset crossing --renumber-instances --seed 2 --out scenes   (tracking: instance ids renumbered every frame)\n  metamoran simulate --preset site --seed 1 --out sites   (three poles, one site: site-1/site.toml and a bundle per pole)"
)]
pub struct Args {
    /// Scene preset.
    #[arg(long, value_enum)]
    preset: PresetArg,
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
    radar: RadarArg,
    /// Harder scenes (issue #17): monocular error growing past 50 m at Table I's slope, masks
    /// off by up to two pixels, strong clutter inside an 8-element beam at other ranges, movers
    /// to 35 m/s. Scenes go to OUT/<preset>-hard-<seed>-<index>; the same seed without it still
    /// gives the standard scenes.
    #[arg(long)]
    hard: bool,
    /// A seeded imperfect board (issue #19): each (TX, RX) channel gets a phase uniform in
    /// ±180°, a gain in ±3 dB and a delay in ±0.5 range bin, the same for every scene of the
    /// same board. Scenes go to OUT/<preset>-board<B>-<seed>-<index>.
    #[arg(long, value_name = "B")]
    board: Option<u64>,
    /// Number the camera's instances afresh every frame, as a real segmenter does (issue #20):
    /// the same scene with its mask and instances.json ids permuted per frame; truth.json keeps
    /// each object's identity as `object`. Scenes go to OUT/<preset>-renumbered-<seed>-<index>.
    #[arg(long)]
    renumber_instances: bool,
}

/// Runs `metamoran simulate`.
///
/// # Errors
/// A scene that could not be written.
pub fn run(args: &Args) -> super::Result {
    let Some(preset) = args.preset.scene() else {
        return site(args);
    };
    if args.radar == RadarArg::Imaging && preset.environment().is_none() {
        return Err(
            "--radar imaging is the mapping presets' 4D board (--preset drive, tunnel, \
             parking-area or garage); the depth presets run on cascade, mmwcas or xwr18xx"
                .into(),
        );
    }
    let bar = super::progress::bar(args.count, "scenes", true);
    bar.set_message(format!("simulating {}", preset.name()));
    let difficulty = if args.hard {
        metamoran_sim::Difficulty::Hard
    } else {
        metamoran_sim::Difficulty::Standard
    };
    let variant = metamoran_sim::Variant {
        difficulty,
        board: args.board,
        renumber: args.renumber_instances,
    };
    let dirs = metamoran_sim::simulate_with(
        preset,
        args.radar.into(),
        variant,
        args.seed,
        args.count,
        &args.out,
        &|| bar.inc(1),
    )?;
    bar.finish();
    eprintln!("wrote {} bundle(s) to {}", dirs.len(), args.out.display());
    Ok(())
}

/// `--preset site`: the three poles' bundles and the site file.
fn site(args: &Args) -> super::Result {
    let kind: metamoran_sim::radar::RadarKind = args.radar.into();
    if kind == metamoran_sim::radar::RadarKind::Mmwcas
        || kind == metamoran_sim::radar::RadarKind::Imaging
        || args.hard
        || args.board.is_some()
        || args.renumber_instances
        || args.count != 1
    {
        return Err(
            "--preset site: one site per run (--count 1) on --radar cascade or \
                    xwr18xx, without --hard, --board or --renumber-instances"
                .into(),
        );
    }
    let dir = metamoran_sim::site::simulate_site(kind, args.seed, &args.out)?;
    eprintln!(
        "wrote {} ({} poles and site.toml)",
        dir.display(),
        metamoran_sim::site::POLES.len()
    );
    Ok(())
}
