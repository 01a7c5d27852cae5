//! Building the firmware and running it under QEMU (`qemu-system-arm -machine mps2-an500`).
//!
//! The firmware is its own Cargo workspace in `firmware/` (see its manifest); binaries talk to
//! the host through semihosting and end QEMU with their exit code.

use crate::EdgeError;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// The embedded target.
pub const TARGET: &str = "thumbv7em-none-eabihf";

/// Whether `qemu-system-arm` runs on this machine.
pub fn available() -> bool {
    Command::new("qemu-system-arm")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// The firmware's Cargo workspace of the Metamoran checkout this runs in: the first
/// `firmware/` folder with a `Cargo.toml` in the current folder or one of its parents. `None`
/// outside a checkout (an installed `metamoran` then takes `--firmware DIR`).
pub fn find_firmware() -> Option<PathBuf> {
    let cwd = std::env::current_dir().ok()?;
    cwd.ancestors()
        .map(|a| a.join("firmware"))
        .find(|f| f.join("Cargo.toml").is_file())
}

/// Builds binary `bin` of the firmware workspace `firmware` in release mode, with the device
/// key in `key_file` built in (`METAMORAN_LINK_KEY_FILE`; `None`: the checkout's QEMU module
/// key, [`crate::keys::checkout_key`]), and returns its ELF path. Binaries built with the same
/// key file share one build.
///
/// # Errors
/// [`EdgeError`] with cargo's output if the build fails, or the key file cannot be made.
pub fn build(firmware: &Path, bin: &str, key_file: Option<&Path>) -> Result<PathBuf, EdgeError> {
    let dir = firmware;
    let key_file = match key_file {
        Some(k) => k.to_owned(),
        None => crate::keys::checkout_key(firmware)?,
    };
    let out = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .current_dir(dir)
        .env(crate::keys::KEY_FILE_ENV, &key_file)
        .args(["build", "--release", "--target", TARGET, "--bin", bin])
        .output()
        .map_err(EdgeError::Cargo)?;
    if !out.status.success() {
        return Err(EdgeError::Build {
            bin: bin.to_owned(),
            target: TARGET,
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        });
    }
    Ok(dir.join("target").join(TARGET).join("release").join(bin))
}

/// Runs `elf` under QEMU with semihosting, optionally with deterministic instruction counting;
/// returns what it printed. Gives up after `timeout`.
///
/// # Errors
/// [`EdgeError`] if QEMU is missing, times out, or the firmware exits with failure.
pub fn run(elf: &Path, icount: bool, timeout: Duration) -> Result<String, EdgeError> {
    let mut cmd = Command::new("timeout");
    cmd.arg(timeout.as_secs().max(1).to_string())
        .args([
            "qemu-system-arm",
            "-machine",
            "mps2-an500",
            "-cpu",
            "cortex-m7",
            "-nographic",
            "-monitor",
            "none",
        ])
        .args(["-semihosting-config", "enable=on,target=native"]);
    if icount {
        cmd.args(["-icount", "shift=0"]);
    }
    let out = cmd
        .arg("-kernel")
        .arg(elf)
        .output()
        .map_err(EdgeError::QemuMissing)?;
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    match out.status.code() {
        Some(0) => Ok(stdout),
        Some(124) => Err(EdgeError::Timeout {
            after: timeout,
            output: stdout,
        }),
        Some(127) => Err(EdgeError::QemuMissing(std::io::ErrorKind::NotFound.into())),
        _ => Err(EdgeError::Failed {
            elf: elf.to_owned(),
            status: out.status,
            output: stdout + &String::from_utf8_lossy(&out.stderr),
        }),
    }
}
