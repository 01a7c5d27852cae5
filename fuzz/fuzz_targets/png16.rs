//! The 16-bit grayscale PNG reader: two bytes choose the expected size (1–64 × 1–64), the rest
//! is the file. A decoded image has exactly that many pixels.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|bytes: &[u8]| {
    let [w, h, png @ ..] = bytes else { return };
    let (w, h) = (1 + u32::from(*w % 64), 1 + u32::from(*h % 64));
    if let Ok(px) = metamoran_bundle::parse_png16(Path::new("000000_mask.png"), png, w, h) {
        assert_eq!(px.len(), (w * h) as usize);
    }
});
