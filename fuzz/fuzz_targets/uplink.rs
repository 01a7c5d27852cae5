//! The host's end of the link on any byte stream: the deframer and `HostLink::open` count and
//! reject what is not an authentic frame, and never panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use metamoran_dsp::wire::{DEV_KEY, Deframer, DeviceKey, HostLink, MAX_WIRE};

fuzz_target!(|bytes: &[u8]| {
    let mut host = HostLink::new(DeviceKey::new(DEV_KEY));
    let mut out = [0u8; MAX_WIRE];
    // Half the runs in a session, so session frames reach the replay window.
    if bytes.first().is_some_and(|b| b & 1 == 1) {
        let _ = host.pair([1; 16], [2; 16], &mut out);
    }
    let mut deframer: Deframer = Deframer::new();
    for &b in bytes {
        match deframer.push(b) {
            Some(Ok(frame)) => {
                let _ = host.open(frame);
            }
            Some(Err(e)) => host.count(e),
            None => {}
        }
    }
});
