//! Perimeter TOML: any text is a checked perimeter or an error.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|text: &str| {
    if let Ok(p) = metamoran_operator::geofence::Perimeter::parse(text) {
        assert!(!p.zones.is_empty() && !p.restricted_classes.is_empty());
    }
});
