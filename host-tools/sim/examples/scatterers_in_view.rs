//! How dense can a submap get? Counts the static scatterers of a mapping scene that the drive
//! radar sees at the last frame's pose (within its range and field of view, not hidden behind
//! another object: the echoes the signal model renders) and the depth-image pixels they fill
//! (320 × 80, nearest wins, as `metamoran map` projects points). A submap holds at most what
//! is there, so these pixels over a frame's filled pixels bound its density growth factor
//! (issue #21, part 2). It also prints how the echoes' amplitudes spread below the strongest:
//! what a detector with a given dynamic range can hope to find.
//!
//! ```sh
//! cargo run --release -p metamoran-sim --example scatterers_in_view -- drive 6500 3
//! ```
//!
//! Arguments: the preset (`drive`, `tunnel`, `parking-area` or `garage`), the run seed and the
//! number of scenes, as `metamoran simulate` takes them. Movers are left out, and so is what
//! they hide.

use metamoran_bundle::lidar::{HEIGHT, WIDTH, pixel};
use metamoran_sim::drive::{self, Environment, World};
use metamoran_sim::radar::{self, RadarKind};
use metamoran_sim::{DRIVE_ELEVATION_BEAM_DEG, signal};

/// Amplitude spreads below the strongest echo that are counted, dB.
const BELOW_DB: [f64; 4] = [10.0, 20.0, 30.0, 40.0];

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [preset, seed, count] = args.as_slice() else {
        return Err("usage: scatterers_in_view PRESET SEED COUNT".into());
    };
    let env = match preset.as_str() {
        "drive" => Environment::Street,
        "tunnel" => Environment::Tunnel,
        "parking-area" => Environment::ParkingArea,
        "garage" => Environment::Garage,
        other => return Err(format!("{other}: not a mapping preset")),
    };
    let number = |s: &str| s.parse::<u64>().map_err(|e| format!("{s}: {e}"));
    let (seed, count) = (number(seed)?, number(count)?);
    let (config, _) = radar::drive_config(RadarKind::Imaging);
    for index in 0..count {
        let (world, plan) = metamoran_sim::drive_world(env, seed, index);
        let statics = World {
            objects: (world.objects.into_iter())
                .filter(|o| o.velocity == [0.0; 2])
                .collect(),
            ..world
        };
        let poses = plan.poses(drive::FRAMES, drive::FRAME_PERIOD_S);
        let Some((pose, radar_v)) = poses.last() else {
            return Err("a drive without frames".into());
        };
        let t = (poses.len() - 1) as f64 * drive::FRAME_PERIOD_S;
        let (objects, surfaces) = statics.seen_from(t, pose, *radar_v);
        let all = [objects.as_slice(), &surfaces].concat();
        let echoes = signal::echoes(&all, &[], &config, DRIVE_ELEVATION_BEAM_DEG);
        let mut image = vec![0.0_f64; WIDTH * HEIGHT];
        let mut seen = Vec::new();
        for e in &echoes {
            let cos_az = (1.0 - e.sin_az * e.sin_az).sqrt();
            let tan_el = e.sin_el / (1.0 - e.sin_el * e.sin_el).sqrt();
            let p = [e.range * e.sin_az, -e.range * tan_el, e.range * cos_az];
            if let Some((row, col, range_m)) = pixel(p) {
                seen.push(e.amplitude);
                let px = &mut image[row * WIDTH + col];
                if *px == 0.0 || range_m < *px {
                    *px = range_m;
                }
            }
        }
        let filled = image.iter().filter(|&&r| r > 0.0).count();
        let strongest = seen.iter().copied().fold(0.0, f64::max);
        let spread: Vec<String> = BELOW_DB
            .iter()
            .map(|&db| {
                let floor = strongest * 10f64.powf(-db / 20.0);
                let n = seen.iter().filter(|&&a| a >= floor).count();
                format!("{n} within {db} dB")
            })
            .collect();
        println!(
            "{preset}-{seed}-{index:04}: {} static scatterers seen, filling {filled} pixels; {}",
            seen.len(),
            spread.join(", ")
        );
    }
    Ok(())
}
