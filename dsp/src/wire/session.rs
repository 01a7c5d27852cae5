//! Sessions: fresh keys for every pairing of a module boot with a host run, so nothing recorded
//! in one session is accepted in another (issue #18, item 1).
//!
//! ```text
//! module boots       N_m ← TRNG                 ── HandshakeUp::Hello { N_m } ──────────▶ host
//! host               N_h ← OS RNG        ◀── HandshakeDown::Session { N_m, N_h } ──
//! module (N_m is its pending nonce)  K_up, K_down ← HKDF(device key, N_m ‖ N_h)
//!                                               ── Uplink::Ready (K_up, counter 1) ──────▶ host
//! host restarts                          ◀── HandshakeDown::Sync ── (module re-sends Hello)
//! ```
//!
//! - The long-term **device key** ([`DeviceKey`], provisioned per module) never tags a frame:
//!   HKDF-SHA-256 (RFC 5869) derives a handshake key from it, and per session one key per
//!   direction from it and both nonces (salt `N_m ‖ N_h`).
//! - Handshake frames are tagged with the handshake key on their own stream bytes; their
//!   freshness comes from the nonces, not counters. The module accepts a `Session` only for
//!   its pending nonce, once, so a recorded `Session` is useless after the module reboots or
//!   pairs again; the host accepts the session only when `Ready` arrives under keys that
//!   depend on its fresh `N_h`, so a replayed `Hello` cannot pair it with a recording.
//! - Session frames carry counters from 1 in each direction, checked by the receiver's replay
//!   window; a new session starts both over under new keys, so frames of an older session
//!   (before a reboot, or of another host run) fail the tag.
//! - A module keeps its pending nonce until a `Session` consumes it: a `Sync` (or a replayed
//!   one) re-sends the same `Hello`, and an established session keeps running until the next
//!   handshake completes.

use super::auth::{KEY_LEN, Key, KeyError};
use core::fmt;
use hkdf::Hkdf;
use serde::{Deserialize, Serialize};
use sha2::Sha256;

/// Bytes of a session nonce (each side contributes one).
pub const NONCE_LEN: usize = 16;

/// One side's contribution to a session.
pub type Nonce = [u8; NONCE_LEN];

/// The HKDF `info` of the handshake key.
const HANDSHAKE_INFO: &[u8] = b"metamoran/3 handshake";
/// The HKDF `info` of a session's uplink key.
const UPLINK_INFO: &[u8] = b"metamoran/3 uplink";
/// The HKDF `info` of a session's downlink key.
const DOWNLINK_INFO: &[u8] = b"metamoran/3 downlink";

/// A module's provisioned long-term secret (`metamoran provision`). It only derives keys:
/// [`DeviceKey::handshake`] and [`DeviceKey::session`]. `Debug` never prints it.
#[derive(Clone)]
pub struct DeviceKey([u8; KEY_LEN]);

impl fmt::Debug for DeviceKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("DeviceKey(..)")
    }
}

/// The two keys of one session.
#[derive(Clone, Debug)]
pub struct SessionKeys {
    /// Tags module → host frames.
    pub uplink: Key,
    /// Tags host → module frames.
    pub downlink: Key,
}

impl DeviceKey {
    /// The key `bytes`.
    pub const fn new(bytes: [u8; KEY_LEN]) -> Self {
        Self(bytes)
    }

    /// The key written as [`KEY_LEN`] × 2 hexadecimal digits (surrounding whitespace ignored).
    /// (`(high << 4) | low` and `^` agree: cargo-mutants' equivalent mutant here.)
    ///
    /// # Errors
    /// [`KeyError::Hex`] for any other text.
    pub fn from_hex(text: &str) -> Result<Self, KeyError> {
        let text = text.trim().as_bytes();
        if text.len() != 2 * KEY_LEN {
            return Err(KeyError::Hex);
        }
        let digit = |c: u8| match c {
            b'0'..=b'9' => Ok(c - b'0'),
            b'a'..=b'f' => Ok(c - b'a' + 10),
            b'A'..=b'F' => Ok(c - b'A' + 10),
            _ => Err(KeyError::Hex),
        };
        let mut bytes = [0u8; KEY_LEN];
        for (b, pair) in bytes.iter_mut().zip(text.chunks_exact(2)) {
            *b = (digit(pair[0])? << 4) | digit(pair[1])?;
        }
        Ok(Self(bytes))
    }

    /// `label`'s 32-byte key: HKDF-SHA-256 with `salt`, this key as input keying material.
    fn derive(&self, salt: Option<&[u8]>, label: &[u8]) -> Key {
        let mut okm = [0u8; KEY_LEN];
        // 32 bytes is far below HKDF-SHA-256's 255 × 32-byte limit: expand cannot fail.
        let _ = Hkdf::<Sha256>::new(salt, &self.0).expand(label, &mut okm);
        Key::new(&okm)
    }

    /// The key that tags handshake frames (both directions; their stream bytes differ).
    pub fn handshake(&self) -> Key {
        self.derive(None, HANDSHAKE_INFO)
    }

    /// The keys of the session the module's nonce `module` and the host's `host` open.
    /// Four HMAC-SHA-256 runs.
    pub fn session(&self, module: &Nonce, host: &Nonce) -> SessionKeys {
        let mut salt = [0u8; 2 * NONCE_LEN];
        salt[..NONCE_LEN].copy_from_slice(module);
        salt[NONCE_LEN..].copy_from_slice(host);
        SessionKeys {
            uplink: self.derive(Some(&salt), UPLINK_INFO),
            downlink: self.derive(Some(&salt), DOWNLINK_INFO),
        }
    }
}

/// Module → host handshake messages (tagged with the handshake key).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum HandshakeUp {
    /// The module is up and offers its pending nonce; sent at boot and for every `Sync`.
    Hello {
        /// Firmware version (major · 10000 + minor · 100 + patch).
        firmware: u32,
        /// Words of frame arena the module has.
        arena_words: u32,
        /// The module's pending nonce.
        nonce: Nonce,
    },
}

/// Host → module handshake messages (tagged with the handshake key).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum HandshakeDown {
    /// The host (re)started: send `Hello` again.
    Sync,
    /// Open the session of `module` (the module's pending nonce) and `host` (fresh).
    Session {
        /// The module's nonce, from its `Hello`.
        module: Nonce,
        /// The host's fresh nonce.
        host: Nonce,
    },
}

/// A fresh nonce from `rng` (the board's TRNG, the host's OS RNG).
///
/// # Errors
/// The source's error (a TRNG that failed its health test).
pub fn fresh_nonce<R: rand_core::TryCryptoRng + ?Sized>(rng: &mut R) -> Result<Nonce, R::Error> {
    let mut nonce = [0u8; NONCE_LEN];
    rng.try_fill_bytes(&mut nonce)?;
    Ok(nonce)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hmac::{Hmac, Mac};

    /// A nonce is the source's bytes, in order.
    #[test]
    fn nonces_come_from_the_source() {
        struct Counting(u8);
        impl rand_core::TryRngCore for Counting {
            type Error = core::convert::Infallible;
            fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
                unreachable!()
            }
            fn try_next_u64(&mut self) -> Result<u64, Self::Error> {
                unreachable!()
            }
            fn try_fill_bytes(&mut self, dest: &mut [u8]) -> Result<(), Self::Error> {
                for b in dest {
                    self.0 += 1;
                    *b = self.0;
                }
                Ok(())
            }
        }
        impl rand_core::TryCryptoRng for Counting {}
        let mut source = Counting(0);
        let first = fresh_nonce(&mut source).unwrap();
        assert_eq!(first, core::array::from_fn(|i| i as u8 + 1));
        assert_ne!(fresh_nonce(&mut source).unwrap(), first);
    }

    /// RFC 5869 test case 1: the HKDF this module uses, against the RFC's output.
    #[test]
    fn hkdf_matches_rfc_5869() {
        let ikm = [0x0b; 22];
        let salt: [u8; 13] = core::array::from_fn(|i| i as u8);
        let info: [u8; 10] = core::array::from_fn(|i| 0xf0 + i as u8);
        let mut okm = [0u8; 42];
        Hkdf::<Sha256>::new(Some(&salt), &ikm)
            .expand(&info, &mut okm)
            .unwrap();
        let expected = "3cb25f25faacd57a90434f64d0362f2a2d2d0a90cf1a5a4c5db02d56ecc4c5bf\
                        34007208d5b887185865";
        let hex = |b: &[u8]| {
            b.iter()
                .flat_map(|x| {
                    let d = b"0123456789abcdef";
                    [d[(x >> 4) as usize], d[(x & 15) as usize]]
                })
                .collect::<std::vec::Vec<u8>>()
        };
        assert_eq!(hex(&okm), expected.as_bytes());
    }

    /// Session keys are the closed form HMAC(HMAC(salt, ikm), info ‖ 0x01) (one HKDF block),
    /// differ per direction and per nonce.
    #[test]
    fn session_keys_follow_the_closed_form() {
        let device = DeviceKey::new([5; KEY_LEN]);
        let (m, h) = ([1; NONCE_LEN], [2; NONCE_LEN]);
        let keys = device.session(&m, &h);
        let prk = {
            let mut mac = Hmac::<Sha256>::new_from_slice(&[[1u8; 16], [2u8; 16]].concat()).unwrap();
            mac.update(&[5; KEY_LEN]);
            mac.finalize().into_bytes()
        };
        let okm = |info: &[u8]| {
            let mut mac = Hmac::<Sha256>::new_from_slice(&prk).unwrap();
            mac.update(info);
            mac.update(&[1]);
            let out: [u8; 32] = mac.finalize().into_bytes().into();
            Key::new(&out)
        };
        let msg = b"frame";
        assert_eq!(keys.uplink.tag(msg), okm(UPLINK_INFO).tag(msg));
        assert_eq!(keys.downlink.tag(msg), okm(DOWNLINK_INFO).tag(msg));
        assert_ne!(keys.uplink.tag(msg), keys.downlink.tag(msg));
        let other = device.session(&m, &[3; NONCE_LEN]);
        assert_ne!(other.uplink.tag(msg), keys.uplink.tag(msg));
        assert_ne!(device.handshake().tag(msg), keys.uplink.tag(msg));
    }

    #[test]
    fn hex_keys() {
        let hex = "00112233445566778899aabbccddeeff00112233445566778899AABBCCDDEEFF";
        assert_eq!(DeviceKey::from_hex(hex).unwrap().0[1], 0x11);
        // Every digit, both cases, at both nibbles.
        let all = "0123456789abcdefABCDEF9876543210fedcbaFEDCBA0f1e2d3c4b5a69788796";
        let expected = [
            0x01, 0x23, 0x45, 0x67, 0x89, 0xab, 0xcd, 0xef, 0xab, 0xcd, 0xef, 0x98, 0x76, 0x54,
            0x32, 0x10, 0xfe, 0xdc, 0xba, 0xfe, 0xdc, 0xba, 0x0f, 0x1e, 0x2d, 0x3c, 0x4b, 0x5a,
            0x69, 0x78, 0x87, 0x96,
        ];
        assert_eq!(
            DeviceKey::from_hex(&std::format!(" {all}\n")).unwrap().0,
            expected
        );
        assert_eq!(DeviceKey::from_hex(&hex[1..]).unwrap_err(), KeyError::Hex);
        assert_eq!(
            DeviceKey::from_hex(&hex.replace('0', "g")).unwrap_err(),
            KeyError::Hex
        );
    }
}
