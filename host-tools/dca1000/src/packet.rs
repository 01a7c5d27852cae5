//! The DCA1000EVM's raw-mode data packets (UDP, data port [`DATA_PORT`]): a 4-byte sequence
//! number (from 1), a 6-byte count of the stream's bytes sent before this packet, then the
//! samples, all little-endian. Nothing here allocates.

/// The host's data port the board sends samples to.
pub const DATA_PORT: u16 = 4098;
/// Sequence number and byte count.
pub const HEADER_LEN: usize = 10;
/// Samples per packet the board sends by default (`CONFIG_PACKET_DATA` 1472 − 16).
pub const DEFAULT_PAYLOAD: usize = 1456;
/// Largest sample payload one UDP datagram can carry.
pub const MAX_PAYLOAD: usize = 65_507 - HEADER_LEN;

/// One data packet, borrowed from its datagram.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DataPacket<'a> {
    /// Sequence number (the board starts at 1).
    pub seq: u32,
    /// Bytes of the stream sent before this packet: where `payload` starts.
    pub offset: u64,
    /// The samples.
    pub payload: &'a [u8],
}

/// Why a datagram is not a data packet.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PacketError {
    /// Shorter than the header plus one byte.
    #[error(
        "{0} bytes: a DCA1000 data packet has a 10-byte header and at least one byte of samples"
    )]
    Short(usize),
}

impl<'a> DataPacket<'a> {
    /// Parses a datagram. O(1).
    ///
    /// # Errors
    /// [`PacketError::Short`] for a datagram without samples.
    ///
    /// # Example
    /// ```
    /// use metamoran_dca1000::packet::DataPacket;
    ///
    /// let mut datagram = vec![2, 0, 0, 0, 0xB0, 5, 0, 0, 0, 0];
    /// datagram.extend_from_slice(&[7; 1456]);
    /// let p = DataPacket::parse(&datagram)?;
    /// assert_eq!((p.seq, p.offset, p.payload.len()), (2, 1456, 1456));
    /// # Ok::<(), metamoran_dca1000::packet::PacketError>(())
    /// ```
    pub fn parse(datagram: &'a [u8]) -> Result<Self, PacketError> {
        let (Some(header), Some(payload)) =
            (datagram.get(..HEADER_LEN), datagram.get(HEADER_LEN..))
        else {
            return Err(PacketError::Short(datagram.len()));
        };
        if payload.is_empty() {
            return Err(PacketError::Short(datagram.len()));
        }
        let mut seq = [0u8; 4];
        seq.copy_from_slice(&header[..4]);
        let mut offset = [0u8; 8];
        offset[..6].copy_from_slice(&header[4..10]);
        Ok(Self {
            seq: u32::from_le_bytes(seq),
            offset: u64::from_le_bytes(offset),
            payload,
        })
    }

    /// The datagram: header then payload, into `out` (cleared first). The offset keeps its low
    /// 48 bits, as the board's counter does.
    pub fn encode(&self, out: &mut Vec<u8>) {
        out.clear();
        out.extend_from_slice(&self.seq.to_le_bytes());
        out.extend_from_slice(&self.offset.to_le_bytes()[..6]);
        out.extend_from_slice(self.payload);
    }
}
