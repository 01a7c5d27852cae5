//! IP-Basic depth completion (`map::ip_basic`) against OpenCV running the same sequence
//! (`oracles/ip_basic.py`, opencv-python-headless in the test venv), on a radar submap's depth
//! image and on a random sparse one.

use metamoran_e2e::run_oracle;
use metamoran_map::cylinder::{HEIGHT, WIDTH};
use metamoran_map::ip_basic::complete;

fn compare(depth: &[f32], what: &str) {
    let dir = tempfile::tempdir().unwrap();
    let (input, output) = (dir.path().join("in.f32"), dir.path().join("out.f32"));
    let bytes: Vec<u8> = depth.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(&input, bytes).unwrap();
    let (w, h) = (WIDTH.to_string(), HEIGHT.to_string());
    let args = [
        input.as_os_str(),
        output.as_os_str(),
        std::ffi::OsStr::new(&w),
        std::ffi::OsStr::new(&h),
    ];
    if run_oracle("ip_basic.py", &args, "opencv").is_none() {
        return;
    }
    let want: Vec<f32> = std::fs::read(&output)
        .unwrap()
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let got = complete(depth);
    assert_eq!(got.len(), want.len());
    let worst = got
        .iter()
        .zip(&want)
        .map(|(g, w)| (g - w).abs())
        .fold(0.0f32, f32::max);
    assert!(
        worst < 1e-3,
        "{what}: largest difference from OpenCV {worst} m"
    );
    let filled = |v: &[f32]| v.iter().filter(|&&d| d > 0.1).count();
    assert!(filled(&got) > 2 * filled(depth), "{what}: completion fills");
}

#[test]
fn completion_matches_opencv() {
    // A random sparse image: 3 % of pixels at 5–60 m.
    let mut state = 0x1234_5678u32;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state
    };
    let sparse: Vec<f32> = (0..WIDTH * HEIGHT)
        .map(|_| {
            if next() % 100 < 3 {
                5.0 + (next() % 5500) as f32 / 100.0
            } else {
                0.0
            }
        })
        .collect();
    compare(&sparse, "random");
    // A drive scene's submap.
    let scenes = tempfile::tempdir().unwrap();
    let dirs = metamoran_sim::simulate(
        metamoran_sim::layout::Preset::Drive,
        metamoran_sim::radar::RadarKind::Xwr18xx,
        8,
        1,
        scenes.path(),
        &|| (),
    )
    .unwrap();
    let o = metamoran_map::odometry::run(&dirs[0], &metamoran_sim::drive::MOUNT).unwrap();
    let images = metamoran_map::depth::last(&dirs[0], &o, None)
        .unwrap()
        .unwrap();
    compare(&images.submap.range_m, "submap");
    // The map's own completion is this one.
    assert_eq!(images.ip_basic.range_m, complete(&images.submap.range_m));
}
