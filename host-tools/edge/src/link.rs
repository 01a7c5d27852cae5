//! The module under QEMU as the host's edge: `process --edge qemu` builds the `edge` firmware,
//! starts `qemu-system-arm` with UART0 on a loopback TCP socket and the bundle's `radar.bin` as
//! the capture file, and speaks the telemetry protocol (`metamoran_dsp::wire`) to it: configuration, then
//! per frame the hints and a `Frame` message, then the per-object results until the frame's
//! summary.

use crate::{EdgeError, keys, qemu};
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::range::calibration::AppliedCalibration;
use metamoran_dsp::wire::{
    CalibrationRow, Deframer, DeviceKey, Downlink, Fault, HandshakeUp, Health, Hint, HostLink,
    LinkError, MAX_WIRE, ObjectResult, Opened, Uplink,
};
use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// How long the module may take to answer one message.
const ANSWER_TIMEOUT: Duration = Duration::from_secs(60);
/// How long to wait for a `Hello` before asking again with `Sync`.
const HELLO_RETRY: Duration = Duration::from_secs(1);

/// A running module under QEMU.
pub struct QemuEdge {
    child: Child,
    stream: TcpStream,
    link_state: HostLink,
    deframer: Deframer,
    link: PathBuf,
    /// The firmware ELF (its defmt strings decode the log).
    elf: PathBuf,
    /// Faults the module reported, with their frame.
    pub faults: Vec<(u32, Fault)>,
}

/// What the module said when it stopped.
#[derive(Clone, Debug)]
pub struct EdgeLog {
    /// Its health counters.
    pub health: Health,
    /// Its semihosting console: defmt frames (decode with
    /// `defmt-print -e firmware/target/thumbv7em-none-eabihf/release/edge`).
    pub defmt: Vec<u8>,
    /// The firmware ELF that wrote it (defmt-print needs it to decode the log).
    pub elf: PathBuf,
}

/// The module's defmt log as text through `defmt-print -e ELF` (the tool `cargo install
/// defmt-print` provides), or a note saying how to read it when the tool is missing.
pub fn decode_defmt(elf: &Path, log: &[u8]) -> String {
    if log.is_empty() {
        return String::new();
    }
    let tool = ["defmt-print".into(), cargo_bin("defmt-print")];
    for t in &tool {
        let child = Command::new(t)
            .args(["-e"])
            .arg(elf)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn();
        let Ok(mut child) = child else { continue };
        if let Some(mut i) = child.stdin.take() {
            let _ = i.write_all(log);
        }
        if let Ok(out) = child.wait_with_output() {
            return String::from_utf8_lossy(&out.stdout).into_owned();
        }
    }
    format!(
        "({} bytes of defmt log: `cargo install defmt-print` to read them)",
        log.len()
    )
}

/// `~/.cargo/bin/NAME`.
fn cargo_bin(name: &str) -> PathBuf {
    let home = std::env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cargo")))
        .unwrap_or_default();
    home.join("bin").join(name)
}

impl QemuEdge {
    /// Builds the firmware in workspace `firmware` with the device key in `key_file`, starts
    /// it on `capture` (a bundle's `radar.bin`, read by the module as the radar board's
    /// stream) and opens a session with it.
    ///
    /// # Errors
    /// [`EdgeError`] if the key, the build, QEMU or the handshake fails.
    pub fn start(capture: &Path, key_file: &Path, firmware: &Path) -> Result<Self, EdgeError> {
        let device = keys::read_key_file(key_file)?;
        let elf = qemu::build(firmware, "edge", Some(key_file))?;
        Self::launch(capture, device, elf)
    }

    /// Starts the built `edge` image `elf` on `capture` and opens a session with it under
    /// `device` (which must be the key the image was built with).
    ///
    /// # Errors
    /// [`EdgeError`] if QEMU or the handshake fails.
    pub fn launch(capture: &Path, device: DeviceKey, elf: PathBuf) -> Result<Self, EdgeError> {
        let capture = capture.canonicalize().map_err(|source| EdgeError::File {
            path: capture.to_owned(),
            source,
        })?;
        // QEMU's option syntax and the semihosting command line split on commas and spaces:
        // hand the module a plain path.
        let port = TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .map_err(EdgeError::Port)?
            .port();
        let link =
            std::env::temp_dir().join(format!("metamoran-edge-{}-{port}.bin", std::process::id()));
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(&capture, &link).map_err(|source| EdgeError::File {
            path: link.clone(),
            source,
        })?;
        let child = Command::new("qemu-system-arm")
            .args(["-machine", "mps2-an500", "-cpu", "cortex-m7", "-nographic"])
            .args(["-monitor", "none"])
            .arg("-serial")
            .arg(format!("tcp:127.0.0.1:{port},server=on,wait=on"))
            .arg("-semihosting-config")
            .arg(format!(
                "enable=on,target=native,arg=edge,arg={}",
                link.display()
            ))
            .arg("-kernel")
            .arg(&elf)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(EdgeError::QemuMissing)?;
        let mut edge = Self {
            child,
            stream: connect(port)?,
            link_state: HostLink::new(device),
            deframer: Deframer::new(),
            link,
            elf: elf.clone(),
            faults: Vec::new(),
        };
        edge.pair()?;
        Ok(edge)
    }

    /// The handshake: waits for the module's `Hello` (asking again with `Sync` every
    /// [`HELLO_RETRY`]), answers with a fresh nonce and waits for `Ready` under the new keys.
    fn pair(&mut self) -> Result<(), EdgeError> {
        let deadline = Instant::now() + ANSWER_TIMEOUT;
        let nonce = loop {
            let retry = (Instant::now() + HELLO_RETRY).min(deadline);
            match self.next_frame(retry)? {
                Some(Opened::Handshake(HandshakeUp::Hello { nonce, .. })) => break nonce,
                Some(_) => {}
                None if Instant::now() >= deadline => {
                    return Err(EdgeError::NoHello(format!(
                        "no Hello within {ANSWER_TIMEOUT:?}"
                    )));
                }
                None => {
                    let mut buf = [0u8; MAX_WIRE];
                    let n = self.link_state.sync(&mut buf).map_err(EdgeError::Encode)?;
                    self.stream.write_all(&buf[..n]).map_err(EdgeError::Link)?;
                }
            }
        };
        let mut buf = [0u8; MAX_WIRE];
        let n = self
            .link_state
            .pair(nonce, keys::host_nonce()?, &mut buf)
            .map_err(EdgeError::Encode)?;
        self.stream.write_all(&buf[..n]).map_err(EdgeError::Link)?;
        match self.receive()? {
            Uplink::Ready => Ok(()),
            other => Err(EdgeError::NoHello(format!("expected Ready, got {other:?}"))),
        }
    }

    /// Sends the radar configuration.
    ///
    /// # Errors
    /// [`EdgeError`] if the link fails or the module rejects it.
    pub fn configure(&mut self, config: &RadarConfig) -> Result<(), EdgeError> {
        self.send(&Downlink::Config(config.clone()))?;
        self.confirm()
    }

    /// Sends the channel calibration (after [`Self::configure`]; a new configuration clears
    /// it): one [`CalibrationRow`] per TX, applied by the module once all have arrived.
    ///
    /// # Errors
    /// [`EdgeError`] if the link fails or the module rejects it (it does not fit the
    /// configuration, or the frame has more chirps per element than the module calibrates).
    pub fn calibrate(&mut self, calibration: &AppliedCalibration) -> Result<(), EdgeError> {
        let (tx, rx) = calibration.size();
        for t in 0..tx {
            let row = (0..rx).filter_map(|r| calibration.get(t, r));
            self.send(&Downlink::Calibration(CalibrationRow {
                tx: t as u8,
                of: tx as u8,
                gains: row.clone().map(|(g, _)| (g.re.0, g.im.0)).collect(),
                steps: row.map(|(_, step)| step.0).collect(),
            }))?;
        }
        self.confirm()
    }

    /// Waits for the answer to a health request: a rejected configuration or calibration is
    /// answered with a fault before it.
    fn confirm(&mut self) -> Result<(), EdgeError> {
        self.send(&Downlink::Health)?;
        loop {
            match self.receive()? {
                Uplink::Health(_) => return Ok(()),
                Uplink::Fault { fault, .. } => return Err(EdgeError::Config(fault)),
                _ => {}
            }
        }
    }

    /// Runs frame `frame` with `hints`; returns each hint's result (`None` where the module
    /// reported a fault for it).
    ///
    /// # Errors
    /// [`EdgeError`] if the link fails.
    pub fn frame(
        &mut self,
        frame: u32,
        hints: &[Hint],
    ) -> Result<Vec<Option<ObjectResult>>, EdgeError> {
        for h in hints {
            self.send(&Downlink::Hint(h.clone()))?;
        }
        self.send(&Downlink::Frame {
            frame,
            objects: hints.len().min(255) as u8,
            clutter: heapless::Vec::new(),
        })?;
        loop {
            match self.receive()? {
                Uplink::Results { summary, objects } if summary.frame == frame => {
                    return Ok(hints
                        .iter()
                        .map(|h| objects.iter().find(|r| r.instance == h.instance).copied())
                        .collect());
                }
                Uplink::Fault {
                    frame: f, fault, ..
                } => {
                    self.faults.push((f, fault));
                    if matches!(fault, Fault::Capture | Fault::NoConfig | Fault::Config)
                        && f == frame
                    {
                        return Err(EdgeError::Frame { frame, fault });
                    }
                }
                _ => {}
            }
        }
    }

    /// Stops the module and collects its counters and console.
    ///
    /// # Errors
    /// [`EdgeError`] if the module does not stop cleanly.
    pub fn stop(mut self) -> Result<EdgeLog, EdgeError> {
        self.send(&Downlink::Stop)?;
        let health = loop {
            if let Uplink::Health(h) = self.receive()? {
                break h;
            }
        };
        let deadline = Instant::now() + Duration::from_secs(10);
        let status = loop {
            if let Some(s) = self.child.try_wait().map_err(EdgeError::Wait)? {
                break s;
            }
            if Instant::now() > deadline {
                return Err(EdgeError::NoExit);
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        let mut defmt = Vec::new();
        if let Some(mut o) = self.child.stdout.take() {
            let _ = o.read_to_end(&mut defmt);
        }
        if !status.success() {
            return Err(EdgeError::Exit {
                status,
                log: decode_defmt(&self.elf, &defmt),
            });
        }
        Ok(EdgeLog {
            health,
            defmt,
            elf: self.elf.clone(),
        })
    }

    fn send(&mut self, msg: &Downlink) -> Result<(), EdgeError> {
        let mut buf = [0u8; MAX_WIRE];
        let n = self
            .link_state
            .encode(msg, &mut buf)
            .map_err(EdgeError::Encode)?;
        self.stream.write_all(&buf[..n]).map_err(EdgeError::Link)
    }

    /// The next authentic session message; rejected frames are counted and skipped, and a
    /// `Hello` (the module rebooted) ends the run.
    fn receive(&mut self) -> Result<Uplink, EdgeError> {
        match self.next_frame(Instant::now() + ANSWER_TIMEOUT)? {
            Some(Opened::Session(m)) => Ok(m),
            Some(Opened::Handshake(_)) => Err(EdgeError::Rebooted),
            None => Err(EdgeError::Silent(ANSWER_TIMEOUT)),
        }
    }

    /// The next authentic frame before `deadline` (`None` at the deadline); rejected frames
    /// are counted and skipped.
    fn next_frame(
        &mut self,
        deadline: Instant,
    ) -> Result<Option<Opened<HandshakeUp, Uplink>>, EdgeError> {
        let mut byte = [0u8; 1];
        loop {
            if Instant::now() > deadline {
                return Ok(None);
            }
            match self.stream.read(&mut byte) {
                Ok(0) => return Err(self.died()),
                Ok(_) => {}
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                    ) =>
                {
                    continue;
                }
                Err(e) => return Err(EdgeError::Link(e)),
            }
            match self.deframer.push(byte[0]) {
                Some(Ok(frame)) => match self.link_state.open(frame) {
                    Ok(m) => return Ok(Some(m)),
                    Err(e @ LinkError::Tag) if self.link_state.stats().accepted == 0 => {
                        return Err(EdgeError::Key(e));
                    }
                    Err(_) => {}
                },
                Some(Err(e)) => self.link_state.count(e),
                None => {}
            }
        }
    }

    /// Why the link closed, from QEMU's output.
    fn died(&mut self) -> EdgeError {
        let _ = self.child.wait();
        let mut log = Vec::new();
        if let Some(mut o) = self.child.stdout.take() {
            let _ = o.read_to_end(&mut log);
        }
        let mut text = decode_defmt(&self.elf, &log);
        if let Some(mut e) = self.child.stderr.take() {
            let _ = e.read_to_string(&mut text);
        }
        EdgeError::Closed(text)
    }

    /// The host side's receive counters.
    pub fn link_stats(&self) -> metamoran_dsp::wire::LinkStats {
        self.link_state.stats()
    }
}

impl Drop for QemuEdge {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_file(&self.link);
    }
}

/// Connects to QEMU's serial socket, waiting for it to listen.
fn connect(port: u16) -> Result<TcpStream, EdgeError> {
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        match TcpStream::connect(("127.0.0.1", port)) {
            Ok(s) => {
                s.set_read_timeout(Some(Duration::from_millis(200)))
                    .map_err(EdgeError::Link)?;
                let _ = s.set_nodelay(true);
                return Ok(s);
            }
            Err(_) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(50)),
            Err(source) => return Err(EdgeError::Connect { port, source }),
        }
    }
}
