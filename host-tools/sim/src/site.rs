//! The `site` preset (issue #20 part 2): one world on a site plan seen by three poles with
//! overlapping coverage, each a bundle of its own, and the site file that places them.
//!
//! The plan's frame: `x` east, `y` north, metres; a pole's heading is degrees clockwise from
//! north. A pole's radar frame (x right, z forward) is the plan moved to its position and turned
//! to its heading, so a pole at the origin facing north sees the plan as it is.

use crate::layout::site_world;
use crate::{Difficulty, SimError, film_frames, scene_seed, writer};
use metamoran_bundle::pose::Pose;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use std::path::{Path, PathBuf};

/// One pole of the site.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pole {
    /// Sensor id.
    pub id: &'static str,
    /// Position on the plan, `[x, y]`, m.
    pub position: [f64; 2],
    /// Boresight, degrees clockwise from north.
    pub heading_deg: f64,
}

impl Pole {
    /// The pose of the pole's radar on the plan (the plan's `y` is the pose's `z`).
    pub fn pose(&self) -> Pose {
        Pose {
            position: self.position,
            yaw: -self.heading_deg.to_radians(),
        }
    }
}

/// The three poles: two at the south edge looking in towards each other's coverage, one at the
/// north edge looking south; all three see the crossing near (0, 22).
pub const POLES: [Pole; 3] = [
    Pole {
        id: "pole-a",
        position: [-18.0, 0.0],
        heading_deg: 35.0,
    },
    Pole {
        id: "pole-b",
        position: [18.0, 0.0],
        heading_deg: -35.0,
    },
    Pole {
        id: "pole-c",
        position: [0.0, 48.0],
        heading_deg: 180.0,
    },
];

/// The site file the simulator writes beside the poles' bundles.
pub fn site_toml(name: &str) -> String {
    let mut t = format!(
        "# A site of three poles (metamoran simulate --preset site); see README, \"Site\".\n\
         name = \"{name}\"\n\
         extent = [[-40.0, -5.0], [40.0, 55.0]]   # plan corners [x, y], m\n\n"
    );
    for p in POLES {
        t.push_str(&format!(
            "[[sensor]]\nid = \"{}\"\nposition = [{:.1}, {:.1}]\nheading_deg = {:.1}\n\
             range_m = 50.0\nfov_deg = 60.0\n\n",
            p.id, p.position[0], p.position[1], p.heading_deg
        ));
    }
    t.push_str(
        "[perimeter]\nrestricted_classes = [\"person\", \"car\"]\nmin_confidence_db = 6.0\n\
         hysteresis_m = 1.0\n\n\
         [[perimeter.zone]]\nname = \"yard\"\n\
         polygon = [[-4.0, 17.0], [4.0, 17.0], [4.0, 27.0], [-4.0, 27.0]]\ndwell_s = 3.0\n",
    );
    t
}

/// Simulates the site with run seed `seed` into `out/site-<seed>/`: `site.toml` and one bundle
/// per pole (`pole-a/`, …), each with the pole's radar of `kind` and its camera. Returns the
/// site folder.
///
/// # Errors
/// [`SimError`] naming the file that could not be written.
pub fn simulate_site(
    kind: crate::radar::RadarKind,
    seed: u64,
    out: &Path,
) -> Result<PathBuf, SimError> {
    let dir = out.join(format!("site-{seed}"));
    let io = |path: &Path, e: std::io::Error| SimError::Write {
        path: path.to_owned(),
        source: e.into(),
    };
    std::fs::create_dir_all(&dir).map_err(|e| io(&dir, e))?;
    let mut world_rng = Pcg64Mcg::seed_from_u64(scene_seed(seed, 0));
    let world = site_world(&mut world_rng);
    for (k, pole) in POLES.iter().enumerate() {
        let mut rng = Pcg64Mcg::seed_from_u64(scene_seed(seed, 1 + k as u64));
        let mut config = crate::radar::config(kind, crate::radar::max_range_for(48.0), 2);
        config.frames = u32::from(world.frames);
        config.frame_period_s = world.frame_period_s;
        let ground = crate::ground(&mut rng, config.max_range() as f64);
        let pose = pole.pose();
        let view =
            |o: &crate::object::SceneObject| crate::drive::in_radar_frame(o, &pose, [0.0; 2]);
        let (adc, shots, frames) = film_frames(
            &config,
            (&world.objects, &world.paths),
            &view,
            (&ground, &[], None),
            Difficulty::Standard,
            &mut rng,
        );
        let bundle = dir.join(pole.id);
        writer::write(
            &bundle,
            &writer::BundleContents {
                name: pole.id,
                radar: &config,
                camera: &crate::camera_config(),
                adc: &adc,
                tx_elevation: &[],
                layout: metamoran_bundle::AdcLayout::Dca1000,
                shots: &shots,
                lidar: &[],
                truth: &metamoran_bundle::Truth { frames },
            },
        )?;
    }
    let p = dir.join("site.toml");
    std::fs::write(&p, site_toml(&format!("site-{seed}"))).map_err(|e| io(&p, e))?;
    Ok(dir)
}
