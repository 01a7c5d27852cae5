//! 3D-RadarHR (dense radar mapping, Sec. 3.3): a sparsity-invariant U-Net that completes the
//! cylindrical depth image of a radar submap (320 × 80, horizontal range in metres, 0 = empty)
//! into a dense one, trained against lidar. The trained model ships in the crate
//! (`models/radarhr.onnx`, written by `train/radarhr.py`); another can be loaded from a file.
//!
//! # Model contract
//! * Input 0 `f32 [1, C, H, W]`, `C` = 1 or 2: channel 0 is the submap's depth / `max_depth_m`,
//!   clipped to 1, 0 = no observation (the network binarizes it into its observation mask); a
//!   second channel, if the model has one, is a guide image scaled the same way (the submap's
//!   IP-Basic completion, which the caller computes: see [`RadarHr::channels`]).
//! * Output 0 `f32 [1, 1, H, W]`: depth / `max_depth_m`; depths under `min_depth_m` mean "no
//!   return" (sky, beyond the lidar's range).
//! * Metadata properties `max_depth_m` and `min_depth_m` (metres).

use crate::error::VisionError;
use crate::network::{input_dims, metadata};
use crate::plan::Plan;
use std::path::{Path, PathBuf};
use tract_onnx::prelude::*;

/// The trained network shipped with the crate for the small (xWR1843-like) board's drive
/// submaps (ONNX, opset 13, about 0.4 MB).
pub const SHIPPED: &[u8] = include_bytes!("../models/radarhr.onnx");

/// The same network trained on the 4D imaging board's submaps, cut to what is visible, over
/// streets, parking areas and covered car parks (the tunnel held out):
/// `models/radarhr-imaging.onnx`.
pub const SHIPPED_IMAGING: &[u8] = include_bytes!("../models/radarhr-imaging.onnx");

/// A loaded 3D-RadarHR network, optimized for its fixed input size.
pub struct RadarHr {
    source: PathBuf,
    plan: Plan,
    width: usize,
    height: usize,
    channels: usize,
    max_depth_m: f32,
    min_depth_m: f32,
}

impl RadarHr {
    /// The network shipped with the crate ([`SHIPPED`]).
    ///
    /// # Errors
    /// As [`RadarHr::from_bytes`] (only if the shipped file is damaged).
    pub fn shipped() -> Result<Self, VisionError> {
        Self::from_bytes(Path::new("<shipped models/radarhr.onnx>"), SHIPPED)
    }

    /// The network shipped for the 4D imaging board ([`SHIPPED_IMAGING`]).
    ///
    /// # Errors
    /// As [`RadarHr::from_bytes`] (only if the shipped file is damaged).
    pub fn shipped_imaging() -> Result<Self, VisionError> {
        Self::from_bytes(
            Path::new("<shipped models/radarhr-imaging.onnx>"),
            SHIPPED_IMAGING,
        )
    }

    /// Loads the ONNX model at `path`.
    ///
    /// # Errors
    /// [`VisionError::Load`] if it cannot be read, [`VisionError::Contract`] if it does not
    /// follow the contract (module docs).
    pub fn load(path: &Path) -> Result<Self, VisionError> {
        let bytes = std::fs::read(path).map_err(|e| VisionError::Load {
            path: path.to_owned(),
            reason: e.to_string(),
        })?;
        Self::from_bytes(path, &bytes)
    }

    /// Loads a model from its bytes; `source` names it in errors.
    ///
    /// # Errors
    /// As [`RadarHr::load`].
    pub fn from_bytes(source: &Path, bytes: &[u8]) -> Result<Self, VisionError> {
        let load = |e: TractError| VisionError::Load {
            path: source.to_owned(),
            reason: format!("{e:#}"),
        };
        let contract = |what: String| VisionError::Contract {
            path: source.to_owned(),
            what,
        };
        let model = onnx().model_for_read(&mut &bytes[..]).map_err(load)?;
        let dims = input_dims(&model).map_err(load)?;
        let (channels, height, width) = match dims[..] {
            [Some(1), Some(c @ (1 | 2)), Some(h), Some(w)] if model.inputs.len() == 1 => (c, h, w),
            _ => {
                return Err(contract(format!(
                    "its input is {dims:?} (None = free); the contract is one fixed \
                     [1, 1, H, W] (a submap) or [1, 2, H, W] (a submap and its guide)"
                )));
            }
        };
        let property = |key: &str| -> Result<f32, VisionError> {
            metadata(&model, key)
                .and_then(|v| v.parse::<f32>().ok())
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| {
                    contract(format!("metadata property {key} is missing or not metres"))
                })
        };
        let (max_depth_m, min_depth_m) = (property("max_depth_m")?, property("min_depth_m")?);
        if max_depth_m <= min_depth_m {
            return Err(contract(format!(
                "max_depth_m {max_depth_m} is not above min_depth_m {min_depth_m}"
            )));
        }
        let plan = crate::plan::optimized(model).map_err(load)?;
        Ok(Self {
            source: source.to_owned(),
            plan,
            width,
            height,
            channels,
            max_depth_m,
            min_depth_m,
        })
    }

    /// `(width, height)` of the depth images it takes and gives.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// How many images it takes: 1 (the submap) or 2 (the submap and a guide, the submap's
    /// IP-Basic completion, that [`RadarHr::complete`] then needs).
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// The largest depth it represents, m.
    pub fn max_depth_m(&self) -> f32 {
        self.max_depth_m
    }

    /// Completes `range_m` (row-major `width × height`, metres, 0 = empty) into a dense depth
    /// image of the same layout (0 = no return), with `guide` (same layout and units) as the
    /// second channel of a two-channel model. One inference: O(pixels × weights).
    ///
    /// # Errors
    /// [`VisionError::Contract`] for an image of another size or with a negative or non-finite
    /// depth, or a guide the model does not take (or lacks); [`VisionError::Run`] if inference
    /// fails.
    pub fn complete(
        &self,
        range_m: &[f32],
        guide: Option<&[f32]>,
    ) -> Result<Vec<f32>, VisionError> {
        let contract = |what: String| VisionError::Contract {
            path: self.source.clone(),
            what,
        };
        let images: &[(&str, &[f32])] = match (guide, self.channels) {
            (None, 1) => &[("depth image", range_m)],
            (Some(g), 2) => &[("depth image", range_m), ("guide", g)],
            (g, c) => {
                return Err(contract(format!(
                    "it takes {c} image(s) and was given {}",
                    1 + usize::from(g.is_some())
                )));
            }
        };
        let pixels = self.width * self.height;
        let mut input = Vec::with_capacity(pixels * images.len());
        for (what, img) in images {
            if img.len() != pixels {
                return Err(contract(format!(
                    "the {what} has {} pixels; the network takes {} × {}",
                    img.len(),
                    self.width,
                    self.height
                )));
            }
            if let Some(i) = img.iter().position(|r| !(r.is_finite() && *r >= 0.0)) {
                return Err(contract(format!(
                    "pixel {i} of the {what} is {} m; depths are finite and ≥ 0",
                    img[i]
                )));
            }
            input.extend(img.iter().map(|&r| (r / self.max_depth_m).min(1.0)));
        }
        let run = |reason: String| VisionError::Run {
            path: self.source.clone(),
            reason,
        };
        let tensor = Tensor::from_shape(&[1, images.len(), self.height, self.width], &input)
            .map_err(|e| run(format!("{e:#}")))?;
        let out = crate::plan::run(&self.plan, tvec!(tensor.into()))
            .map_err(|e| run(format!("{e:#}")))?;
        let values = out
            .first()
            .ok_or_else(|| run("the model produced no output".into()))?
            .try_as_plain_ram()
            .and_then(|v| v.as_slice::<f32>())
            .map_err(|e| run(format!("output is not f32 ({e})")))?;
        if values.len() != pixels {
            return Err(contract(format!(
                "its output has {} values; the contract is [1, 1, {}, {}]",
                values.len(),
                self.height,
                self.width
            )));
        }
        Ok(values
            .iter()
            .map(|&v| {
                let d = v * self.max_depth_m;
                if d >= self.min_depth_m { d } else { 0.0 }
            })
            .collect())
    }
}
