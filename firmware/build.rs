//! Picks the memory layout and the cortex-m-rt linker script for embedded targets only, so the
//! crate's portable library also builds and tests on the host.

use std::{env, fs, path::PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=../memory.x");
    println!("cargo:rerun-if-changed=memory-qemu.x");
    if !env::var("TARGET").unwrap_or_default().starts_with("thumbv") {
        return;
    }
    let layout: &[u8] = if env::var_os("CARGO_FEATURE_BOARD_QEMU").is_some() {
        include_bytes!("memory-qemu.x")
    } else {
        include_bytes!("../memory.x")
    };
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::write(out.join("memory.x"), layout).expect("OUT_DIR is writable");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    // defmt's interned strings live in an info section of the ELF; defmt-print reads them.
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
