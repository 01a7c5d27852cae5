//! The semantic segmenter: per-pixel classes from an image (arg-max of the class scores).

use crate::error::VisionError;
use crate::image::Image;
use crate::network::Network;
use std::path::Path;

/// A segmenter network and its class names.
pub struct Segmenter {
    network: Network,
    labels: Vec<String>,
}

/// Per-pixel classes of one image.
#[derive(Clone, Debug, PartialEq)]
pub struct ClassMap {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Class index per pixel, row-major (0 = background).
    pub classes: Vec<u16>,
}

impl Segmenter {
    /// Loads the model at `path` and its labels (metadata `labels`, else `path.labels`).
    ///
    /// # Errors
    /// As [`Network::load`]; [`VisionError::Contract`] without labels.
    pub fn load(path: &Path) -> Result<Self, VisionError> {
        let network = Network::load(path)?;
        let sidecar = path.with_extension("labels");
        let text = match network.metadata("labels") {
            Some(t) => t.split(',').map(str::to_owned).collect::<Vec<_>>(),
            None => std::fs::read_to_string(&sidecar)
                .map_err(|_| VisionError::Contract {
                    path: path.to_owned(),
                    what: format!(
                        "has no metadata property 'labels' and {} cannot be read; list the class names",
                        sidecar.display()
                    ),
                })?
                .lines()
                .map(str::to_owned)
                .collect(),
        };
        let labels: Vec<String> = text
            .iter()
            .map(|l| l.trim().to_owned())
            .filter(|l| !l.is_empty())
            .collect();
        if labels.len() < 2 {
            return Err(VisionError::Contract {
                path: path.to_owned(),
                what: "lists fewer than two labels (background and one class)".into(),
            });
        }
        Ok(Self { network, labels })
    }

    /// Class names; index 0 is the background.
    pub fn labels(&self) -> &[String] {
        &self.labels
    }

    /// Classes of every pixel of `image`. Ties go to the lower class index. O(C·w·h) after
    /// inference.
    ///
    /// # Errors
    /// As [`Network::run`]; [`VisionError::Contract`] if the scores' channels are not one per label.
    pub fn segment(&self, image: &Image) -> Result<ClassMap, VisionError> {
        let out = self.network.run(image)?;
        if out.channels != self.labels.len() {
            return Err(VisionError::Contract {
                path: self.network.path().to_owned(),
                what: format!(
                    "gives {} class scores per pixel but lists {} labels",
                    out.channels,
                    self.labels.len()
                ),
            });
        }
        let n = out.width * out.height;
        let classes = (0..n)
            .map(|i| {
                let mut best = 0;
                for c in 1..out.channels {
                    if out.values[c * n + i] > out.values[best * n + i] {
                        best = c;
                    }
                }
                best as u16
            })
            .collect();
        Ok(ClassMap {
            width: out.width,
            height: out.height,
            classes,
        })
    }
}
