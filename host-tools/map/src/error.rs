//! The mapping crate's errors.

use metamoran_bundle::error::InputError;
use metamoran_process::ProcessError;
use std::path::PathBuf;

/// Why a map could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MapError {
    /// A bad or unreadable bundle file.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A frame could not be processed.
    #[error(transparent)]
    Process(#[from] ProcessError),
    /// The antennas cannot give point clouds with elevation.
    #[error("{}: {source}", scene.display())]
    Geometry {
        /// The bundle's `scene.toml`.
        scene: PathBuf,
        /// What is wrong with the array.
        source: metamoran_dsp::points::GeometryError,
    },
    /// The 3D-RadarHR model failed to load or run.
    #[error("{0}")]
    Network(String),
    /// The network was asked for in a build without ONNX support.
    #[error(
        "this metamoran was built without ONNX support; build it with `cargo build --release -p metamoran --features onnx` to run the 3D-RadarHR network, or pass --no-network"
    )]
    NoOnnx,
}
