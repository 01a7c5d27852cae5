//! The DCA1000EVM's configuration protocol (UDP, the board's port [`CONFIG_PORT`]), as TI's
//! `DCA1000EVM_CLI_Control` speaks it: a request is `0xA55A`, a command code, a data size, the
//! data and `0xEEAA` (little-endian `u16`s); the reply repeats the code with a status (0 =
//! success). The board also sends an unrequested status (code 0x0A) when a recording ends.

/// The config port, on the board and on the host.
pub const CONFIG_PORT: u16 = 4096;
/// First two bytes of every command and reply.
pub const HEADER: u16 = 0xA55A;
/// Last two bytes.
pub const FOOTER: u16 = 0xEEAA;
/// Bytes of a reply.
pub const REPLY_LEN: usize = 8;

/// The commands (`rf_api.h` `CMD_CODE_*`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum Command {
    /// Reset the FPGA.
    ResetFpga = 0x01,
    /// Reset the radar device.
    ResetRadar = 0x02,
    /// Configure the FPGA: log mode, LVDS lanes, transfer, capture and data format.
    ConfigFpga = 0x03,
    /// Configure the EEPROM (IP and MAC addresses).
    ConfigEeprom = 0x04,
    /// Start recording.
    StartRecord = 0x05,
    /// Stop recording.
    StopRecord = 0x06,
    /// Is the board there (system connect).
    Connect = 0x09,
    /// Unrequested status from the board (e.g. the recording ended).
    AsyncStatus = 0x0A,
    /// Configure packet size and inter-packet delay.
    ConfigPacket = 0x0B,
    /// Read the FPGA version.
    ReadFpgaVersion = 0x0E,
}

impl Command {
    /// Every command.
    pub const ALL: [Command; 10] = [
        Command::ResetFpga,
        Command::ResetRadar,
        Command::ConfigFpga,
        Command::ConfigEeprom,
        Command::StartRecord,
        Command::StopRecord,
        Command::Connect,
        Command::AsyncStatus,
        Command::ConfigPacket,
        Command::ReadFpgaVersion,
    ];

    /// The command of `code`.
    pub fn from_code(code: u16) -> Option<Self> {
        Self::ALL.into_iter().find(|c| *c as u16 == code)
    }
}

/// Why bytes are not a command or reply.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CommandError {
    /// Not framed by `0xA55A` … `0xEEAA`, or too short.
    #[error("{0} bytes not framed as a DCA1000 command (0xA55A … 0xEEAA)")]
    Framing(usize),
    /// The size field disagrees with the bytes.
    #[error("the data size says {said} bytes but {got} follow")]
    Size {
        /// The size field.
        said: usize,
        /// Bytes between it and the footer.
        got: usize,
    },
    /// A code that is no command.
    #[error("unknown DCA1000 command code {0:#06x}")]
    Unknown(u16),
}

fn word(bytes: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes([*bytes.get(at)?, *bytes.get(at + 1)?]))
}

/// A command's bytes.
pub fn request(command: Command, data: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(8 + data.len());
    for w in [HEADER, command as u16, data.len() as u16] {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out.extend_from_slice(data);
    out.extend_from_slice(&FOOTER.to_le_bytes());
    out
}

/// Parses a command: its code and data. O(1).
///
/// # Errors
/// [`CommandError`] for bytes that are not one command.
pub fn parse_request(bytes: &[u8]) -> Result<(Command, &[u8]), CommandError> {
    let framed = bytes.len() >= 8
        && word(bytes, 0) == Some(HEADER)
        && word(bytes, bytes.len() - 2) == Some(FOOTER);
    if !framed {
        return Err(CommandError::Framing(bytes.len()));
    }
    let code = word(bytes, 2).unwrap_or_default();
    let said = usize::from(word(bytes, 4).unwrap_or_default());
    let data = &bytes[6..bytes.len() - 2];
    if data.len() != said {
        return Err(CommandError::Size {
            said,
            got: data.len(),
        });
    }
    Ok((
        Command::from_code(code).ok_or(CommandError::Unknown(code))?,
        data,
    ))
}

/// A reply: the command it answers and its status (0 = success).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reply {
    /// The command.
    pub command: Command,
    /// Its status.
    pub status: u16,
}

impl Reply {
    /// The reply's bytes.
    pub fn to_bytes(self) -> [u8; REPLY_LEN] {
        let mut out = [0u8; REPLY_LEN];
        for (i, w) in [HEADER, self.command as u16, self.status, FOOTER]
            .into_iter()
            .enumerate()
        {
            out[2 * i..2 * i + 2].copy_from_slice(&w.to_le_bytes());
        }
        out
    }

    /// Parses a reply.
    ///
    /// # Errors
    /// [`CommandError`] for bytes that are not one reply.
    pub fn parse(bytes: &[u8]) -> Result<Self, CommandError> {
        if bytes.len() != REPLY_LEN
            || word(bytes, 0) != Some(HEADER)
            || word(bytes, 6) != Some(FOOTER)
        {
            return Err(CommandError::Framing(bytes.len()));
        }
        let code = word(bytes, 2).unwrap_or_default();
        Ok(Self {
            command: Command::from_code(code).ok_or(CommandError::Unknown(code))?,
            status: word(bytes, 4).unwrap_or_default(),
        })
    }
}

/// `CONFIG_FPGA_GEN` data for raw-mode streaming of 16-bit samples over Ethernet, as TI's
/// CLI sends it for xWR16xx/18xx boards: log mode raw (1), LVDS 2 lanes (2), LVDS capture (1),
/// Ethernet streaming (2), 16-bit (3), a 30 s timer.
pub const RAW_STREAMING: [u8; 6] = [1, 2, 1, 2, 3, 30];

/// `CONFIG_PACKET_DATA` data: `payload + 16` bytes per packet (header and UDP framing) and the
/// inter-packet delay in µs.
pub fn packet_config(payload: u16, delay_us: u16) -> [u8; 6] {
    let size = (payload + 16).to_le_bytes();
    let delay = delay_us.to_le_bytes();
    [size[0], size[1], delay[0], delay[1], 0, 0]
}
