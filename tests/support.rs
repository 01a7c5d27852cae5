//! Helpers shared by the end-to-end tests.

use std::path::PathBuf;

/// `shared/data/real/<name>`.
pub fn real_capture_dir(name: &str) -> PathBuf {
    host_tools::shared_dir().join("data/real").join(name)
}

/// The radar config we ship for real capture `name`.
pub fn real_capture_config(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("data/real")
        .join(format!("{name}.toml"))
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
    host_tools::qemu::available()
}
