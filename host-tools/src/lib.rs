//! The library half of the `metamoran` command-line tool: the [`demo`] that runs the whole
//! system on a built-in scene and the [benchmarks](mod@bench). They sit on top of every other host
//! crate; the binary (`main.rs` and its `commands`) is a thin CLI over them and the crates
//! below:
//!
//! ```text
//! metamoran-bundle → metamoran-sim
//!        ↓                 ↓
//! metamoran-edge → metamoran-process → metamoran-map, metamoran-operator → metamoran
//! ```

pub mod bench;
pub mod demo;
pub mod live;
pub mod site;

/// What the demo and the benchmarks fail with: any host crate's error, or a message of their
/// own (they sit at the binary's edge, where strings are allowed).
pub type Error = Box<dyn std::error::Error + Send + Sync>;

/// The shared data folder (real captures) of the checkout this runs in: the first `shared/`
/// holding `data/` beside the current folder or one of its parents. `None` outside a checkout
/// (the binary then takes `--shared DIR` or `METAMORAN_SHARED`).
pub fn find_shared() -> Option<std::path::PathBuf> {
    let cwd = std::env::current_dir().ok()?;
    cwd.ancestors()
        .map(|a| a.join("shared"))
        .find(|s| s.join("data").is_dir())
}
