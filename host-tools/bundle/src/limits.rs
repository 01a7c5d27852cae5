//! Size limits on everything read from a bundle or a capture, and the one way files are opened.
//!
//! Every size a header or config states is checked against these limits before anything is
//! allocated, and only regular files are read (a FIFO, a device such as `/dev/zero` or a folder is
//! refused by name): a small hostile input cannot exhaust the host's memory or hang a reader
//! (issue #18, item 4). The limits sit far above every real radar and camera we know of; the
//! README's "Input limits" table lists them.

use crate::error::InputError;
use std::fs::File;
use std::io::Read;
use std::path::Path;

/// Most pixels of a camera image (8K UHD, 7680 × 4320): 66 MB per 16-bit product.
pub const MAX_PIXELS: u64 = 7680 * 4320;
/// Largest PNG file (a 16-bit 8K image that does not compress is 66 MB).
pub const MAX_PNG_BYTES: u64 = 256 << 20;
/// Largest radar frame, bytes (an MMWCAS cascade frame of 12 TX × 16 RX × 256 samples × 128
/// loops is 25 MB).
pub const MAX_FRAME_BYTES: u64 = 256 << 20;
/// Most frames of one capture (a day at 10 Hz is 864,000).
pub const MAX_FRAMES: u32 = 10_000_000;
/// Largest TOML file (`scene.toml`, a radar config, a perimeter).
pub const MAX_TOML_BYTES: u64 = 1 << 20;
/// Largest `F_instances.json` (65,535 instances at ~40 bytes each).
pub const MAX_INSTANCES_BYTES: u64 = 16 << 20;
/// Largest `truth.json` or lidar file.
pub const MAX_TRUTH_BYTES: u64 = 1 << 30;

/// Opens `path` for reading if it is a regular file of at most `limit` bytes; its size.
///
/// # Errors
/// [`InputError`] naming the file: missing, not a regular file, or over the limit.
pub fn open_regular(path: &Path, limit: u64) -> Result<(File, u64), InputError> {
    let not_regular = || {
        InputError::file(
            path,
            "is not a regular file (a FIFO, device or folder); give a file",
        )
    };
    // Before opening: opening a FIFO blocks until something writes to it.
    let meta = std::fs::metadata(path).map_err(|e| InputError::io(path, e))?;
    if !meta.is_file() {
        return Err(not_regular());
    }
    let file = File::open(path).map_err(|e| InputError::io(path, e))?;
    let meta = file.metadata().map_err(|e| InputError::io(path, e))?;
    if !meta.is_file() {
        return Err(not_regular());
    }
    if meta.len() > limit {
        return Err(InputError::file(
            path,
            format!(
                "is {} bytes; files of this kind are at most {limit} bytes (README, \"Input limits\")",
                meta.len()
            ),
        ));
    }
    Ok((file, meta.len()))
}

/// Reads the whole of regular file `path`, of at most `limit` bytes (even if it grows while
/// being read).
///
/// # Errors
/// As [`open_regular`], or a read error.
pub fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, InputError> {
    let (file, len) = open_regular(path, limit)?;
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(limit)
        .read_to_end(&mut bytes)
        .map_err(|e| InputError::io(path, e))?;
    Ok(bytes)
}

/// Checks that `dir` (canonical) holds `path` once every symlink is resolved.
///
/// # Errors
/// [`InputError`] naming `path` if it resolves outside `dir` (or cannot be resolved).
pub fn confined(dir: &Path, path: &Path) -> Result<(), InputError> {
    let real = path.canonicalize().map_err(|e| InputError::io(path, e))?;
    if real.starts_with(dir) {
        Ok(())
    } else {
        Err(InputError::file(
            path,
            format!(
                "resolves to {}; every file of a bundle must be inside the bundle folder {} \
                 (copy it in rather than linking to it)",
                real.display(),
                dir.display()
            ),
        ))
    }
}
