//! Frame authentication: HMAC-SHA-256 over a pre-shared key, truncated to [`TAG_LEN`] bytes.
//!
//! The design follows MAVLink 2 message signing (a truncated SHA-256 MAC over the frame and a
//! monotonically increasing counter, see [`super::receiver`] for the replay window), with the
//! HMAC construction instead of MAVLink's plain `SHA-256(key ‖ data)` so the tag is not open to
//! length extension. The keyed inner and outer states are computed once per key, so a tag
//! costs two SHA-256 compressions plus one per 64 bytes of frame.

use core::fmt;
use hmac::{Hmac, Mac};
use sha2::Sha256;

/// Bytes of the truncated tag on the wire (MAVLink 2 uses 6; 8 keeps forgery at 2⁻⁶⁴ per try).
pub const TAG_LEN: usize = 8;
/// Bytes of a pre-shared key.
pub const KEY_LEN: usize = 32;

/// The public development device key, for tests and firmware built with the explicit
/// `insecure-dev-key` feature only (`"metamoran development link key!!"`). Deployed modules get
/// their own key from `metamoran provision`; no release build falls back to this one.
#[cfg(feature = "dev-key")]
pub const DEV_KEY: [u8; KEY_LEN] = *b"metamoran development link key!!";

/// A frame-tagging key (a session's or the handshake's, derived from the device key by
/// [`super::session::DeviceKey`]), with its HMAC states precomputed. `Debug` never prints it.
#[derive(Clone)]
pub struct Key {
    mac: Hmac<Sha256>,
}

/// Why a key could not be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum KeyError {
    /// The text is not [`KEY_LEN`] bytes of hexadecimal.
    Hex,
}

impl core::error::Error for KeyError {}

impl fmt::Display for KeyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "a link key is {KEY_LEN} bytes written as {} hexadecimal digits",
            2 * KEY_LEN
        )
    }
}

impl fmt::Debug for Key {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Key(..)")
    }
}

impl Key {
    /// The key `bytes`.
    pub fn new(bytes: &[u8; KEY_LEN]) -> Self {
        // HMAC pads keys shorter than SHA-256's 64-byte block with zeros (RFC 2104): padding here
        // gives the same MAC through the infallible block-sized constructor.
        let mut block = [0u8; 64];
        block[..KEY_LEN].copy_from_slice(bytes);
        let mac = <Hmac<Sha256> as hmac::digest::KeyInit>::new(&block.into());
        Self { mac }
    }

    /// The tag of `data`. O(len).
    pub fn tag(&self, data: &[u8]) -> [u8; TAG_LEN] {
        let mut mac = self.mac.clone();
        mac.update(data);
        let full = mac.finalize().into_bytes();
        let mut tag = [0u8; TAG_LEN];
        tag.copy_from_slice(&full[..TAG_LEN]);
        tag
    }

    /// Whether `tag` is the tag of `data`, compared in constant time. O(len).
    pub fn verify(&self, data: &[u8], tag: &[u8]) -> bool {
        let mut mac = self.mac.clone();
        mac.update(data);
        tag.len() == TAG_LEN && mac.verify_truncated_left(tag).is_ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RFC 4231 test case 2 ("Jefe"), truncated: an independent reference for the HMAC.
    #[test]
    fn matches_rfc_4231() {
        let mac = Hmac::<Sha256>::new_from_slice(b"Jefe").unwrap();
        let key = Key { mac };
        let tag = key.tag(b"what do ya want for nothing?");
        assert_eq!(tag, [0x5b, 0xdc, 0xc1, 0x46, 0xbf, 0x60, 0x75, 0x4e]);
        assert!(key.verify(b"what do ya want for nothing?", &tag));
        assert!(!key.verify(b"what do ya want for nothing!", &tag));
    }
}
