//! Issue #18, "Load", as a test (the 10,000-frame figures are `cd firmware && cargo bench
//! --bench soak`): 600 frames of the module's loop on the host over a line with 1 % loss, 1 %
//! reordering and 1 % corrupt frames both ways. Every frame is accounted for, and every frame
//! whose messages arrived intact gives exactly the clean run's results.

// Shared with benches/soak.rs, which uses the rest of it.
#[allow(dead_code)]
#[path = "soak/rig.rs"]
mod rig;

use rig::{Faults, run};

#[test]
fn every_frame_is_accounted_for_and_intact_frames_match_a_clean_run() {
    let frames = 600;
    let clean = run(frames, Faults::NONE, 1, None, |_| {});
    assert_eq!(clean.processed, frames, "{clean:?}");
    assert_eq!(clean.module.frames, frames);
    let faults = Faults {
        loss: 0.01,
        reorder: 0.01,
        corrupt: 0.01,
    };
    let r = run(frames, faults, 2, Some(&clean.results), |_| {});
    println!(
        "processed {} (intact {}), lost {} down / {} up, differ {}; host {:?}; module {:?}; faults {:?}",
        r.processed,
        r.intact,
        r.lost_downlink,
        r.lost_uplink,
        r.differ,
        r.host_link,
        r.module,
        r.faults
    );
    assert_eq!(r.processed + r.lost_downlink + r.lost_uplink, frames);
    assert_eq!(r.wrong, 0, "an intact frame gave other results");
    assert_eq!(
        r.unexplained, 0,
        "frames lost without a damaged frame to explain them"
    );
    // The line did misbehave, and the link saw it.
    assert!(r.lost_downlink + r.lost_uplink > 0);
    assert!(
        r.host_link.bad_tag + r.host_link.malformed > 0,
        "{:?}",
        r.host_link
    );
    assert!(
        r.module.link.bad_tag + r.module.link.malformed > 0,
        "{:?}",
        r.module.link
    );
    assert!(r.processed as f64 >= 0.9 * frames as f64, "{r:?}");
}
