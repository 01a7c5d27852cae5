//! The module's application: the telemetry link on UART0, frames from the capture file named on
//! the semihosting command line (QEMU stands in for the radar board's SPI port), the pipeline per
//! object. Exits through semihosting when the host sends `Stop`.
//!
//! Logs are defmt frames on the semihosting console (QEMU's stdout): pipe it through
//! `defmt-print -e firmware/target/thumbv7em-none-eabihf/release/edge` to read them, or let
//! `metamoran process … --edge qemu --edge-log FILE` keep them.
//!
//! Run by `metamoran process BUNDLE --mode metamoran --edge qemu`; by hand:
//! `qemu-system-arm -machine mps2-an500 -nographic -monitor none -serial tcp:127.0.0.1:PORT,server=on,wait=on
//!  -semihosting-config enable=on,target=native,arg=edge,arg=BUNDLE/radar.bin -kernel edge`.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
mod app {
    use cortex_m_rt::entry;
    use firmware::board::{HostEntropy, SemihostingFile, StackGauge, Timer0};
    use firmware::module::{Module, Poll, Scratch};
    use firmware::uart::{CmsdkUart, UART0};

    firmware::hard_fault_exits!();

    // No image carries the public development key by accident.
    #[cfg(not(feature = "insecure-dev-key"))]
    const _: () = assert!(
        firmware::provisioned::LINK_KEY.is_some(),
        "no device key: build with METAMORAN_LINK_KEY_FILE=<a key file from `metamoran provision`>, \
         or with the explicit `insecure-dev-key` feature for development only"
    );

    /// Frame arena: the cascade-86 × 512-sample budget (352 KiB).
    const ARENA_WORDS: usize = firmware::bench_scene::ARENA_WORDS;
    static mut ARENA: [u32; ARENA_WORDS] = [0; ARENA_WORDS];
    static mut SCRATCH: Scratch = Scratch::new();

    #[entry]
    fn main() -> ! {
        let _ = StackGauge::paint();
        let Some(key) = firmware::provisioned::device_key() else {
            defmt::error!("no device key in this image: provision it");
            firmware::board::exit(false)
        };
        let Some(entropy) = HostEntropy::open() else {
            defmt::error!("no entropy source: QEMU must allow semihosting to open /dev/urandom");
            firmware::board::exit(false)
        };
        let Some(capture) = SemihostingFile::from_cmdline(1) else {
            defmt::error!("no capture: pass the capture file as the second semihosting argument");
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
        let mut module = Module::new(capture, uart, Timer0::start(), entropy, arena, scratch, key)
            .with_stack_gauge(StackGauge::stack_high_water);
        defmt::info!("edge module up: waiting for the host on UART0");
        loop {
            if module.poll() == Poll::Stopped {
                let h = module.health();
                defmt::info!(
                    "stopped after {=u32} frames: {=u32} capture, {=u32} pipeline, {=u32} protocol errors; stack {=u32} bytes",
                    h.frames,
                    h.capture_errors,
                    h.pipeline_errors,
                    h.protocol_errors,
                    h.stack_bytes
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
