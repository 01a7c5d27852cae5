//! CMSIS-DSP's fixed-point FFTs as the baseline of `bench fft`, run from the project's Python
//! venv (PyPI's `cmsisdsp`).
//!
//! The venv is `$METAMORAN_VENV`, else the first `.venv` in the current folder or one of its
//! parents (`scripts/setup` makes it at the checkout's root).

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};

/// The CMSIS-DSP script (in the binary, so it runs from any folder).
const CMSIS_FFT_PY: &str = include_str!("cmsis_fft.py");

/// The venv's Python interpreter, if the venv exists.
pub fn venv_python() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("METAMORAN_VENV") {
        let py = PathBuf::from(dir).join("bin/python");
        return py.exists().then_some(py);
    }
    let cwd = std::env::current_dir().ok()?;
    cwd.ancestors()
        .map(|a| a.join(".venv/bin/python"))
        .find(|py| py.exists())
}

/// A fixed-point format CMSIS can transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CmsisFormat {
    /// `arm_cfft_q15`.
    Q15,
    /// `arm_cfft_q31`.
    Q31,
}

/// One CMSIS FFT request: interleaved raw `re, im` integers of length `2·n`.
pub struct CmsisRequest {
    /// Format.
    pub format: CmsisFormat,
    /// Raw interleaved input.
    pub data: Vec<i64>,
}

/// Runs CMSIS's CFFT on each request in one Python process. The true DFT of a result is
/// `raw / 2^frac_bits · n`.
///
/// # Errors
/// A message if the venv, Python or `cmsisdsp` is missing or fails.
pub fn cmsis_fft(requests: &[CmsisRequest]) -> Result<Vec<Vec<i64>>, String> {
    let py = venv_python()
        .ok_or("no test venv: run scripts/test (or set METAMORAN_VENV) to install cmsisdsp")?;
    let body: Vec<serde_json::Value> = requests
        .iter()
        .map(|r| {
            serde_json::json!({
                "format": match r.format { CmsisFormat::Q15 => "q15", CmsisFormat::Q31 => "q31" },
                "n": r.data.len() / 2,
                "data": r.data,
            })
        })
        .collect();
    let mut child = Command::new(&py)
        .args(["-c", CMSIS_FFT_PY])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start {}: {e}", py.display()))?;
    let input = serde_json::to_vec(&body).map_err(|e| e.to_string())?;
    child
        .stdin
        .take()
        .ok_or("no stdin")?
        .write_all(&input)
        .map_err(|e| e.to_string())?;
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(format!(
            "CMSIS oracle failed: {}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let parsed: Vec<serde_json::Value> =
        serde_json::from_slice(&out.stdout).map_err(|e| e.to_string())?;
    parsed
        .iter()
        .map(|v| {
            v["data"]
                .as_array()
                .ok_or("oracle answer without data")?
                .iter()
                .map(|x| {
                    x.as_i64()
                        .ok_or_else(|| "non-integer in oracle answer".to_owned())
                })
                .collect()
        })
        .collect()
}
