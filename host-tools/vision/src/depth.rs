//! The monocular depth network: metres along the optical axis per pixel.

use crate::error::VisionError;
use crate::image::Image;
use crate::network::Network;
use std::path::Path;

/// A depth network.
pub struct DepthNetwork {
    network: Network,
}

impl DepthNetwork {
    /// Loads the model at `path`.
    ///
    /// # Errors
    /// As [`Network::load`].
    pub fn load(path: &Path) -> Result<Self, VisionError> {
        Network::load(path).map(|network| Self { network })
    }

    /// Depth per pixel of `image`, metres, row-major; `None` where the network gave no finite
    /// positive value.
    ///
    /// # Errors
    /// As [`Network::run`]; [`VisionError::Contract`] for more than one output channel.
    pub fn estimate(&self, image: &Image) -> Result<Vec<Option<f32>>, VisionError> {
        let out = self.network.run(image)?;
        if out.channels != 1 {
            return Err(VisionError::Contract {
                path: self.network.path().to_owned(),
                what: format!("gives {} channels; a depth network gives one", out.channels),
            });
        }
        Ok(out
            .values
            .iter()
            .map(|&d| (d.is_finite() && d > 0.0).then_some(d))
            .collect())
    }
}
