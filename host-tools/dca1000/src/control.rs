//! The host's side of the board's configuration port: the command sequence TI's
//! `DCA1000EVM_CLI_Control` sends to record in raw mode (connect, reset the FPGA, configure it
//! and the packets, start), each answered before the next, and the stop at the end.

use crate::command::{CONFIG_PORT, Command, RAW_STREAMING, Reply, packet_config, request};
use crate::packet::DEFAULT_PAYLOAD;
use std::io;
use std::net::{IpAddr, SocketAddr, UdpSocket};
use std::time::Duration;

/// Why the board did not do as asked.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ControlError {
    /// No reply in time, or a socket error.
    #[error(
        "DCA1000 at {board}: no reply to {command:?} ({source}); check the Ethernet link and the board's IP (192.168.33.180 by default)"
    )]
    Io {
        /// The board.
        board: SocketAddr,
        /// The command.
        command: Command,
        /// What failed.
        source: io::Error,
    },
    /// A reply with a non-zero status.
    #[error("DCA1000 at {board}: {command:?} failed with status {status:#06x}")]
    Refused {
        /// The board.
        board: SocketAddr,
        /// The command.
        command: Command,
        /// Its status.
        status: u16,
    },
}

/// A board's config port.
pub struct Board {
    socket: UdpSocket,
    addr: SocketAddr,
    timeout: Duration,
}

impl Board {
    /// The board at `board` (its IP; the config port is [`CONFIG_PORT`]), spoken to from
    /// `local` (the host's IP, usually on port 4096 too).
    ///
    /// # Errors
    /// The socket cannot be bound.
    pub fn new(board: IpAddr, local: SocketAddr, timeout: Duration) -> io::Result<Self> {
        Self::at(SocketAddr::new(board, CONFIG_PORT), local, timeout)
    }

    /// The board's config port at `addr` (any port: an emulator in a test).
    ///
    /// # Errors
    /// The socket cannot be bound.
    pub fn at(addr: SocketAddr, local: SocketAddr, timeout: Duration) -> io::Result<Self> {
        let socket = UdpSocket::bind(local)?;
        socket.set_read_timeout(Some(timeout))?;
        Ok(Self {
            socket,
            addr,
            timeout,
        })
    }

    /// Sends `command` with `data` and waits for its reply (other replies are skipped).
    ///
    /// # Errors
    /// [`ControlError`] on a timeout, a socket error or a failure status.
    pub fn command(&self, command: Command, data: &[u8]) -> Result<(), ControlError> {
        let io = |source| ControlError::Io {
            board: self.addr,
            command,
            source,
        };
        self.socket
            .send_to(&request(command, data), self.addr)
            .map_err(io)?;
        let mut buf = [0u8; 64];
        let deadline = std::time::Instant::now() + self.timeout;
        loop {
            let (n, _) = self.socket.recv_from(&mut buf).map_err(io)?;
            match Reply::parse(&buf[..n]) {
                Ok(r) if r.command == command && r.status == 0 => return Ok(()),
                Ok(r) if r.command == command => {
                    return Err(ControlError::Refused {
                        board: self.addr,
                        command,
                        status: r.status,
                    });
                }
                _ if std::time::Instant::now() > deadline => {
                    return Err(io(io::ErrorKind::TimedOut.into()));
                }
                _ => {}
            }
        }
    }

    /// Connects, resets and configures the FPGA for raw streaming of `DEFAULT_PAYLOAD`-byte
    /// packets, and starts recording.
    ///
    /// # Errors
    /// The first command that fails.
    pub fn start(&self) -> Result<(), ControlError> {
        self.command(Command::Connect, &[])?;
        self.command(Command::ResetFpga, &[])?;
        self.command(Command::ConfigFpga, &RAW_STREAMING)?;
        self.command(
            Command::ConfigPacket,
            &packet_config(DEFAULT_PAYLOAD as u16, 25),
        )?;
        self.command(Command::StartRecord, &[])
    }

    /// Stops recording.
    ///
    /// # Errors
    /// As [`Board::command`].
    pub fn stop(&self) -> Result<(), ControlError> {
        self.command(Command::StopRecord, &[])
    }
}
