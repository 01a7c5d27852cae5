//! The Metamoran method on fresh simulated scenes (seeds used nowhere else): the production
//! search agrees with the brute-force reference, and the method meets the accuracy goals.

use metamoran_bundle::geometry::CameraModel;
use metamoran_bundle::{Bundle, OpenOptions};
use metamoran_dsp::search::depth::FINE_STEPS_PER_BIN;
use metamoran_process::Mode;
use metamoran_process::camera_points::objects_of_interest;
use metamoran_process::eval;
use metamoran_process::metamoran::{StaticScene, both_searches, prepare};
use metamoran_sim::{layout::Preset, radar::RadarKind, simulate};

#[test]
fn coarse_to_fine_agrees_with_brute_force() {
    let tmp = tempfile::tempdir().unwrap();
    let dirs = simulate(
        Preset::ParkingLot,
        RadarKind::Xwr18xx,
        31_337,
        24,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    let (mut agree, mut total, mut worst_ratio) = (0, 0, f64::INFINITY);
    for dir in &dirs {
        let mut b = Bundle::open(dir, OpenOptions::default()).unwrap();
        let cam = b.camera_frame(0).unwrap();
        let mut frame = Vec::new();
        b.read_radar_frame(0, &mut frame).unwrap();
        let mut scene = StaticScene::new(&b.scene.radar, &frame).unwrap();
        for obj in objects_of_interest(&CameraModel::new(&b.scene.camera), &cam) {
            let Some(p) = prepare(&mut scene, &obj) else {
                continue;
            };
            let (fast, reference) = both_searches(&mut scene, &p).unwrap();
            total += 1;
            if (fast.depth_bins - reference.depth_bins).abs()
                <= 1.0 / FINE_STEPS_PER_BIN as f32 + 1e-3
            {
                agree += 1;
            }
            worst_ratio = worst_ratio.min(reference.macs as f64 / fast.macs as f64);
        }
    }
    println!("agreement {agree}/{total}, smallest MAC ratio {worst_ratio:.0}×");
    assert!(total >= 24);
    assert!(
        agree as f64 >= 0.99 * total as f64,
        "coarse-to-fine agreed on {agree} of {total}"
    );
    // The 8-channel, 256-sample board here has less to save than the cascade (brute force
    // scales with C·N): 345× at worst on these seeds (issue #18: the bound was a loose 50×).
    assert!(worst_ratio >= 300.0, "MAC ratio {worst_ratio}");
}

/// `metamoran bench search`'s figure in the README (cascade-86, 512 samples: 1714× fewer MACs
/// than the brute force, the same depth). MAC counts are exact, so the bound is tight.
#[test]
fn the_cascade_search_costs_what_the_readme_says() {
    let r = metamoran::bench::search::run().unwrap();
    println!("{r}");
    assert!(
        (1650.0..1800.0).contains(&r.mac_ratio),
        "MAC ratio {} (README: 1714×)",
        r.mac_ratio
    );
    assert!(
        (r.depths_m.0 - r.depths_m.1).abs() < 0.01,
        "{:?}",
        r.depths_m
    );
}

#[test]
fn meets_the_accuracy_goals_on_static_scenes() {
    let tmp = tempfile::tempdir().unwrap();
    simulate(
        Preset::ParkingLot,
        RadarKind::Cascade,
        90_001,
        30,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    simulate(
        Preset::LongRange,
        RadarKind::Cascade,
        90_002,
        30,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    let (report, samples) = eval::run(tmp.path(), &[Mode::Metamoran, Mode::Naive], &|| ()).unwrap();
    println!("{report}");
    let m = &report.modes["metamoran"].all;
    assert!(m.mae_m.unwrap() <= 0.20, "median error {:?}", m.mae_m);
    assert!(m.mhd_m.unwrap() <= 0.6, "median MHD {:?}", m.mhd_m);
    let cars: Vec<_> = samples
        .iter()
        .filter(|s| s.mode == Mode::Metamoran && s.class == "car" && s.truth_m < 90.0)
        .collect();
    let detected = cars.iter().filter(|s| s.error_m.is_some()).count();
    assert!(
        detected as f64 >= 0.95 * cars.len() as f64,
        "cars detected {detected}/{}",
        cars.len()
    );
    // Far fewer gross errors than naive fusion.
    let naive = &report.modes["naive"].all;
    assert!(
        m.over_1m.unwrap() * 3.0 < naive.over_1m.unwrap(),
        "over 1 m: {:?} vs naive {:?}",
        m.over_1m,
        naive.over_1m
    );
}

#[test]
fn finds_moving_cars_to_300_m() {
    let tmp = tempfile::tempdir().unwrap();
    simulate(
        Preset::Moving,
        RadarKind::Cascade,
        90_003,
        24,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    let (_, samples) = eval::run(tmp.path(), &[Mode::Metamoran], &|| ()).unwrap();
    let good = |s: &eval::Sample| s.error_m.is_some_and(|e| e.abs() < 1.0);
    let cars: Vec<&eval::Sample> = samples.iter().filter(|s| s.class == "car").collect();
    let far: Vec<&eval::Sample> = cars.iter().copied().filter(|s| s.truth_m > 200.0).collect();
    let (good_all, good_far) = (
        cars.iter().filter(|s| good(s)).count(),
        far.iter().filter(|s| good(s)).count(),
    );
    println!(
        "cars within 1 m: {good_all}/{}; beyond 200 m: {good_far}/{}",
        cars.len(),
        far.len()
    );
    assert!(!far.is_empty(), "the seed drew no car beyond 200 m");
    // Measured on this seed: 8 of 10 cars within 1 m, 4 of 4 beyond 200 m, median error of the
    // detected ones near the README's 0.21 m (issue #18: the bounds were half of that).
    assert!(
        good_far as f64 >= 0.75 * far.len() as f64,
        "far cars within 1 m: {good_far}/{}",
        far.len()
    );
    assert!(good_all as f64 >= 0.8 * cars.len() as f64);
    let mut errors: Vec<f64> = cars
        .iter()
        .filter_map(|s| s.error_m.map(f64::abs))
        .collect();
    errors.sort_by(f64::total_cmp);
    let median = errors[errors.len() / 2];
    println!("median |error| of detected cars {median:.3} m");
    assert!(median <= 0.3, "median {median}");
}

/// Issue #17 on fresh seeds of every preset and both radars: what the trust test calls detected
/// is right (confidently wrong — detected and > 3 m off — at most 2 % of objects), its
/// confidence is calibrated (each reliability bin with enough objects within 15 points of what
/// it predicts), and a mover's reported radial velocity is the simulator's (modulo what one
/// frame can tell).
#[test]
fn the_trust_test_is_calibrated_and_rarely_confidently_wrong() {
    let tmp = tempfile::tempdir().unwrap();
    for (preset, radar, seed, count) in [
        (Preset::ParkingLot, RadarKind::Cascade, 90_171, 16),
        (Preset::ParkingLot, RadarKind::Xwr18xx, 90_172, 16),
        (Preset::Moving, RadarKind::Cascade, 90_173, 16),
        (Preset::Moving, RadarKind::Xwr18xx, 90_174, 8),
    ] {
        simulate(preset, radar, seed, count, tmp.path(), &|| ()).unwrap();
    }
    let (report, samples) = eval::run(tmp.path(), &[Mode::Metamoran], &|| ()).unwrap();
    println!("{report}");
    let m = &report.modes["metamoran"];
    assert!(
        m.all.confidently_wrong <= 0.02,
        "confidently wrong {:.3}",
        m.all.confidently_wrong
    );
    // Calibrated: each bin's observed rate within two binomial standard errors (plus 5 points)
    // of its mean prediction.
    for bin in m.reliability.iter().filter(|b| b.n >= 10) {
        let (p, o) = (bin.predicted.unwrap(), bin.observed.unwrap());
        let tolerance = 0.05 + 2.0 * (p * (1.0 - p) / bin.n as f64).sqrt();
        assert!((p - o).abs() <= tolerance, "{bin:?}");
    }
    // A single frame of uniform TDM samples the scene's phase once per chirp period T, so a
    // radial velocity is known modulo λ / (2T) (32.4 m/s at 77 GHz and 60 µs): the truth is
    // folded into that interval before comparing.
    let mut folded = Vec::new();
    for s in &samples {
        let Some(e) = s.velocity_error_mps else {
            continue;
        };
        let b = Bundle::open(&tmp.path().join(&s.bundle), OpenOptions::default()).unwrap();
        let r = &b.scene.radar;
        let interval = r.wavelength_m() / (2.0 * r.chirp_period_s);
        folded.push(e - interval * (e / interval).round());
    }
    println!(
        "{} movers with a velocity: folded errors {folded:?}",
        folded.len()
    );
    assert!(folded.len() >= 10);
    // Within two Doppler bins (the cascade's bin is 0.17 m/s, the 8-element board's 1 m/s).
    let close = folded.iter().filter(|e| e.abs() <= 2.1).count();
    assert!(close as f64 >= 0.9 * folded.len() as f64, "{folded:?}");
}

/// Issue #17's far movers on fresh seeds of their own preset (cars at 100–300 m, people at
/// 100–230 m, cascade): people detected ≥ 70 % (the goal), cars detected ≥ 85 % (goal 90 %:
/// 86–100 % per seed of 48 scenes, so the test guards what holds) within a median 1.0 m, and
/// confidently wrong (detected and > 3 m off) at most 2 % of the objects.
#[test]
fn far_movers_are_found_to_300_m() {
    let tmp = tempfile::tempdir().unwrap();
    simulate(
        Preset::FarMoving,
        RadarKind::Cascade,
        90_176,
        48,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    let (_, samples) = eval::run(tmp.path(), &[Mode::Metamoran], &|| ()).unwrap();
    let share = |class: &str, f: &dyn Fn(&eval::Sample) -> bool| {
        let of: Vec<_> = samples.iter().filter(|s| s.class == class).collect();
        assert!(of.len() >= 20, "{} {class}", of.len());
        of.iter().filter(|s| f(s)).count() as f64 / of.len() as f64
    };
    let detected = |s: &eval::Sample| s.error_m.is_some();
    let (people, cars) = (share("person", &detected), share("car", &detected));
    println!("detected: people {people:.3}, cars {cars:.3}");
    assert!(people >= 0.7, "people detected {people}");
    assert!(cars >= 0.85, "cars detected {cars}");
    let mut errors: Vec<f64> = samples
        .iter()
        .filter(|s| s.class == "car")
        .filter_map(|s| s.error_m.map(f64::abs))
        .collect();
    errors.sort_by(f64::total_cmp);
    assert!(errors[errors.len() / 2] <= 1.0, "{errors:?}");
    let wrong = samples
        .iter()
        .filter(|s| s.error_m.is_some_and(|e| e.abs() > 3.0))
        .count();
    assert!(
        wrong as f64 <= 0.02 * samples.len() as f64,
        "{wrong} of {} confidently wrong",
        samples.len()
    );
}

/// A far car's strongest return in its Doppler bin is often its body, metres behind the closest
/// point the depth is about, and its mask (a few pixels) gives the template no shape to place
/// the closest point with: the Doppler path reports the mover's leading edge too
/// (`metamoran_process::lead`). On the 8-element board's far movers of this seed, without it a
/// car at 4.1 m behind its closest point was reported as detected; with it no detected car is
/// more than 3 m off (and 15 of the 22 are detected).
#[test]
fn a_far_car_is_reported_at_its_closest_point_not_its_body() {
    let tmp = tempfile::tempdir().unwrap();
    simulate(
        Preset::FarMoving,
        RadarKind::Xwr18xx,
        90_177,
        32,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    let (_, samples) = eval::run(tmp.path(), &[Mode::Metamoran], &|| ()).unwrap();
    let cars: Vec<&eval::Sample> = samples.iter().filter(|s| s.class == "car").collect();
    let detected: Vec<f64> = cars.iter().filter_map(|s| s.error_m).collect();
    println!("{} cars, detected errors {detected:?}", cars.len());
    assert!(cars.len() >= 20, "{} cars", cars.len());
    assert!(detected.len() >= 12, "{} detected", detected.len());
    assert!(
        detected.iter().all(|e| e.abs() <= 3.0),
        "confidently wrong cars: {detected:?}"
    );
}

/// A car at 241 m, past the 256 m the depth image holds once its monocular error is added: only
/// its mask's grown bottom row has a depth, the ground's, whose spread across the mask is
/// metres. Taken for the car's contour it put the depth 3.8 m in front of the car (detected, at
/// confidence 0.97); with a flat contour the depth is within 1 m.
#[test]
fn a_mask_without_its_own_depths_gets_a_flat_contour() {
    let tmp = tempfile::tempdir().unwrap();
    metamoran_sim::simulate_one(
        Preset::FarMoving,
        RadarKind::Cascade,
        10_501,
        89,
        &tmp.path().join("far-car"),
    )
    .unwrap();
    let (_, samples) = eval::run(tmp.path(), &[Mode::Metamoran], &|| ()).unwrap();
    let [car] = samples.as_slice() else {
        panic!("{samples:?}")
    };
    let truth = car.truth_m;
    assert!((240.0..241.5).contains(&truth), "another scene: {truth}");
    let error = car.error_m.expect("detected");
    assert!(error.abs() <= 1.0, "{error} m off");
}
