//! The engineer's products: `process --out` and `inspect` on a simulated cascade scene, checked
//! against the scene's truth and against the definition of what each plot shows, not against the
//! code's own output: the chosen depth is the truth's, the score curve peaks there, the map after
//! SIC is weaker than before at every reflector SIC cancelled, and the PNGs decode with the
//! colours their legends name.

use metamoran_bundle::OpenOptions;
use metamoran_operator::inspect;
use metamoran_operator::outputs::write_products;
use metamoran_process::inspect::ObjectView;
use metamoran_process::{Mode, ProcessOptions, process};
use metamoran_sim::{layout::Preset, radar::RadarKind, simulate};

fn decode_rgb(path: &std::path::Path) -> (u32, u32, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())),
    ));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0u8; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb, "{}", path.display());
    let pixels = buf[..info.buffer_size()]
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    (info.width, info.height, pixels)
}

fn count(pixels: &[[u8; 3]], colour: [u8; 3]) -> usize {
    pixels.iter().filter(|&&p| p == colour).count()
}

fn median(mut v: Vec<f32>) -> f32 {
    v.sort_by(f32::total_cmp);
    v[v.len() / 2]
}

#[test]
fn inspect_and_process_out_show_what_the_module_decided() {
    let dir = tempfile::tempdir().unwrap();
    let bundles = simulate(
        Preset::ParkingLot,
        RadarKind::Cascade,
        3,
        1,
        &dir.path().join("scenes"),
        &|| (),
    )
    .unwrap();
    let bundle = &bundles[0];
    let truth: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(bundle.join("truth.json")).unwrap()).unwrap();
    let truth = truth["frames"][0]["objects"].as_array().unwrap().clone();
    let out = dir.path().join("inspect");
    let report = inspect::run(bundle, 0, &out, OpenOptions::default()).unwrap();
    assert!(report.objects.len() >= 2, "{report}");
    for v in &report.objects {
        check_view(v, &truth);
        for (name, size) in [
            (
                format!("frame0_obj{}_range_azimuth.png", v.instance),
                (1400, 700),
            ),
            (format!("frame0_obj{}_score.png", v.instance), (900, 450)),
        ] {
            assert!(report.files.contains(&name), "{name} not listed");
            let (w, h, px) = decode_rgb(&out.join(&name));
            assert_eq!((w, h), size, "{name}");
            // The legend's colours are drawn: the chosen depth (magenta) in both plots,
            // cancelled reflectors (red) on the map.
            assert!(
                count(&px, [255, 0, 255]) > 50,
                "{name}: no chosen-depth marker"
            );
            if name.contains("range_azimuth") && !v.cancelled.is_empty() {
                assert!(
                    count(&px, [255, 0, 0]) > 20,
                    "{name}: no cancelled reflectors"
                );
            }
        }
    }
    assert!(
        inspect::run(bundle, 99, &out, OpenOptions::default())
            .unwrap_err()
            .to_string()
            .contains("frame 99")
    );

    // process --out: the same plots plus results.json, the depth image and the point cloud.
    let products = dir.path().join("products");
    let output = process(bundle, &ProcessOptions::mode(Mode::Metamoran)).unwrap();
    let files = write_products(&products, bundle, OpenOptions::default(), &output).unwrap();
    for f in ["results.json", "depth_0.png", "points_0.ply"] {
        assert!(
            files.iter().any(|x| x == f) && products.join(f).is_file(),
            "{f}"
        );
    }
    for v in &report.objects {
        let name = format!("frame0_obj{}_score.png", v.instance);
        assert!(products.join(&name).is_file(), "{name}");
    }
}

/// One object's view against the truth and against the meaning of each plotted quantity.
fn check_view(v: &ObjectView, truth: &[serde_json::Value]) {
    let t = truth
        .iter()
        .find(|o| o["instance"].as_u64() == Some(v.instance as u64))
        .unwrap_or_else(|| panic!("object {} not in the truth", v.instance));
    let (depth, az) = (
        t["depth_m"].as_f64().unwrap(),
        t["azimuth_deg"].as_f64().unwrap(),
    );
    assert!(v.detected, "{v:?}");
    assert!(
        (v.depth_m - depth).abs() < 1.0,
        "depth {} vs truth {depth}",
        v.depth_m
    );
    assert!(
        v.span_deg.0 - 1.0 <= az && az <= v.span_deg.1 + 1.0,
        "truth azimuth {az} outside the span {:?}",
        v.span_deg
    );
    // The score curve peaks where the module chose (within the coarse grid's two bins).
    let bin_m = v.before.bin_m;
    let best = v.scores.iter().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    assert!(
        (best.0 - v.depth_m).abs() <= 2.0 * bin_m + 1e-9,
        "P(d) peaks at {}",
        best.0
    );
    assert!(
        best.1 > v.floor,
        "peak {} not above the floor {}",
        best.1,
        v.floor
    );
    // SIC removed power where it says it cancelled reflectors: the median drop at their
    // cells is at least 6 dB, and the maps agree far from every reflector and the object.
    if !v.cancelled.is_empty() {
        let drops: Vec<f32> = v
            .cancelled
            .iter()
            .filter_map(|&(r, a)| Some(v.before.at(a, r)? - v.after.at(a, r)?))
            .collect();
        assert!(!drops.is_empty());
        assert!(median(drops.clone()) >= 6.0, "drops {drops:?}");
    }
    assert_eq!(
        v.before.db.len(),
        v.before.azimuth_deg.len() * v.before.bins
    );
    assert_eq!(v.after.db.len(), v.before.db.len());
}
