//! Scene layouts of the presets: where the objects of interest and the clutter go.
//!
//! Clutter is placed to create what makes the problem hard (Metamoran, Sec. III-B): strong
//! reflectors at another azimuth and another range, whose azimuth side lobes fall inside the
//! object's angular span, plus buildings, poles, fences, trees, parked vehicles and ground.
//! Nothing is placed in front of an object of interest, so the camera always sees it.

use super::motion::Path;
use super::object::{self, GROUND_Y, SceneObject};
use super::shape::Shape;
use crate::Difficulty;
use rand::Rng;
use std::f64::consts::PI;

/// A scene preset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// Static, cluttered parking lot; cars, people and signs at 3–60 m.
    ParkingLot,
    /// Static cars at 10–90 m among clutter.
    LongRange,
    /// Moving car, person or sign at 20–300 m among static clutter.
    Moving,
    /// Far movers among static clutter (issue #17's goal for movers): cars at 100–300 m and
    /// people at 100–230 m, where the paper still finds them (305 m and 229 m).
    FarMoving,
    /// A perimeter over 22 frames (0.5 s apart): a car parked in the far lot at 36–44 m and a
    /// person who walks into the gate zone near 12 m, back to 0.6 m outside its border (within
    /// the demo perimeter's hysteresis), in again and out (the demo scene).
    Perimeter,
    /// Multi-object tracking (issue #20): 30 frames (0.25 s apart) of two people whose walks
    /// cross at 13–15 m, 1.5 m apart in depth as their azimuths cross (the nearer one hides the
    /// farther from the camera for a frame or two), and a car crawling across the lot at 32–38 m.
    Crossing,
    /// The radar on a vehicle driving down a street of walls, poles and parked cars among
    /// traffic, 20 frames at 10 Hz, on the xWR1843-like board with an elevated TX (or the 4D
    /// imaging board with `--radar imaging`): dense radar mapping's scenes. Ego pose and
    /// velocity in truth.json.
    Drive,
    /// The drive preset's vehicle in a road tunnel (issue #21): walls 3.5–5 m either side up to
    /// a ceiling 4.5–5.5 m over the road, both densely scattering, one or two other cars.
    Tunnel,
    /// The drive preset's vehicle crossing an open parking area (issue #21): rows of parked
    /// cars either side of the lane, lamp posts, building fronts 18–30 m off, little traffic.
    ParkingArea,
    /// The drive preset's vehicle through a covered car park (issue #21): a ceiling 2.8–4.2 m
    /// over rows of columns and parked cars, walls 14–20 m off; trained on, so that the tunnel
    /// can stay held out while the network still sees a roof.
    Garage,
    /// A calibration capture (TI's procedure, Metamoran §V): a corner reflector on a thin
    /// mast 5 m away on boresight at the radar's height, over the ground and nothing else.
    Corner,
}

/// Range of the [`Preset::Corner`] reflector, m.
pub const CORNER_RANGE_M: f64 = 5.0;
/// Radar cross-section of that reflector, m² (a 10 cm trihedral at 77 GHz is about 10 dBsm).
pub const CORNER_RCS_M2: f64 = 10.0;

impl Preset {
    /// The moving-platform environment of a mapping preset (`None` for the depth presets).
    pub fn environment(self) -> Option<crate::drive::Environment> {
        use crate::drive::Environment;
        match self {
            Preset::Drive => Some(Environment::Street),
            Preset::Tunnel => Some(Environment::Tunnel),
            Preset::ParkingArea => Some(Environment::ParkingArea),
            Preset::Garage => Some(Environment::Garage),
            _ => None,
        }
    }

    /// Name used in bundle names.
    pub fn name(self) -> &'static str {
        match self {
            Preset::ParkingLot => "parking-lot",
            Preset::LongRange => "long-range",
            Preset::Moving => "moving",
            Preset::FarMoving => "far-moving",
            Preset::Perimeter => "perimeter",
            Preset::Crossing => "crossing",
            Preset::Drive => "drive",
            Preset::Tunnel => "tunnel",
            Preset::ParkingArea => "parking-area",
            Preset::Garage => "garage",
            Preset::Corner => "corner",
        }
    }
}

/// The objects of a layout; ids 1.. in placement order (objects of interest first).
pub struct Layout {
    /// Every object, as at the first frame.
    pub objects: Vec<SceneObject>,
    /// Scripted walks (the others move straight on at their velocity).
    pub paths: Vec<Path>,
    /// Frames to simulate.
    pub frames: u16,
    /// Time between frames, s.
    pub frame_period_s: f64,
}

fn polar(range: f64, az: f64) -> [f64; 2] {
    [range * az.sin(), range * az.cos()]
}

/// Angular half-width (rad) of a footprint of radius `r` at `range`.
fn half_span(r: f64, range: f64) -> f64 {
    (r / range.max(r + 0.1)).asin()
}

struct Placer<'a, R: Rng> {
    rng: &'a mut R,
    difficulty: Difficulty,
    objects: Vec<SceneObject>,
    /// (range, azimuth, angular half-width) of each object of interest.
    keep_clear: Vec<(f64, f64, f64)>,
    max_range: f64,
}

impl<R: Rng> Placer<'_, R> {
    fn next_id(&self) -> u16 {
        self.objects.len() as u16 + 1
    }

    /// Whether a footprint of radius `r` at `c` is clear of the others and does not hide an
    /// object of interest from the radar or camera.
    fn free(&self, c: [f64; 2], r: f64) -> bool {
        let (range, az) = (c[0].hypot(c[1]), c[0].atan2(c[1]));
        let apart = self.objects.iter().all(|o| {
            let oc = o.centre();
            (oc[0] - c[0]).hypot(oc[1] - c[1]) > r + radius(&o.shape) + 0.8
        });
        let unblocking = self.keep_clear.iter().all(|&(kr, kaz, kspan)| {
            range > kr + 2.0 || (az - kaz).abs() > kspan + half_span(r, range) + 1f64.to_radians()
        });
        apart && unblocking && range > 2.0
    }

    fn push(&mut self, class: &'static str, shape: Shape, velocity: [f64; 2]) {
        let scatterers = match class {
            "car" | "vehicle_parked" => object::vehicle(self.rng, &shape),
            "person" => object::person(self.rng, &shape),
            "sign" => object::sign(self.rng, &shape),
            "building" => {
                let flash = self.rng.random_range(800.0..3000.0);
                object::facade(self.rng, &shape, 0.4, flash, 3.0)
            }
            "wall" => {
                let flash = self.rng.random_range(150.0..600.0);
                object::facade(self.rng, &shape, 0.25, flash, 4.0)
            }
            "fence" => object::fence(self.rng, &shape),
            "pole" => {
                let rcs = self.rng.random_range(5.0..25.0);
                object::pole(&shape, rcs)
            }
            _ => object::tree(self.rng, &shape),
        };
        let mut scatterers = scatterers;
        object::random_phases(self.rng, &mut scatterers);
        let id = self.next_id();
        self.objects.push(SceneObject {
            id,
            class,
            shape,
            velocity,
            scatterers,
        });
    }

    /// A shape of `class` centred at `c` with a random orientation.
    fn shape(&mut self, class: &str, c: [f64; 2]) -> Shape {
        let heading = self.rng.random_range(0.0..PI);
        match class {
            "car" | "vehicle_parked" => Shape::Box {
                centre: c,
                half_length: self.rng.random_range(2.1..2.4),
                half_width: self.rng.random_range(0.85..0.95),
                heading,
                y_top: GROUND_Y - self.rng.random_range(1.4..1.6),
                y_bottom: GROUND_Y,
            },
            "person" => Shape::Cylinder {
                centre: c,
                radius: 0.25,
                y_top: GROUND_Y - self.rng.random_range(1.6..1.9),
                y_bottom: GROUND_Y,
            },
            "sign" => {
                // Facing the radar within ±35°.
                let face =
                    c[0].atan2(c[1]) + PI / 2.0 + self.rng.random_range(-35f64..35.0).to_radians();
                let h = 0.3;
                Shape::Panel {
                    a: [c[0] - h * face.sin(), c[1] - h * face.cos()],
                    b: [c[0] + h * face.sin(), c[1] + h * face.cos()],
                    y_top: GROUND_Y - 2.2,
                    y_bottom: GROUND_Y - 1.6,
                }
            }
            "pole" => Shape::Cylinder {
                centre: c,
                radius: 0.12,
                y_top: GROUND_Y - 7.0,
                y_bottom: GROUND_Y,
            },
            "tree" => Shape::Cylinder {
                centre: c,
                radius: self.rng.random_range(1.2..2.5),
                y_top: GROUND_Y - 7.0,
                y_bottom: GROUND_Y,
            },
            _ => {
                let (len, height) = match class {
                    "building" => (
                        self.rng.random_range(15.0..50.0),
                        self.rng.random_range(6.0..20.0),
                    ),
                    "wall" => (
                        self.rng.random_range(5.0..20.0),
                        self.rng.random_range(2.0..3.5),
                    ),
                    _ => (self.rng.random_range(5.0..25.0), 1.5),
                };
                // Roughly facing the radar (within ±50°), as streets and lots are laid out.
                let along =
                    c[0].atan2(c[1]) + PI / 2.0 + self.rng.random_range(-50f64..50.0).to_radians();
                let h = len / 2.0;
                Shape::Panel {
                    a: [c[0] - h * along.sin(), c[1] - h * along.cos()],
                    b: [c[0] + h * along.sin(), c[1] + h * along.cos()],
                    y_top: GROUND_Y - height,
                    y_bottom: GROUND_Y,
                }
            }
        }
    }

    /// Tries to place `class` at range in `ranges` and azimuth in `azs` (degrees); returns whether it did.
    fn try_place(
        &mut self,
        class: &'static str,
        ranges: std::ops::Range<f64>,
        azs: std::ops::Range<f64>,
        velocity: [f64; 2],
    ) -> bool {
        for _ in 0..40 {
            let range = self.rng.random_range(ranges.clone());
            let az = self.rng.random_range(azs.clone()).to_radians();
            let c = polar(range, az);
            let shape = self.shape(class, c);
            if range < self.max_range * 0.95 && self.free(c, radius(&shape)) {
                self.push(class, shape, velocity);
                return true;
            }
        }
        false
    }
}

/// A footprint's bounding radius.
fn radius(s: &Shape) -> f64 {
    match *s {
        Shape::Box {
            half_length,
            half_width,
            ..
        } => half_length.hypot(half_width),
        Shape::Cylinder { radius, .. } => radius,
        Shape::Panel { a, b, .. } => (a[0] - b[0]).hypot(a[1] - b[1]) / 2.0,
    }
}

/// The class and range of the objects of interest a preset draws, and their speed (hard: cars
/// to 35 m/s, beyond the ±16 m/s one TDM frame tells apart; people to 3.5 m/s).
fn interest(
    preset: Preset,
    difficulty: Difficulty,
    rng: &mut impl Rng,
) -> (&'static str, f64, f64) {
    let class = match (preset, rng.random_range(0.0..1.0)) {
        (Preset::LongRange, _) => "car",
        (Preset::FarMoving, u) if u < 0.5 => "car",
        (Preset::FarMoving, _) => "person",
        (_, u) if u < 0.55 => "car",
        (_, u) if u < 0.8 => "person",
        _ => "sign",
    };
    let range = match (preset, class) {
        (
            Preset::ParkingLot
            | Preset::Perimeter
            | Preset::Crossing
            | Preset::Drive
            | Preset::Tunnel
            | Preset::ParkingArea
            | Preset::Garage
            | Preset::Corner,
            _,
        ) => rng.random_range(3.0..60.0),
        (Preset::LongRange, _) => rng.random_range(10.0..90.0),
        (Preset::Moving, "person") => rng.random_range(20.0..150.0),
        (Preset::Moving, _) => rng.random_range(20.0..300.0),
        (Preset::FarMoving, "person") => rng.random_range(100.0..230.0),
        (Preset::FarMoving, _) => rng.random_range(100.0..300.0),
    };
    let speed = match (preset, class, difficulty) {
        (Preset::Moving | Preset::FarMoving, "person", Difficulty::Standard) => {
            rng.random_range(0.8..2.5)
        }
        (Preset::Moving | Preset::FarMoving, "person", Difficulty::Hard) => {
            rng.random_range(0.8..3.5)
        }
        (Preset::Moving | Preset::FarMoving, _, Difficulty::Standard) => {
            rng.random_range(4.0..25.0)
        }
        (Preset::Moving | Preset::FarMoving, _, Difficulty::Hard) => rng.random_range(4.0..35.0),
        _ => 0.0,
    };
    (class, range, speed)
}

/// Draws a layout for `preset`; returns it with the largest object-of-interest depth.
pub fn draw(
    preset: Preset,
    difficulty: Difficulty,
    rng: &mut impl Rng,
    max_range: impl Fn(f64) -> f64,
) -> (Layout, f64) {
    if preset == Preset::Perimeter {
        return perimeter(rng, max_range);
    }
    if preset == Preset::Corner {
        return corner(rng);
    }
    if preset == Preset::Crossing {
        return crossing(rng, max_range);
    }
    let count = if rng.random_range(0.0..1.0) < 0.3 {
        2
    } else {
        1
    };
    let drawn: Vec<_> = (0..count)
        .map(|_| interest(preset, difficulty, rng))
        .collect();
    let deepest = drawn.iter().map(|d| d.1).fold(0.0, f64::max);
    let mut p = Placer {
        rng,
        difficulty,
        objects: Vec::new(),
        keep_clear: Vec::new(),
        max_range: max_range(deepest),
    };
    for (class, range, speed) in drawn {
        // Objects of interest stay inside the camera's view and apart from each other.
        let heading = p.rng.random_range(0.0..2.0 * PI);
        let velocity = [speed * heading.sin(), speed * heading.cos()];
        if p.try_place(class, range - 0.5..range + 0.5, -22.0..22.0, velocity) {
            p.keep_clear_of_last();
        }
    }
    p.clutter();
    let layout = Layout {
        objects: p.objects,
        paths: Vec::new(),
        frames: 1,
        frame_period_s: 0.1,
    };
    (layout, deepest)
}

/// The corner preset: one reflector on boresight.
fn corner(rng: &mut impl Rng) -> (Layout, f64) {
    let shape = Shape::Cylinder {
        centre: [0.0, CORNER_RANGE_M],
        radius: 0.05,
        y_top: -0.1,
        y_bottom: GROUND_Y,
    };
    let mut scatterers = vec![object::scatterer(0.0, 0.0, CORNER_RANGE_M, CORNER_RCS_M2)];
    object::random_phases(rng, &mut scatterers);
    let reflector = SceneObject {
        id: 1,
        class: "pole",
        shape,
        velocity: [0.0; 2],
        scatterers,
    };
    let layout = Layout {
        objects: vec![reflector],
        paths: Vec::new(),
        frames: 1,
        frame_period_s: 0.1,
    };
    (layout, CORNER_RANGE_M)
}

/// The perimeter preset: a parked car in the far lot and a scripted walker at the gate.
fn perimeter(rng: &mut impl Rng, max_range: impl Fn(f64) -> f64) -> (Layout, f64) {
    const FRAMES: u16 = 22;
    let car_range = rng.random_range(36.0..44.0);
    let mut p = Placer {
        rng,
        difficulty: Difficulty::Standard,
        objects: Vec::new(),
        keep_clear: Vec::new(),
        max_range: max_range(car_range),
    };
    if p.try_place(
        "car",
        car_range - 0.5..car_range + 0.5,
        -8.0..12.0,
        [0.0; 2],
    ) {
        p.keep_clear_of_last();
    }
    // The gate's border is at x = −3 m: in to −1, back out to −3.6 (inside the hysteresis), in
    // to −1.5 and away to −6.
    let z = p.rng.random_range(11.5..12.5);
    let waypoints: Vec<[f64; 2]> = [-6.0, -1.0, -3.6, -1.5, -6.0]
        .iter()
        .map(|&x| [x, z])
        .collect();
    let shape = p.shape("person", waypoints[0]);
    p.push("person", shape, [0.0; 2]);
    let id = p.next_id() - 1;
    // The car gets the failure case; the walker's path stays clear (below).
    let car = p.keep_clear.clone();
    p.side_lobe_clutter(&car);
    // Nothing in front of, on or within 20 m behind the walk: the demo shows the perimeter, not
    // the hard case of a weak walker in front of a wall (the eval presets have that).
    for x in (-12..=-2).map(|k| f64::from(k) / 2.0) {
        let range = x.hypot(z);
        p.keep_clear
            .push((range + 20.0, x.atan2(z), half_span(0.6, range)));
    }
    p.background_clutter();
    let path = Path {
        id,
        waypoints,
        speed: 1.4,
    };
    let layout = Layout {
        objects: p.objects,
        paths: vec![path],
        frames: FRAMES,
        frame_period_s: 0.5,
    };
    (layout, car_range)
}

/// The site preset's world on the site plan (`[x, y]`, m; [`crate::site`]): two people whose
/// walks cross near (0, 22) and a car driving across at y = 33, 40 frames 0.25 s apart. No
/// clutter but each pole's ground: the preset is about several sensors seeing one object.
pub fn site_world(rng: &mut impl Rng) -> Layout {
    let mut p = Placer {
        rng,
        difficulty: Difficulty::Standard,
        objects: Vec::new(),
        keep_clear: Vec::new(),
        max_range: 60.0,
    };
    let y = p.rng.random_range(18.0..19.0);
    let walks = [
        ("person", [-8.0, y], [8.0, y + 7.0], 1.4),
        ("person", [8.0, y + 1.0], [-8.0, y + 6.0], 1.5),
        ("car", [-14.0, 33.0], [16.0, 33.0], 3.0),
    ];
    let paths = walks
        .into_iter()
        .map(|(class, from, to, speed)| p.walker(class, from, to, speed))
        .collect();
    Layout {
        objects: p.objects,
        paths,
        frames: 40,
        frame_period_s: 0.25,
    }
}

/// The crossing preset: two walkers whose paths cross and a slow car behind them.
fn crossing(rng: &mut impl Rng, max_range: impl Fn(f64) -> f64) -> (Layout, f64) {
    const FRAMES: u16 = 30;
    let car_z = rng.random_range(32.0..38.0);
    let z = rng.random_range(12.0..13.0);
    let mut p = Placer {
        rng,
        difficulty: Difficulty::Standard,
        objects: Vec::new(),
        keep_clear: Vec::new(),
        max_range: max_range(car_z + 2.0),
    };
    // Walker A left to right from z to z + 3; walker B right to left 1.5 m deeper: at x = 0
    // they are at the same azimuth, B behind A.
    let walks = [
        ([-6.0, z], [6.0, z + 3.0], 1.4),
        ([6.0, z + 1.5], [-6.0, z + 4.5], 1.6),
        ([-9.0, car_z], [9.0, car_z], 2.5),
    ];
    let paths: Vec<Path> = walks
        .iter()
        .enumerate()
        .map(|(k, &(from, to, speed))| {
            let class = if k < 2 { "person" } else { "car" };
            p.walker(class, from, to, speed)
        })
        .collect();
    // Nothing on or within 20 m behind the walks and the drive.
    for (from, to, _) in walks {
        for k in 0..=24 {
            let t = f64::from(k) / 24.0;
            let c = [
                from[0] + t * (to[0] - from[0]),
                from[1] + t * (to[1] - from[1]),
            ];
            let range = c[0].hypot(c[1]);
            p.keep_clear
                .push((range + 20.0, c[0].atan2(c[1]), half_span(2.5, range)));
        }
    }
    p.background_clutter();
    let layout = Layout {
        objects: p.objects,
        paths,
        frames: FRAMES,
        frame_period_s: 0.25,
    };
    (layout, car_z + 2.0)
}

impl<R: Rng> Placer<'_, R> {
    /// A `class` object placed at `from` that walks straight to `to` at `speed` m/s.
    fn walker(&mut self, class: &'static str, from: [f64; 2], to: [f64; 2], speed: f64) -> Path {
        let shape = self.shape(class, from);
        self.push(class, shape, [0.0; 2]);
        Path {
            id: self.next_id() - 1,
            waypoints: vec![from, to],
            speed,
        }
    }

    /// Keeps the line of sight to the object placed last clear of clutter.
    fn keep_clear_of_last(&mut self) {
        let o = self.objects.last().map(|o| (o.centre(), radius(&o.shape)));
        if let Some((c, r)) = o {
            let range = c[0].hypot(c[1]);
            self.keep_clear
                .push((range, c[0].atan2(c[1]), half_span(r, range)));
        }
    }

    /// The clutter around the objects of interest: [`Self::side_lobe_clutter`], then
    /// [`Self::background_clutter`].
    fn clutter(&mut self) {
        let targets = self.keep_clear.clone();
        self.side_lobe_clutter(&targets);
        if self.difficulty == Difficulty::Hard {
            self.in_beam_clutter(&targets);
        }
        self.background_clutter();
    }

    /// Hard scenes: for every target, a strong reflector inside an 8-element radar's beam
    /// (within 7° of the target's azimuth) at another range: behind it (3–25 m) or nearer and
    /// just beside its span (1–4° outside, so the camera still sees the target).
    fn in_beam_clutter(&mut self, targets: &[(f64, f64, f64)]) {
        for &(range, az, span) in targets {
            let class = ["pole", "wall", "vehicle_parked"][self.rng.random_range(0..3)];
            let side = if self.rng.random_range(0.0..1.0) < 0.5 {
                -1.0
            } else {
                1.0
            };
            let behind = (
                range + self.rng.random_range(3.0..25.0),
                az.to_degrees() + side * self.rng.random_range(0.0..7.0),
            );
            let nearer = (
                (range - self.rng.random_range(3.0..20.0)).max(3.0),
                az.to_degrees() + side * (span.to_degrees() + self.rng.random_range(1.0..4.0)),
            );
            let order = if self.rng.random_range(0.0..1.0) < 0.5 {
                [nearer, behind]
            } else {
                [behind, nearer]
            };
            // The other place when the first is taken or would hide the target.
            for (r, a) in order {
                if self.try_place(class, r - 1.0..r + 1.0, a - 0.5..a + 0.5, [0.0, 0.0]) {
                    break;
                }
            }
        }
    }

    /// The paper's failure case for most `targets` (range, azimuth, half-span): a strong
    /// reflector at another azimuth (3–12° outside the span) and another range (2–12 m).
    fn side_lobe_clutter(&mut self, targets: &[(f64, f64, f64)]) {
        for &(range, az, span) in targets {
            if self.rng.random_range(0.0..1.0) < 0.75 {
                let side = if self.rng.random_range(0.0..1.0) < 0.5 {
                    -1.0
                } else {
                    1.0
                };
                let off = span.to_degrees() + self.rng.random_range(3.0..12.0);
                let dr = self.rng.random_range(2.0..12.0)
                    * if self.rng.random_range(0.0..1.0) < 0.5 {
                        -1.0
                    } else {
                        1.0
                    };
                let class =
                    ["pole", "wall", "building", "vehicle_parked"][self.rng.random_range(0..4)];
                let r = (range + dr).max(3.0);
                let a = az.to_degrees() + side * off;
                self.try_place(class, r - 1.0..r + 1.0, a - 1.0..a + 1.0, [0.0, 0.0]);
            }
        }
    }

    /// Buildings, poles, parked vehicles, trees, a fence and a wall anywhere in view.
    fn background_clutter(&mut self) {
        let far = self.max_range * 0.9;
        let n = |rng: &mut dyn rand::RngCore, lo: usize, hi: usize| {
            (rng.next_u32() as usize % (hi - lo + 1)) + lo
        };
        let buildings = n(self.rng, 0, 2);
        for _ in 0..buildings {
            self.try_place("building", 15.0..far.max(16.0), -60.0..60.0, [0.0, 0.0]);
        }
        for (class, lo, hi) in [
            ("pole", 1, 5),
            ("vehicle_parked", 1, 4),
            ("tree", 0, 3),
            ("fence", 0, 1),
            ("wall", 0, 1),
        ] {
            for _ in 0..n(self.rng, lo, hi) {
                self.try_place(class, 4.0..far.max(5.0), -60.0..60.0, [0.0, 0.0]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn far_movers_are_cars_to_300_m_and_people_to_230_m() {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(17);
        let (mut cars, mut people) = (0, 0);
        for difficulty in [Difficulty::Standard, Difficulty::Hard] {
            for _ in 0..400 {
                let (class, range, speed) = interest(Preset::FarMoving, difficulty, &mut rng);
                let reach = match class {
                    "car" => {
                        cars += 1;
                        300.0
                    }
                    "person" => {
                        people += 1;
                        230.0
                    }
                    other => panic!("{other}"),
                };
                assert!((100.0..reach).contains(&range), "{class} at {range} m");
                assert!(speed >= 0.8, "{class} at {speed} m/s");
            }
        }
        // About half each.
        assert!(cars > 320 && people > 320, "{cars} cars, {people} people");
    }
}
