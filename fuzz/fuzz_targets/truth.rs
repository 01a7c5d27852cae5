//! `truth.json`: any bytes are checked truth for the capture's frames or an `InputError`.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|bytes: &[u8]| {
    if let Ok(t) = metamoran_bundle::Truth::parse(Path::new("bundle/truth.json"), bytes, 4) {
        // What the reader accepts keeps its promises.
        for f in &t.frames {
            assert!(f.frame < 4);
            for o in &f.objects {
                assert!(o.depth_m.is_finite() && o.depth_m >= 0.0);
                assert!(o.points.iter().flatten().all(|v| v.is_finite()));
            }
        }
    }
});
