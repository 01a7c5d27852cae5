//! One ONNX network under the model contract (crate docs): loading, the input size it wants,
//! and running it on an [`Image`], its output brought back to the image's size.

use crate::error::VisionError;
use crate::image::{Image, nearest};
use crate::plan::Plan;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use tract_onnx::prelude::*;
use tract_onnx::tract_hir::infer::Factoid;

/// The shape of `model`'s first input, `None` where a dimension is free.
pub(crate) fn input_dims(model: &InferenceModel) -> TractResult<Vec<Option<usize>>> {
    Ok(model
        .input_fact(0)?
        .shape
        .dims()
        .map(|d| {
            d.concretize()
                .and_then(|d| d.to_i64().ok())
                .map(|d| d as usize)
        })
        .collect())
}

/// A string property of `model` (ONNX `metadata_props` key `key`).
pub(crate) fn metadata(model: &InferenceModel, key: &str) -> Option<String> {
    model
        .properties
        .get(&format!("onnx.metadata_props.{key}"))
        .and_then(|t| {
            t.try_as_plain_ram()
                .ok()?
                .to_scalar::<String>()
                .ok()
                .cloned()
        })
}

/// A loaded network; optimized plans are built once per input size and kept.
pub struct Network {
    path: PathBuf,
    model: InferenceModel,
    /// `(width, height)` the model fixes, if it does.
    fixed: Option<(usize, usize)>,
    plans: Mutex<HashMap<(usize, usize), Plan>>,
}

/// A network's first output, `channels × height × width` at the image's size.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// Channels (classes, or 1 for depth).
    pub channels: usize,
    /// Width, pixels (the image's).
    pub width: usize,
    /// Height, pixels (the image's).
    pub height: usize,
    /// The values, planar.
    pub values: Vec<f32>,
}

impl Network {
    /// Loads the ONNX model at `path` and checks its input against the contract.
    ///
    /// # Errors
    /// [`VisionError::Load`] if tract cannot read it, [`VisionError::Contract`] if its input is
    /// not `[1, 3, H, W]`.
    pub fn load(path: &Path) -> Result<Self, VisionError> {
        let load = |e: TractError| VisionError::Load {
            path: path.to_owned(),
            reason: format!("{e:#}"),
        };
        let model = onnx().model_for_path(path).map_err(load)?;
        let contract = |what: String| VisionError::Contract {
            path: path.to_owned(),
            what,
        };
        if model.inputs.len() != 1 {
            return Err(contract(format!(
                "has {} inputs; the contract is one image [1, 3, H, W]",
                model.inputs.len()
            )));
        }
        let dims = input_dims(&model).map_err(load)?;
        if dims.len() != 4 || dims[0].is_some_and(|b| b != 1) || dims[1].is_some_and(|c| c != 3) {
            return Err(contract(format!(
                "its input is {dims:?} (None = free); the contract is [1, 3, H, W]"
            )));
        }
        let fixed = dims[3].zip(dims[2]);
        Ok(Self {
            path: path.to_owned(),
            model,
            fixed,
            plans: Mutex::new(HashMap::new()),
        })
    }

    /// The model file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// A string property of the model (ONNX `metadata_props` key `key`).
    pub fn metadata(&self, key: &str) -> Option<String> {
        metadata(&self.model, key)
    }

    /// The input size the model fixes, `(width, height)`, if it does.
    pub fn fixed_size(&self) -> Option<(usize, usize)> {
        self.fixed
    }

    fn run_error(&self, e: impl std::fmt::Display) -> VisionError {
        VisionError::Run {
            path: self.path.clone(),
            reason: e.to_string(),
        }
    }

    fn plan(&self, width: usize, height: usize) -> Result<Plan, VisionError> {
        let mut plans = self.plans.lock().map_err(|e| self.run_error(e))?;
        if let Some(p) = plans.get(&(width, height)) {
            return Ok(p.clone());
        }
        let plan = self
            .model
            .clone()
            .with_input_fact(0, f32::fact([1, 3, height, width]).into())
            .and_then(crate::plan::optimized)
            .map_err(|e| self.run_error(format!("{e:#}")))?;
        plans.insert((width, height), plan.clone());
        Ok(plan)
    }

    /// Runs the network on `image`; the first output, resized (nearest) to the image.
    /// Expects `[1, C, h, w]` or `[1, h, w]` (read as C = 1).
    ///
    /// # Errors
    /// [`VisionError::Run`] if inference fails, [`VisionError::Contract`] for another output
    /// shape.
    pub fn run(&self, image: &Image) -> Result<Output, VisionError> {
        let (w, h) = self.fixed.unwrap_or((image.width, image.height));
        let input = image.resized(w, h);
        let tensor =
            Tensor::from_shape(&[1, 3, h, w], &input.planes).map_err(|e| self.run_error(e))?;
        let plan = self.plan(w, h)?;
        let out = crate::plan::run(&plan, tvec!(tensor.into()))
            .map_err(|e| self.run_error(format!("{e:#}")))?;
        let first = out
            .first()
            .ok_or_else(|| self.run_error("the model produced no output"))?;
        let shape = first.shape().to_vec();
        let (c, oh, ow) = match shape[..] {
            [1, c, oh, ow] => (c, oh, ow),
            [1, oh, ow] => (1, oh, ow),
            _ => {
                return Err(VisionError::Contract {
                    path: self.path.clone(),
                    what: format!("its output is {shape:?}; the contract is [1, C, H, W]"),
                });
            }
        };
        let values = first
            .try_as_plain_ram()
            .and_then(|v| v.as_slice::<f32>())
            .map_err(|e| self.run_error(format!("output is not f32 ({e})")))?;
        Ok(Output {
            channels: c,
            width: image.width,
            height: image.height,
            values: nearest(values, c, (ow, oh), (image.width, image.height)),
        })
    }
}
