//! ONNX camera models through tract (`process --segmenter/--depth-model`), checked against
//! independent references:
//!
//! * a network of MaxPool, Conv, Relu, Resize and Sigmoid, against numpy in float64;
//! * a segmenter and a depth network whose outputs are known in closed form (see
//!   `oracles/camera_models.py`), run on an image drawn from a simulated bundle's own mask and
//!   depth: the products they make must be that mask (up to instance numbering) and that depth,
//!   and `process` must give the same estimates as from the bundle's files.
//!
//! The models are written by the `onnx` package from PyPI in the test venv.

use metamoran_bundle::{Bundle, CameraModels, CameraPaths, OpenOptions};
use metamoran_e2e::run_oracle;
use metamoran_process::{Mode, ProcessOptions, process};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Writes the test models into a temporary folder (`None`: no venv, test skipped).
fn models() -> Option<(tempfile::TempDir, PathBuf)> {
    let dir = tempfile::tempdir().unwrap();
    run_oracle("camera_models.py", &[dir.path().as_os_str()], "onnx")?;
    let path = dir.path().to_owned();
    Some((dir, path))
}

fn json<T: serde::de::DeserializeOwned>(path: &Path) -> T {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn tract_runs_a_small_network_as_numpy_does() {
    let Some((_keep, dir)) = models() else { return };
    let net = metamoran_vision::Network::load(&dir.join("fixed.onnx")).unwrap();
    assert_eq!(net.fixed_size(), Some((12, 8)));
    let x: Vec<f64> = json(&dir.join("fixed_input.json"));
    let want: Vec<f64> = json(&dir.join("fixed_expected.json"));
    let image = metamoran_vision::Image {
        width: 12,
        height: 8,
        planes: x.iter().map(|&v| v as f32).collect(),
    };
    let out = net.run(&image).unwrap();
    assert_eq!((out.channels, out.width, out.height), (2, 12, 8));
    let worst = out
        .values
        .iter()
        .zip(&want)
        .map(|(&g, &w)| (f64::from(g) - w).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-5, "largest difference from numpy {worst}");
    // Another image size: resized to the model's 12 × 8 and the output back to the image's.
    let big = metamoran_vision::Image {
        width: 24,
        height: 16,
        planes: vec![0.5; 3 * 24 * 16],
    };
    let out = net.run(&big).unwrap();
    assert_eq!(
        (out.width, out.height, out.values.len()),
        (24, 16, 2 * 24 * 16)
    );
}

#[test]
fn bad_models_are_clear_errors() {
    let Some((_keep, dir)) = models() else { return };
    let junk = dir.join("junk.onnx");
    std::fs::write(&junk, b"not a model").unwrap();
    let err = CameraModels::load(Some(&junk), None)
        .unwrap_err()
        .to_string();
    assert!(err.contains("junk.onnx") && err.contains("ONNX"), "{err}");
    // A depth network used as a segmenter has no labels.
    let err = CameraModels::load(Some(&dir.join("depth.onnx")), None)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("depth.onnx") && err.contains("labels"),
        "{err}"
    );
}

/// Draws `F_image.png` (16-bit RGB) from a bundle's products: each pixel is its class colour
/// times its KITTI depth value, so the test models recover both exactly.
fn draw_image(bundle: &Path, frame: u32, palette: &serde_json::Value) {
    let b = Bundle::open(bundle, OpenOptions::default()).unwrap();
    let cam = b.camera_frame(frame).unwrap();
    let labels: Vec<&str> = palette["labels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap())
        .collect();
    let colours: Vec<[f64; 3]> = palette["colours"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| [0, 1, 2].map(|i| c[i].as_f64().unwrap()))
        .collect();
    let class_of: HashMap<u16, usize> = cam
        .instances
        .iter()
        .map(|i| (i.id, labels.iter().position(|l| *l == i.class).unwrap()))
        .collect();
    let mut bytes = Vec::new();
    for (&id, &v) in cam.mask.iter().zip(&cam.depth) {
        let colour = colours[if id == 0 { 0 } else { class_of[&id] }];
        for c in colour {
            bytes.extend_from_slice(&((f64::from(v) * c).round() as u16).to_be_bytes());
        }
    }
    let path = CameraPaths::new(bundle, frame).image;
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(file, cam.width, cam.height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Sixteen);
    enc.write_header()
        .unwrap()
        .write_image_data(&bytes)
        .unwrap();
}

#[test]
fn process_from_the_image_matches_the_bundles_own_products() {
    let Some((_keep, dir)) = models() else { return };
    let palette: serde_json::Value = json(&dir.join("palette.json"));
    let scenes = tempfile::tempdir().unwrap();
    let bundles = metamoran_sim::simulate(
        metamoran_sim::layout::Preset::ParkingLot,
        metamoran_sim::radar::RadarKind::Xwr18xx,
        21,
        3,
        scenes.path(),
        &|| (),
    )
    .unwrap();
    let models = CameraModels::load(
        Some(&dir.join("segmenter.onnx")),
        Some(&dir.join("depth.onnx")),
    )
    .unwrap();
    let with_models = OpenOptions {
        camera_models: models,
        ..OpenOptions::default()
    };
    let mut objects = 0;
    for bundle in &bundles {
        draw_image(bundle, 0, &palette);
        let own = Bundle::open(bundle, OpenOptions::default())
            .unwrap()
            .camera_frame(0)
            .unwrap();
        // Only the image is left.
        let image_only = scenes.path().join("image-only");
        let _ = std::fs::remove_dir_all(&image_only);
        std::fs::create_dir_all(image_only.join("camera")).unwrap();
        for f in ["scene.toml", "radar.bin", "truth.json"] {
            std::fs::copy(bundle.join(f), image_only.join(f)).unwrap();
        }
        let image = CameraPaths::new(bundle, 0).image;
        std::fs::copy(&image, CameraPaths::new(&image_only, 0).image).unwrap();
        let err = Bundle::open(&image_only, OpenOptions::default()).unwrap_err();
        assert!(err.to_string().contains("000000_mask.png"), "{err}");

        let made = Bundle::open(&image_only, with_models.clone())
            .unwrap()
            .camera_frame(0)
            .unwrap();
        assert_eq!(made.depth, own.depth, "depth differs from F_depth.png");
        // The mask is the bundle's up to numbering: a one-to-one map of ids, classes kept
        // (regions under MIN_INSTANCE_PIXELS become background).
        let mut size: HashMap<u16, usize> = HashMap::new();
        for &id in &own.mask {
            *size.entry(id).or_default() += 1;
        }
        let mut map: HashMap<u16, u16> = HashMap::new();
        let mut back: HashMap<u16, u16> = HashMap::new();
        for ((&a, &b), &v) in own.mask.iter().zip(&made.mask).zip(&own.depth) {
            // A pixel without depth is black in the image: no class can be seen there.
            if a == 0 || v == 0 {
                assert_eq!(b, 0);
                continue;
            }
            if size[&a] < metamoran_bundle::camera_models::MIN_INSTANCE_PIXELS {
                continue;
            }
            assert_eq!(*map.entry(a).or_insert(b), b, "instance {a} split");
            assert_eq!(*back.entry(b).or_insert(a), a, "instances merged into {b}");
        }
        for (a, b) in &map {
            let class = |insts: &[metamoran_bundle::Instance], id| {
                insts.iter().find(|i| i.id == id).unwrap().class.clone()
            };
            assert_eq!(class(&own.instances, *a), class(&made.instances, *b));
        }

        // The estimates are the same, object for object.
        let from_files = process(bundle, &ProcessOptions::mode(Mode::Metamoran)).unwrap();
        let from_image = process(
            &image_only,
            &ProcessOptions {
                open: with_models.clone(),
                ..ProcessOptions::mode(Mode::Metamoran)
            },
        )
        .unwrap();
        let by_id = |out: &metamoran_process::ProcessOutput| -> HashMap<u16, Option<f64>> {
            out.frames[0]
                .objects
                .iter()
                .map(|o| (o.instance, o.depth_m))
                .collect()
        };
        let (want, got) = (by_id(&from_files), by_id(&from_image));
        for (id, depth) in &want {
            if let Some(new_id) = map.get(id) {
                assert_eq!(got[new_id], *depth, "object {id} (now {new_id})");
                objects += 1;
            }
        }
    }
    assert!(objects >= 3, "only {objects} objects compared");
}
