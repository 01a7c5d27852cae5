//! `metamoran record`, `summarize`, `process`, `inspect` and `demo` with `--dca1000` against
//! `metamoran dca1000-emulate`, as processes on loopback (issue #19): the real DCA1000 session
//! replayed is recorded as its `adc_data.bin`; a live stream summarizes, processes, inspects and
//! runs the demo as its file does; a frame that does not arrive whole is skipped, the others
//! kept.

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_metamoran")
}

fn real(file: &str) -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    std::env::var_os("METAMORAN_SHARED")
        .map_or_else(|| root.join("../shared"), PathBuf::from)
        .join("data/real/mmwave_capture_std_one_frame")
        .join(file)
}

/// The listener's address: `--dca1000` with port 0, so the OS picks a free one that the
/// listener holds from the start (a probed "free" port could be taken by another test's
/// sending socket before the listener binds it).
const ANY_PORT: &str = "127.0.0.1:0";

/// Runs `listen` (a receiving command, with `--dca1000 127.0.0.1:0`) and, once it says on
/// stderr where it listens, `send` (an emulator command) with `--to` that address.
fn listen_while_sending(listen: &[&str], send: &[&str]) -> Output {
    let mut child = Command::new(bin())
        .args(listen)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let (mut seen, mut line) = (String::new(), String::new());
    let at = loop {
        line.clear();
        if stderr.read_line(&mut line).unwrap() == 0 {
            break None; // it failed before listening: its output says why
        }
        seen.push_str(&line);
        if let Some(at) = line
            .trim()
            .strip_prefix("listening for the DCA1000's samples on ")
        {
            break Some(at.to_owned());
        }
    };
    let rest = std::thread::spawn(move || {
        let mut rest = String::new();
        stderr.read_to_string(&mut rest).map(|_| rest)
    });
    if let Some(at) = at {
        let sent = Command::new(bin())
            .args([send, &["--to", &at]].concat())
            .output()
            .unwrap();
        assert!(
            sent.status.success(),
            "{}",
            String::from_utf8_lossy(&sent.stderr)
        );
    }
    let mut out = child.wait_with_output().unwrap();
    seen.push_str(&rest.join().unwrap().unwrap());
    out.stderr = seen.into_bytes();
    out
}

#[test]
fn record_writes_the_replayed_session_as_its_adc_data() {
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join("capture.bin");
    let (cfg, pcap) = (
        real("xwr18xx_profile_2023_01_01T00_00_00_000.cfg"),
        real("test_one_frame.pcap"),
    );
    let o = listen_while_sending(
        &[
            "record",
            "--dca1000",
            ANY_PORT,
            "--config",
            cfg.to_str().unwrap(),
            "--idle-s",
            "0.5",
            "--out",
            file.to_str().unwrap(),
            "--json",
        ],
        &["dca1000-emulate", pcap.to_str().unwrap()],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(&file).unwrap(),
        std::fs::read(real("adc_data.bin")).unwrap()
    );
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(report["packets"], 12);
    assert_eq!(report["lost"], 0);
    // The stream ended inside the .cfg's first frame: that frame is listed as incomplete.
    assert_eq!(report["incomplete_frames"], serde_json::json!([0]));
}

#[test]
fn a_live_stream_summarizes_as_its_file() {
    let capture = real("adc_data.bin");
    let toml = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/real/mmwave_capture_std_one_frame.toml");
    let args = [
        "--config",
        toml.to_str().unwrap(),
        "--iq-order",
        "qqii",
        "--json",
    ];
    let o = listen_while_sending(
        &[&["summarize", "--dca1000", ANY_PORT][..], &args].concat(),
        &[
            "dca1000-emulate",
            capture.to_str().unwrap(),
            "--mbps",
            "200",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let file = Command::new(bin())
        .args([&["summarize", capture.to_str().unwrap()][..], &args].concat())
        .output()
        .unwrap();
    assert!(file.status.success());
    let (live, offline): (serde_json::Value, serde_json::Value) = (
        serde_json::from_slice(&o.stdout).unwrap(),
        serde_json::from_slice(&file.stdout).unwrap(),
    );
    assert_eq!(live["frames"], offline["frames"]);
    assert!(!live["frames"].as_array().unwrap().is_empty());
}

/// Runs `metamoran ARGS` and returns its output, asserting it succeeded.
fn run_ok(args: &[&str]) -> Output {
    let o = Command::new(bin()).args(args).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

/// A simulated 22-frame xWR18xx perimeter bundle in `dir`.
fn perimeter(dir: &Path) -> PathBuf {
    run_ok(&[
        "simulate",
        "--preset",
        "perimeter",
        "--radar",
        "xwr18xx",
        "--seed",
        "3",
        "--out",
        dir.to_str().unwrap(),
    ]);
    dir.join("perimeter-3-0000")
}

/// `metamoran ARGS --dca1000 127.0.0.1:0 --idle-s 0.5` while `dca1000-emulate CAPTURE` (with
/// `send` flags) streams to it on loopback.
fn live(args: &[&str], capture: &Path, send: &[&str]) -> Output {
    let listen = [args, &["--dca1000", ANY_PORT, "--idle-s", "0.5"]].concat();
    let emulate = [&["dca1000-emulate", capture.to_str().unwrap()][..], send].concat();
    listen_while_sending(&listen, &emulate)
}

/// Command arguments as `&str`s.
fn strs<const N: usize>(a: &[String; N]) -> [&str; N] {
    a.each_ref().map(String::as_str)
}

/// The first `kept` of `of` frames of capture `src`, written to `dst`: a stream cut short.
fn first_frames(src: &Path, dst: &Path, kept: usize, of: usize) -> PathBuf {
    let bytes = std::fs::read(src).unwrap();
    std::fs::write(dst, &bytes[..bytes.len() / of * kept]).unwrap();
    dst.to_owned()
}

/// `metamoran process BUNDLE --json` on the live stream of `capture` sent with `impair`
/// (emulator flags): the JSON, stderr and whether it succeeded.
fn process_live(
    bundle: &str,
    capture: &Path,
    impair: &[&str],
) -> (serde_json::Value, String, bool) {
    let send = [&["--mbps", "200"][..], impair].concat();
    let o = live(&["process", bundle, "--json"], capture, &send);
    (
        serde_json::from_slice(&o.stdout).unwrap(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        o.status.success(),
    )
}

#[test]
fn process_takes_a_live_stream_as_the_bundles_capture() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = perimeter(dir.path());
    let b = bundle.to_str().unwrap();
    let radar = bundle.join("radar.bin");
    let offline: serde_json::Value =
        serde_json::from_slice(&run_ok(&["process", b, "--json"]).stdout).unwrap();
    let frames = offline["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 22);

    // Whole: the same JSON as the file, bit for bit.
    let (live, _, ok) = process_live(b, &radar, &[]);
    assert!(ok);
    assert_eq!(live, offline);

    // Lossy: the frames the receiver lists as incomplete are skipped with an error naming them;
    // every other frame is the file's.
    let (lossy, err, ok) = process_live(
        b,
        &radar,
        &[
            "--loss",
            "0.02",
            "--reorder",
            "0.02",
            "--duplicate",
            "0.02",
            "--seed",
            "5",
        ],
    );
    assert!(!ok, "skipped frames fail the run: {err}");
    let listed = err
        .lines()
        .find_map(|l| l.split_once("frames incomplete (zero-filled): "))
        .map(|(_, list)| serde_json::from_str::<Vec<u64>>(list).unwrap())
        .unwrap_or_else(|| panic!("no incomplete frames listed: {err}"));
    assert!(!listed.is_empty() && listed.len() < 22, "{listed:?}");
    for (f, (got, want)) in lossy["frames"]
        .as_array()
        .unwrap()
        .iter()
        .zip(frames)
        .enumerate()
    {
        if listed.contains(&(f as u64)) {
            let why = got["error"]
                .as_str()
                .unwrap_or_else(|| panic!("frame {f}: {got}"));
            assert!(
                why.contains(&format!("frame {f} did not arrive whole")),
                "{why}"
            );
            assert!(
                got["objects"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .all(|o| o["detected"] == false)
            );
        } else {
            assert_eq!(got, want, "frame {f}");
        }
    }

    // Cut short after 10 frames: those 10 are the file's, the 12 the stream ended before are
    // skipped.
    let short = first_frames(&radar, &dir.path().join("ten-frames.bin"), 10, 22);
    let (cut, err, ok) = process_live(b, &short, &[]);
    assert!(!ok, "{err}");
    for (f, (got, want)) in cut["frames"]
        .as_array()
        .unwrap()
        .iter()
        .zip(frames)
        .enumerate()
    {
        if f < 10 {
            assert_eq!(got, want, "frame {f}");
        } else {
            assert!(got["error"].as_str().is_some(), "frame {f}: {got}");
        }
    }
}

#[test]
fn inspect_takes_a_live_stream_as_the_bundles_capture() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = perimeter(dir.path());
    let (b, radar) = (bundle.to_str().unwrap(), bundle.join("radar.bin"));
    let (file_out, live_out) = (dir.path().join("file-plots"), dir.path().join("live-plots"));
    let args = |out: &Path| {
        [
            "inspect",
            b,
            "--frame",
            "7",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ]
        .map(str::to_owned)
    };
    let offline = run_ok(&strs(&args(&file_out)));
    let streamed = live(&strs(&args(&live_out)), &radar, &[]);
    assert!(
        streamed.status.success(),
        "{}",
        String::from_utf8_lossy(&streamed.stderr)
    );
    let report = |o: &Output| {
        let mut v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        v.as_object_mut().unwrap().remove("out");
        v
    };
    assert_eq!(report(&streamed), report(&offline));
    let plots = |d: &PathBuf| {
        let mut names: Vec<_> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        names
    };
    assert!(!plots(&file_out).is_empty());
    assert_eq!(plots(&live_out), plots(&file_out));
    for name in plots(&file_out) {
        assert_eq!(
            std::fs::read(live_out.join(&name)).unwrap(),
            std::fs::read(file_out.join(&name)).unwrap(),
            "{name:?}"
        );
    }

    // The stream, not the bundle's file, is what was read: one that ends before frame 7 fails.
    let short = first_frames(&radar, &dir.path().join("five-frames.bin"), 5, 22);
    let cut = live(&strs(&args(&dir.path().join("short-plots"))), &short, &[]);
    assert!(!cut.status.success());
    let err = String::from_utf8_lossy(&cut.stderr);
    assert!(err.contains("frame 7 did not arrive whole"), "{err}");
}

#[test]
fn the_demo_takes_a_live_stream_as_its_radar() {
    let dir = tempfile::tempdir().unwrap();
    let (first, second) = (dir.path().join("file"), dir.path().join("live"));
    let demo = |out: &Path| {
        [
            "demo",
            "--edge",
            "in-process",
            "--no-live",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ]
        .map(str::to_owned)
    };
    let offline = run_ok(&strs(&demo(&first)));
    // The board replays the scene the first run simulated.
    let capture = dir.path().join("board.bin");
    std::fs::copy(first.join("scene/perimeter-3-0000/radar.bin"), &capture).unwrap();
    let streamed = live(&strs(&demo(&second)), &capture, &["--mbps", "400"]);
    assert!(
        streamed.status.success(),
        "{}",
        String::from_utf8_lossy(&streamed.stderr)
    );
    let (a, b): (serde_json::Value, serde_json::Value) = (
        serde_json::from_slice(&offline.stdout).unwrap(),
        serde_json::from_slice(&streamed.stdout).unwrap(),
    );
    for key in ["frames", "tracks", "alerts", "faults"] {
        assert_eq!(a[key], b[key], "{key}");
    }
    assert!(
        !a["alerts"].as_array().unwrap().is_empty(),
        "the perimeter scene alerts"
    );
    assert!(a.get("radar").is_none());
    let radar = b["radar"].as_str().unwrap();
    assert!(
        radar.contains("22 frame(s) received, 0 not whole"),
        "{radar}"
    );
    // It names the address the OS gave the listener, not the port 0 it was asked for.
    let err = String::from_utf8_lossy(&streamed.stderr);
    let at = err
        .lines()
        .find_map(|l| l.strip_prefix("listening for the DCA1000's samples on "))
        .unwrap();
    assert!(
        !at.ends_with(":0") && radar.starts_with(&format!("DCA1000 stream on {at}:")),
        "{radar}"
    );
    assert_eq!(
        std::fs::read(second.join("results.json")).unwrap(),
        std::fs::read(first.join("results.json")).unwrap()
    );

    // The stream, not the simulated file, is what was processed: one that ends after 20
    // frames has the last two skipped.
    let short = first_frames(&capture, &dir.path().join("twenty.bin"), 20, 22);
    let cut = live(
        &strs(&demo(&dir.path().join("short"))),
        &short,
        &["--mbps", "400"],
    );
    let c: serde_json::Value = serde_json::from_slice(&cut.stdout).unwrap_or_default();
    let faults = c["faults"].as_str().unwrap_or_default();
    assert!(
        faults.contains("frame 20 skipped") && faults.contains("frame 21 skipped"),
        "{c}\n{}",
        String::from_utf8_lossy(&cut.stderr)
    );
    assert!(!faults.contains("frame 19 "), "{faults}");
}
