//! Picks the memory layout and the cortex-m-rt linker script for embedded targets only, so the
//! crate's portable library also builds and tests on the host.

use std::{env, fs, path::PathBuf};

/// The provisioned device key: 64 hex digits in the file `METAMORAN_LINK_KEY_FILE` names
/// (`metamoran provision` writes it), as the Rust source of `LINK_KEY`.
fn link_key() -> String {
    println!("cargo:rerun-if-env-changed=METAMORAN_LINK_KEY_FILE");
    let Some(path) = env::var_os("METAMORAN_LINK_KEY_FILE") else {
        return "/// No key was provisioned at build time.\npub const LINK_KEY: Option<[u8; 32]> = None;\n"
            .into();
    };
    let path = PathBuf::from(path);
    println!("cargo:rerun-if-changed={}", path.display());
    let text = fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "METAMORAN_LINK_KEY_FILE={}: cannot read it ({e})",
            path.display()
        )
    });
    let hex = text.trim();
    let bytes: Option<Vec<u8>> = (hex.len() == 64)
        .then(|| {
            (0..32)
                .map(|i| u8::from_str_radix(hex.get(2 * i..2 * i + 2)?, 16).ok())
                .collect()
        })
        .flatten();
    let Some(bytes) = bytes else {
        panic!(
            "METAMORAN_LINK_KEY_FILE={}: not a device key (64 hex digits); write one with \
             `metamoran provision`",
            path.display()
        )
    };
    format!(
        "/// The device key provisioned at build time.\npub const LINK_KEY: Option<[u8; 32]> = Some({bytes:?});\n"
    )
}

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::write(out.join("link_key.rs"), link_key()).expect("OUT_DIR is writable");
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
    fs::write(out.join("memory.x"), layout).expect("OUT_DIR is writable");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    // defmt's interned strings live in an info section of the ELF; defmt-print reads them.
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
