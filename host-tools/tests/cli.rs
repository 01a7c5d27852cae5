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
        host_tools::shared_dir()
            .join("data/real")
            .join(name)
            .join("adc_data.bin"),
        root.join("tests/data/real").join(format!("{name}.toml")),
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
