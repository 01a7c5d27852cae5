//! `metamoran record` and `summarize --dca1000` against `metamoran dca1000-emulate`, as
//! processes on loopback (issue #19): the real DCA1000 session replayed is recorded as its
//! `adc_data.bin`, and a live stream summarizes as its file does.

use std::net::UdpSocket;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

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

/// A free loopback UDP port.
fn free_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// Runs `listen` (a receiving command) and, once it is up, `send` (an emulator command).
fn listen_while_sending(listen: &[&str], send: &[&str]) -> Output {
    let child = Command::new(bin())
        .args(listen)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The receiver binds before it waits (its --start-s); give it a moment.
    std::thread::sleep(Duration::from_millis(700));
    let sent = Command::new(bin()).args(send).output().unwrap();
    assert!(
        sent.status.success(),
        "{}",
        String::from_utf8_lossy(&sent.stderr)
    );
    child.wait_with_output().unwrap()
}

#[test]
fn record_writes_the_replayed_session_as_its_adc_data() {
    let port = free_port();
    let to = format!("127.0.0.1:{port}");
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
            &to,
            "--config",
            cfg.to_str().unwrap(),
            "--idle-s",
            "0.5",
            "--out",
            file.to_str().unwrap(),
            "--json",
        ],
        &["dca1000-emulate", pcap.to_str().unwrap(), "--to", &to],
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
    let port = free_port();
    let to = format!("127.0.0.1:{port}");
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
        &[&["summarize", "--dca1000", &to][..], &args].concat(),
        &[
            "dca1000-emulate",
            capture.to_str().unwrap(),
            "--to",
            &to,
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
