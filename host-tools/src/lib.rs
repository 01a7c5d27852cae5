//! Host side of the Metamoran runtime: scene-bundle and capture readers, per-frame processing
//! with the module's `dsp` code, summaries and benchmarks. The `metamoran` binary is a thin CLI
//! over this library.

pub mod bench;
pub mod bundle;
pub mod capture;
pub mod demo;
pub mod depth_image;
pub mod edge;
pub mod error;
pub mod eval;
pub mod fields;
pub mod frame;
pub mod geofence;
pub mod geometry;
pub mod inspect;
pub mod live;
pub mod map;
pub mod mqtt;
pub mod oracle;
pub mod process;
pub mod progress;
pub mod qemu;
pub mod record;
pub mod sim;
pub mod summary;

/// Where the shared data folder (`shared/`, beside the repository) is: `$METAMORAN_SHARED` or
/// `../shared` from the workspace root.
pub fn shared_dir() -> std::path::PathBuf {
    std::env::var_os("METAMORAN_SHARED")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| {
            std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared")
        })
}
