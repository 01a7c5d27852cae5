//! What can go wrong with a camera model, naming the model file.

use std::path::PathBuf;

/// A camera model that cannot be loaded or run.
#[derive(Debug, thiserror::Error)]
pub enum VisionError {
    /// The file is not an ONNX model tract can load.
    #[error("{path}: cannot load the ONNX model ({reason}); give an ONNX file (opset ≥ 11)")]
    Load {
        /// Model file.
        path: PathBuf,
        /// tract's reason.
        reason: String,
    },
    /// The model does not follow the contract (crate docs, README "Camera models").
    #[error("{path}: {what}; see the README's \"Camera models\" for the input and output layout")]
    Contract {
        /// Model file.
        path: PathBuf,
        /// What is wrong.
        what: String,
    },
    /// Inference failed.
    #[error("{path}: inference failed ({reason})")]
    Run {
        /// Model file.
        path: PathBuf,
        /// tract's reason.
        reason: String,
    },
}
