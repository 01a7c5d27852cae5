//! `process --edge qemu`: the firmware under QEMU, fed over the authenticated telemetry link,
//! must give exactly the JSON of the in-process pipeline, frame after frame.

use metamoran_dsp::wire::DeviceKey;
use metamoran_e2e::{firmware_dir, oracles_required, qemu_available};
use metamoran_process::{Mode, ProcessOptions, Runner, process, process_streamed};
use metamoran_sim::radar::RadarKind;
use metamoran_sim::{layout::Preset, simulate};
use std::path::Path;

/// The module under QEMU with the checkout's device key.
fn qemu() -> Runner {
    Runner::Qemu {
        firmware: firmware_dir(),
        key_file: metamoran_edge::keys::checkout_key(&firmware_dir()).unwrap(),
    }
}

fn json(dir: &Path, runner: Runner) -> Result<String, String> {
    let options = ProcessOptions {
        runner,
        ..ProcessOptions::mode(Mode::Metamoran)
    };
    let out = process(dir, &options).map_err(|e| e.to_string())?;
    Ok(serde_json::to_string(&out).unwrap())
}

/// Turns a one-frame bundle into a `frames`-frame one by repeating its frame (the truth file,
/// which is optional, is dropped).
fn repeat_frames(dir: &Path, frames: u32) {
    let scene = std::fs::read_to_string(dir.join("scene.toml")).unwrap();
    let lines: Vec<String> = scene
        .lines()
        .map(|l| match l.split_once('=') {
            Some((k, _)) if k.trim() == "frames" => format!("frames = {frames}"),
            _ => l.to_owned(),
        })
        .collect();
    assert!(lines.iter().any(|l| l == &format!("frames = {frames}")));
    let scene = lines.join("\n");
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    let radar = std::fs::read(dir.join("radar.bin")).unwrap();
    std::fs::write(dir.join("radar.bin"), radar.repeat(frames as usize)).unwrap();
    for entry in std::fs::read_dir(dir.join("camera")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_str().unwrap().to_owned();
        if let Some(rest) = name.strip_prefix("000000") {
            for f in 1..frames {
                std::fs::copy(&path, path.with_file_name(format!("{f:06}{rest}"))).unwrap();
            }
        }
    }
    let _ = std::fs::remove_file(dir.join("truth.json"));
}

/// One single-frame xWR18xx bundle of `preset` simulated into `dir`.
fn one_bundle(preset: Preset, seed: u64, dir: &Path) -> std::path::PathBuf {
    simulate(preset, RadarKind::Xwr18xx, seed, 1, dir, &|| ()).unwrap();
    std::fs::read_dir(dir)
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path()
}

#[test]
fn qemu_edge_gives_the_in_process_json_bit_for_bit() {
    if !qemu_available() {
        assert!(!oracles_required(), "qemu-system-arm is required");
        eprintln!("SKIPPED: qemu-system-arm not installed");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    simulate(
        Preset::ParkingLot,
        RadarKind::Cascade,
        71,
        2,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    simulate(
        Preset::Moving,
        RadarKind::Xwr18xx,
        72,
        1,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    // The MMWCAS board's four device files: the module reads them copied into one file.
    simulate(
        Preset::LongRange,
        RadarKind::Mmwcas,
        73,
        1,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    let mut bundles: Vec<_> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    bundles.sort();
    let parking = bundles
        .iter()
        .find(|b| {
            b.file_name()
                .unwrap()
                .to_str()
                .unwrap()
                .starts_with("parking-lot")
        })
        .unwrap();
    repeat_frames(parking, 3);
    let mut detected = 0;
    for b in &bundles {
        let here = json(b, Runner::InProcess).unwrap();
        let module = json(b, qemu()).unwrap();
        assert_eq!(module, here, "{}", b.display());
        detected += here.matches("\"detected\":true").count();
    }
    assert!(detected >= 3, "too few detections to compare: {detected}");
}

/// A cascade parking lot on an imperfect board (seeded channel errors) with the calibration
/// `metamoran calibrate` makes from the board's own corner-reflector capture, named in its
/// scene.toml (`None`: as recorded).
fn calibrated_bundle(dir: &Path, calibrated: bool) -> std::path::PathBuf {
    use metamoran_sim::{Difficulty, Variant, simulate_scene_with, simulate_with};
    let board = Variant {
        difficulty: Difficulty::Standard,
        board: Some(5),
        renumber: false,
    };
    let bundle = simulate_with(
        Preset::ParkingLot,
        RadarKind::Cascade,
        board,
        74,
        1,
        dir,
        &|| (),
    )
    .unwrap()
    .remove(0);
    if !calibrated {
        return bundle;
    }
    let corner = simulate_scene_with(Preset::Corner, RadarKind::Cascade, board, 1, 0);
    let capture = dir.join("corner.bin");
    std::fs::write(&capture, &corner.adc).unwrap();
    let mut file = metamoran_bundle::RadarFile::open(
        &capture,
        corner.radar,
        metamoran_dsp::capture::IqOrder::Iiqq,
    )
    .unwrap();
    let means = metamoran_process::calibrate::ChannelMeans::read(&mut file, true).unwrap();
    let m = metamoran_process::calibrate::calibrate(&means, Default::default()).unwrap();
    std::fs::write(bundle.join("calibration.toml"), m.file.to_toml()).unwrap();
    let scene = std::fs::read_to_string(bundle.join("scene.toml")).unwrap();
    let scene = scene.replacen(
        "adc_file",
        "calibration_file = \"calibration.toml\"\nadc_file",
        1,
    );
    std::fs::write(bundle.join("scene.toml"), scene).unwrap();
    bundle
}

#[test]
fn qemu_edge_applies_the_bundles_calibration_bit_for_bit() {
    if !qemu_available() {
        assert!(!oracles_required(), "qemu-system-arm is required");
        eprintln!("SKIPPED: qemu-system-arm not installed");
        return;
    }
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let (calibrated, recorded) = (
        calibrated_bundle(a.path(), true),
        calibrated_bundle(b.path(), false),
    );
    let here = json(&calibrated, Runner::InProcess).unwrap();
    let module = json(&calibrated, qemu()).unwrap();
    assert_eq!(
        module, here,
        "the module's calibrated answer differs from the host's"
    );
    // The calibration is what makes the imperfect board work: objects within 1 m of the truth.
    let within = |bundle: &Path| {
        let out = process(bundle, &ProcessOptions::mode(Mode::Metamoran)).unwrap();
        let truth = metamoran_bundle::Truth::read(&bundle.join("truth.json"), 1).unwrap();
        let mut near = 0;
        for o in &out.frames[0].objects {
            let t = truth.frames[0]
                .objects
                .iter()
                .find(|t| t.instance == o.instance);
            if let (Some(t), Some(d), true) = (t, o.depth_m, o.detected) {
                near += usize::from((d - t.depth_m).abs() < 1.0);
            }
        }
        (near, out.frames[0].objects.len())
    };
    let ((good, of), (bad, _)) = (within(&calibrated), within(&recorded));
    assert!(
        good > bad && 2 * good > of,
        "within 1 m: calibrated {good} of {of}, as recorded {bad}"
    );
}

#[test]
fn qemu_edge_refuses_a_wrong_link_key() {
    if !qemu_available() {
        assert!(!oracles_required(), "qemu-system-arm is required");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let b = one_bundle(Preset::LongRange, 73, tmp.path());
    let elf = metamoran_edge::qemu::build(&firmware_dir(), "edge", None).unwrap();
    let capture = b.join("radar.bin");
    let err = metamoran_edge::link::QemuEdge::launch(&capture, DeviceKey::new([0x42; 32]), elf)
        .err()
        .expect("a wrong key must not pair")
        .to_string();
    assert!(err.contains("--link-key-file"), "{err}");
}

/// The module's defmt log, decoded by `defmt-print` with the firmware's ELF, tells what it did;
/// its Health carries the stack high-water mark.
#[test]
fn qemu_edge_logs_through_defmt() {
    if !qemu_available() {
        assert!(!oracles_required(), "qemu-system-arm is required");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let b = one_bundle(Preset::ParkingLot, 74, tmp.path());
    let options = ProcessOptions {
        runner: qemu(),
        ..ProcessOptions::mode(Mode::Metamoran)
    };
    let (out, log) = process_streamed(&b, &options, |_| Ok(())).unwrap();
    let log = log.expect("the QEMU module reports when it stops");
    // The stack must fit beside the static RAM in the module's 512 KiB (README, "Budgets"), and
    // the gauge must see the pipeline's real depth (tens of KiB), not an idle loop's.
    let statics = firmware::bench_scene::ARENA_WORDS * 4 + size_of::<firmware::module::Scratch>();
    let stack = log.health.stack_bytes as usize;
    assert!(
        stack + statics <= 512 * 1024 && stack >= 32 * 1024,
        "stack {stack} B beside {statics} B of arena and scratch: {:?}",
        log.health
    );
    assert_eq!(log.health.frames, 1);
    let text = metamoran_edge::link::decode_defmt(&log.elf, &log.defmt);
    if text.contains("cargo install defmt-print") {
        assert!(!oracles_required(), "defmt-print is required: {text}");
        return;
    }
    let objects = out.frames[0].objects.len();
    for line in [
        "INFO  edge module up".to_owned(),
        "INFO  session open".to_owned(),
        "INFO  configured: ".to_owned(),
        format!("of {objects} objects detected"),
        format!(
            "INFO  stopped after 1 frames: 0 capture, 0 pipeline, 0 protocol errors; stack {} bytes",
            log.health.stack_bytes
        ),
    ] {
        assert!(text.contains(&line), "no {line:?} in the log:\n{text}");
    }
}

/// Issue #18, item 2: a key from `metamoran provision` (a file, never the command line) goes
/// into the image and pairs the host with it; a key file others can read is refused.
#[test]
fn a_provisioned_key_file_pairs_and_a_readable_one_is_refused() {
    if !qemu_available() {
        assert!(!oracles_required(), "qemu-system-arm is required");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let b = one_bundle(Preset::ParkingLot, 75, tmp.path());
    let key_file = tmp.path().join("gate.key");
    metamoran_edge::keys::write_key_file(&key_file).unwrap();
    let runner = Runner::Qemu {
        firmware: firmware_dir(),
        key_file: key_file.clone(),
    };
    assert_eq!(
        json(&b, runner.clone()).unwrap(),
        json(&b, Runner::InProcess).unwrap()
    );
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&key_file, std::fs::Permissions::from_mode(0o644)).unwrap();
    let err = json(&b, runner).unwrap_err();
    assert!(
        err.contains("gate.key") && err.contains("chmod 600"),
        "{err}"
    );
}
