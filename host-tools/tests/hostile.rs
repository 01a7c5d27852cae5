//! Issue #18, inputs: the release binary against hand-made hostile bundles, each run with a
//! 3 GiB address-space limit and a 60 s deadline. Every case used to abort, hang, escape the
//! bundle or answer confidently; each must now be a clear error naming the file and the field
//! (or, for a bad frame, a skipped frame and the rest processed).

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// What a bounded run of the binary did.
struct Run {
    status: ExitStatus,
    stdout: String,
    stderr: String,
}

impl Run {
    /// Asserts a clean failure whose message names every one of `needles`.
    fn refuses(&self, needles: &[&str]) {
        assert!(
            self.status.code().is_some_and(|c| c != 0),
            "expected an error exit, got {:?}; stderr: {}",
            self.status,
            self.stderr
        );
        assert!(!self.stderr.contains("panicked"), "{}", self.stderr);
        for n in needles {
            assert!(self.stderr.contains(n), "no `{n}` in: {}", self.stderr);
        }
    }
}

/// Runs `metamoran args…` under `ulimit -v` 3 GiB; a run past 60 s is killed and fails the test.
fn metamoran(args: &[&str]) -> Run {
    let mut child = Command::new("bash")
        .arg("-c")
        .arg(r#"ulimit -v 3145728; exec "$0" "$@""#)
        .arg(env!("CARGO_BIN_EXE_metamoran"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pipe = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            let _ = r.read_to_string(&mut s);
            s
        })
    };
    let out = pipe(Box::new(child.stdout.take().unwrap()));
    let err = pipe(Box::new(child.stderr.take().unwrap()));
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("metamoran {args:?} hung (killed after 60 s)");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    Run {
        status,
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

/// A simulated one-frame parking lot (xWR18xx-like radar, 640 × 360 camera) in `tmp`.
fn bundle(tmp: &Path) -> PathBuf {
    let out = tmp.join("scenes");
    let run = metamoran(&[
        "simulate",
        "--preset",
        "parking-lot",
        "--radar",
        "xwr18xx",
        "--seed",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.status.success(), "{}", run.stderr);
    out.join("parking-lot-1-0000")
}

fn edit(path: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(from), "{from} not in {}", path.display());
    std::fs::write(path, text.replacen(from, to, 1)).unwrap();
}

fn process(dir: &Path) -> Run {
    metamoran(&["process", dir.to_str().unwrap(), "--json"])
}

/// A 16-bit grayscale PNG of `width` × `height` whose header is valid and whose image data is
/// empty: a header check passes, decoding would allocate the whole image first.
fn png_header(width: u32, height: u32) -> Vec<u8> {
    let mut ihdr = width.to_be_bytes().to_vec();
    ihdr.extend(height.to_be_bytes());
    ihdr.extend([16, 0, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    for (kind, data) in [(b"IHDR", &ihdr[..]), (b"IDAT", &[]), (b"IEND", &[])] {
        png.extend((data.len() as u32).to_be_bytes());
        let body = [&kind[..], data].concat();
        png.extend(&body);
        png.extend(crc32(&body).to_be_bytes());
    }
    png
}

/// CRC-32 (IEEE, as PNG chunks use it), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// Item 4: a 65535 × 65535 camera with matching PNG headers allocated 8.6 GB per product.
#[test]
fn a_huge_camera_is_refused_before_anything_is_allocated() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = bundle(tmp.path());
    edit(&dir.join("scene.toml"), "width = 640", "width = 65535");
    edit(&dir.join("scene.toml"), "height = 360", "height = 65535");
    for product in ["mask", "depth"] {
        let path = dir.join(format!("camera/000000_{product}.png"));
        std::fs::write(path, png_header(65535, 65535)).unwrap();
    }
    process(&dir).refuses(&["scene.toml", "camera.width", "pixels"]);
}

/// Item 4: the PNG header check read the whole file (a mask with a 4 GiB tail, a FIFO that
/// never ends); only regular files of bounded size are read now.
#[test]
fn camera_files_are_bounded_regular_files() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = bundle(tmp.path());
    let mask = dir.join("camera/000000_mask.png");
    std::fs::File::options()
        .append(true)
        .open(&mask)
        .unwrap()
        .set_len(4 << 30)
        .unwrap();
    process(&dir).refuses(&["000000_mask.png", "bytes"]);

    let dir = bundle(&tmp.path().join("fifo"));
    let depth = dir.join("camera/000000_depth.png");
    std::fs::remove_file(&depth).unwrap();
    let made = Command::new("mkfifo").arg(&depth).status().unwrap();
    assert!(made.success());
    process(&dir).refuses(&["000000_depth.png", "not a regular file"]);
}

/// Item 4: a 300-byte config and a sparse 4 GiB capture: one 4 GiB frame was read whole.
#[test]
fn a_frame_larger_than_the_limit_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let config = tmp.path().join("radar.toml");
    std::fs::write(
        &config,
        "[radar]\nstart_frequency_hz = 77e9\nslope_hz_per_s = 30e12\nsample_rate_hz = 10e6\n\
         adc_samples = 2048\nchirp_period_s = 300e-6\nchirps_per_tx = 2048\nframe_period_s = 10\n\
         tx_positions = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15]\n\
         rx_positions = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15]\n\
         tx_order = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15]\nframes = 1\n",
    )
    .unwrap();
    let bin = tmp.path().join("capture.bin");
    let file = std::fs::File::create(&bin).unwrap();
    file.set_len(2048 * 2048 * 16 * 16 * 4).unwrap();
    let run = metamoran(&[
        "summarize",
        bin.to_str().unwrap(),
        "--config",
        config.to_str().unwrap(),
    ]);
    run.refuses(&["radar.toml", "adc_samples", "bytes"]);
}

/// Item 5: `slope_hz_per_s = 1e-300` passed, R_max was infinite and the plots spun forever.
#[test]
fn implausible_derived_quantities_are_refused_before_plotting() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = bundle(tmp.path());
    let scene = dir.join("scene.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    let slope = text
        .lines()
        .find(|l| l.starts_with("slope_hz_per_s"))
        .unwrap();
    edit(&scene, slope, "slope_hz_per_s = 1e-300");
    let out = tmp.path().join("out");
    for args in [
        vec![
            "inspect",
            dir.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        vec![
            "process",
            dir.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    ] {
        metamoran(&args).refuses(&["scene.toml", "radar.slope_hz_per_s", "maximum range"]);
    }
}

/// Item 6: `adc_file` could name a file outside the bundle, directly or through a symlink.
#[test]
fn bundle_paths_stay_inside_the_bundle() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = bundle(tmp.path());
    let outside = tmp.path().join("outside.bin");
    std::fs::copy(dir.join("radar.bin"), &outside).unwrap();
    edit(
        &dir.join("scene.toml"),
        "adc_file = \"radar.bin\"",
        "adc_file = \"../outside.bin\"",
    );
    process(&dir).refuses(&["scene.toml", "radar.adc_file", "inside the bundle"]);

    edit(
        &dir.join("scene.toml"),
        "adc_file = \"../outside.bin\"",
        "adc_file = \"radar.bin\"",
    );
    std::fs::remove_file(dir.join("radar.bin")).unwrap();
    std::os::unix::fs::symlink(&outside, dir.join("radar.bin")).unwrap();
    process(&dir).refuses(&["radar.bin", "inside the bundle"]);
}

/// Item 6: a misspelt key (`tx_elevaton`) was silently ignored.
#[test]
fn unknown_keys_are_refused_with_a_suggestion() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = bundle(tmp.path());
    edit(
        &dir.join("scene.toml"),
        "tx_order = [0, 1]",
        "tx_order = [0, 1]\ntx_elevaton = [0, 0]",
    );
    process(&dir).refuses(&["scene.toml", "radar.tx_elevaton", "tx_elevation"]);

    let dir = bundle(&tmp.path().join("b"));
    edit(&dir.join("scene.toml"), "fx = ", "focal = 3\nfx = ");
    process(&dir).refuses(&["scene.toml", "camera.focal", "unknown"]);
}

/// Item 6: a camera turned 150° away from the radar put objects at azimuth 158° and reported
/// them `detected: true`: nothing outside the radar's field of view is detected.
#[test]
fn nothing_outside_the_field_of_view_is_detected() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = bundle(tmp.path());
    edit(&dir.join("scene.toml"), "yaw_deg = 0.0", "yaw_deg = 150.0");
    let run = process(&dir);
    assert!(run.status.success(), "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    let objects = json["frames"][0]["objects"].as_array().unwrap();
    assert!(!objects.is_empty());
    for o in objects {
        let az = o["azimuth_deg"].as_f64();
        assert!(
            o["detected"] == false || az.is_some_and(|a| a.abs() <= 90.0),
            "detected out of the field of view: #{} at {az:?}°",
            o["instance"]
        );
    }
}

/// Item 8: `demo --perimeter OUT/perimeter.toml --out OUT` copied the file onto itself,
/// truncating it to 0 bytes, and exited 0.
#[test]
fn the_demo_never_destroys_its_perimeter() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let demo = |extra: &[&str]| {
        let mut args = vec![
            "demo",
            "--edge",
            "in-process",
            "--no-live",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        metamoran(&args)
    };
    let first = demo(&[]);
    assert!(first.status.success(), "{}", first.stderr);
    let perimeter = out.join("perimeter.toml");
    let before = std::fs::read(&perimeter).unwrap();
    assert!(!before.is_empty());
    let again = demo(&["--perimeter", perimeter.to_str().unwrap()]);
    assert!(again.status.success(), "{}", again.stderr);
    assert_eq!(std::fs::read(&perimeter).unwrap(), before);

    // A perimeter inside the folder the demo replaces is refused, and left where it is.
    let inside = out.join("scene/perimeter.toml");
    std::fs::write(&inside, &before).unwrap();
    demo(&["--perimeter", inside.to_str().unwrap()]).refuses(&["--perimeter", "replaces"]);
    assert_eq!(std::fs::read(&inside).unwrap(), before);
}

/// Item 9: one corrupt frame (frame 21 of 22) discarded the 21 good ones. Now it is reported
/// and skipped, the others are processed exactly as in a clean run, and the products of the
/// good frames are written.
#[test]
fn a_corrupt_frame_is_skipped_and_the_others_kept() {
    let tmp = tempfile::tempdir().unwrap();
    let scenes = tmp.path().join("scenes");
    let sim = metamoran(&[
        "simulate",
        "--preset",
        "perimeter",
        "--seed",
        "3",
        "--out",
        scenes.to_str().unwrap(),
    ]);
    assert!(sim.status.success(), "{}", sim.stderr);
    let dir = scenes.join("perimeter-3-0000");
    let clean = process(&dir);
    assert!(clean.status.success(), "{}", clean.stderr);
    let clean: serde_json::Value = serde_json::from_str(&clean.stdout).unwrap();
    let frames = clean["frames"].as_array().unwrap().len();
    assert_eq!(frames, 22);

    // Keep the PNG header and the start of the image data of frame 21's mask.
    let mask = dir.join("camera/000021_mask.png");
    let bytes = std::fs::read(&mask).unwrap();
    std::fs::write(&mask, &bytes[..bytes.len() / 2]).unwrap();
    let out = tmp.path().join("out");
    let run = metamoran(&[
        "process",
        dir.to_str().unwrap(),
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    run.refuses(&["frame 21 skipped", "000021_mask.png"]);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    let got = json["frames"].as_array().unwrap();
    assert_eq!(got.len(), frames);
    for f in 0..21 {
        assert_eq!(
            got[f], clean["frames"][f],
            "frame {f} differs from the clean run"
        );
    }
    let bad = &got[21];
    assert!(bad["error"].as_str().unwrap().contains("000021_mask.png"));
    let objects = bad["objects"].as_array().unwrap();
    assert_eq!(
        objects.len(),
        clean["frames"][21]["objects"].as_array().unwrap().len()
    );
    assert!(objects.iter().all(|o| o["detected"] == false));
    assert!(out.join("results.json").is_file() && out.join("depth_20.png").is_file());

    // An --out that cannot be made fails before any work.
    let run = metamoran(&["process", dir.to_str().unwrap(), "--out", "/dev/null/out"]);
    run.refuses(&["--out", "/dev/null/out"]);
    assert!(run.stdout.is_empty());
}

/// Item 2: `metamoran provision` writes a private key file, never prints the key, and never
/// overwrites a key.
#[test]
fn provisioned_keys_are_private_files() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("keys");
    let run = metamoran(&[
        "provision",
        "--device",
        "gate-east",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.status.success(), "{}", run.stderr);
    let file = out.join("gate-east.key");
    let key = std::fs::read_to_string(&file).unwrap();
    let key = key.trim();
    assert_eq!(key.len(), 64);
    assert!(!run.stdout.contains(key) && !run.stderr.contains(key));
    use std::os::unix::fs::PermissionsExt;
    let mode = std::fs::metadata(&file).unwrap().permissions().mode();
    assert_eq!(mode & 0o777, 0o600);
    metamoran(&[
        "provision",
        "--device",
        "gate-east",
        "--out",
        out.to_str().unwrap(),
    ])
    .refuses(&["gate-east.key", "never overwritten"]);
    assert_eq!(std::fs::read_to_string(&file).unwrap().trim(), key);
    metamoran(&[
        "provision",
        "--device",
        "../x",
        "--out",
        out.to_str().unwrap(),
    ])
    .refuses(&["--device"]);
}
