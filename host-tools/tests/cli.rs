//! The `metamoran` binary as a user runs it: clear errors (file and field, non-zero exit, no
//! panic) and JSON that parses.

use std::path::PathBuf;
use std::process::{Command, Output};

fn metamoran(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_metamoran"))
        .args(args)
        .output()
        .unwrap()
}

fn real(name: &str) -> (PathBuf, PathBuf) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    (
        std::env::var_os("METAMORAN_SHARED")
            .map_or_else(|| root.join("../shared"), PathBuf::from)
            .join("data/real")
            .join(name)
            .join("adc_data.bin"),
        // The binary's own config of its demo capture, else the tests' configs.
        [root.join("host-tools/data"), root.join("tests/data/real")]
            .map(|d| d.join(format!("{name}.toml")))
            .into_iter()
            .find(|p| p.exists())
            .expect("a radar config for the capture"),
    )
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn bad_inputs_are_clear_errors() {
    let o = metamoran(&["summarize", "/nonexistent/capture.bin"]);
    assert!(
        !o.status.success() && stderr(&o).contains("/nonexistent/capture.bin"),
        "{}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains("panicked"));

    let (bin, cfg) = real("openradar_frame");
    let tmp = tempfile::tempdir().unwrap();
    let cut = tmp.path().join("cut.bin");
    std::fs::write(&cut, &std::fs::read(&bin).unwrap()[..1000]).unwrap();
    let o = metamoran(&[
        "summarize",
        cut.to_str().unwrap(),
        "--config",
        cfg.to_str().unwrap(),
    ]);
    assert!(
        !o.status.success() && stderr(&o).contains("cut.bin") && stderr(&o).contains("1000 bytes"),
        "{}",
        stderr(&o)
    );

    let bad = tmp.path().join("bad.toml");
    std::fs::write(
        &bad,
        std::fs::read_to_string(&cfg)
            .unwrap()
            .replace("chirps_per_tx      = 128", "chirps_per_tx = -4"),
    )
    .unwrap();
    let o = metamoran(&[
        "summarize",
        bin.to_str().unwrap(),
        "--config",
        bad.to_str().unwrap(),
    ]);
    assert!(
        stderr(&o).contains("bad.toml") && stderr(&o).contains("radar.chirps_per_tx"),
        "{}",
        stderr(&o)
    );

    let o = metamoran(&["bench", "fft", "--sizes", "100"]);
    assert!(
        !o.status.success() && stderr(&o).contains("--sizes 100"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn summarize_json_finds_the_two_movers() {
    let (bin, cfg) = real("openradar_doppler_example_1");
    let o = metamoran(&[
        "summarize",
        bin.to_str().unwrap(),
        "--config",
        cfg.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is only JSON");
    let frame = &v["frames"][0];
    // The README's range–Doppler peaks: (60, +7) and (60, −10); the static reflector at bin 107.
    let movers: Vec<(u64, i64)> = frame["moving_targets"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            (
                t["range_bin"].as_u64().unwrap(),
                t["doppler_bin"].as_i64().unwrap(),
            )
        })
        .collect();
    assert!(
        movers.contains(&(60, 7)) && movers.contains(&(60, -10)),
        "{movers:?}"
    );
    let peaks: Vec<u64> = frame["range_peaks"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["bin"].as_u64().unwrap())
        .collect();
    assert!(peaks[..3].contains(&107), "{peaks:?}");
    let res = v["config"]["range_resolution_m"].as_f64().unwrap();
    assert!((res - 0.048794).abs() < 1e-5, "range resolution {res}");
}

#[test]
fn map_json_has_the_issue_keys_and_writes_images_and_clouds() {
    let scenes = tempfile::tempdir().unwrap();
    let sim = metamoran(&[
        "simulate",
        "--preset",
        "drive",
        "--seed",
        "12",
        "--count",
        "1",
        "--out",
        scenes.path().to_str().unwrap(),
    ]);
    assert!(sim.status.success(), "{}", stderr(&sim));
    let bundle = scenes.path().join("drive-12-0000");
    let out = scenes.path().join("map");
    let mut args = vec![
        "map",
        bundle.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
        "--training-pairs",
    ];
    // The network needs tract (feature onnx, which the workspace's e2e tests turn on).
    let network = cfg!(feature = "onnx");
    if !network {
        args.push("--no-network");
    }
    let o = metamoran(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let keys = |v: &serde_json::Value| {
        let mut k: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
        k.sort();
        k
    };
    assert_eq!(
        keys(&v),
        [
            "density_growth_factor",
            "ego_velocity_error_mps",
            "lidar_pixels",
            "mae_m",
            "network_density_growth_factor",
            "network_fps",
            "own_pixels",
            "point_accuracy_m",
            "rmse_m"
        ]
    );
    for errors in [
        &v["mae_m"],
        &v["rmse_m"],
        &v["point_accuracy_m"],
        &v["lidar_pixels"]["mae_m"],
        &v["own_pixels"]["rmse_m"],
    ] {
        assert_eq!(keys(errors), ["frame", "ip_basic", "network", "submap"]);
        assert!(errors["submap"].as_f64().unwrap() > 0.0);
        assert_eq!(errors["network"].is_number(), network, "{v}");
    }
    // Over every lidar pixel an empty pixel counts as 0 m: the frame's few returns leave most
    // of the lidar's depth as error, where IP-Basic's filled image does not.
    let lidar_mae = &v["lidar_pixels"]["mae_m"];
    let frame = lidar_mae["frame"].as_f64().unwrap();
    assert!(
        frame > 1.3 * lidar_mae["ip_basic"].as_f64().unwrap()
            && frame > 2.0 * v["mae_m"]["frame"].as_f64().unwrap(),
        "{v}"
    );
    assert_eq!(v["network_fps"].is_number(), network, "{v}");
    assert_eq!(
        v["network_density_growth_factor"].is_number(),
        network,
        "{v}"
    );
    assert!(v["ego_velocity_error_mps"].as_f64().unwrap() < 0.2, "{v}");
    let mut images = vec!["frame.png", "submap.png", "ip_basic.png", "lidar.png"];
    let mut clouds = vec!["submap.ply"];
    if network {
        images.push("network.png");
        clouds.push("network.ply");
    }
    for name in images
        .iter()
        .chain(["pairs/submap_000019.png", "pairs/lidar_000000.png"].iter())
    {
        let info = png::Decoder::new(std::io::BufReader::new(
            std::fs::File::open(out.join(name)).unwrap(),
        ))
        .read_info()
        .unwrap()
        .info()
        .clone();
        assert_eq!(
            (info.width, info.height, info.bit_depth),
            (320, 80, png::BitDepth::Sixteen),
            "{name}"
        );
    }
    for name in clouds {
        let points = metamoran_bundle::lidar::read(&out.join(name)).unwrap();
        assert!(points.len() > 100, "{name}: {} points", points.len());
    }
    // A missing bundle is an error naming it, not a panic.
    let o = metamoran(&["map", "no-such-bundle", "--no-network"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("no-such-bundle"), "{}", stderr(&o));
}

#[test]
fn calibrate_json_is_exactly_the_issue_shape_and_the_file_applies() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().to_str().unwrap();
    let o = metamoran(&[
        "simulate", "--preset", "corner", "--radar", "xwr18xx", "--board", "3", "--seed", "1",
        "--out", out,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let corner = tmp.path().join("corner-board3-1-0000");
    let cal = tmp.path().join("board3.toml");
    let o = metamoran(&[
        "calibrate",
        corner.to_str().unwrap(),
        "--out",
        cal.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let keys = |v: &serde_json::Value| {
        let mut k: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
        k.sort();
        k
    };
    assert_eq!(keys(&v), ["channels", "reference", "target_range_m"]);
    assert_eq!(keys(&v["reference"]), ["rx", "tx"]);
    assert!((v["target_range_m"].as_f64().unwrap() - 5.0).abs() < 0.1);
    let channels = v["channels"].as_array().unwrap();
    // 2 TX × 4 RX, each pair once.
    assert_eq!(channels.len(), 8);
    let mut pairs: Vec<(u64, u64)> = channels
        .iter()
        .map(|c| {
            assert_eq!(keys(c), ["frequency_bins", "gain", "rx", "tx"]);
            assert_eq!(c["gain"].as_array().unwrap().len(), 2);
            (c["tx"].as_u64().unwrap(), c["rx"].as_u64().unwrap())
        })
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    assert_eq!(pairs.len(), 8);
    // The bundle that names the file is read calibrated: its summary finds the reflector as
    // strong on every channel, so the calibration file is accepted by the reader.
    std::fs::copy(&cal, corner.join("calibration.toml")).unwrap();
    let scene = std::fs::read_to_string(corner.join("scene.toml")).unwrap();
    let named = scene.replacen(
        "adc_layout",
        "calibration_file = \"calibration.toml\"\nadc_layout",
        1,
    );
    std::fs::write(corner.join("scene.toml"), named).unwrap();
    let o = metamoran(&["summarize", corner.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The module is sent the calibration and answers as this process does.
    let run = |edge: &str| {
        let o = metamoran(&[
            "process",
            corner.to_str().unwrap(),
            "--mode",
            "metamoran",
            "--edge",
            edge,
            "--json",
        ]);
        assert!(o.status.success(), "--edge {edge}: {}", stderr(&o));
        o.stdout
    };
    assert_eq!(run("qemu"), run("in-process"));
}

#[test]
fn a_reader_that_goes_away_ends_the_run_quietly() {
    use std::io::Write;
    use std::process::{Command, Stdio};
    // The reader of standard output is gone before anything is printed.
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let mut child = Command::new(env!("CARGO_BIN_EXE_metamoran"))
        .arg("hash-password")
        .stdin(Stdio::piped())
        .stdout(writer)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b"a password\n")
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(141), "{}", stderr(&out));
    assert!(!stderr(&out).contains("panicked"), "{}", stderr(&out));
}

#[test]
fn eval_writes_its_samples_into_a_folder_it_creates() {
    let dir = tempfile::tempdir().unwrap();
    let bundles = dir.path().join("bundles");
    let o = metamoran(&[
        "simulate",
        "--preset",
        "parking-lot",
        "--radar",
        "xwr18xx",
        "--seed",
        "5",
        "--out",
        bundles.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let samples = dir.path().join("not/yet/there/samples.json");
    let o = metamoran(&[
        "eval",
        bundles.to_str().unwrap(),
        "--modes",
        "naive",
        "--json",
        "--samples",
        samples.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let written: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&samples).unwrap()).unwrap();
    // One sample per object the bundle's truth lists, each naming its bundle.
    let truth: serde_json::Value = serde_json::from_slice(
        &std::fs::read(bundles.join("parking-lot-5-0000/truth.json")).unwrap(),
    )
    .unwrap();
    let objects: usize = truth["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["objects"].as_array().unwrap().len())
        .sum();
    let rows = written.as_array().unwrap();
    assert!(
        objects > 0 && rows.len() == objects,
        "{objects} objects, {rows:?}"
    );
    assert!(
        rows.iter().all(|r| r["bundle"] == "parking-lot-5-0000"),
        "{rows:?}"
    );
}
