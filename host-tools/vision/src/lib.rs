//! Camera models for Metamoran bundles that carry only `camera/F_image.png`: an ONNX semantic
//! segmenter and an ONNX monocular depth network, run on the CPU through tract.
//!
//! The pipeline's camera input is an instance mask, a monocular depth image and the instances'
//! classes (bundle.md). Where a bundle has the image alone, [`Segmenter`] gives per-pixel
//! classes, [`instances::split`] turns them into instances (connected components), and
//! [`DepthNetwork`] gives depth along z in metres.
//!
//! # Model contract
//! * Input 0: `f32 [1, 3, H, W]`, RGB in `0..=1`, rows top to bottom. `H` and `W` may be free
//!   (the image's size is used) or fixed (the image is resized bilinearly to them and the
//!   output back to the image with nearest neighbour).
//! * Segmenter output 0: `f32 [1, C, H, W]` class scores; a pixel's class is the arg-max.
//!   Class names come from the model's metadata property `labels` (comma-separated, index 0 =
//!   background), or else from a `MODEL.labels` file beside it (one name per line).
//! * Depth output 0: `f32 [1, 1, H, W]` or `[1, H, W]`, metres along the optical axis; values
//!   that are not finite and positive mean "no estimate".
//!
//! It also runs the radar's own network, [`RadarHr`]: 3D-RadarHR of the dense-radar-mapping
//! paper, which completes a sparse radar submap depth image into a dense one.
//!
//! This crate is kept apart because tract takes 11–16 minutes to build from cold: nothing in
//! the `dsp`/firmware edit–test loop depends on it.

pub mod depth;
pub mod error;
pub mod image;
pub mod instances;
pub mod network;
mod plan;
pub mod radarhr;
pub mod segmenter;

pub use depth::DepthNetwork;
pub use error::VisionError;
pub use image::Image;
pub use network::Network;
pub use radarhr::RadarHr;
pub use segmenter::{ClassMap, Segmenter};
