//! Helpers shared by the end-to-end tests.

use std::path::{Path, PathBuf};

/// The shared data folder: `$METAMORAN_SHARED`, else `shared/` beside the checkout.
pub fn shared_dir() -> PathBuf {
    std::env::var_os("METAMORAN_SHARED").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared"),
        PathBuf::from,
    )
}

/// The firmware's Cargo workspace of this checkout.
pub fn firmware_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../firmware")
}

/// `shared/data/real/<name>`.
pub fn real_capture_dir(name: &str) -> PathBuf {
    shared_dir().join("data/real").join(name)
}

/// The radar config we ship for real capture `name`: beside the tests, or in the binary's data
/// (the one `metamoran demo-capture` embeds).
pub fn real_capture_config(name: &str) -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let file = format!("{name}.toml");
    let here = root.join("data/real").join(&file);
    if here.exists() {
        here
    } else {
        root.join("../host-tools/data").join(file)
    }
}

/// Whether tests that need an external oracle (venv, QEMU) must run rather than skip:
/// `scripts/test` sets `METAMORAN_REQUIRE_ORACLES=1`.
pub fn oracles_required() -> bool {
    std::env::var_os("METAMORAN_REQUIRE_ORACLES").is_some_and(|v| v == "1")
}

/// Indices of the `k` largest values, largest first.
pub fn top_k(x: &[f32], k: usize) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..x.len()).collect();
    idx.sort_by(|&a, &b| x[b].total_cmp(&x[a]));
    idx.truncate(k);
    idx
}

/// Whether `qemu-system-arm` runs on this machine.
pub fn qemu_available() -> bool {
    metamoran_edge::qemu::available()
}

/// Runs Python oracle `tests/oracles/<script>` with `args` in the test venv; its stdout. `None`
/// (the caller skips) when there is no venv and the oracles are not required; `what` names the
/// package the oracle needs.
pub fn run_oracle(script: &str, args: &[&std::ffi::OsStr], what: &str) -> Option<Vec<u8>> {
    let Some(py) = metamoran::bench::cmsis::venv_python() else {
        assert!(!oracles_required(), "the test venv ({what}) is required");
        eprintln!("SKIPPED: no test venv for {what}");
        return None;
    };
    let run = std::process::Command::new(py)
        .arg(
            PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("oracles")
                .join(script),
        )
        .args(args)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{script}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    Some(run.stdout)
}

/// A free TCP port on loopback (for a server a test starts).
pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// The simulated three-pole site the site, NATS and browser tests share (cascade, seed 11),
/// written under `out`.
pub fn site_folder(out: &Path) -> PathBuf {
    metamoran_sim::site::simulate_site(metamoran_sim::radar::RadarKind::Cascade, 11, out).unwrap()
}

/// One raw HTTP/1.1 request (`Connection: close` is added) to `addr` with `body`; the whole
/// reply.
pub fn http(addr: std::net::SocketAddr, head: &str, body: &str) -> String {
    use std::io::{Read, Write};
    let mut s = std::net::TcpStream::connect(addr).unwrap();
    write!(
        s,
        "{head}\r\nHost: {addr}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut reply = Vec::new();
    let _ = s.read_to_end(&mut reply);
    // A PNG body comes back with its non-UTF-8 bytes replaced; the head is ASCII.
    String::from_utf8_lossy(&reply).into_owned()
}

/// The status code of an HTTP reply.
pub fn status_of(reply: &str) -> u16 {
    reply
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0)
}

/// Posts a login form to the web view at `addr`; the reply.
pub fn post_login(addr: std::net::SocketAddr, body: &str) -> String {
    http(
        addr,
        "POST /login HTTP/1.1\r\nContent-Type: application/x-www-form-urlencoded",
        body,
    )
}

/// Waits (up to 2 minutes) until the file at `path` has `n` lines; returns its lines.
pub fn wait_for_lines(path: &Path, n: usize) -> Vec<String> {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    loop {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        if text.lines().count() >= n {
            return text.lines().map(String::from).collect();
        }
        assert!(
            std::time::Instant::now() < deadline,
            "{} never had {n} lines",
            path.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}
