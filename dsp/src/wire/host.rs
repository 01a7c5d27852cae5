//! The host's end of the link: pairs with a module through the handshake of [`super::session`]
//! and then frames downlink messages and checks uplink ones under the session's keys.
//!
//! ```text
//! HandshakeUp::Hello { N_m } ─▶ HostLink::pair(N_m, N_h) ─▶ HandshakeDown::Session { N_m, N_h }
//! Uplink::Ready (session keys) ─▶ HostLink::open ─▶ the session is confirmed
//! ```

use super::frame::{EncodeError, Sender, Stream};
use super::message::{Downlink, Uplink};
use super::receiver::{LinkError, Opened, Receiver};
use super::session::{DeviceKey, HandshakeDown, HandshakeUp, Nonce};

/// A host's link state with one module.
#[derive(Debug)]
pub struct HostLink {
    device: DeviceKey,
    handshake: Sender,
    /// Tags downlink session frames (under the handshake key, unusable, until paired).
    sender: Sender,
    receiver: Receiver,
    paired: bool,
}

impl HostLink {
    /// A link to the module provisioned with `device`, not yet paired.
    pub fn new(device: DeviceKey) -> Self {
        let handshake = device.handshake();
        Self {
            handshake: Sender::new(handshake.clone(), Stream::DownlinkHandshake),
            sender: Sender::new(handshake.clone(), Stream::DownlinkHandshake),
            receiver: Receiver::with_handshake(handshake, Stream::Uplink),
            device,
            paired: false,
        }
    }

    /// Frames `HandshakeDown::Sync` (ask the module to send `Hello` again) into `out`.
    ///
    /// # Errors
    /// [`EncodeError`] if `out` is too small.
    pub fn sync(&mut self, out: &mut [u8]) -> Result<usize, EncodeError> {
        self.handshake.encode(&HandshakeDown::Sync, out)
    }

    /// Opens the session of the module's nonce `module` (from its `Hello`) and the host's
    /// fresh nonce `host`: frames the `Session` message into `out` and switches to the new keys
    /// (the module's `Ready` under them confirms the session).
    ///
    /// # Errors
    /// [`EncodeError`] if `out` is too small.
    pub fn pair(
        &mut self,
        module: Nonce,
        host: Nonce,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let n = self
            .handshake
            .encode(&HandshakeDown::Session { module, host }, out)?;
        let keys = self.device.session(&module, &host);
        self.receiver.install(keys.uplink);
        self.sender = Sender::new(keys.downlink, Stream::Downlink);
        self.paired = true;
        Ok(n)
    }

    /// Frames session message `msg` into `out`.
    ///
    /// # Errors
    /// [`EncodeError::NoSession`] before [`HostLink::pair`]; otherwise as [`Sender::encode`].
    pub fn encode(&mut self, msg: &Downlink, out: &mut [u8]) -> Result<usize, EncodeError> {
        if !self.paired {
            return Err(EncodeError::NoSession);
        }
        self.sender.encode(msg, out)
    }

    /// Checks an uplink frame (COBS-encoded, decoded in place).
    ///
    /// # Errors
    /// [`LinkError`] naming the first check that failed (counted).
    pub fn open(&mut self, frame: &mut [u8]) -> Result<Opened<HandshakeUp, Uplink>, LinkError> {
        self.receiver.open_any(frame)
    }

    /// The uplink receive counters.
    pub fn stats(&self) -> super::message::LinkStats {
        self.receiver.stats()
    }

    /// Counts a rejection seen before [`HostLink::open`] (a deframer overflow).
    pub fn count(&mut self, error: LinkError) {
        self.receiver.count(error);
    }
}
