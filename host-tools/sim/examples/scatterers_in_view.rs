//! How dense can a submap get? Counts the static scatterers of a mapping scene that lie within
//! the drive radar's range at the last frame's pose, and the depth-image pixels they fill
//! (320 × 80, nearest wins, as `metamoran map` projects points). A submap holds at most what
//! is there, so these pixels over a frame's filled pixels bound its density growth factor
//! (issue #21, part 2), before occlusion lowers it further.
//!
//! ```sh
//! cargo run --release -p metamoran-sim --example scatterers_in_view -- drive 6500 3
//! ```
//!
//! Arguments: the preset (`drive`, `tunnel`, `parking-area` or `garage`), the run seed and the
//! number of scenes, as `metamoran simulate` takes them.

use metamoran_bundle::lidar::{HEIGHT, WIDTH, pixel};
use metamoran_sim::drive::{self, Environment};
use metamoran_sim::radar::{self, RadarKind};

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
    let max_range_m = radar::drive_config(RadarKind::Imaging).0.max_range_m();
    for index in 0..count {
        let (world, plan) = metamoran_sim::drive_world(env, seed, index);
        let poses = plan.poses(drive::FRAMES, drive::FRAME_PERIOD_S);
        let Some((pose, _)) = poses.last() else {
            return Err("a drive without frames".into());
        };
        let statics = world
            .objects
            .iter()
            .filter(|o| o.velocity == [0.0; 2])
            .flat_map(|o| &o.scatterers)
            .chain(&world.ground)
            .chain(world.ceiling.iter().flat_map(|(_, c)| c));
        let mut image = vec![0.0_f64; WIDTH * HEIGHT];
        let mut in_view = 0;
        for s in statics {
            let [x, z] = pose.to_radar([s.position.x, s.position.z]);
            let p = [x, s.position.y, z];
            if p.iter().map(|v| v * v).sum::<f64>().sqrt() > max_range_m {
                continue;
            }
            if let Some((row, col, range_m)) = pixel(p) {
                in_view += 1;
                let px = &mut image[row * WIDTH + col];
                if *px == 0.0 || range_m < *px {
                    *px = range_m;
                }
            }
        }
        let filled = image.iter().filter(|&&r| r > 0.0).count();
        println!(
            "{preset}-{seed}-{index:04}: {in_view} static scatterers within {max_range_m:.1} m \
             in view, filling {filled} pixels"
        );
    }
    Ok(())
}
