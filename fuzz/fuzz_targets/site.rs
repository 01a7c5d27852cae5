//! The site process's inputs: any text is a checked site file or an error, and any bytes a
//! sensor sends on its `tracks` subject are taken or refused (named and counted), never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use metamoran_operator::site::{SensorTracks, Site, SiteConfig, SiteFile};

const SITE: &str = r#"
name = "f"
extent = [[-50.0, -50.0], [50.0, 50.0]]
[[sensor]]
id = "a"
position = [0.0, -40.0]
heading_deg = 0.0
[[sensor]]
id = "b"
position = [0.0, 40.0]
heading_deg = 180.0
[perimeter]
restricted_classes = ["person", "car"]
[[perimeter.zone]]
name = "z"
polygon = [[-5.0, -5.0], [5.0, -5.0], [5.0, 5.0], [-5.0, 5.0]]
dwell_s = 1.0
approach_mps = 1.0
"#;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data)
        && let Ok(file) = SiteFile::parse(text)
    {
        assert!(!file.sensors.is_empty());
    }
    let mut site = Site::new(SiteFile::parse(SITE).unwrap(), SiteConfig::default());
    // The bytes as a stream of messages, one JSON document per line, alternating sensors.
    for (k, line) in data.split(|&b| b == b'\n').enumerate() {
        if let Ok(m) = serde_json::from_slice::<SensorTracks>(line) {
            let sensor = if k % 2 == 0 { "a" } else { "b" };
            let _ = site.ingest(sensor, &m);
            for t in site.tracks() {
                assert!(t.position_m.iter().all(|v| v.is_finite()), "{t:?}");
            }
        }
    }
});
