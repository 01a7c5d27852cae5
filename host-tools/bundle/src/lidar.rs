//! The lidar-like truth of drive scenes: one ray per pixel centre of the cylindrical depth image
//! (`metamoran_map::cylinder`, whose grid is defined here), the nearest surface (objects and ground) up to [`RANGE_M`], stored per frame as
//! `lidar/FFFFFF.ply` (binary little-endian, float x y z in the radar frame, m) beside
//! truth.json.

use crate::error::InputError;
use std::path::{Path, PathBuf};

// The cylindrical grid (dense radar mapping, Sec. 3.3): 320 × 80 pixels over θ ∈ −40..40°
// (0.25°) and φ ∈ −20..20° (0.5°); row 0 is the top (+20°), column 0 the left (−40°).

/// Image width: 80° of azimuth in 0.25° columns.
pub const WIDTH: usize = 320;
/// Image height: 40° of elevation in 0.5° rows.
pub const HEIGHT: usize = 80;
/// Azimuth per column, degrees.
pub const AZ_STEP_DEG: f64 = 0.25;
/// Elevation per row, degrees.
pub const EL_STEP_DEG: f64 = 0.5;

/// The pixel `(row, column)` of a point `[x, y, z]` (radar frame: x right, y down, z forward),
/// with its horizontal range; `None` outside the field of view.
pub fn pixel(p: [f64; 3]) -> Option<(usize, usize, f64)> {
    let r = p[0].hypot(p[2]);
    if r <= 0.0 {
        return None;
    }
    let az = p[0].atan2(p[2]).to_degrees();
    let el = (-p[1]).atan2(r).to_degrees();
    let col = ((az + 40.0) / AZ_STEP_DEG).floor();
    let row = ((20.0 - el) / EL_STEP_DEG).floor();
    ((0.0..WIDTH as f64).contains(&col) && (0.0..HEIGHT as f64).contains(&row)).then_some((
        row as usize,
        col as usize,
        r,
    ))
}

/// Farthest lidar return, m.
pub const RANGE_M: f64 = 80.0;

/// `lidar/FFFFFF.ply` of bundle folder `dir`.
pub fn path(dir: &Path, frame: u32) -> PathBuf {
    dir.join("lidar").join(format!("{frame:06}.ply"))
}

/// The unit ray through the centre of pixel `(row, col)` (radar frame).
pub fn ray(row: usize, col: usize) -> [f64; 3] {
    let az = (-40.0 + (col as f64 + 0.5) * AZ_STEP_DEG).to_radians();
    let el = (20.0 - (row as f64 + 0.5) * EL_STEP_DEG).to_radians();
    [el.cos() * az.sin(), -el.sin(), el.cos() * az.cos()]
}

/// Casts every pixel's ray with `hit(direction) -> distance`; the points hit within range.
pub fn scan(hit: impl Fn([f64; 3]) -> Option<f64>) -> Vec<[f64; 3]> {
    (0..HEIGHT)
        .flat_map(|row| (0..WIDTH).map(move |col| ray(row, col)))
        .filter_map(|d| {
            hit(d)
                .filter(|&t| t > 0.0 && t <= RANGE_M)
                .map(|t| [d[0] * t, d[1] * t, d[2] * t])
        })
        .collect()
}

/// Writes points as a binary little-endian PLY.
///
/// # Errors
/// [`InputError::Write`] naming the file or folder.
pub fn write(path: &Path, points: &[[f64; 3]]) -> Result<(), InputError> {
    let header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        points.len()
    );
    let mut bytes = header.into_bytes();
    for p in points {
        for v in p {
            bytes.extend_from_slice(&(*v as f32).to_le_bytes());
        }
    }
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| InputError::write(dir, e))?;
    }
    std::fs::write(path, bytes).map_err(|e| InputError::write(path, e))
}

/// Reads a PLY written by [`write`](fn@write).
///
/// # Errors
/// [`InputError`] naming the file: unreadable, another layout, or truncated.
pub fn read(path: &Path) -> Result<Vec<[f64; 3]>, InputError> {
    parse(
        path,
        &crate::error::read(path, crate::limits::MAX_TRUTH_BYTES)?,
    )
}

/// Parses the contents of a PLY written by [`write`](fn@write) (`path` names it in errors).
///
/// # Errors
/// [`InputError`] naming the file: another layout, or truncated.
pub fn parse(path: &Path, bytes: &[u8]) -> Result<Vec<[f64; 3]>, InputError> {
    let end = b"end_header\n";
    let at = bytes
        .windows(end.len())
        .position(|w| w == end)
        .ok_or_else(|| InputError::file(path, "is not a PLY file (no end_header)"))?;
    let header = String::from_utf8_lossy(&bytes[..at]);
    if !header.starts_with("ply\nformat binary_little_endian 1.0\n") {
        return Err(InputError::file(
            path,
            "is not a binary little-endian PLY of float x y z",
        ));
    }
    let n: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .and_then(|v| v.trim().parse().ok())
        .ok_or_else(|| InputError::field(path, "element vertex", "is missing or not a count"))?;
    let body = &bytes[at + end.len()..];
    if n.checked_mul(12) != Some(body.len()) {
        return Err(InputError::field(
            path,
            "element vertex",
            format!(
                "says {n} points but the file holds {} bytes of them",
                body.len()
            ),
        ));
    }
    Ok(body
        .chunks_exact(12)
        .map(|c| {
            let f = |i: usize| f64::from(f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]));
            [f(0), f(4), f(8)]
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wall_scanned_fills_its_pixels_and_reads_back() {
        // A wall across the view at z = 10 m: every ray with a forward component hits it at
        // t = 10 / d_z, and each point projects back into its own pixel at range 10/cos(az)·cos.
        let pts = scan(|d| (d[2] > 0.0).then(|| 10.0 / d[2]));
        assert_eq!(pts.len(), WIDTH * HEIGHT, "every ray hits within 80 m");
        for (i, p) in pts.iter().enumerate().step_by(997) {
            let (row, col, _) = pixel(*p).unwrap();
            assert_eq!((row, col), (i / WIDTH, i % WIDTH));
            assert!((p[2] - 10.0).abs() < 1e-9);
        }
        let pixels: std::collections::HashSet<_> = pts
            .iter()
            .filter_map(|p| pixel(*p).map(|(r, c, _)| (r, c)))
            .collect();
        assert_eq!(pixels.len(), WIDTH * HEIGHT, "one ray per pixel");
        let dir = tempfile::tempdir().unwrap();
        let f = path(dir.path(), 3);
        write(&f, &pts[..5]).unwrap();
        let back = read(&f).unwrap();
        assert_eq!(back.len(), 5);
        assert!((back[4][2] - 10.0).abs() < 1e-5);
        let whole = std::fs::read(&f).unwrap();
        std::fs::write(&f, &whole[..whole.len() - 7]).unwrap();
        let err = read(&f).unwrap_err().to_string();
        assert!(
            err.contains("000003.ply") && err.contains("element vertex"),
            "{err}"
        );
    }
}
