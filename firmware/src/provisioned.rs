//! The device key built into the image: the file `METAMORAN_LINK_KEY_FILE` named at build time
//! (written by `metamoran provision`), embedded by `build.rs`. The `edge` image does not build
//! without one unless the explicit `insecure-dev-key` feature is set, which falls back to the
//! public development key.

use metamoran_dsp::wire::DeviceKey;

include!(concat!(env!("OUT_DIR"), "/link_key.rs"));

/// The device key of this image: the provisioned one, else (with `insecure-dev-key` only) the
/// public development key; `None` when neither.
pub fn device_key() -> Option<DeviceKey> {
    match LINK_KEY {
        Some(bytes) => Some(DeviceKey::new(bytes)),
        #[cfg(feature = "insecure-dev-key")]
        None => Some(DeviceKey::new(metamoran_dsp::wire::DEV_KEY)),
        #[cfg(not(feature = "insecure-dev-key"))]
        None => None,
    }
}
