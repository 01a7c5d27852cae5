//! The UDP datagrams of a packet capture (`.pcap`, Ethernet, IPv4 or IPv6): how a recorded
//! DCA1000 session (Wireshark, tcpdump) is replayed through the receiver.

use std::net::{IpAddr, SocketAddr};

/// One UDP datagram of the capture.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Datagram {
    /// Its source.
    pub from: SocketAddr,
    /// Its destination.
    pub to: SocketAddr,
    /// The UDP payload.
    pub payload: Vec<u8>,
}

/// Why a capture cannot be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PcapError {
    /// Not a pcap file, or a broken one.
    #[error(
        "not a readable pcap capture ({0}): give a .pcap file (not .pcapng) of Ethernet frames"
    )]
    Format(String),
}

/// The UDP datagrams of `bytes` (a pcap file) sent to port `port`, in capture order; frames that
/// are not Ethernet/IP/UDP are skipped.
///
/// # Errors
/// [`PcapError::Format`] for bytes that are not a pcap file.
pub fn udp_to_port(bytes: &[u8], port: u16) -> Result<Vec<Datagram>, PcapError> {
    let mut reader =
        pcap_file::pcap::PcapReader::new(bytes).map_err(|e| PcapError::Format(e.to_string()))?;
    let mut out = Vec::new();
    while let Some(packet) = reader.next_packet() {
        let packet = packet.map_err(|e| PcapError::Format(e.to_string()))?;
        let Ok(sliced) = etherparse::SlicedPacket::from_ethernet(&packet.data) else {
            continue;
        };
        let (Some(net), Some(etherparse::TransportSlice::Udp(udp))) =
            (sliced.net, sliced.transport)
        else {
            continue;
        };
        let (src, dst): (IpAddr, IpAddr) = match net {
            etherparse::NetSlice::Ipv4(ip) => (
                ip.header().source_addr().into(),
                ip.header().destination_addr().into(),
            ),
            etherparse::NetSlice::Ipv6(ip) => (
                ip.header().source_addr().into(),
                ip.header().destination_addr().into(),
            ),
        };
        if udp.destination_port() != port {
            continue;
        }
        out.push(Datagram {
            from: SocketAddr::new(src, udp.source_port()),
            to: SocketAddr::new(dst, udp.destination_port()),
            payload: udp.payload().to_vec(),
        });
    }
    Ok(out)
}
