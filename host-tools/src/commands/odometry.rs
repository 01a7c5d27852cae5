//! `metamoran odometry`: Doppler odometry of a moving-platform bundle.

use metamoran_map::odometry::Odometry;
use std::fmt;
use std::path::PathBuf;

/// Doppler odometry of a moving-platform bundle (`simulate --preset drive`): per frame the
/// radar's velocity by RANSAC over its point cloud, the vehicle's speed and yaw rate
/// (Ackermann, radar 3.7 m ahead of the rear axle), and the error against the truth.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Example:\n  metamoran simulate --preset drive --seed 3 --count 1 --out drives\n  metamoran odometry drives/drive-3-0000"
)]
pub struct Args {
    /// The bundle folder.
    bundle: PathBuf,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

/// Runs `metamoran odometry`.
///
/// # Errors
/// A bad bundle.
pub fn run(args: &Args) -> super::Result {
    let o = metamoran_map::odometry::run(&args.bundle, &metamoran_sim::drive::MOUNT)?;
    if args.json {
        super::print_json(&o)
    } else {
        print!("{}", Table(&o));
        Ok(())
    }
}

/// `x` with `decimals`, or "—".
pub fn figure(x: Option<f64>, decimals: usize) -> String {
    x.map_or("—".to_owned(), |x| format!("{x:.decimals$}"))
}

/// The odometry as a table, one frame a row.
struct Table<'a>(&'a Odometry);

impl fmt::Display for Table<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let o = self.0;
        writeln!(
            f,
            "frame  points  static  v_x m/s  v_z m/s  speed m/s  yaw rate rad/s  error m/s"
        )?;
        for r in &o.frames {
            writeln!(
                f,
                "{:>5}  {:>6}  {:>6}  {:>7}  {:>7}  {:>9}  {:>14}  {:>9}",
                r.frame,
                r.points,
                r.inliers,
                figure(r.velocity_mps.map(|v| v[0]), 3),
                figure(r.velocity_mps.map(|v| v[1]), 3),
                figure(r.speed_mps, 3),
                figure(r.yaw_rate_rps, 3),
                figure(r.error_mps, 3)
            )?;
        }
        writeln!(
            f,
            "mean ego-velocity error {} m/s; integrated position error at the last frame {} m",
            figure(o.ego_velocity_error_mps, 3),
            figure(o.final_position_error_m, 3)
        )
    }
}
