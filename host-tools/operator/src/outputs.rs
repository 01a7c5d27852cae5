//! The files a run leaves for people and tools: `results.json` (cli.md's shape), per frame the
//! fused depth image (KITTI PNG) and point cloud (PLY), `recording.mcap`, and the inspection
//! plots.

use crate::OperatorError;
use crate::depth_image::{kitti_depth, write_ply, write_png16};
use crate::geofence::Alert;
use metamoran_bundle::geometry::CameraModel;
use metamoran_bundle::{Bundle, OpenOptions};
use metamoran_process::inspect::inspect_frame;
use metamoran_process::{Mode, ProcessOutput};
use std::path::Path;

/// Writes `bytes` to `path` through a temporary file beside it renamed into place: a reader
/// sees the old file or the new one, never a truncated one, and an input that happens to be
/// `path` is read whole before it is replaced (issue #18, item 8).
///
/// # Errors
/// [`OperatorError::Output`] naming the file.
pub fn write(path: &Path, bytes: &[u8]) -> Result<(), OperatorError> {
    let fail = |e: std::io::Error| OperatorError::output(path, "write", e);
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut tmp = tempfile::NamedTempFile::new_in(dir).map_err(fail)?;
    std::io::Write::write_all(&mut tmp, bytes).map_err(fail)?;
    // The temporary file is private (0600); the output is as readable as `std::fs::write`
    // leaves a file under the usual umask.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::Permissions::from_mode(0o644);
        tmp.as_file().set_permissions(mode).map_err(fail)?;
    }
    tmp.persist(path).map_err(|e| fail(e.error))?;
    Ok(())
}

/// `results.json` (cli.md's shape), per frame `depth_F.png` (KITTI, through `camera`) and
/// `points_F.ply`, and `recording.mcap` with the frames (every `period_s`) and `alerts`.
///
/// # Errors
/// [`OperatorError`] naming the file that could not be written.
pub fn write_outputs(
    out: &Path,
    camera: &CameraModel,
    output: &ProcessOutput,
    period_s: f64,
    alerts: &[Alert],
) -> Result<Vec<String>, OperatorError> {
    let json = serde_json::to_vec(output)
        .map_err(|e| OperatorError::output(&out.join("results.json"), "write", e))?;
    write(&out.join("results.json"), &json)?;
    let mut files = vec!["results.json".to_owned()];
    for f in &output.frames {
        let img = kitti_depth(camera, f);
        let png = format!("depth_{}.png", f.frame);
        write_png16(&out.join(&png), camera.width, camera.height, &img)?;
        let ply = format!("points_{}.ply", f.frame);
        write_ply(&out.join(&ply), f)?;
        files.extend([png, ply]);
    }
    crate::record::record(
        &out.join("recording.mcap"),
        &output.frames,
        period_s,
        alerts,
    )?;
    files.push("recording.mcap".into());
    Ok(files)
}

/// `process --out DIR`: writes `results.json`, per frame the fused depth image (`depth_F.png`,
/// 16-bit KITTI) and point cloud (`points_F.ply`), `recording.mcap`, and for the Metamoran mode the inspection
/// plots of every object of every frame ([`crate::inspect`]). Returns the file names.
///
/// # Errors
/// [`OperatorError`] naming the folder or file that could not be written, or the bad bundle field.
pub fn write_products(
    dir: &Path,
    bundle_dir: &Path,
    options: OpenOptions,
    out: &ProcessOutput,
) -> Result<Vec<String>, OperatorError> {
    std::fs::create_dir_all(dir)
        .map_err(|e| OperatorError::output(dir, "create the --out folder", e))?;
    let mut bundle = Bundle::open(bundle_dir, options)?;
    let camera = CameraModel::new(&bundle.scene.camera);
    let period = bundle.scene.radar.frame_period_s;
    let mut files = write_outputs(dir, &camera, out, period, &[])?;
    if out.mode == Mode::Metamoran {
        // A frame that could not be processed has nothing to plot.
        for f in out.frames.iter().filter(|f| f.error.is_none()) {
            let views = inspect_frame(&mut bundle, f.frame)?;
            files.extend(crate::inspect::write_plots(dir, f.frame, &views)?);
        }
    }
    Ok(files)
}
