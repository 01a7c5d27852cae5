//! `scene.toml`: any text is a clean `Ok` or an `InputError`, never a panic, hang or large
//! allocation.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|text: &str| {
    let _ = metamoran_bundle::Scene::parse(Path::new("bundle/scene.toml"), text);
});
