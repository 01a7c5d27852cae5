//! defmt's global logger on the QEMU board: encoded frames to the semihosting console (QEMU's
//! stdout), decoded on the host by `defmt-print -e ELF`.
//!
//! Written here instead of taken from `defmt-semihosting`, whose re-entrancy guards panic: this
//! one has no panic path (the release firmware links none, see `scripts/panic-paths`), and a log
//! call nested inside another (a fault while logging) is dropped instead.

use core::ptr::addr_of_mut;
use cortex_m_semihosting::hio::{self, HostStream};

#[defmt::global_logger]
struct Logger;

struct State {
    encoder: defmt::Encoder,
    out: Option<HostStream>,
    /// Open `acquire`s; only the outermost one writes.
    depth: u32,
    /// Whether interrupts were enabled before the outermost `acquire`.
    reenable: bool,
}

static mut STATE: State = State {
    encoder: defmt::Encoder::new(),
    out: None,
    depth: 0,
    reenable: false,
};

/// The logger's state. Callers hold interrupts off (single core), so nothing else holds it.
fn state() -> &'static mut State {
    // SAFETY: only reached between `acquire` (interrupts off) and `release` on a single core,
    // and no reference outlives the call that took it.
    unsafe { &mut *addr_of_mut!(STATE) }
}

fn emit(out: &mut Option<HostStream>, bytes: &[u8]) {
    if let Some(o) = out {
        let _ = o.write_all(bytes);
    }
}

// SAFETY: `acquire`/`release` bracket every frame with interrupts disabled (single core), so
// frames never interleave; nested calls are counted and write nothing.
unsafe impl defmt::Logger for Logger {
    fn acquire() {
        let was_enabled = cortex_m::register::primask::read().is_active();
        cortex_m::interrupt::disable();
        let s = state();
        s.depth = s.depth.saturating_add(1);
        if s.depth == 1 {
            s.reenable = was_enabled;
            if s.out.is_none() {
                s.out = hio::hstdout().ok();
            }
            s.encoder.start_frame(|b| emit(&mut s.out, b));
        }
    }

    unsafe fn flush() {}

    unsafe fn release() {
        let s = state();
        match s.depth {
            0 => {}
            1 => {
                s.encoder.end_frame(|b| emit(&mut s.out, b));
                s.depth = 0;
                if s.reenable {
                    // SAFETY: restores the interrupt state `acquire` found.
                    unsafe { cortex_m::interrupt::enable() };
                }
            }
            _ => s.depth -= 1,
        }
    }

    unsafe fn write(bytes: &[u8]) {
        let s = state();
        if s.depth == 1 {
            s.encoder.write(bytes, |b| emit(&mut s.out, b));
        }
    }
}
