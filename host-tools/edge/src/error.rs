//! The edge crate's errors: what failed between the host and the module, and what to do.

use metamoran_dsp::wire::{EncodeError, Fault, LinkError};
use std::path::PathBuf;
use std::time::Duration;

/// Why the module could not be built, started or spoken to.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EdgeError {
    /// `cargo` could not be started.
    #[error("cannot run cargo: {0}")]
    Cargo(#[source] std::io::Error),
    /// The firmware did not build.
    #[error(
        "building firmware binary {bin} failed (is the target installed? rustup target add {target}):\n{stderr}"
    )]
    Build {
        /// The binary.
        bin: String,
        /// The Rust target it was built for.
        target: &'static str,
        /// What cargo printed.
        stderr: String,
    },
    /// `qemu-system-arm` (or `timeout`) could not be started.
    #[error("cannot start qemu-system-arm ({0}): apt-get install -y qemu-system-arm")]
    QemuMissing(#[source] std::io::Error),
    /// The firmware ran longer than allowed.
    #[error("QEMU timed out after {after:?}; output so far:\n{output}")]
    Timeout {
        /// The limit.
        after: Duration,
        /// What it printed until then.
        output: String,
    },
    /// The firmware exited with failure under QEMU.
    #[error("firmware {} failed under QEMU ({status}):\n{output}", elf.display())]
    Failed {
        /// The firmware image.
        elf: PathBuf,
        /// QEMU's exit status.
        status: std::process::ExitStatus,
        /// What it printed.
        output: String,
    },
    /// A file the run needs could not be read or made (the capture, its link name).
    #[error("{}: {source}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A loopback socket for the UART could not be had.
    #[error("no free loopback port: {0}")]
    Port(#[source] std::io::Error),
    /// QEMU's UART socket did not accept the host.
    #[error("QEMU's UART socket on port {port}: {source}")]
    Connect {
        /// The port.
        port: u16,
        /// The OS error.
        source: std::io::Error,
    },
    /// Reading or writing the link failed.
    #[error("link to the module: {0}")]
    Link(#[source] std::io::Error),
    /// A message did not fit a link frame.
    #[error("link to the module: {0}")]
    Encode(EncodeError),
    /// The module's handshake failed authentication.
    #[error(
        "the module's handshake failed authentication ({0}): give --link-key-file (or METAMORAN_LINK_KEY_FILE) the key file the firmware was built with"
    )]
    Key(LinkError),
    /// The module did not pair.
    #[error("the module did not open a session: {0}")]
    NoHello(String),
    /// The module sent `Hello` in the middle of a session: it rebooted.
    #[error("the module rebooted during the run (it sent Hello again); its configuration is gone")]
    Rebooted,
    /// A key file could not be read or written.
    #[error("{}: {problem}", path.display())]
    KeyFile {
        /// The key file.
        path: PathBuf,
        /// What is wrong, and what to do.
        problem: String,
    },
    /// The OS has no random generator.
    #[error("cannot draw a nonce from the OS: {0}")]
    Entropy(String),
    /// The module refused the radar configuration.
    #[error(
        "the module rejected the radar configuration ({0:?}): it takes at most 1024 samples per chirp and frames whose sums fit its 352 KiB arena"
    )]
    Config(Fault),
    /// The module could not run a frame.
    #[error("the module could not run frame {frame}: {fault:?}")]
    Frame {
        /// The frame.
        frame: u32,
        /// What it reported.
        fault: Fault,
    },
    /// The module did not answer in time.
    #[error("the module did not answer within {0:?}")]
    Silent(Duration),
    /// The module closed the link.
    #[error("the module closed the link:\n{0}")]
    Closed(String),
    /// The module did not exit after `Stop`.
    #[error("the module did not exit after Stop")]
    NoExit,
    /// Waiting for QEMU failed.
    #[error("waiting for QEMU: {0}")]
    Wait(#[source] std::io::Error),
    /// The module exited with failure after `Stop`.
    #[error("the module exited with {status}:\n{log}")]
    Exit {
        /// Its exit status.
        status: std::process::ExitStatus,
        /// Its decoded log.
        log: String,
    },
}
