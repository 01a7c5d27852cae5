//! The scene-bundle reader against bundle.md: a valid bundle reads back exactly, and each kind
//! of violation is an error that names the file and the field.

use metamoran_bundle::{Bundle, OpenOptions};
use metamoran_dsp::capture::IqOrder;
use std::path::Path;

const SCENE: &str = r#"format = "metamoran-bundle/1"
name = "hand-made"

[radar]
start_frequency_hz = 77.0e9
slope_hz_per_s     = 29.982e12
sample_rate_hz     = 10.0e6
adc_samples        = 8
chirp_period_s     = 60.0e-6
chirps_per_tx      = 2
frames             = 2
frame_period_s     = 0.1
tx_positions       = [0, 4]
rx_positions       = [0, 1, 2, 3]
tx_order           = [0, 1]
adc_file           = "radar.bin"
adc_layout         = "dca1000-xwr18xx"

[camera]
width  = 8
height = 4
fx = 1000.0
fy = 1000.0
cx = 4.0
cy = 2.0
translation_m = [0.0, -0.15, 0.0]
yaw_deg   = 0.0
pitch_deg = 0.0
roll_deg  = 0.0
"#;

/// Samples per frame: 2 loops × 2 slots × 4 RX × 8 samples.
const PER_FRAME: usize = 2 * 2 * 4 * 8;

fn write_png(path: &Path, width: u32, height: u32, depth: png::BitDepth, values: &[u16]) {
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(depth);
    let mut w = enc.write_header().unwrap();
    let bytes: Vec<u8> = match depth {
        png::BitDepth::Sixteen => values.iter().flat_map(|v| v.to_be_bytes()).collect(),
        _ => values.iter().map(|&v| v as u8).collect(),
    };
    w.write_image_data(&bytes).unwrap();
}

/// Raw I/Q of complex sample `k` of the file: distinct values everywhere.
fn iq(k: usize) -> (i16, i16) {
    (
        (k as i16).wrapping_mul(7) - 1000,
        3000 - (k as i16).wrapping_mul(5),
    )
}

/// Writes a valid two-frame bundle into `dir`.
fn write_bundle(dir: &Path) {
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let mut bytes = Vec::new();
    for g in 0..(2 * PER_FRAME / 2) {
        let ((i0, q0), (i1, q1)) = (iq(2 * g), iq(2 * g + 1));
        for w in [i0, i1, q0, q1] {
            bytes.extend_from_slice(&w.to_le_bytes());
        }
    }
    std::fs::write(dir.join("radar.bin"), bytes).unwrap();
    std::fs::create_dir(dir.join("camera")).unwrap();
    for f in 0..2 {
        let mask: Vec<u16> = (0..32)
            .map(|p| {
                if p % 8 >= 3 && p % 8 <= 5 {
                    1
                } else if p % 8 == 0 {
                    2
                } else {
                    0
                }
            })
            .collect();
        let depth: Vec<u16> = (0..32).map(|p| 256 * 20 + p as u16).collect();
        write_png(
            &dir.join(format!("camera/{f:06}_mask.png")),
            8,
            4,
            png::BitDepth::Sixteen,
            &mask,
        );
        write_png(
            &dir.join(format!("camera/{f:06}_depth.png")),
            8,
            4,
            png::BitDepth::Sixteen,
            &depth,
        );
        std::fs::write(
            dir.join(format!("camera/{f:06}_instances.json")),
            r#"{"instances": [{"id": 1, "class": "car"}, {"id": 2, "class": "wall"}]}"#,
        )
        .unwrap();
    }
    std::fs::write(
        dir.join("truth.json"),
        r#"{"frames": [{"frame": 0, "ego": {"x": 0.0, "z": 0.0, "yaw": 0.0, "vx": 0.0, "vz": 0.0},
            "objects": [{"instance": 1, "class": "car", "depth_m": 20.1, "azimuth_deg": 0.0,
                         "radial_velocity_mps": 0.0, "points": [[0.0, 0.2, 20.1]]}]}]}"#,
    )
    .unwrap();
}

fn open(dir: &Path) -> Result<Bundle, String> {
    Bundle::open(dir, OpenOptions::default()).map_err(|e| e.to_string())
}

#[test]
fn valid_bundle_reads_back_exactly() {
    let tmp = tempfile::tempdir().unwrap();
    write_bundle(tmp.path());
    let mut b = open(tmp.path()).unwrap();
    assert_eq!(b.frames(), 2);
    assert_eq!(b.scene.name, "hand-made");
    assert_eq!(b.instances(1)[1].class, "wall");
    assert!(b.instances(0)[0].is_object_of_interest() && b.instances(0)[1].is_clutter());
    let mut s = Vec::new();
    for f in 0..2 {
        b.read_radar_frame(f, &mut s).unwrap();
        for (k, z) in s.iter().enumerate() {
            assert_eq!(
                (z.re.0, z.im.0),
                iq(f as usize * PER_FRAME + k),
                "frame {f} sample {k}"
            );
        }
    }
    let cam = b.camera_frame(1).unwrap();
    assert_eq!(cam.mask[3], 1);
    assert_eq!(cam.depth_m(1, 0), Some(20.0 + 1.0 / 256.0));
    assert_eq!(b.truth.as_ref().unwrap().frames[0].objects[0].depth_m, 20.1);
    // The QQII option swaps the pairs.
    let mut q = Bundle::open(tmp.path(), OpenOptions::iq(IqOrder::Qqii)).unwrap();
    q.read_radar_frame(0, &mut s).unwrap();
    assert_eq!((s[0].re.0, s[0].im.0), (iq(0).1, iq(0).0));
}

/// Applies `corrupt` to a fresh valid bundle and returns the open error.
fn error_after(corrupt: impl FnOnce(&Path)) -> String {
    let tmp = tempfile::tempdir().unwrap();
    write_bundle(tmp.path());
    corrupt(tmp.path());
    match open(tmp.path()) {
        Ok(b) => b
            .camera_frame(0)
            .map(|_| ())
            .map_err(|e| e.to_string())
            .expect_err("corrupt bundle accepted"),
        Err(e) => e,
    }
}

fn edit_scene(dir: &Path, from: &str, to: &str) {
    let p = dir.join("scene.toml");
    let s = std::fs::read_to_string(&p).unwrap();
    assert!(s.contains(from), "test bug: {from:?} not in scene.toml");
    std::fs::write(p, s.replacen(from, to, 1)).unwrap();
}

fn assert_names(err: &str, file: &str, field: &str) {
    assert!(
        err.contains(file) && err.contains(field),
        "error does not name {file} / {field}: {err}"
    );
}

#[test]
fn scene_toml_violations_name_the_field() {
    let cases: &[(&str, &str, &str)] = &[
        ("metamoran-bundle/1", "metamoran-bundle/2", "`format`"),
        (
            "slope_hz_per_s     = 29.982e12\n",
            "",
            "`radar.slope_hz_per_s`",
        ),
        (
            "slope_hz_per_s     = 29.982e12",
            "slope_hz_per_s = nan",
            "`radar.slope_hz_per_s`",
        ),
        (
            "sample_rate_hz     = 10.0e6",
            "sample_rate_hz = -1.0",
            "`radar.sample_rate_hz`",
        ),
        (
            "adc_samples        = 8",
            "adc_samples = 7",
            "`radar.adc_samples`",
        ),
        (
            "adc_samples        = 8",
            "adc_samples = \"8\"",
            "`radar.adc_samples`",
        ),
        (
            "tx_order           = [0, 1]",
            "tx_order = [0, 2]",
            "`radar.tx_order[1]`",
        ),
        (
            "rx_positions       = [0, 1, 2, 3]",
            "rx_positions = [0, 1.5, 2, 3]",
            "`radar.rx_positions[1]`",
        ),
        (
            "rx_positions       = [0, 1, 2, 3]",
            "rx_positions = []",
            "`radar.rx_positions`",
        ),
        (
            "adc_layout         = \"dca1000-xwr18xx\"",
            "adc_layout = \"dca1000-xwr16xx\"",
            "`radar.adc_layout`",
        ),
        (
            "translation_m = [0.0, -0.15, 0.0]",
            "translation_m = [0.0, -0.15]",
            "`camera.translation_m`",
        ),
        ("width  = 8", "width  = 0", "`camera.width`"),
        ("frames             = 2", "frames = 0", "`radar.frames`"),
    ];
    for (from, to, field) in cases {
        let err = error_after(|d| edit_scene(d, from, to));
        assert_names(&err, "scene.toml", field);
    }
    let err = error_after(|d| std::fs::write(d.join("scene.toml"), "format = \n").unwrap());
    assert_names(&err, "scene.toml", "TOML");
}

#[test]
fn radar_bin_size_must_match_the_config() {
    let err = error_after(|d| {
        let p = d.join("radar.bin");
        let b = std::fs::read(&p).unwrap();
        std::fs::write(&p, &b[..b.len() - 4]).unwrap();
    });
    assert_names(&err, "radar.bin", "bytes");
    let err = error_after(|d| edit_scene(d, "chirps_per_tx      = 2", "chirps_per_tx = 3"));
    assert_names(&err, "radar.bin", "chirps_per_tx");
    let err = error_after(|d| std::fs::remove_file(d.join("radar.bin")).unwrap());
    assert_names(&err, "radar.bin", "cannot read");
}

#[test]
fn camera_violations_name_the_file() {
    let err = error_after(|d| {
        write_png(
            &d.join("camera/000001_mask.png"),
            8,
            3,
            png::BitDepth::Sixteen,
            &[0; 24],
        );
    });
    assert_names(&err, "000001_mask.png", "8×3");
    let err = error_after(|d| {
        write_png(
            &d.join("camera/000000_depth.png"),
            8,
            4,
            png::BitDepth::Eight,
            &[0; 32],
        );
    });
    assert_names(&err, "000000_depth.png", "16-bit");
    let err = error_after(|d| {
        std::fs::write(
            d.join("camera/000000_mask.png"),
            b"\x89PNG\r\n\x1a\nnot really",
        )
        .unwrap();
    });
    assert_names(&err, "000000_mask.png", "PNG");
    let err = error_after(|d| std::fs::remove_file(d.join("camera/000001_depth.png")).unwrap());
    assert_names(&err, "000001_depth.png", "cannot read");
    let err = error_after(|d| {
        std::fs::write(
            d.join("camera/000000_instances.json"),
            r#"{"instances": [{"id": 1, "class": 5}]}"#,
        )
        .unwrap();
    });
    assert_names(&err, "000000_instances.json", "instances[0].class");
    let err = error_after(|d| {
        std::fs::write(
            d.join("camera/000000_instances.json"),
            r#"{"instances": [{"id": 1, "class": "car"}, {"id": 1, "class": "car"}]}"#,
        )
        .unwrap();
    });
    assert_names(&err, "000000_instances.json", "instances[1].id");
    // Id 0 means "no instance" in the mask: listing it is an error (issue #18: disabling this
    // check survived every test).
    let err = error_after(|d| {
        std::fs::write(
            d.join("camera/000000_instances.json"),
            r#"{"instances": [{"id": 0, "class": "car"}, {"id": 1, "class": "car"}, {"id": 2, "class": "wall"}]}"#,
        )
        .unwrap();
    });
    assert_names(&err, "000000_instances.json", "instances[0].id");
    assert!(err.contains("ids start at 1"), "{err}");
    let err = error_after(|d| {
        std::fs::write(
            d.join("camera/000000_instances.json"),
            r#"{"instances": [{"id": 1, "class": "car"}]}"#,
        )
        .unwrap();
    });
    assert_names(&err, "000000_mask.png", "instance id 2");
}

#[test]
fn truth_violations_name_the_field() {
    let err = error_after(|d| {
        let p = d.join("truth.json");
        let s = std::fs::read_to_string(&p)
            .unwrap()
            .replace("\"depth_m\": 20.1", "\"depth_m\": -3");
        std::fs::write(p, s).unwrap();
    });
    assert_names(&err, "truth.json", "frames[0].objects[0].depth_m");
    let err = error_after(|d| {
        let p = d.join("truth.json");
        let s = std::fs::read_to_string(&p)
            .unwrap()
            .replace("\"vz\": 0.0", "\"vz\": \"fast\"");
        std::fs::write(p, s).unwrap();
    });
    assert_names(&err, "truth.json", "frames[0].ego.vz");
    let err = error_after(|d| {
        let p = d.join("truth.json");
        let s = std::fs::read_to_string(&p)
            .unwrap()
            .replace("\"frame\": 0", "\"frame\": 9");
        std::fs::write(p, s).unwrap();
    });
    assert_names(&err, "truth.json", "frames[0].frame");
}

#[test]
fn elevation_lists_are_optional_and_checked() {
    // The README's extension: tx_elevation / rx_elevation in [radar], one per antenna.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("b");
    metamoran_sim::simulate_one(
        metamoran_sim::layout::Preset::ParkingLot,
        metamoran_sim::radar::RadarKind::Xwr18xx,
        1,
        0,
        &dir,
    )
    .unwrap();
    let toml = std::fs::read_to_string(dir.join("scene.toml")).unwrap();
    assert!(
        !toml.contains("elevation"),
        "version-1 bundles stay as they are"
    );
    let b = Bundle::open(&dir, OpenOptions::default()).unwrap();
    assert!(b.scene.tx_elevation.is_empty() && b.scene.rx_elevation.is_empty());
    let with = |line: &str| {
        std::fs::write(
            dir.join("scene.toml"),
            toml.replacen("\n\n[camera]", &format!("\n{line}\n\n[camera]"), 1),
        )
        .unwrap();
        Bundle::open(&dir, OpenOptions::default())
    };
    let b = with("tx_elevation = [0, 1]\nrx_elevation = [0, 0, 0, 2]").unwrap();
    assert_eq!(b.scene.tx_elevation, [0, 1]);
    assert_eq!(b.scene.rx_elevation, [0, 0, 0, 2]);
    let err = with("tx_elevation = [0, 1, 1]").unwrap_err().to_string();
    assert!(
        err.contains("scene.toml") && err.contains("tx_elevation") && err.contains("one elevation"),
        "{err}"
    );
}

// Tests that kill cargo-mutants' survivors in the reader (issue #18; README, "Mutation testing").

/// The `[radar]` table of `SCENE` as a bare capture's config, without `frames`, `adc_file` and
/// `adc_layout`.
fn bare_config() -> String {
    let radar = SCENE
        .split("[radar]")
        .nth(1)
        .unwrap()
        .split("[camera]")
        .next()
        .unwrap();
    let lines: Vec<&str> = radar
        .lines()
        .filter(|l| {
            !["frames", "adc_file", "adc_layout"]
                .iter()
                .any(|k| l.starts_with(k))
        })
        .collect();
    format!("[radar]\n{}", lines.join("\n"))
}

#[test]
fn a_bare_capture_takes_its_frame_count_from_the_size_or_the_config() {
    let tmp = tempfile::tempdir().unwrap();
    let (bin, cfg) = (tmp.path().join("c.bin"), tmp.path().join("c.toml"));
    std::fs::write(&cfg, bare_config()).unwrap();
    let frame = vec![7u8; PER_FRAME * 4];
    std::fs::write(&bin, frame.repeat(3)).unwrap();
    let f = metamoran_bundle::capture::open_bare(&bin, &cfg, Some(IqOrder::Iiqq), None).unwrap();
    assert_eq!(f.config().frames, 3);
    // Not a whole number of frames, or empty: an error saying so.
    for len in [3 * frame.len() - 4, 0] {
        std::fs::write(&bin, &frame.repeat(3)[..len]).unwrap();
        let err = metamoran_bundle::capture::open_bare(&bin, &cfg, Some(IqOrder::Iiqq), None)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("c.bin") && err.contains("whole number"),
            "{err}"
        );
    }
    // A frame count given in the config is taken, not derived.
    let given = format!("{}\nframes = 2\n", bare_config());
    let config =
        metamoran_bundle::capture::parse_radar_config(Path::new("c.toml"), &given).unwrap();
    assert_eq!(config.frames, 2);
}

#[test]
fn unknown_keys_get_the_nearest_known_one_only_when_near() {
    let parse = |text: &str| metamoran_bundle::Scene::parse(Path::new("scene.toml"), text);
    let with = |extra: &str| SCENE.replace("[camera]", &format!("{extra}\n[camera]"));
    // One letter off: suggested.
    let err = parse(&with("tx_elevaton = [0, 0]"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("did you mean `radar.tx_elevation`?"), "{err}");
    // Five letters off an 18-letter key is within a third of it: suggested.
    let err = parse(&with("start_frequen = 1.0")).unwrap_err().to_string();
    assert!(
        err.contains("did you mean `radar.start_frequency_hz`?"),
        "{err}"
    );
    // Nothing near: the table's keys are listed instead.
    let err = parse(&with("zzzzzzzzzzzzzzzz = 1"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("`radar.zzzzzzzzzzzzzzzz`") && err.contains("this table has"),
        "{err}"
    );
}

#[test]
fn fields_at_their_bounds() {
    let parse = |from: &str, to: &str| {
        assert!(SCENE.contains(from), "test bug: {from}");
        metamoran_bundle::Scene::parse(Path::new("scene.toml"), &SCENE.replacen(from, to, 1))
            .map_err(|e| e.to_string())
    };
    let err = parse("frame_period_s     = 0.1", "frame_period_s = 0.0").unwrap_err();
    assert!(
        err.contains("`radar.frame_period_s`") && err.contains("greater than zero"),
        "{err}"
    );
    let err = parse(
        "translation_m = [0.0, -0.15, 0.0]",
        "translation_m = [nan, -0.15, 0.0]",
    )
    .unwrap_err();
    assert!(err.contains("`camera.translation_m[0]`"), "{err}");
    let err = parse("adc_file           = \"radar.bin\"", "adc_file = \"\"").unwrap_err();
    assert!(err.contains("`radar.adc_file`"), "{err}");
    // A derived quantity out of range names the field it comes from (R_max = fs·c/2S).
    let err = parse("slope_hz_per_s     = 29.982e12", "slope_hz_per_s = 1e-300").unwrap_err();
    assert!(err.contains("`radar.slope_hz_per_s`"), "{err}");
    // The pixel limit: 8K UHD is allowed, one column more is not.
    let big = |w: u32, h: u32| {
        parse(
            "width  = 8\nheight = 4",
            &format!("width = {w}\nheight = {h}"),
        )
    };
    assert!(big(7680, 4320).is_ok(), "{:?}", big(7680, 4320));
    let err = big(7681, 4320).unwrap_err();
    assert!(
        err.contains("`camera.width`") && err.contains("pixels"),
        "{err}"
    );
    // The frame limit (256 MiB): 2048 samples × 2048 loops × 16 slots × 1 RX × 4 bytes is
    // exactly it and passes that check; a second RX does not.
    let frame = |rx: &str| {
        let slots = format!("tx_order = [{}]", vec!["0"; 16].join(", "));
        let text = SCENE
            .replacen("adc_samples        = 8", "adc_samples = 2048", 1)
            .replacen("chirps_per_tx      = 2", "chirps_per_tx = 2048", 1)
            .replacen("tx_order           = [0, 1]", &slots, 1)
            .replacen("rx_positions       = [0, 1, 2, 3]", rx, 1);
        metamoran_bundle::Scene::parse(Path::new("scene.toml"), &text).map_err(|e| e.to_string())
    };
    if let Err(e) = frame("rx_positions = [0]") {
        assert!(!e.contains("per frame"), "{e}");
    }
    let err = frame("rx_positions = [0, 1]").unwrap_err();
    assert!(
        err.contains("`radar.adc_samples`") && err.contains("per frame"),
        "{err}"
    );
}

#[test]
fn files_of_a_bundle_resolve_inside_it() {
    use std::os::unix::fs::symlink;
    for name in [
        "000000_mask.png",
        "000000_depth.png",
        "000000_instances.json",
    ] {
        let outside = tempfile::tempdir().unwrap();
        let err = error_after(|d| {
            let p = d.join("camera").join(name);
            std::fs::copy(&p, outside.path().join(name)).unwrap();
            std::fs::remove_file(&p).unwrap();
            symlink(outside.path().join(name), &p).unwrap();
        });
        assert_names(&err, name, "resolves to");
    }
    // A file the reader does not read (the RGB image without camera models) is not checked.
    let tmp = tempfile::tempdir().unwrap();
    let outside = tempfile::tempdir().unwrap();
    write_bundle(tmp.path());
    std::fs::write(outside.path().join("image.png"), b"x").unwrap();
    symlink(
        outside.path().join("image.png"),
        tmp.path().join("camera/000000_image.png"),
    )
    .unwrap();
    open(tmp.path()).unwrap();
    // And the check itself.
    let root = tmp.path().canonicalize().unwrap();
    let link = tmp.path().join("camera/000000_image.png");
    assert!(metamoran_bundle::limits::confined(&root, &link).is_err());
    assert!(metamoran_bundle::limits::confined(&root, &tmp.path().join("scene.toml")).is_ok());
}

#[test]
fn a_file_at_its_size_limit_reads_one_byte_more_does_not() {
    let tmp = tempfile::tempdir().unwrap();
    let p = tmp.path().join("f");
    std::fs::write(&p, [1u8; 100]).unwrap();
    assert_eq!(
        metamoran_bundle::limits::read_bounded(&p, 100)
            .unwrap()
            .len(),
        100
    );
    let err = metamoran_bundle::limits::read_bounded(&p, 99)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("100 bytes") && err.contains("at most 99"),
        "{err}"
    );
}

#[test]
fn classes_are_lowercase_words_and_sorted_into_kinds() {
    let parse =
        |json: &str| metamoran_bundle::parse_instances(Path::new("i.json"), json.as_bytes());
    for bad in ["Car", "", "car park"] {
        let json = format!(r#"{{"instances": [{{"id": 1, "class": "{bad}"}}]}}"#);
        let err = parse(&json).unwrap_err().to_string();
        assert!(err.contains("instances[0].class"), "{bad:?}: {err}");
    }
    let list =
        parse(r#"{"instances": [{"id": 1, "class": "car"}, {"id": 2, "class": "tree"}]}"#).unwrap();
    assert!(list[0].is_object_of_interest() && !list[0].is_clutter());
    assert!(list[1].is_clutter() && !list[1].is_object_of_interest());
    // Truncated and malformed JSON are syntax errors, not field errors.
    for broken in [r#"{"instances": ["#, r#"{"instances": ]"#] {
        let e = parse(broken).unwrap_err();
        assert!(
            matches!(e, metamoran_bundle::error::InputError::Syntax { .. }),
            "{broken}: {e:?}"
        );
    }
}

#[test]
fn png16_and_depth_read_back_exactly() {
    let tmp = tempfile::tempdir().unwrap();
    let p = tmp.path().join("d.png");
    let values: Vec<u16> = (0..12).map(|i| 1000 * i + 7).collect();
    write_png(&p, 4, 3, png::BitDepth::Sixteen, &values);
    let bytes = std::fs::read(&p).unwrap();
    assert_eq!(
        metamoran_bundle::parse_png16(&p, &bytes, 4, 3).unwrap(),
        values
    );
    // depth_m indexes row-major: pixel (2, 3) of the 8×4 depth is 256·20 + 3·8 + 2.
    let tmp = tempfile::tempdir().unwrap();
    write_bundle(tmp.path());
    let cam = open(tmp.path()).unwrap().camera_frame(0).unwrap();
    assert_eq!(cam.depth_m(2, 3), Some(20.0 + 26.0 / 256.0));
}

/// A calibration for the hand-made board (2 TX × 4 RX, N = 8): gain 2j everywhere and, on
/// (tx 1, rx 3), `frequency_bins` = `bins`; `skip` leaves one channel out.
fn calibration_toml(bins: f64, skip: Option<(usize, usize)>) -> String {
    let mut s = String::from(
        "format = \"metamoran-calibration/1\"\nslope_hz_per_s = 29.982e12\nsample_rate_hz = 10.0e6\nadc_samples = 8\ntarget_range_m = 5.0\nreference = { tx = 0, rx = 0 }\n",
    );
    for t in 0..2 {
        for r in 0..4 {
            if skip == Some((t, r)) {
                continue;
            }
            let f = if (t, r) == (1, 3) { bins } else { 0.0 };
            s.push_str(&format!(
                "\n[[channels]]\ntx = {t}\nrx = {r}\ngain = [0.0, 2.0]\nfrequency_bins = {f}\n"
            ));
        }
    }
    s
}

fn name_calibration(dir: &Path, name: &str) {
    let scene = SCENE.replace(
        "adc_layout         = \"dca1000-xwr18xx\"",
        &format!("adc_layout         = \"dca1000-xwr18xx\"\ncalibration_file = \"{name}\""),
    );
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
}

#[test]
fn a_named_calibration_is_applied_to_every_frame() {
    let tmp = tempfile::tempdir().unwrap();
    write_bundle(tmp.path());
    name_calibration(tmp.path(), "cal.toml");
    // Two bins on (tx 1, rx 3) of an 8-sample chirp: sample n turns by j^n.
    std::fs::write(tmp.path().join("cal.toml"), calibration_toml(2.0, None)).unwrap();
    let mut b = open(tmp.path()).unwrap();
    let mut s = Vec::new();
    for f in 0..2 {
        b.read_radar_frame(f, &mut s).unwrap();
        for (k, z) in s.iter().enumerate() {
            let (re, im) = iq(f as usize * PER_FRAME + k);
            // Gains are normalized by the largest (2): j·x.
            let (mut wr, mut wi) = (-i32::from(im), i32::from(re));
            // Chirp c, RX r: row k / 8; slot c % 2 is TX c % 2.
            let (row, n) = (k / 8, k % 8);
            if (row / 4) % 2 == 1 && row % 4 == 3 {
                for _ in 0..n % 4 {
                    (wr, wi) = (-wi, wr);
                }
            }
            let err = (i32::from(z.re.0) - wr)
                .abs()
                .max((i32::from(z.im.0) - wi).abs());
            assert!(err <= 1, "frame {f} sample {k}: {z:?} vs ({wr}, {wi})");
        }
    }
}

#[test]
fn a_calibration_that_does_not_fit_is_refused_by_name() {
    let tmp = tempfile::tempdir().unwrap();
    write_bundle(tmp.path());
    name_calibration(tmp.path(), "../cal.toml");
    let e = open(tmp.path()).unwrap_err();
    assert!(
        e.contains("radar.calibration_file") && e.contains("inside the bundle"),
        "{e}"
    );
    name_calibration(tmp.path(), "cal.toml");
    let cases = [
        (calibration_toml(0.0, Some((1, 2))), "(tx 1, rx 2)"),
        (calibration_toml(4.5, None), "frequency_bins"),
        (
            calibration_toml(0.0, None).replace("rx = 3\n", "rx = 4\n"),
            "not on this board",
        ),
        (
            calibration_toml(0.0, None).replace("tx = 1\nrx = 3", "tx = 1\nrx = 2"),
            "appears twice",
        ),
        (
            calibration_toml(0.0, None).replacen("[0.0, 2.0]", "[nan, 2.0]", 1),
            "channels[0].gain",
        ),
        (
            calibration_toml(0.0, None).replacen("[0.0, 2.0]", "[0.0, 0.0]", 1),
            "dead channel",
        ),
        (
            calibration_toml(0.0, None).replace("adc_samples = 8", "adc_sample = 8"),
            "adc_sample",
        ),
        (
            calibration_toml(0.0, None).replace("calibration/1", "calibration/2"),
            "format",
        ),
    ];
    for (text, needle) in cases {
        std::fs::write(tmp.path().join("cal.toml"), &text).unwrap();
        let e = open(tmp.path()).unwrap_err();
        assert!(
            e.contains("cal.toml") && e.contains(needle),
            "{needle}: {e}"
        );
    }
    std::fs::remove_file(tmp.path().join("cal.toml")).unwrap();
    let e = open(tmp.path()).unwrap_err();
    assert!(e.contains("cal.toml"), "{e}");
}

#[test]
fn frequency_corrections_follow_the_chirp_they_are_applied_to() {
    use metamoran_bundle::calibration::CalibrationFile;
    use metamoran_dsp::trig::Phase;
    let path = Path::new("cal.toml");
    let file = CalibrationFile::parse(path, &calibration_toml(0.25, None)).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    write_bundle(tmp.path());
    let mut config = Bundle::open(tmp.path(), OpenOptions::iq(IqOrder::Iiqq))
        .unwrap()
        .scene
        .radar;
    // A delay makes a beat frequency S·τ: twice the slope, half the sample rate and twice the
    // samples give 8× the bins, in a transform of 16: 2 bins of 16 = 1/8 turn per sample.
    config.slope_hz_per_s *= 2.0;
    config.sample_rate_hz /= 2.0;
    config.adc_samples = 16;
    let cal = file.for_config(path, &config).unwrap();
    assert_eq!(cal.get(1, 3).unwrap().step, Phase::from_turns(2.0 / 16.0));
    assert_eq!(cal.get(0, 0).unwrap().step, Phase(0));
}

#[test]
fn a_live_capture_replaces_the_radar_file_and_its_incomplete_frames_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    write_bundle(tmp.path());
    // The stream: the bundle's samples negated, frame 1 not whole.
    let recorded = tmp.path().join("stream.bin");
    let bytes = std::fs::read(tmp.path().join("radar.bin")).unwrap();
    let negated: Vec<u8> = bytes
        .chunks_exact(2)
        .flat_map(|b| {
            i16::from_le_bytes([b[0], b[1]])
                .wrapping_neg()
                .to_le_bytes()
        })
        .collect();
    std::fs::write(&recorded, &negated).unwrap();
    let options = OpenOptions {
        capture: Some(metamoran_bundle::LiveCapture {
            file: recorded.clone(),
            incomplete: vec![1],
        }),
        ..OpenOptions::default()
    };
    let mut b = Bundle::open(tmp.path(), options.clone()).unwrap();
    assert_eq!(b.scene.adc_file, recorded, "later readers take the stream");
    let mut s = Vec::new();
    b.read_radar_frame(0, &mut s).unwrap();
    for (k, z) in s.iter().enumerate() {
        let (re, im) = iq(k);
        assert_eq!(
            (z.re.0, z.im.0),
            (re.wrapping_neg(), im.wrapping_neg()),
            "{k}"
        );
    }
    let err = b.read_radar_frame(1, &mut s).unwrap_err().to_string();
    assert!(
        err.contains("stream.bin") && err.contains("frame 1 did not arrive whole"),
        "{err}"
    );
    assert_eq!(
        b.camera_frame(1).unwrap().mask[3],
        1,
        "the camera is the bundle's"
    );
    // A stream of another size than the bundle's frames is refused by name.
    std::fs::write(&recorded, &negated[..negated.len() - 4]).unwrap();
    let err = Bundle::open(tmp.path(), options.clone())
        .unwrap_err()
        .to_string();
    assert!(err.contains("stream.bin"), "{err}");
    // An MMWCAS bundle cannot take one device's stream.
    std::fs::write(&recorded, &negated).unwrap();
    edit_scene(tmp.path(), "\"dca1000-xwr18xx\"", "\"mmwcas-rf-evm\"");
    let err = Bundle::open(tmp.path(), options).unwrap_err().to_string();
    assert!(
        err.contains("scene.toml") && err.contains("MMWCAS"),
        "{err}"
    );
}
