//! The 3D-RadarHR network behind `metamoran map` (`metamoran_vision::RadarHr` through tract): the model
//! shipped in the vision crate, or another ONNX file. Needs the `onnx` feature; without it,
//! loading says how to build with it.

use crate::MapError;
use std::path::Path;

/// A loaded depth-completion network.
pub struct CompletionNetwork {
    #[cfg(feature = "onnx")]
    inner: metamoran_vision::RadarHr,
    /// Without tract there is no network: the type has no values.
    #[cfg(not(feature = "onnx"))]
    none: std::convert::Infallible,
}

impl CompletionNetwork {
    /// The ONNX model at `path`, or the shipped one.
    ///
    /// # Errors
    /// [`MapError`] naming the model that cannot be loaded or breaks the contract, or saying how
    /// to build with ONNX support.
    pub fn load(path: Option<&Path>) -> Result<Self, MapError> {
        #[cfg(feature = "onnx")]
        {
            let inner = match path {
                Some(p) => metamoran_vision::RadarHr::load(p),
                None => metamoran_vision::RadarHr::shipped(),
            }
            .map_err(|e| MapError::Network(e.to_string()))?;
            Ok(Self { inner })
        }
        #[cfg(not(feature = "onnx"))]
        {
            let _ = path;
            Err(MapError::NoOnnx)
        }
    }

    /// Completes a 320 × 80 submap depth image (row-major ranges, m, 0 = empty).
    ///
    /// # Errors
    /// The model's message (wrong size, bad depth, inference failure).
    pub fn complete(&self, range_m: &[f32]) -> Result<Vec<f32>, MapError> {
        #[cfg(feature = "onnx")]
        {
            self.inner
                .complete(range_m)
                .map_err(|e| MapError::Network(e.to_string()))
        }
        #[cfg(not(feature = "onnx"))]
        {
            let _ = range_m;
            match self.none {}
        }
    }
}
