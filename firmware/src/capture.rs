//! Where radar frames come from: the capture source trait and its three implementations.
//!
//! The module reads each (chirp, receiver) row as the radar board sends it: `4·N` bytes of
//! DCA1000 groups (the bundle's `radar.bin` layout, see `metamoran_dsp::capture::dca1000`), frames in
//! order. [`SpiCapture`] reads them from the board over an embedded-hal SPI device,
//! [`SliceCapture`] from memory (host tests, mocks), and on QEMU `board::SemihostingFile` from
//! a file on the host.

use core::fmt;
use embedded_hal::digital::InputPin;
use embedded_hal::spi::SpiDevice;

/// Why a capture read failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SourceError {
    /// The source ended before the frame did.
    Ended,
    /// The device reported an error.
    Device,
    /// The data-ready line did not rise in time.
    Timeout,
}

impl fmt::Display for SourceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Ended => write!(f, "the capture ended mid-frame: check the capture length"),
            Self::Device => write!(
                f,
                "the capture device reported an error: check the radar link"
            ),
            Self::Timeout => write!(
                f,
                "no data from the radar board: is it configured and running?"
            ),
        }
    }
}

/// A stream of raw capture bytes.
pub trait CaptureSource {
    /// Fills `buf` with the next bytes of the capture.
    ///
    /// # Errors
    /// [`SourceError`] if the bytes are not available; the stream position is then undefined.
    fn read_exact(&mut self, buf: &mut [u8]) -> Result<(), SourceError>;
}

/// A capture held in memory (tests; a frame buffer filled by DMA).
#[derive(Debug)]
pub struct SliceCapture<'a> {
    bytes: &'a [u8],
}

impl<'a> SliceCapture<'a> {
    /// Reads `bytes` from the start.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes }
    }
}

impl CaptureSource for SliceCapture<'_> {
    fn read_exact(&mut self, buf: &mut [u8]) -> Result<(), SourceError> {
        if self.bytes.len() < buf.len() {
            self.bytes = &[];
            return Err(SourceError::Ended);
        }
        let (head, tail) = self.bytes.split_at(buf.len());
        buf.copy_from_slice(head);
        self.bytes = tail;
        Ok(())
    }
}

/// The radar board's data port: an SPI device plus a data-ready line that is high while a
/// chirp row waits in the board's buffer.
#[derive(Debug)]
pub struct SpiCapture<D, P> {
    spi: D,
    ready: P,
    polls: u32,
}

impl<D: SpiDevice, P: InputPin> SpiCapture<D, P> {
    /// Reads from `spi` when `ready` is high, giving up after `polls` polls of the line.
    pub fn new(spi: D, ready: P, polls: u32) -> Self {
        Self { spi, ready, polls }
    }
}

impl<D: SpiDevice, P: InputPin> CaptureSource for SpiCapture<D, P> {
    fn read_exact(&mut self, buf: &mut [u8]) -> Result<(), SourceError> {
        let mut left = self.polls;
        while !self.ready.is_high().map_err(|_| SourceError::Device)? {
            left = left.checked_sub(1).ok_or(SourceError::Timeout)?;
        }
        self.spi.read(buf).map_err(|_| SourceError::Device)
    }
}
