//! The bare-capture radar config (a `[radar]` table): any text parses or is an error.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|text: &str| {
    let _ = metamoran_bundle::capture::parse_radar_config(Path::new("radar.toml"), text);
});
