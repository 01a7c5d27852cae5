//! Camera products computed from `camera/F_image.png` by ONNX models given on the command line
//! (`process --segmenter/--depth-model`), for bundles that carry the image but no mask or depth.
//!
//! The models run through tract in the `metamoran-vision` crate, compiled in with the `onnx`
//! feature (tract takes 11–16 minutes to build from cold, so the default build leaves it out).
//! Image decoding and the conversion to bundle products are here and always built.

use super::camera::Instance;
use crate::error::InputError;
use std::path::Path;
use std::sync::Arc;

/// Instances smaller than this many pixels are left as background: segmenter speckle.
pub const MIN_INSTANCE_PIXELS: usize = 8;

/// An RGB(A) PNG's samples, interleaved, with their full scale.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbSamples {
    /// Samples per pixel: 3 (RGB) or 4 (RGBA; alpha is ignored).
    pub channels: usize,
    /// Full scale: 255 or 65535.
    pub max: u16,
    /// `width × height × channels` samples, row-major.
    pub samples: Vec<u16>,
}

/// Decodes an 8- or 16-bit RGB or RGBA PNG of the given size.
///
/// # Errors
/// [`InputError`] naming the file: unreadable, another colour type or size, corrupt data.
pub fn read_rgb(path: &Path, width: u32, height: u32) -> Result<RgbSamples, InputError> {
    let mut reader = super::camera::open_png(path)?;
    let info = reader.info();
    let channels = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        other => {
            return Err(InputError::file(
                path,
                format!("is {other:?}; the camera models need an RGB or RGBA image"),
            ));
        }
    };
    let sixteen = match info.bit_depth {
        png::BitDepth::Eight => false,
        png::BitDepth::Sixteen => true,
        other => {
            return Err(InputError::file(
                path,
                format!("has {other:?} bits per sample; give 8 or 16"),
            ));
        }
    };
    super::camera::check_size(path, info, width, height)?;
    let n = width as usize * height as usize * channels;
    let mut buf = vec![0u8; n * if sixteen { 2 } else { 1 }];
    reader
        .next_frame(&mut buf)
        .map_err(|e| InputError::file(path, format!("corrupt PNG data ({e})")))?;
    let samples = if sixteen {
        buf.chunks_exact(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
            .collect()
    } else {
        buf.iter().map(|&b| u16::from(b)).collect()
    };
    Ok(RgbSamples {
        channels,
        max: if sixteen { u16::MAX } else { 255 },
        samples,
    })
}

/// KITTI depth value (metres × 256, 0 = none) of a depth in metres.
pub fn kitti_value(depth_m: Option<f32>) -> u16 {
    match depth_m {
        Some(d) if d > 0.0 && d.is_finite() => (d * 256.0).round().clamp(1.0, 65535.0) as u16,
        _ => 0,
    }
}

/// What the models made of one frame's image: the products they replace.
#[derive(Clone, Debug, Default)]
pub struct ImageProducts {
    /// Instance mask and instances (with a segmenter).
    pub segmentation: Option<(Vec<u16>, Vec<Instance>)>,
    /// Monocular depth, metres × 256 (with a depth network).
    pub depth: Option<Vec<u16>>,
}

/// The camera models of a run: a segmenter, a depth network, or both.
pub struct CameraModels {
    #[cfg(feature = "onnx")]
    segmenter: Option<metamoran_vision::Segmenter>,
    #[cfg(feature = "onnx")]
    depth: Option<metamoran_vision::DepthNetwork>,
    segments: bool,
    estimates_depth: bool,
}

impl std::fmt::Debug for CameraModels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CameraModels")
            .field("segmenter", &self.segments)
            .field("depth", &self.estimates_depth)
            .finish()
    }
}

impl CameraModels {
    /// Loads the models given (`None` if neither is).
    ///
    /// # Errors
    /// [`InputError::Model`] naming the model file that cannot be loaded or breaks the
    /// contract, or [`InputError::NoOnnx`] in a build without ONNX support.
    pub fn load(
        segmenter: Option<&Path>,
        depth: Option<&Path>,
    ) -> Result<Option<Arc<Self>>, InputError> {
        if segmenter.is_none() && depth.is_none() {
            return Ok(None);
        }
        #[cfg(feature = "onnx")]
        {
            let segmenter = segmenter
                .map(metamoran_vision::Segmenter::load)
                .transpose()
                .map_err(|e| InputError::Model(e.to_string()))?;
            let depth = depth
                .map(metamoran_vision::DepthNetwork::load)
                .transpose()
                .map_err(|e| InputError::Model(e.to_string()))?;
            Ok(Some(Arc::new(Self {
                segments: segmenter.is_some(),
                estimates_depth: depth.is_some(),
                segmenter,
                depth,
            })))
        }
        #[cfg(not(feature = "onnx"))]
        {
            Err(InputError::NoOnnx)
        }
    }

    /// Whether the mask and instances come from the segmenter.
    pub fn segments(&self) -> bool {
        self.segments
    }

    /// Whether the depth comes from the depth network.
    pub fn estimates_depth(&self) -> bool {
        self.estimates_depth
    }

    /// Runs the models on the image at `path` (`width × height`).
    ///
    /// # Errors
    /// [`InputError`] naming the image, or the model that failed.
    pub fn run(&self, path: &Path, width: u32, height: u32) -> Result<ImageProducts, InputError> {
        let rgb = read_rgb(path, width, height)?;
        self.run_on(path, width, height, &rgb)
    }

    #[cfg(feature = "onnx")]
    fn run_on(
        &self,
        path: &Path,
        width: u32,
        height: u32,
        rgb: &RgbSamples,
    ) -> Result<ImageProducts, InputError> {
        let (w, h) = (width as usize, height as usize);
        let image = metamoran_vision::Image::from_interleaved(
            w,
            h,
            rgb.channels,
            f32::from(rgb.max),
            &rgb.samples,
        )
        .ok_or_else(|| InputError::file(path, "has fewer samples than its size"))?;
        let failed = |e: metamoran_vision::VisionError| InputError::file(path, e.to_string());
        let segmentation = match &self.segmenter {
            Some(s) => {
                let map = s.segment(&image).map_err(failed)?;
                let (mask, regions) = metamoran_vision::instances::split(&map, MIN_INSTANCE_PIXELS);
                let instances = regions
                    .iter()
                    .map(|r| Instance {
                        id: r.id,
                        class: s.labels()[usize::from(r.class)].clone(),
                    })
                    .collect();
                Some((mask, instances))
            }
            None => None,
        };
        let depth = match &self.depth {
            Some(d) => Some(
                d.estimate(&image)
                    .map_err(failed)?
                    .into_iter()
                    .map(kitti_value)
                    .collect(),
            ),
            None => None,
        };
        Ok(ImageProducts {
            segmentation,
            depth,
        })
    }

    #[cfg(not(feature = "onnx"))]
    fn run_on(
        &self,
        path: &Path,
        _width: u32,
        _height: u32,
        _rgb: &RgbSamples,
    ) -> Result<ImageProducts, InputError> {
        // Unreachable: without the feature `load` never makes a `CameraModels`.
        Err(InputError::file(path, "this build has no ONNX support"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb_pngs_of_both_depths_decode_and_others_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str, color, depth, data: &[u8]| {
            let p = dir.path().join(name);
            let f = std::fs::File::create(&p).unwrap();
            let mut e = png::Encoder::new(f, 2, 1);
            e.set_color(color);
            e.set_depth(depth);
            e.write_header().unwrap().write_image_data(data).unwrap();
            p
        };
        let p = write(
            "a.png",
            png::ColorType::Rgb,
            png::BitDepth::Eight,
            &[1, 2, 3, 4, 5, 6],
        );
        let rgb = read_rgb(&p, 2, 1).unwrap();
        assert_eq!((rgb.channels, rgb.max), (3, 255));
        assert_eq!(rgb.samples, vec![1, 2, 3, 4, 5, 6]);
        let sixteen: Vec<u8> = [1000u16, 2, 3, 4, 5, 6, 7, 65535]
            .iter()
            .flat_map(|v| v.to_be_bytes())
            .collect();
        let p = write(
            "b.png",
            png::ColorType::Rgba,
            png::BitDepth::Sixteen,
            &sixteen,
        );
        let rgb = read_rgb(&p, 2, 1).unwrap();
        assert_eq!((rgb.channels, rgb.max), (4, 65535));
        assert_eq!(rgb.samples[0], 1000);
        let err = read_rgb(&p, 3, 1).unwrap_err().to_string();
        assert!(err.contains("b.png") && err.contains("3×1"), "{err}");
        let p = write(
            "g.png",
            png::ColorType::Grayscale,
            png::BitDepth::Eight,
            &[1, 2],
        );
        let err = read_rgb(&p, 2, 1).unwrap_err().to_string();
        assert!(err.contains("g.png") && err.contains("RGB"), "{err}");
        assert_eq!(kitti_value(Some(12.5)), 3200);
        assert_eq!(kitti_value(Some(f32::NAN)), 0);
        assert_eq!(kitti_value(Some(-1.0)), 0);
        assert_eq!(kitti_value(Some(1000.0)), 65535);
    }
}
