//! 3D-RadarHR, the dense-radar-mapping paper's network (issue #7), as shipped:
//!
//! * tract runs both shipped ONNX graphs (the small board's and the imaging board's, which also
//!   takes the submap's IP-Basic completion as a guide) as an independent numpy float64
//!   evaluation of them does (`oracles/onnx_reference.py`, written from the ONNX operator
//!   definitions), on a real submap depth image;
//! * on drive scenes it was not trained on (the training script uses seed 5000), its depth image
//!   is closer to the lidar truth than IP-Basic's on every scene and than the submap's over the
//!   scenes, and it covers most of what the lidar sees;
//! * the imaging board's network, on a tunnel (an environment held out of its training):
//!   over every lidar pixel it is better than the submap, which is better than the frame, and
//!   it is more than 50× as dense as the frame; on a street it did not see, its points are
//!   within 0.1 m of the lidar's (median) and it beats IP-Basic, which beats the submap;
//! * a model that breaks the contract, or a bad depth image, is refused with a message naming
//!   the model.

use metamoran_e2e::run_oracle;
use metamoran_map::network::{Board, CompletionNetwork};
use metamoran_map::{depth, ip_basic, report};
use metamoran_sim::drive::MOUNT;
use metamoran_sim::{layout::Preset, radar::RadarKind, simulate};
use metamoran_vision::RadarHr;
use std::path::PathBuf;

fn scenes(
    preset: Preset,
    kind: RadarKind,
    seed: u64,
    count: u64,
) -> (tempfile::TempDir, Vec<PathBuf>) {
    let dir = tempfile::tempdir().unwrap();
    let dirs = simulate(preset, kind, seed, count, dir.path(), &|| ()).unwrap();
    (dir, dirs)
}

/// Drive scenes of the small board.
fn drives(seed: u64, count: u64) -> (tempfile::TempDir, Vec<PathBuf>) {
    scenes(Preset::Drive, RadarKind::Xwr18xx, seed, count)
}

#[test]
fn tract_runs_the_shipped_networks_as_numpy_does() {
    let (_keep, dirs) = drives(8, 1);
    let odometry = metamoran_map::odometry::run(&dirs[0], &MOUNT).unwrap();
    let images = depth::last(&dirs[0], &odometry, None).unwrap().unwrap();
    for (name, bytes) in [
        ("radarhr.onnx", metamoran_vision::radarhr::SHIPPED),
        (
            "radarhr-imaging.onnx",
            metamoran_vision::radarhr::SHIPPED_IMAGING,
        ),
    ] {
        let net = RadarHr::from_bytes(std::path::Path::new(name), bytes).unwrap();
        assert_eq!(net.size(), (320, 80));
        // A guided model's second image is the submap's IP-Basic completion, as `map` gives it.
        let submap = &images.submap.range_m;
        let guide = (net.channels() == 2).then(|| ip_basic::complete(submap));
        let got = net.complete(submap, guide.as_deref()).unwrap();

        // The reference gets the input as the contract defines it (depth / max, clipped to 1).
        let max = net.max_depth_m();
        let tmp = tempfile::tempdir().unwrap();
        let (model, input, output) = (
            tmp.path().join(name),
            tmp.path().join("in.f32"),
            tmp.path().join("out.f64"),
        );
        std::fs::write(&model, bytes).unwrap();
        let input_bytes: Vec<u8> = submap
            .iter()
            .chain(guide.iter().flatten())
            .flat_map(|r| (r / max).min(1.0).to_le_bytes())
            .collect();
        std::fs::write(&input, input_bytes).unwrap();
        let args = [model.as_os_str(), input.as_os_str(), output.as_os_str()];
        if run_oracle("onnx_reference.py", &args, "onnx").is_none() {
            return;
        }
        let want: Vec<f64> = std::fs::read(&output)
            .unwrap()
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()) * f64::from(max))
            .collect();
        assert_eq!(want.len(), got.len());
        let mut compared = 0;
        for (i, (&g, &w)) in got.iter().zip(&want).enumerate() {
            // Depths under 1 m read as "no return"; a pixel within 1 mm of that line may fall
            // either side of it.
            if (w - 1.0).abs() < 1e-3 {
                continue;
            }
            let w = if w >= 1.0 { w } else { 0.0 };
            assert!(
                (f64::from(g) - w).abs() < 1e-3,
                "{name}, pixel {i}: tract {g} m, numpy {w} m"
            );
            compared += 1;
        }
        assert!(compared > 20_000, "{name}: {compared} pixels compared");
    }
}

#[test]
fn the_network_beats_ip_basic_and_the_submap_on_unseen_drives() {
    let (_keep, dirs) = drives(41, 3);
    let net = CompletionNetwork::load(None, Board::Small).unwrap();
    let complete = |r: &[f32]| net.complete(r);
    let (mut network_mae, mut submap_mae, mut accuracies) = (0.0, 0.0, Vec::new());
    for dir in &dirs {
        let (rep, _, images) = report::run(dir, &MOUNT, Some(&complete)).unwrap();
        let images = images.unwrap();
        let (mae, rmse) = (rep.mae_m.unwrap(), rep.rmse_m.unwrap());
        let accuracy = rep.point_accuracy_m.unwrap().network.unwrap();
        eprintln!(
            "{}: MAE {mae:?} RMSE {rmse:?} point accuracy {accuracy}",
            dir.display()
        );
        accuracies.push(accuracy);
        // Against IP-Basic, the paper's conventional completion, on every scene.
        assert!(mae.network.unwrap() < mae.ip_basic.unwrap(), "{mae:?}");
        assert!(rmse.network.unwrap() < rmse.ip_basic.unwrap(), "{rmse:?}");
        network_mae += mae.network.unwrap();
        submap_mae += mae.submap.unwrap();
        // Dense: nearly every pixel the lidar sees (the submap covers 3–5 %).
        let lidar = images.lidar.unwrap();
        let covered = |img: &metamoran_map::cylinder::DepthImage| {
            img.range_m
                .iter()
                .zip(&lidar.range_m)
                .filter(|&(&a, &b)| a > 0.0 && b > 0.0)
                .count() as f64
                / lidar.filled() as f64
        };
        let (n, s) = (covered(&images.network.unwrap()), covered(&images.submap));
        eprintln!("  lidar pixels covered: network {n:.3}, submap {s:.3}");
        assert!(n > 0.75 && n > 10.0 * s, "coverage {n} vs the submap's {s}");
        assert!(rep.network_fps.unwrap() > 0.0);
    }
    // The submap's error swings with how many wall points land in ground rows (3.6–14 m on
    // these scenes); over the three the network's is lower.
    assert!(
        network_mae < submap_mae,
        "mean MAE: network {} m, submap {} m",
        network_mae / 3.0,
        submap_mae / 3.0
    );
    // Point accuracy (median distance to the nearest lidar point) within a decimetre on the
    // median scene: 0.07, 0.09 and 0.77 m here. The network trained with the paper's loss alone
    // (before session 30's L1 term) was 0.46, 0.33 and 0.88 m.
    accuracies.sort_by(f64::total_cmp);
    assert!(accuracies[1] <= 0.1, "point accuracy {accuracies:?} m");
}

/// The imaging board's report of scene 0 of `preset` at `seed`, mapped with its shipped network
/// and its default submap options.
fn imaging_report(preset: Preset, seed: u64) -> report::MapReport {
    let (_keep, dirs) = scenes(preset, RadarKind::Imaging, seed, 1);
    let net = CompletionNetwork::load(None, Board::Imaging).unwrap();
    let complete = |r: &[f32]| net.complete(r);
    let (rep, _, _) = report::run_with(
        &dirs[0],
        &MOUNT,
        Some(&complete),
        &Board::Imaging.submap_options(),
    )
    .unwrap();
    rep
}

#[test]
fn the_imaging_network_completes_a_tunnel_it_never_saw() {
    // The imaging board's network was trained on streets, parking areas and covered car parks
    // (scripts/train-radarhr, BOARD=imaging): the tunnel is the held-out environment.
    // The street of the test below, for the comparison at the end, mapped alongside.
    let (rep, street) = std::thread::scope(|s| {
        let street = s.spawn(|| imaging_report(Preset::Drive, 44));
        (imaging_report(Preset::Tunnel, 43), street.join().unwrap())
    });
    let lidar = rep.lidar_pixels.unwrap().mae_m;
    eprintln!(
        "tunnel: MAE over every lidar pixel {lidar:?}, over both {:?}, density growth {:?} / {:?}",
        rep.mae_m, rep.density_growth_factor, rep.network_density_growth_factor
    );
    let (frame, submap, network) = (
        lidar.frame.unwrap(),
        lidar.submap.unwrap(),
        lidar.network.unwrap(),
    );
    // Over every lidar pixel (an empty pixel counting as 0 m) the submap adds to the frame and
    // the network completes both: each better than the one before.
    assert!(
        network < 0.7 * submap && submap < frame,
        "frame {frame}, submap {submap}, network {network}"
    );
    // The paper's "more than 50×" density over a single frame.
    assert!(rep.network_density_growth_factor.unwrap() > 50.0, "{rep:?}");
    // Better than IP-Basic's dilation, whose walls and ceiling fill the view at 3–5 m. The
    // network trained without a roof (streets and parking areas only) was worse than IP-Basic
    // here: 4.58 m against 4.05 m.
    let ip_basic = lidar.ip_basic.unwrap();
    assert!(
        network < 0.7 * ip_basic,
        "IP-Basic {ip_basic}, network {network}"
    );
    // Issue #21: the held-out environment within twice the error of a street it never saw,
    // over every lidar pixel (the roofless network: 4.58 m against 1.07 m).
    let street = street.lidar_pixels.unwrap().mae_m.network.unwrap();
    assert!(
        network <= 2.0 * street,
        "tunnel {network} m, street {street} m"
    );
}

#[test]
fn the_imaging_network_places_an_unseen_street_within_a_decimetre() {
    // Issue #21's street goal for point accuracy: the median distance from the network's points
    // to the nearest lidar point at most 0.1 m. Seed 44 is in neither training nor validation
    // (streets of seed 6000, parking areas of seed 6100, car parks of seed 6200). The network
    // trained with the paper's loss alone was 0.3-0.4 m here.
    let rep = imaging_report(Preset::Drive, 44);
    let acc = rep.point_accuracy_m.unwrap();
    let lidar = rep.lidar_pixels.unwrap().mae_m;
    eprintln!("street: point accuracy {acc:?}, MAE over every lidar pixel {lidar:?}");
    let network = acc.network.unwrap();
    assert!(network <= 0.1, "network point accuracy {network} m");
    // Over every lidar pixel each stage is better than the one before, the network by far.
    let (frame, submap, ip_basic, network) = (
        lidar.frame.unwrap(),
        lidar.submap.unwrap(),
        lidar.ip_basic.unwrap(),
        lidar.network.unwrap(),
    );
    assert!(
        network < 0.5 * ip_basic && ip_basic < submap && submap < frame,
        "frame {frame}, submap {submap}, IP-Basic {ip_basic}, network {network}"
    );
}

#[test]
fn bad_models_and_images_are_refused_naming_the_model() {
    let tmp = tempfile::tempdir().unwrap();
    let cut = tmp.path().join("cut.onnx");
    std::fs::write(&cut, &metamoran_vision::radarhr::SHIPPED[..1000]).unwrap();
    let err = RadarHr::load(&cut).err().unwrap().to_string();
    assert!(err.contains("cut.onnx"), "{err}");
    let missing = tmp.path().join("missing.onnx");
    let err = RadarHr::load(&missing).err().unwrap().to_string();
    assert!(err.contains("missing.onnx"), "{err}");
    let net = RadarHr::shipped().unwrap();
    let err = net.complete(&[0.0; 100], None).unwrap_err().to_string();
    assert!(err.contains("100 pixels") && err.contains("320"), "{err}");
    let mut img = vec![0.0f32; 320 * 80];
    img[7] = f32::NAN;
    let err = net.complete(&img, None).unwrap_err().to_string();
    assert!(err.contains("pixel 7"), "{err}");
    // The small board's model takes one image; a guide is refused, not ignored.
    let err = net.complete(&img, Some(&img)).unwrap_err().to_string();
    assert!(err.contains("takes 1 image"), "{err}");
    // A camera model (input [1, 3, H, W]) is not a depth-completion network.
    if run_oracle("camera_models.py", &[tmp.path().as_os_str()], "onnx").is_some() {
        let err = RadarHr::load(&tmp.path().join("fixed.onnx"))
            .err()
            .unwrap()
            .to_string();
        assert!(
            err.contains("fixed.onnx") && err.contains("[1, 1, H, W]"),
            "{err}"
        );
    }
}
