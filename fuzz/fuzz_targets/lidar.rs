//! Lidar truth (`lidar/F.ply`): any bytes are the points the header counts or an `InputError`.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|bytes: &[u8]| {
    if let Ok(points) = metamoran_bundle::lidar::parse(Path::new("bundle/lidar/000000.ply"), bytes)
    {
        // Twelve bytes a point after the header: never more points than the input could hold.
        assert!(points.len() * 12 <= bytes.len());
    }
});
