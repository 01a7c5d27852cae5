//! Device keys on the host: read from a key file (never the command line), written by
//! `metamoran provision` with the OS's random generator and mode 0600.
//!
//! A key file holds the 32-byte device key as 64 hexadecimal digits and a newline. The host
//! refuses one that other users can read, as ssh does. The firmware embeds the same file at
//! build time (`METAMORAN_LINK_KEY_FILE`), so one file pairs one module with its hosts.

use crate::EdgeError;
use metamoran_dsp::wire::{DeviceKey, KEY_LEN, Nonce, session::NONCE_LEN};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The environment variable that names a key file (the firmware's build reads it too).
pub const KEY_FILE_ENV: &str = "METAMORAN_LINK_KEY_FILE";

/// The key of the QEMU module of the checkout whose firmware workspace is `firmware`:
/// `firmware/target/qemu-link.key`, provisioned on first use.
///
/// # Errors
/// [`EdgeError::KeyFile`] if it cannot be read or written.
pub fn checkout_key(firmware: &Path) -> Result<PathBuf, EdgeError> {
    let path = firmware.join("target").join("qemu-link.key");
    if !path.exists() {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| key_error(dir, e.to_string()))?;
        }
        write_key_file(&path)?;
    }
    Ok(path)
}

fn key_error(path: &Path, problem: impl Into<String>) -> EdgeError {
    EdgeError::KeyFile {
        path: path.to_owned(),
        problem: problem.into(),
    }
}

/// Reads the device key in `path`.
///
/// # Errors
/// [`EdgeError::KeyFile`] naming the file: missing, not a regular file, readable by others,
/// or not 64 hexadecimal digits.
pub fn read_key_file(path: &Path) -> Result<DeviceKey, EdgeError> {
    let meta = std::fs::metadata(path).map_err(|e| key_error(path, e.to_string()))?;
    if !meta.is_file() || meta.len() > 1024 {
        return Err(key_error(path, "is not a key file (64 hex digits)"));
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = meta.permissions().mode();
        if mode & 0o077 != 0 {
            return Err(key_error(
                path,
                format!(
                    "is readable by other users (mode {:o}); run `chmod 600 {}`",
                    mode & 0o777,
                    path.display()
                ),
            ));
        }
    }
    let text = std::fs::read_to_string(path).map_err(|e| key_error(path, e.to_string()))?;
    DeviceKey::from_hex(&text).map_err(|e| key_error(path, e.to_string()))
}

/// Writes a fresh device key to `path` (created, mode 0600; an existing file is never
/// overwritten) and returns it.
///
/// # Errors
/// [`EdgeError::KeyFile`] if the file exists or cannot be written, or the OS has no entropy.
pub fn write_key_file(path: &Path) -> Result<DeviceKey, EdgeError> {
    let mut bytes = [0u8; KEY_LEN];
    getrandom::fill(&mut bytes).map_err(|e| key_error(path, format!("no OS entropy: {e}")))?;
    let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
    let mut options = std::fs::OpenOptions::new();
    options.write(true).create_new(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::mode(&mut options, 0o600);
    let mut file = options.open(path).map_err(|e| {
        key_error(
            path,
            format!("cannot create it ({e}); a key file is never overwritten"),
        )
    })?;
    file.write_all(format!("{hex}\n").as_bytes())
        .and_then(|()| file.sync_all())
        .map_err(|e| key_error(path, e.to_string()))?;
    Ok(DeviceKey::new(bytes))
}

/// A fresh nonce from the OS's random generator.
///
/// # Errors
/// [`EdgeError::Entropy`] if the OS has none.
pub fn host_nonce() -> Result<Nonce, EdgeError> {
    let mut n = [0u8; NONCE_LEN];
    getrandom::fill(&mut n).map_err(|e| EdgeError::Entropy(e.to_string()))?;
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_files_round_trip_and_are_private() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("gate.key");
        let written = write_key_file(&path).unwrap();
        let read = read_key_file(&path).unwrap();
        let probe = [9u8; NONCE_LEN];
        assert_eq!(
            written.session(&probe, &probe).uplink.tag(b"x"),
            read.session(&probe, &probe).uplink.tag(b"x")
        );
        assert!(write_key_file(&path).is_err(), "never overwritten");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&path).unwrap().permissions().mode();
            assert_eq!(mode & 0o777, 0o600);
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o644)).unwrap();
            let e = read_key_file(&path).unwrap_err().to_string();
            assert!(e.contains("chmod 600"), "{e}");
        }
        // Two keys differ (the OS generator, not a constant).
        let other = write_key_file(&dir.path().join("other.key")).unwrap();
        assert_ne!(
            other.session(&probe, &probe).uplink.tag(b"x"),
            read.session(&probe, &probe).uplink.tag(b"x")
        );
    }
}
