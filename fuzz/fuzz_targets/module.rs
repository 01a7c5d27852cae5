//! The firmware's message handling with authentic but hostile messages: the input is read as a
//! sequence of postcard-encoded `Downlink` messages (undecodable bytes are skipped), each one
//! signed by a paired host and fed to the module, interleaved with raw bytes when a selector
//! byte says so. The module must never panic, and must answer `Health` with counters that add
//! up.
#![no_main]
use firmware::capture::SliceCapture;
use firmware::clock::StepClock;
use firmware::host_mock::{Line, SeededNonces};
use firmware::module::{Module, Poll, Scratch};
use libfuzzer_sys::fuzz_target;
use metamoran_dsp::wire::{
    DEV_KEY, Deframer, DeviceKey, Downlink, HandshakeUp, HostLink, MAX_WIRE, Opened,
};
use std::sync::Mutex;

/// The module's memory, allocated once.
static MEMORY: Mutex<Option<(Vec<u32>, Box<Scratch>)>> = Mutex::new(None);
/// A short capture: frames of small configurations run whole, larger ones end in a fault.
static CAPTURE: [u8; 16 * 1024] = [0x11; 16 * 1024];

fn run(m: &mut Module<'_, SliceCapture<'_>, Line, StepClock, SeededNonces>) -> bool {
    for _ in 0..100_000 {
        match m.poll() {
            Poll::Busy => {}
            Poll::Idle => return false,
            Poll::Stopped => return true,
        }
    }
    panic!("the module never went idle");
}

fuzz_target!(|bytes: &[u8]| {
    let mut memory = MEMORY.lock().unwrap();
    let (arena, scratch) = memory.get_or_insert_with(|| {
        (
            vec![0; firmware::bench_scene::ARENA_WORDS],
            Box::new(Scratch::new()),
        )
    });
    let mut m = Module::new(
        SliceCapture::new(&CAPTURE),
        Line::default(),
        StepClock::new(1_000),
        SeededNonces(0),
        arena,
        scratch,
        DeviceKey::new(DEV_KEY),
    );
    // Pair.
    let mut host = HostLink::new(DeviceKey::new(DEV_KEY));
    let mut out = [0u8; MAX_WIRE];
    let hello = std::mem::take(&mut m.link_mut().tx);
    let mut d: Deframer = Deframer::new();
    let mut nonce = None;
    for &b in &hello {
        if let Some(Ok(f)) = d.push(b)
            && let Ok(Opened::Handshake(HandshakeUp::Hello { nonce: n, .. })) = host.open(f)
        {
            nonce = Some(n);
        }
    }
    let n = host.pair(nonce.expect("Hello"), [9; 16], &mut out).unwrap();
    m.link_mut().rx.extend(&out[..n]);
    run(&mut m);
    assert!(m.in_session());
    // The fuzzer's messages.
    let mut rest = bytes;
    while let [selector, tail @ ..] = rest {
        if selector & 0x0F == 0 {
            // Raw bytes straight onto the link (up to 32).
            let k = usize::from(selector >> 4).min(tail.len());
            m.link_mut().rx.extend(&tail[..k]);
            rest = &tail[k..];
        } else {
            match postcard::take_from_bytes::<Downlink>(tail) {
                Ok((msg, after)) => {
                    if let Ok(n) = host.encode(&msg, &mut out) {
                        m.link_mut().rx.extend(&out[..n]);
                    }
                    rest = after;
                }
                Err(_) => rest = tail,
            }
        }
        if run(&mut m) {
            return;
        }
    }
    let h = m.health();
    assert!(h.link.accepted >= 1, "{h:?}");
});
