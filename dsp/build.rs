//! Enables `cfg(arm_dsp)` on targets with the ARMv7E-M DSP extension (its SIMD instructions),
//! which `cfg(target_feature)` does not expose on ARM in stable Rust.

fn main() {
    println!("cargo::rustc-check-cfg=cfg(arm_dsp)");
    let target = std::env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumbv7em") || target.starts_with("thumbv8m.main") {
        println!("cargo::rustc-cfg=arm_dsp");
    }
}
