//! The host's end of a live DCA1000 stream: a UDP socket on the data port, packets checked and
//! counted, frames out of the [`Assembler`]. Packets from another address than the board's,
//! and datagrams too short to be packets, are dropped and counted.

use crate::assemble::{Assembler, Frame, Stats};
use crate::packet::{DataPacket, MAX_PAYLOAD};
use std::io;
use std::net::{IpAddr, SocketAddr, UdpSocket};
use std::time::Duration;

/// Socket receive buffer asked for, bytes: at 700 Mbit/s the OS's default (about 200 KB) holds
/// 2 ms of packets, too little for a host that is busy a moment (the usual cause of "dropped
/// packets" with DCA1000 tools).
pub const RECEIVE_BUFFER: usize = 32 << 20;

/// What the receiver saw besides the assembler's counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Datagrams shorter than a packet header plus one byte (dropped).
    pub short: u64,
    /// Datagrams from another address than the board's (dropped).
    pub foreign: u64,
    /// The assembler's counts.
    pub assembly: Stats,
}

/// A live stream from one board.
pub struct Receiver {
    socket: UdpSocket,
    board: Option<IpAddr>,
    assembler: Assembler,
    buf: Vec<u8>,
    short: u64,
    foreign: u64,
    started: bool,
    ended: bool,
}

impl Receiver {
    /// Listens on `local` (the host's address the board sends to, port 4098 on a real setup)
    /// for frames of `frame_bytes`, taking packets only from `board` when given.
    ///
    /// # Errors
    /// The socket cannot be bound.
    pub fn bind(local: SocketAddr, frame_bytes: usize, board: Option<IpAddr>) -> io::Result<Self> {
        let socket = socket2::Socket::new(
            socket2::Domain::for_address(local),
            socket2::Type::DGRAM,
            Some(socket2::Protocol::UDP),
        )?;
        // Best effort: the OS caps it (net.core.rmem_max).
        let _ = socket.set_recv_buffer_size(RECEIVE_BUFFER);
        socket.bind(&local.into())?;
        Ok(Self {
            socket: socket.into(),
            board,
            assembler: Assembler::new(frame_bytes),
            buf: vec![0; MAX_PAYLOAD + 16],
            short: 0,
            foreign: 0,
            started: false,
            ended: false,
        })
    }

    /// The local address it listens on.
    ///
    /// # Errors
    /// The OS cannot say.
    pub fn local_addr(&self) -> io::Result<SocketAddr> {
        self.socket.local_addr()
    }

    /// The next frame, waiting up to `start` for the stream's first packet and ending the stream
    /// once no packet came for `idle`; `None` after the last frame.
    ///
    /// # Errors
    /// The socket fails (other than by a timeout).
    pub fn next_frame(&mut self, start: Duration, idle: Duration) -> io::Result<Option<Frame>> {
        loop {
            if let Some(f) = self.assembler.pop() {
                return Ok(Some(f));
            }
            if self.ended {
                return Ok(None);
            }
            self.socket.set_read_timeout(
                Some(if self.started { idle } else { start }).filter(|d| !d.is_zero()),
            )?;
            match self.socket.recv_from(&mut self.buf) {
                Ok((n, from)) => self.take(n, from),
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                    ) =>
                {
                    self.assembler.finish();
                    self.ended = true;
                }
                Err(e) => return Err(e),
            }
        }
    }

    fn take(&mut self, n: usize, from: SocketAddr) {
        if self.board.is_some_and(|b| b != from.ip()) {
            self.foreign += 1;
            return;
        }
        match DataPacket::parse(&self.buf[..n]) {
            Ok(p) => {
                self.started = true;
                self.assembler.push(&p);
            }
            Err(_) => self.short += 1,
        }
    }

    /// What it saw so far.
    pub fn counters(&self) -> Counters {
        Counters {
            short: self.short,
            foreign: self.foreign,
            assembly: self.assembler.stats(),
        }
    }
}
