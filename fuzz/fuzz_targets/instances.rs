//! `F_instances.json`: any bytes parse into checked instances or are an error.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|bytes: &[u8]| {
    if let Ok(list) = metamoran_bundle::parse_instances(Path::new("000000_instances.json"), bytes) {
        // What the reader accepts keeps its promises.
        assert!(list.iter().all(|i| i.id != 0 && !i.class.is_empty()));
    }
});
