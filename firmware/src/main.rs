//! Firmware entry: for now, the self-test that proves the module computes the host's bits.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
mod app {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::hprintln;

    firmware::hard_fault_exits!();

    #[entry]
    fn main() -> ! {
        hprintln!("metamoran firmware {} self-test", env!("CARGO_PKG_VERSION"));
        firmware::selftest::run(|o| {
            hprintln!("SELFTEST {} exp={} hash={:08x}", o.name, o.exponent, o.hash);
        });
        hprintln!("SELFTEST done");
        firmware::board::exit(true)
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!(
        "the firmware runs on thumbv7em-none-eabihf: cargo run -p firmware --release --target thumbv7em-none-eabihf"
    );
    std::process::exit(2);
}
