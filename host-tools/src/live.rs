//! A live DCA1000 stream in place of a capture file. `record` and `summarize` write the stream
//! as a `.bin`; the commands that read a bundle (`process`, `inspect`, `demo`) keep the bundle's
//! camera products and take the radar samples from the board: the stream is recorded for the
//! bundle's `[radar]` table and frame count, and the frames that did not arrive whole are
//! marked so that they are skipped, never processed as if whole. Sits on `metamoran-dca1000`
//! (the receiver) and `metamoran-bundle` (the reader).

use metamoran_bundle::{LiveCapture, Scene};
use metamoran_dca1000::Receiver;
use metamoran_dca1000::control::Board;
use metamoran_dca1000::record::{Incomplete, Recording, record, record_controlled};
use std::io::Write;
use std::net::{IpAddr, SocketAddr};
use std::path::Path;
use std::time::Duration;

/// Where a live stream arrives and how long it lasts.
#[derive(Clone, Debug)]
pub struct Link {
    /// This host's address and data port the board sends its samples to.
    pub addr: SocketAddr,
    /// The board's IP: packets from elsewhere are dropped and counted.
    pub from: Option<IpAddr>,
    /// Configure and start the board over its config port first, stop it at the end (needs
    /// `from`).
    pub control: bool,
    /// How long to wait for the stream's first packet.
    pub start: Duration,
    /// How long without a packet ends the stream.
    pub idle: Duration,
    /// Called once the socket is bound, with the address it listens on (the port the OS chose
    /// when `addr`'s port is 0), before the first packet is awaited: a sender started after it
    /// cannot race the bind.
    pub on_listen: fn(SocketAddr),
}

/// A stream recorded for a bundle: the capture to open it with, and what arrived.
#[derive(Debug)]
pub struct Live {
    /// The recorded file (removed when this is dropped).
    pub file: tempfile::NamedTempFile,
    /// The capture for [`metamoran_bundle::OpenOptions::capture`].
    pub capture: LiveCapture,
    /// What the receiver took and counted.
    pub recording: Recording,
}

impl Link {
    /// Records frames of `frame_bytes` into `out` until `limit` frames arrived or the stream
    /// goes quiet, doing `incomplete` with frames that are not whole.
    ///
    /// # Errors
    /// The socket cannot be bound, the board does not answer its config port, or `out` fails.
    pub fn record(
        &self,
        frame_bytes: usize,
        limit: Option<u64>,
        out: &mut impl Write,
        incomplete: Incomplete,
    ) -> Result<Recording, crate::Error> {
        let mut rx = Receiver::bind(self.addr, frame_bytes, self.from).map_err(|e| {
            format!(
                "--dca1000 {}: cannot listen there ({e}); give this host's address on the \
                 board's network",
                self.addr
            )
        })?;
        (self.on_listen)(rx.local_addr()?);
        let timeouts = (self.start, self.idle);
        let rec = match (self.control, self.from) {
            (true, Some(ip)) => {
                let local =
                    SocketAddr::new(self.addr.ip(), metamoran_dca1000::command::CONFIG_PORT);
                let b = Board::new(ip, local, Duration::from_secs(2))
                    .map_err(|e| format!("cannot open the config port on {local}: {e}"))?;
                record_controlled(&b, &mut rx, out, frame_bytes, limit, timeouts, incomplete)?
            }
            _ => record(&mut rx, out, frame_bytes, limit, timeouts, incomplete)?,
        };
        Ok(rec)
    }

    /// Records the stream for the bundle in `dir`: its frame count of frames of its `[radar]`
    /// table. Frames that arrive incomplete are kept zero-filled and marked; frames the stream
    /// ended before are zero and marked too, so the frame numbers stay the camera's.
    ///
    /// # Errors
    /// A bad `scene.toml`, a stream that cannot be received, or no frame at all.
    ///
    /// # Example
    /// A bundle's own `radar.bin` sent by the DCA1000 stand-in on loopback comes back whole.
    /// ```
    /// use metamoran::live::Link;
    /// use metamoran_dca1000::emulate::{Impairments, send};
    /// use metamoran_sim::{layout::Preset, radar::RadarKind, simulate};
    /// use std::{net::UdpSocket, time::Duration};
    ///
    /// let dir = tempfile::tempdir()?;
    /// let bundle = &simulate(Preset::ParkingLot, RadarKind::Xwr18xx, 7, 1, dir.path(), &|| ())?[0];
    /// let bytes = std::fs::read(bundle.join("radar.bin"))?;
    /// let port = UdpSocket::bind("127.0.0.1:0")?.local_addr()?.port();
    /// let link = Link {
    ///     addr: format!("127.0.0.1:{port}").parse()?,
    ///     from: None,
    ///     control: false,
    ///     start: Duration::from_secs(10),
    ///     idle: Duration::from_millis(500),
    ///     on_listen: |_| (),
    /// };
    /// let (to, sent) = (link.addr, bytes.clone());
    /// let board = std::thread::spawn(move || {
    ///     std::thread::sleep(Duration::from_millis(300)); // the receiver binds first
    ///     let socket = UdpSocket::bind("127.0.0.1:0")?;
    ///     send(&socket, to, &sent, 1456, &Impairments::default(), None)
    /// });
    /// let live = link.capture_for(bundle)?;
    /// board.join().unwrap()?;
    /// assert!(live.capture.incomplete.is_empty());
    /// assert_eq!(std::fs::read(live.file.path())?, bytes);
    /// # Ok::<(), Box<dyn std::error::Error + Send + Sync>>(())
    /// ```
    pub fn capture_for(&self, dir: &Path) -> Result<Live, crate::Error> {
        let scene = Scene::read(&dir.join("scene.toml"))?;
        let frame_bytes = scene.radar.samples_per_frame() * 4;
        let frames = scene.radar.frames;
        // Named for what it holds: the errors about its frames name it.
        let mut file = tempfile::Builder::new()
            .prefix(&format!("dca1000-stream-{}-", self.addr.port()))
            .suffix(".bin")
            .tempfile()?;
        let recording = {
            let mut out = std::io::BufWriter::new(file.as_file_mut());
            let rec = self.record(
                frame_bytes,
                Some(u64::from(frames)),
                &mut out,
                Incomplete::ZeroFill,
            )?;
            // The frames the stream ended before: zero, and marked below.
            let zeros = vec![0u8; frame_bytes];
            for _ in rec.frames..u64::from(frames) {
                out.write_all(&zeros)?;
            }
            out.flush()?;
            rec
        };
        if recording.frames == 0 {
            return Err(format!(
                "--dca1000 {}: no frame arrived within {:.1} s; is the board streaming to this \
                 address?",
                self.addr,
                self.start.as_secs_f64()
            )
            .into());
        }
        let mut incomplete: Vec<u32> = recording
            .incomplete
            .iter()
            .filter_map(|&f| u32::try_from(f).ok())
            .collect();
        incomplete.extend(u32::try_from(recording.frames).unwrap_or(frames)..frames);
        Ok(Live {
            capture: LiveCapture {
                file: file.path().to_owned(),
                incomplete,
            },
            file,
            recording,
        })
    }
}
