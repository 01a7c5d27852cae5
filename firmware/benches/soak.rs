//! The soak benchmark (issue #18, "Load"): 10,000 frames of the module's loop on the host at
//! full rate, over a line with 1 % loss, 1 % reordering and 1 % corrupt frames both ways,
//! against a clean run of the same frames. Prints frames per second (clean and faulty, same
//! run), peak and resident memory at 1,000 frames and at the end, and the counters.
//!
//! `cd firmware && cargo bench --bench soak` (optimized build).

#[allow(dead_code)]
#[path = "../tests/soak/rig.rs"]
mod rig;

use rig::{Faults, run, status_kib};
use std::time::Instant;

fn main() {
    let frames: u32 = std::env::args()
        .skip_while(|a| a != "--frames")
        .nth(1)
        .and_then(|f| f.parse().ok())
        .unwrap_or(10_000);
    let t = Instant::now();
    let clean = run(frames, Faults::NONE, 1, None, |_| {});
    let clean_s = t.elapsed().as_secs_f64();
    let faults = Faults {
        loss: 0.01,
        reorder: 0.01,
        corrupt: 0.01,
    };
    let mut rss_at_1000 = 0;
    let t = Instant::now();
    let r = run(frames, faults, 2, Some(&clean.results), |done| {
        if done == 1000 {
            rss_at_1000 = status_kib("VmRSS:");
        }
    });
    let faulty_s = t.elapsed().as_secs_f64();
    let rss_end = status_kib("VmRSS:");
    println!("soak: {frames} frames, 1 % loss / reorder / corruption each way");
    println!(
        "  clean line: {:.0} frames/s; faulty line: {:.0} frames/s ({:.2}× the clean rate)",
        f64::from(frames) / clean_s,
        f64::from(frames) / faulty_s,
        clean_s / faulty_s
    );
    println!(
        "  accounted: {} processed ({} intact, all identical to the clean run: {}), {} lost on the downlink, {} on the uplink, {} with a damaged hint giving other results",
        r.processed,
        r.intact,
        r.wrong == 0,
        r.lost_downlink,
        r.lost_uplink,
        r.differ
    );
    println!(
        "  memory: RSS {rss_at_1000} KiB at 1,000 frames, {rss_end} KiB at the end; peak {} KiB",
        status_kib("VmHWM:")
    );
    println!("  host link: {:?}", r.host_link);
    println!("  module: {:?}", r.module);
    println!("  faults reported (with repeats): {:?}", r.faults);
    assert_eq!(r.processed + r.lost_downlink + r.lost_uplink, frames);
    assert_eq!((r.wrong, r.unexplained), (0, 0));
    assert!(
        rss_end <= rss_at_1000 + 1024,
        "memory grew: {rss_at_1000} → {rss_end} KiB"
    );
}
