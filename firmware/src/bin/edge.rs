//! The module's application: the telemetry link on UART0, frames from the capture file named on
//! the semihosting command line (QEMU stands in for the radar board's SPI port), the pipeline per
//! object. Exits through semihosting when the host sends `Stop`.
//!
//! Run by `metamoran process BUNDLE --mode metamoran --edge qemu`; by hand:
//! `qemu-system-arm -machine mps2-an500 -nographic -monitor none -serial tcp:127.0.0.1:PORT,server=on,wait=on
//!  -semihosting-config enable=on,target=native,arg=edge,arg=BUNDLE/radar.bin -kernel edge`.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
mod app {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::hprintln;
    use dsp::wire::{DEV_KEY, Key};
    use firmware::board::{SemihostingFile, Timer0};
    use firmware::module::{Module, Poll, Scratch};
    use firmware::uart::{CmsdkUart, UART0};

    firmware::hard_fault_exits!();

    /// Frame arena: the cascade-86 × 512-sample budget (352 KiB).
    const ARENA_WORDS: usize = firmware::bench_scene::ARENA_WORDS;
    static mut ARENA: [u32; ARENA_WORDS] = [0; ARENA_WORDS];
    static mut SCRATCH: Scratch = Scratch::new();

    #[entry]
    fn main() -> ! {
        let stack = firmware::board::StackGauge::paint();
        let key = match option_env!("METAMORAN_LINK_KEY") {
            Some(hex) => match Key::from_hex(hex) {
                Ok(k) => k,
                Err(e) => {
                    hprintln!("EDGE error=key {}", e);
                    firmware::board::exit(false)
                }
            },
            None => Key::new(&DEV_KEY),
        };
        let Some(capture) = SemihostingFile::from_cmdline(1) else {
            hprintln!(
                "EDGE error=capture: pass the capture file as the second semihosting argument"
            );
            firmware::board::exit(false)
        };
        // SAFETY: the only references to ARENA and SCRATCH, taken once here.
        let (arena, scratch) = unsafe {
            (
                &mut *core::ptr::addr_of_mut!(ARENA),
                &mut *core::ptr::addr_of_mut!(SCRATCH),
            )
        };
        // SAFETY: UART0 is this board's CMSDK UART and nothing else drives it.
        let uart = unsafe { CmsdkUart::new(UART0, 25_000_000, 115_200) };
        let mut module = Module::new(capture, uart, Timer0::start(), arena, scratch, key);
        loop {
            if module.poll() == Poll::Stopped {
                let h = module.health();
                hprintln!(
                    "EDGE stopped frames={} capture_errors={} pipeline_errors={} protocol_errors={} stack_bytes={}",
                    h.frames,
                    h.capture_errors,
                    h.pipeline_errors,
                    h.protocol_errors,
                    stack.high_water()
                );
                firmware::board::exit(true)
            }
        }
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("edge runs on thumbv7em-none-eabihf: metamoran process BUNDLE --edge qemu");
    std::process::exit(2);
}
