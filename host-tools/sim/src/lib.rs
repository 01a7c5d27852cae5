//! The scene simulator behind `metamoran simulate`: layouts → scatterers → FMCW samples and
//! camera products → bundles (bundle.md), with ground truth.
//!
//! * [`layout`]: presets and where things go; [`object`] and [`shape`]: what they are;
//! * [`signal`]: the radar signal model; [`camera`]: rendering and the monocular model;
//! * [`radar`]: the simulated boards; [`writer`]: the bundle files.

pub mod camera;
pub mod drive;
pub mod layout;
pub mod motion;
pub mod object;
pub mod radar;
pub mod shape;
pub mod signal;
pub mod site;
pub mod writer;

/// Why a scene could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// A file or folder of the bundle could not be written.
    #[error("{}: cannot write ({source}); check the folder is writable and has room", path.display())]
    Write {
        /// The file or folder.
        path: PathBuf,
        /// What failed (I/O, PNG or JSON encoding).
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// A bundle file the reader's crate writes (the lidar truth) failed.
    #[error(transparent)]
    Bundle(#[from] metamoran_bundle::error::InputError),
}

use layout::Preset;
use metamoran_bundle::geometry::CameraModel;
use metamoran_bundle::{CameraConfig, Ego, Instance, Truth, TruthFrame, TruthObject};
use object::{GROUND_Y, Scatterer};
use radar::RadarKind;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// The simulated camera: 640 × 360, 65° horizontal field of view, 15 cm above the radar.
pub fn camera_config() -> CameraConfig {
    CameraConfig {
        width: 640,
        height: 360,
        fx: 500.0,
        fy: 500.0,
        cx: 320.0,
        cy: 180.0,
        translation_m: [0.0, -0.15, 0.0],
        yaw_deg: 0.0,
        pitch_deg: 0.0,
        roll_deg: 0.0,
    }
}

/// Diffuse ground clutter: random scatterers on the ground plane inside the radar's view.
fn ground(rng: &mut impl Rng, max_range: f64) -> Vec<Scatterer> {
    const POINTS: usize = 300;
    let area = std::f64::consts::PI / 3.0 * max_range * max_range / POINTS as f64;
    (0..POINTS)
        .map(|_| {
            let r = max_range * rng.random_range(0.0f64..1.0).sqrt().max(0.03);
            let az = rng.random_range(-60f64..60.0).to_radians();
            Scatterer {
                position: nalgebra::Vector3::new(r * az.sin(), GROUND_Y, r * az.cos()),
                rcs: 0.003 * area * rng.random_range(0.2..1.8),
                phase: rng.random_range(0.0..std::f64::consts::TAU),
            }
        })
        .collect()
}

/// One scene's seed from the run seed and the scene index (SplitMix64).
fn scene_seed(seed: u64, index: u64) -> u64 {
    let mut z = seed ^ index.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// What the camera saw in one frame.
pub struct Shot {
    /// The rendered truth (ids and camera depth per pixel).
    pub render: camera::Render,
    /// Segmenter and monocular-depth outputs.
    pub products: camera::CameraProducts,
    /// The instances the segmenter saw.
    pub instances: Vec<Instance>,
}

/// A simulated scene, in memory.
pub struct SimulatedScene {
    /// The objects as at the first frame (ids as in the camera products).
    pub objects: Vec<object::SceneObject>,
    /// Radar configuration (its `frames` and `frame_period_s` say how many and how often).
    pub radar: metamoran_dsp::config::RadarConfig,
    /// Camera configuration.
    pub camera: CameraConfig,
    /// `radar.bin` bytes, every frame.
    pub adc: Vec<u8>,
    /// Elevation of each TX, half-wavelengths (empty: all 0).
    pub tx_elevation: Vec<i16>,
    /// How the radar samples are written.
    pub layout: metamoran_bundle::AdcLayout,
    /// The camera products of every frame.
    pub shots: Vec<Shot>,
    /// The lidar-like truth of every frame (drive preset; empty otherwise).
    pub lidar: Vec<Vec<[f64; 3]>>,
    /// Ground truth, every frame.
    pub truth: Truth,
}

/// How kind a scene is to the method.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Difficulty {
    /// The presets as they were: every seed gives the same bundle as before.
    #[default]
    Standard,
    /// Harder where the standard scenes were kind (issue #17): monocular error growing past
    /// 50 m at Table I's slope, segmentation off by up to two pixels, a strong reflector inside
    /// an 8-element radar's beam at another range, movers up to 35 m/s.
    Hard,
}

/// The range bin that sizes a board's channel delays: that of its 59.4 m chirp (the parking
/// lot's), m.
pub fn board_bin_m(kind: RadarKind) -> f64 {
    let c = radar::config(kind, 59.4, 2);
    f64::from(c.range_bin_size(usize::from(c.adc_samples)))
}

/// How a run's scenes differ from the presets as they were.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Variant {
    /// Scene difficulty.
    pub difficulty: Difficulty,
    /// A seeded board's channel errors ([`signal::ChannelErrors::draw`], delays sized by
    /// [`board_bin_m`]); `None`: a perfect array.
    pub board: Option<u64>,
    /// Number the camera's instances afresh every frame, as a real segmenter does (issue
    /// #20): the same scene, its mask and `instances.json` ids permuted per frame, the truth
    /// keeping each object's identity in `object`.
    pub renumber: bool,
}

impl From<Difficulty> for Variant {
    fn from(difficulty: Difficulty) -> Self {
        Self {
            difficulty,
            ..Self::default()
        }
    }
}

/// Numbers each frame's instances afresh: the visible ids become `1..=n` in an order drawn
/// from `seed` and the frame (its own generator, so the scene's other draws are unchanged),
/// in the mask, `instances.json` and the truth (which keeps the old id as the identity).
fn renumber(shots: &mut [Shot], truth: &mut [TruthFrame], seed: u64) {
    use rand::seq::SliceRandom;
    for (f, (shot, frame)) in shots.iter_mut().zip(truth).enumerate() {
        let mut rng = Pcg64Mcg::seed_from_u64(scene_seed(seed ^ 0x5245_4E55_4D42_4552, f as u64));
        let old: Vec<u16> = shot.instances.iter().map(|i| i.id).collect();
        let mut new: Vec<u16> = (1..=old.len() as u16).collect();
        new.shuffle(&mut rng);
        let map = |id: u16| old.iter().position(|&o| o == id).map_or(id, |k| new[k]);
        for px in &mut shot.products.mask {
            *px = map(*px);
        }
        for i in &mut shot.instances {
            i.id = map(i.id);
        }
        shot.instances.sort_by_key(|i| i.id);
        for o in &mut frame.objects {
            o.object = Some(o.instance);
            o.instance = map(o.instance);
        }
        frame.objects.sort_by_key(|o| o.instance);
    }
}

/// Simulates scene `index` of a run with seed `seed`: every frame of its layout (one, except
/// for the perimeter preset), objects moved along their paths or velocities between frames.
pub fn simulate_scene(preset: Preset, kind: RadarKind, seed: u64, index: u64) -> SimulatedScene {
    simulate_scene_with(preset, kind, Difficulty::Standard, seed, index)
}

/// [`simulate_scene`] as `variant` says (the drive and perimeter presets have one difficulty;
/// the drive preset's board is always perfect).
pub fn simulate_scene_with(
    preset: Preset,
    kind: RadarKind,
    variant: impl Into<Variant>,
    seed: u64,
    index: u64,
) -> SimulatedScene {
    let Variant {
        difficulty,
        board,
        renumber: renumbered,
    } = variant.into();
    let mut rng = Pcg64Mcg::seed_from_u64(scene_seed(seed, index));
    if let Some(env) = preset.environment() {
        let mut scene = drive_scene(&mut rng, kind, env);
        if renumbered {
            renumber(
                &mut scene.shots,
                &mut scene.truth.frames,
                scene_seed(seed, index),
            );
        }
        return scene;
    }
    let (layout, deepest) = layout::draw(preset, difficulty, &mut rng, radar::max_range_for);
    let loops = if matches!(preset, Preset::Moving | Preset::FarMoving) {
        16
    } else {
        2
    };
    let mut config = radar::config(kind, radar::max_range_for(deepest), loops);
    // The MMWCAS board's raised TX add their elevation's phase to every echo.
    let tx_elevation = radar::tx_elevation(kind);
    let elevation: Vec<i16> = (0..config.channels())
        .map(|ch| {
            let tx = config
                .tx_order
                .get(ch / config.rx_count())
                .copied()
                .unwrap_or(0);
            tx_elevation.get(usize::from(tx)).copied().unwrap_or(0)
        })
        .collect();
    config.frames = u32::from(layout.frames);
    config.frame_period_s = layout.frame_period_s;
    let errors = board.map(|b| {
        let (tx, rx) = (config.tx_positions.len(), config.rx_count());
        signal::ChannelErrors::draw(b, tx, rx, board_bin_m(kind))
    });
    let extra = ground(&mut rng, config.max_range() as f64);
    let (adc, mut shots, mut frames) = film_frames(
        &config,
        (&layout.objects, &layout.paths),
        &|o| o.clone(),
        (&extra, &elevation, errors.as_ref()),
        difficulty,
        &mut rng,
    );
    if renumbered {
        renumber(&mut shots, &mut frames, scene_seed(seed, index));
    }
    let camera = camera_config();
    SimulatedScene {
        objects: layout.objects,
        radar: config,
        camera,
        adc,
        tx_elevation,
        layout: if kind == RadarKind::Mmwcas {
            metamoran_bundle::AdcLayout::Mmwcas
        } else {
            metamoran_bundle::AdcLayout::Dca1000
        },
        shots,
        lidar: Vec::new(),
        truth: Truth { frames },
    }
}

/// Every frame of a scene at `config`'s frame count and period: the objects moved along their
/// paths, put into the radar's frame by `view`, their echoes (with `extra` scatterers, per-TX
/// `elevation` and board `errors`) synthesized, and the camera's products and truth.
fn film_frames(
    config: &metamoran_dsp::config::RadarConfig,
    (objects, paths): (&[object::SceneObject], &[motion::Path]),
    view: &dyn Fn(&object::SceneObject) -> object::SceneObject,
    (extra, elevation, errors): (&[Scatterer], &[i16], Option<&signal::ChannelErrors>),
    difficulty: Difficulty,
    rng: &mut Pcg64Mcg,
) -> (Vec<u8>, Vec<Shot>, Vec<TruthFrame>) {
    let camera = camera_config();
    let model = CameraModel::new(&camera);
    let mut adc = Vec::new();
    let mut shots = Vec::new();
    let mut frames = Vec::new();
    for f in 0..config.frames {
        let t = f64::from(f) * config.frame_period_s;
        let moved: Vec<_> = motion::at(objects, paths, t).iter().map(view).collect();
        let echoes = signal::echoes(&moved, extra, config, signal::ELEVATION_BEAM_DEG);
        adc.extend(signal::synthesize(config, &echoes, elevation, errors, rng));
        let (shot, truth_objects) = film(&moved, &model, &camera, difficulty, rng);
        frames.push(TruthFrame {
            frame: f,
            ego: Ego {
                x: 0.0,
                z: 0.0,
                yaw: 0.0,
                vx: 0.0,
                vz: 0.0,
            },
            objects: truth_objects,
        });
        shots.push(shot);
    }
    (adc, shots, frames)
}

/// What the camera makes of `objects` (radar frame), and the truth of the objects of interest.
fn film(
    objects: &[object::SceneObject],
    model: &CameraModel,
    camera: &CameraConfig,
    difficulty: Difficulty,
    rng: &mut impl Rng,
) -> (Shot, Vec<TruthObject>) {
    let render = camera::render(model, objects);
    let products = camera::products(&render, camera.width, camera.height, difficulty, rng);
    let visible: std::collections::BTreeSet<u16> =
        products.mask.iter().copied().filter(|&i| i != 0).collect();
    let seen = |o: &&object::SceneObject| visible.contains(&o.id);
    let instances = objects
        .iter()
        .filter(seen)
        .map(|o| Instance {
            id: o.id,
            class: o.class.to_owned(),
        })
        .collect();
    let truth_objects = objects
        .iter()
        .filter(|o| seen(o) && matches!(o.class, "car" | "person" | "sign"))
        .map(|o| truth_object(o, &render, model, camera))
        .collect();
    let shot = Shot {
        render,
        products,
        instances,
    };
    (shot, truth_objects)
}

/// A drive scene's world and its vehicle's plan, drawn first from the scene's generator.
fn draw_drive(rng: &mut Pcg64Mcg, env: drive::Environment) -> (drive::World, drive::Drive) {
    let world = drive::world(env, rng);
    (world, drive::Drive::draw(rng))
}

/// The world and the vehicle's plan of scene `index` of run `seed` of a mapping preset (the
/// `drive`, `tunnel`, `parking-area` and `garage` presets, whatever the board): what
/// [`simulate_scene_with`] draws before it renders, for diagnostics that need the scatterers
/// themselves (`examples/scatterers_in_view.rs`).
///
/// ```
/// use metamoran_sim::drive::{Environment, FRAMES, FRAME_PERIOD_S};
/// let (world, plan) = metamoran_sim::drive_world(Environment::Street, 6500, 0);
/// assert!(world.ceiling.is_none());
/// assert_eq!(plan.poses(FRAMES, FRAME_PERIOD_S).len(), usize::from(FRAMES));
/// ```
pub fn drive_world(env: drive::Environment, seed: u64, index: u64) -> (drive::World, drive::Drive) {
    draw_drive(&mut Pcg64Mcg::seed_from_u64(scene_seed(seed, index)), env)
}

/// The drive preset: the street moved into the radar's frame at each frame's pose.
fn drive_scene(rng: &mut Pcg64Mcg, kind: RadarKind, env: drive::Environment) -> SimulatedScene {
    let (mut config, tx_elevation) = radar::drive_config(kind);
    config.frames = u32::from(drive::FRAMES);
    config.frame_period_s = drive::FRAME_PERIOD_S;
    let (world, plan) = draw_drive(rng, env);
    let poses = plan.poses(drive::FRAMES, drive::FRAME_PERIOD_S);
    let camera = camera_config();
    let model = CameraModel::new(&camera);
    let elevation: Vec<i16> = (0..config.channels())
        .map(|ch| tx_elevation[config.tx_order[ch / config.rx_count()] as usize])
        .collect();
    let mut adc = Vec::new();
    let mut shots = Vec::new();
    let mut lidar = Vec::new();
    let mut frames = Vec::new();
    for (f, (pose, radar_v)) in poses.iter().enumerate() {
        let t = f as f64 * drive::FRAME_PERIOD_S;
        let (objects, surfaces) = world.seen_from(t, pose, *radar_v);
        let all = [objects.as_slice(), &surfaces].concat();
        let echoes = signal::echoes(&all, &[], &config, DRIVE_ELEVATION_BEAM_DEG);
        adc.extend(signal::synthesize(&config, &echoes, &elevation, None, rng));
        let (shot, truth_objects) = film(&objects, &model, &camera, Difficulty::Standard, rng);
        lidar.push(metamoran_bundle::lidar::scan(|d| {
            let dir = nalgebra::Vector3::new(d[0], d[1], d[2]);
            let origin = nalgebra::Vector3::zeros();
            let ground = (d[1] > 1e-9).then(|| GROUND_Y / d[1]);
            let roof = world
                .ceiling
                .as_ref()
                .filter(|_| d[1] < -1e-9)
                .map(|(h, _)| (GROUND_Y - h) / d[1]);
            objects
                .iter()
                .filter_map(|o| o.shape.intersect(&origin, &dir))
                .chain(ground)
                .chain(roof)
                .min_by(f64::total_cmp)
        }));
        frames.push(TruthFrame {
            frame: f as u32,
            ego: Ego {
                x: pose.position[0],
                z: pose.position[1],
                yaw: pose.yaw,
                vx: radar_v[0],
                vz: radar_v[1],
            },
            objects: truth_objects,
        });
        shots.push(shot);
    }
    SimulatedScene {
        objects: world.objects,
        radar: config,
        camera,
        adc,
        tx_elevation,
        layout: metamoran_bundle::AdcLayout::Dca1000,
        shots,
        lidar,
        truth: Truth { frames },
    }
}

/// Elevation beam (1σ) of the drive preset's board, degrees: wide, to see walls and poles.
pub const DRIVE_ELEVATION_BEAM_DEG: f64 = 15.0;

/// Truth of one object: depth of its closest footprint point, azimuth and radial velocity of
/// its centre, and a lidar-like sample of its visible surface (from the rendered pixels).
fn truth_object(
    o: &object::SceneObject,
    render: &camera::Render,
    model: &CameraModel,
    camera: &CameraConfig,
) -> TruthObject {
    let c = o.shape.closest_point();
    let centre = o.centre();
    let pixels: Vec<usize> = (0..render.ids.len())
        .filter(|&i| render.ids[i] == o.id)
        .collect();
    let step = pixels.len().div_ceil(1500).max(1);
    let mm = |v: f64| (v * 1000.0).round() / 1000.0;
    let points = pixels
        .iter()
        .step_by(step)
        .map(|&i| {
            let (u, v) = (
                (i % camera.width as usize) as u32,
                (i / camera.width as usize) as u32,
            );
            let p = model.back_project(u, v, render.depth[i]);
            [mm(p.x), mm(p.y), mm(p.z)]
        })
        .collect();
    TruthObject {
        instance: o.id,
        class: o.class.to_owned(),
        depth_m: c[0].hypot(c[1]),
        azimuth_deg: centre[0].atan2(centre[1]).to_degrees(),
        radial_velocity_mps: o.radial_velocity(&nalgebra::Vector3::new(centre[0], 0.0, centre[1])),
        points,
        object: None,
    }
}

/// Simulates scene `index` of a run and writes it into `dir`.
///
/// # Errors
/// [`SimError`] naming the file that could not be written.
pub fn simulate_one(
    preset: Preset,
    kind: RadarKind,
    seed: u64,
    index: u64,
    dir: &Path,
) -> Result<(), SimError> {
    simulate_one_with(preset, kind, Difficulty::Standard, seed, index, dir)
}

/// [`simulate_one`] as `variant` says.
///
/// # Errors
/// [`SimError`] naming the file that could not be written.
pub fn simulate_one_with(
    preset: Preset,
    kind: RadarKind,
    variant: impl Into<Variant>,
    seed: u64,
    index: u64,
    dir: &Path,
) -> Result<(), SimError> {
    let s = simulate_scene_with(preset, kind, variant, seed, index);
    let name = dir
        .file_name()
        .map_or_else(|| "scene".into(), |n| n.to_string_lossy().into_owned());
    writer::write(
        dir,
        &writer::BundleContents {
            name: &name,
            radar: &s.radar,
            camera: &s.camera,
            adc: &s.adc,
            tx_elevation: &s.tx_elevation,
            layout: s.layout,
            shots: &s.shots,
            lidar: &s.lidar,
            truth: &s.truth,
        },
    )
}

/// Simulates `count` scenes in parallel into `out/<preset>-<seed>-<index>`; returns the folders.
/// `done` is called (from any thread) as each scene is written, for a progress bar.
///
/// # Errors
/// The first scene that could not be written.
pub fn simulate(
    preset: Preset,
    kind: RadarKind,
    seed: u64,
    count: u64,
    out: &Path,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<PathBuf>, SimError> {
    simulate_with(preset, kind, Difficulty::Standard, seed, count, out, done)
}

/// [`simulate`] as `variant` says; hard scenes go to `out/<preset>-hard-<seed>-<index>`, scenes
/// on an imperfect board to `out/<preset>-board<B>-<seed>-<index>`, the imaging board's to
/// `out/<preset>-imaging-<seed>-<index>`.
///
/// # Errors
/// The first scene that could not be written.
pub fn simulate_with(
    preset: Preset,
    kind: RadarKind,
    variant: impl Into<Variant>,
    seed: u64,
    count: u64,
    out: &Path,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<PathBuf>, SimError> {
    std::fs::create_dir_all(out).map_err(|e| SimError::Write {
        path: out.to_owned(),
        source: e.into(),
    })?;
    let variant = variant.into();
    let mut tag = match variant.difficulty {
        Difficulty::Standard => String::new(),
        Difficulty::Hard => "-hard".to_owned(),
    };
    if let Some(b) = variant.board {
        tag.push_str(&format!("-board{b}"));
    }
    if variant.renumber {
        tag.push_str("-renumbered");
    }
    if kind == RadarKind::Imaging {
        tag.push_str("-imaging");
    }
    let dirs: Vec<PathBuf> = (0..count)
        .map(|k| out.join(format!("{}{tag}-{seed}-{k:04}", preset.name())))
        .collect();
    dirs.par_iter().enumerate().try_for_each(|(k, dir)| {
        let r = simulate_one_with(preset, kind, variant, seed, k as u64, dir);
        done();
        r
    })?;
    Ok(dirs)
}

#[cfg(test)]
mod tests {
    use super::{Difficulty, Preset, RadarKind, Variant, simulate_scene_with};

    /// Renumbering changes the ids and nothing else: the radar samples are the same bytes, and
    /// in each frame the mask is the original under one bijection of the ids, which the
    /// instances list and the truth (through its `object` identity) follow.
    #[test]
    fn renumbering_permutes_each_frames_ids_and_changes_nothing_else() {
        let kind = RadarKind::Xwr18xx;
        let a = simulate_scene_with(Preset::Crossing, kind, Difficulty::Standard, 4, 0);
        let renumber = Variant {
            renumber: true,
            ..Variant::default()
        };
        let b = simulate_scene_with(Preset::Crossing, kind, renumber, 4, 0);
        assert_eq!(a.adc, b.adc);
        let mut changed = 0;
        for (f, (sa, sb)) in a.shots.iter().zip(&b.shots).enumerate() {
            let mut map = std::collections::BTreeMap::new();
            for (&pa, &pb) in sa.products.mask.iter().zip(&sb.products.mask) {
                assert_eq!(*map.entry(pa).or_insert(pb), pb, "frame {f}: not one map");
            }
            let images: std::collections::BTreeSet<_> = map.values().collect();
            assert_eq!(images.len(), map.len(), "frame {f}: two ids merged");
            assert_eq!(map.get(&0).copied().unwrap_or(0), 0, "background stays 0");
            for ia in &sa.instances {
                let new = map[&ia.id];
                let i = sb.instances.iter().find(|i| i.id == new).unwrap();
                assert_eq!(i.class, ia.class);
            }
            for t in &b.truth.frames[f].objects {
                let old = t.identity();
                assert_eq!(map[&old], t.instance, "frame {f}");
            }
            changed += usize::from(map.iter().any(|(k, v)| k != v));
        }
        assert!(changed > a.shots.len() / 2, "{changed} frames renumbered");
    }

    /// Objects of interest with a strong reflector within 7° of them at a range 2.5 m or more
    /// away (what an 8-element beam cannot separate), over `n` scenes.
    fn crowded_beams(difficulty: Difficulty, n: u64) -> (usize, usize) {
        let (mut crowded, mut total) = (0, 0);
        for i in 0..n {
            let s = simulate_scene_with(Preset::ParkingLot, RadarKind::Xwr18xx, difficulty, 5, i);
            let polar = |c: [f64; 2]| (c[0].hypot(c[1]), c[0].atan2(c[1]).to_degrees());
            for o in s
                .objects
                .iter()
                .filter(|o| matches!(o.class, "car" | "person" | "sign"))
            {
                let (r, a) = polar(o.centre());
                total += 1;
                crowded += usize::from(s.objects.iter().any(|c| {
                    let (cr, ca) = polar(c.centre());
                    matches!(c.class, "pole" | "wall" | "vehicle_parked")
                        && (ca - a).abs() < 7.0
                        && (cr - r).abs() > 2.5
                }));
            }
        }
        (crowded, total)
    }

    #[test]
    fn hard_scenes_put_clutter_inside_a_small_radars_beam() {
        let (hard, n) = crowded_beams(Difficulty::Hard, 12);
        let (standard, m) = crowded_beams(Difficulty::Standard, 12);
        assert!(hard as f64 >= 0.8 * n as f64, "{hard}/{n}");
        assert!(
            hard as f64 / n as f64 > standard as f64 / m as f64,
            "{standard}/{m}"
        );
    }
}
