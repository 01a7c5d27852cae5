//! Camera products of one frame: instance mask, monocular depth, instance classes.

use crate::error::{InputError, parse_json, read};
use crate::limits::{MAX_PNG_BYTES, open_regular};
use serde::{Deserialize, Serialize};
use std::fs::File;
use std::io::{BufRead, BufReader, Seek};
use std::path::{Path, PathBuf};

/// Classes whose depth the method estimates.
pub const OBJECTS_OF_INTEREST: [&str; 3] = ["car", "person", "sign"];
/// Classes of strong static reflectors that clutter cancellation may remove.
pub const CLUTTER_CLASSES: [&str; 6] = [
    "building",
    "wall",
    "fence",
    "pole",
    "tree",
    "vehicle_parked",
];

/// One segmented instance.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Instance {
    /// Id used in the mask (1..=65535).
    pub id: u16,
    /// Lowercase class word.
    pub class: String,
}

impl Instance {
    /// Whether this is a car, person or sign.
    pub fn is_object_of_interest(&self) -> bool {
        OBJECTS_OF_INTEREST.contains(&self.class.as_str())
    }

    /// Whether this is a strong static reflector (building, wall, …).
    pub fn is_clutter(&self) -> bool {
        CLUTTER_CLASSES.contains(&self.class.as_str())
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct InstancesFile {
    instances: Vec<Instance>,
}

/// The file names of frame `frame`'s camera products.
#[derive(Clone, Debug)]
pub struct CameraPaths {
    /// `camera/F_mask.png`.
    pub mask: PathBuf,
    /// `camera/F_depth.png`.
    pub depth: PathBuf,
    /// `camera/F_instances.json`.
    pub instances: PathBuf,
    /// `camera/F_image.png` (optional).
    pub image: PathBuf,
}

impl CameraPaths {
    /// Paths inside bundle folder `dir`.
    pub fn new(dir: &Path, frame: u32) -> Self {
        let cam = dir.join("camera");
        let f = format!("{frame:06}");
        Self {
            mask: cam.join(format!("{f}_mask.png")),
            depth: cam.join(format!("{f}_depth.png")),
            instances: cam.join(format!("{f}_instances.json")),
            image: cam.join(format!("{f}_image.png")),
        }
    }

    /// Checks that the files a frame reads resolve inside bundle folder `root` (canonical):
    /// the image when a model `segments` or `estimates_depth`, the mask and instances unless
    /// it segments, the depth unless it estimates it.
    ///
    /// # Errors
    /// [`InputError`] naming the first file that resolves outside (or cannot be resolved).
    pub fn confined(
        &self,
        root: &Path,
        segments: bool,
        estimates_depth: bool,
    ) -> Result<(), InputError> {
        let files = [
            (&self.image, segments || estimates_depth),
            (&self.mask, !segments),
            (&self.instances, !segments),
            (&self.depth, !estimates_depth),
        ];
        for (path, read) in files {
            if read && path.exists() {
                crate::limits::confined(root, path)?;
            }
        }
        Ok(())
    }
}

/// Reads and checks `F_instances.json`: ids unique and non-zero, classes lowercase words.
///
/// # Errors
/// [`InputError`] naming the file and field.
pub fn read_instances(path: &Path) -> Result<Vec<Instance>, InputError> {
    parse_instances(path, &read(path, crate::limits::MAX_INSTANCES_BYTES)?)
}

/// [`read_instances`] on the bytes of `path` already read.
///
/// # Errors
/// [`InputError`] naming the file and field.
pub fn parse_instances(path: &Path, bytes: &[u8]) -> Result<Vec<Instance>, InputError> {
    let file: InstancesFile = parse_json(path, bytes)?;
    let mut seen = std::collections::BTreeSet::new();
    for (i, inst) in file.instances.iter().enumerate() {
        if inst.id == 0 {
            return Err(InputError::field(
                path,
                format!("instances[{i}].id"),
                "0 means 'no instance' in the mask; ids start at 1",
            ));
        }
        if !seen.insert(inst.id) {
            return Err(InputError::field(
                path,
                format!("instances[{i}].id"),
                format!("id {} is listed twice", inst.id),
            ));
        }
        let ok = !inst.class.is_empty()
            && inst
                .class
                .chars()
                .all(|c| c.is_ascii_lowercase() || c == '_' || c.is_ascii_digit());
        if !ok {
            return Err(InputError::field(
                path,
                format!("instances[{i}].class"),
                format!("\"{}\" is not a lowercase word", inst.class),
            ));
        }
    }
    Ok(file.instances)
}

/// A PNG file opened for streaming: a regular file of at most [`MAX_PNG_BYTES`], read as the
/// decoder asks (the header check reads only up to the first image data).
pub(super) type PngReader = png::Reader<BufReader<File>>;

/// Opens PNG `path` (no transformations) and reads its header.
///
/// # Errors
/// [`InputError`] naming the file: not a bounded regular file, or not a PNG.
pub(super) fn open_png(path: &Path) -> Result<PngReader, InputError> {
    let (file, _) = open_regular(path, MAX_PNG_BYTES)?;
    png_reader(path, BufReader::new(file))
}

/// Reads the header of the PNG in `r` (the contents of `path`), without transformations.
fn png_reader<R: BufRead + Seek>(path: &Path, r: R) -> Result<png::Reader<R>, InputError> {
    // The decoder's own allocations: a row or two and the chunk buffers; the image goes into
    // the caller's buffer, whose size the `[camera]` table bounds.
    let limits = png::Limits { bytes: 64 << 20 };
    let mut decoder = png::Decoder::new_with_limits(r, limits);
    decoder.set_transformations(png::Transformations::IDENTITY);
    decoder
        .read_info()
        .map_err(|e| InputError::file(path, format!("not a readable PNG ({e})")))
}

/// Checks that `reader` (of `path`) is a 16-bit grayscale PNG of the expected size.
fn check_png16<R: BufRead + Seek>(
    path: &Path,
    reader: png::Reader<R>,
    width: u32,
    height: u32,
) -> Result<png::Reader<R>, InputError> {
    let info = reader.info();
    if info.color_type != png::ColorType::Grayscale || info.bit_depth != png::BitDepth::Sixteen {
        return Err(InputError::file(
            path,
            format!(
                "is {:?} {:?}-bit; a 16-bit grayscale PNG is required",
                info.color_type, info.bit_depth as u8
            ),
        ));
    }
    check_size(path, info, width, height)?;
    Ok(reader)
}

/// Checks that a camera image is the size `scene.toml`'s `[camera]` gives.
///
/// # Errors
/// [`InputError`] naming the file and both sizes.
pub(super) fn check_size(
    path: &Path,
    info: &png::Info<'_>,
    width: u32,
    height: u32,
) -> Result<(), InputError> {
    if (info.width, info.height) != (width, height) {
        return Err(InputError::file(
            path,
            format!(
                "is {}×{} pixels but scene.toml's [camera] says {width}×{height}",
                info.width, info.height
            ),
        ));
    }
    Ok(())
}

/// Checks the header of a 16-bit grayscale PNG of the given size without decoding it.
///
/// # Errors
/// [`InputError`] naming the file.
pub fn check_png16_header(path: &Path, width: u32, height: u32) -> Result<(), InputError> {
    check_png16(path, open_png(path)?, width, height).map(|_| ())
}

/// Decodes a 16-bit grayscale PNG of the given size into row-major values.
///
/// # Errors
/// [`InputError`] naming the file.
pub fn read_png16(path: &Path, width: u32, height: u32) -> Result<Vec<u16>, InputError> {
    decode_png16(path, open_png(path)?, width, height)
}

/// [`read_png16`] on PNG bytes already in memory (`path` names them in errors).
///
/// # Errors
/// [`InputError`] naming `path`.
pub fn parse_png16(
    path: &Path,
    bytes: &[u8],
    width: u32,
    height: u32,
) -> Result<Vec<u16>, InputError> {
    let reader = png_reader(path, std::io::Cursor::new(bytes))?;
    decode_png16(path, reader, width, height)
}

/// Decodes the 16-bit grayscale PNG `reader` of the given size.
fn decode_png16<R: BufRead + Seek>(
    path: &Path,
    reader: png::Reader<R>,
    width: u32,
    height: u32,
) -> Result<Vec<u16>, InputError> {
    let mut reader = check_png16(path, reader, width, height)?;
    let mut buf = vec![0u8; width as usize * height as usize * 2];
    reader
        .next_frame(&mut buf)
        .map_err(|e| InputError::file(path, format!("corrupt PNG data ({e})")))?;
    Ok(buf
        .chunks_exact(2)
        .map(|b| u16::from_be_bytes([b[0], b[1]]))
        .collect())
}

/// The decoded camera products of one frame.
#[derive(Clone, Debug)]
pub struct CameraFrame {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Instance id per pixel (0 = none), row-major.
    pub mask: Vec<u16>,
    /// Monocular depth along z per pixel, metres × 256 (0 = none), row-major.
    pub depth: Vec<u16>,
    /// The instances of this frame.
    pub instances: Vec<Instance>,
}

impl CameraFrame {
    /// Depth in metres at pixel (x, y), if the estimator gave one.
    pub fn depth_m(&self, x: u32, y: u32) -> Option<f32> {
        let v = *self.depth.get((y * self.width + x) as usize)?;
        (v != 0).then(|| v as f32 / 256.0)
    }
}
