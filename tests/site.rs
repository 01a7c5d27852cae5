//! The site preset end to end (issue #20 part 2): three poles' bundles processed and tracked as
//! their sensors would, fused by the site process. Scored against the simulator's truth on the
//! plan (each pole's truth moved onto the plan by the pole's pose, not by the code under test):
//! every object one site track (no duplicates from the poles that see it twice), the zone's
//! alerts once per object with the sensors that saw it.

use metamoran_bundle::OBJECTS_OF_INTEREST;
use metamoran_operator::geofence::AlertKind;
use metamoran_operator::tracking::score::{FrameObjects, score};
use metamoran_sim::radar::RadarKind;
use metamoran_sim::site::{POLES, simulate_site};
use std::collections::BTreeMap;

#[test]
fn three_poles_make_one_site_track_per_object() {
    let out = tempfile::tempdir().unwrap();
    let dir = simulate_site(RadarKind::Cascade, 11, out.path()).unwrap();
    let report = metamoran::site::run(&dir).unwrap();
    assert_eq!(report.frames, 40);
    // Truth on the plan: each object where the first pole that sees it puts it.
    let truths: Vec<_> = POLES
        .iter()
        .map(|p| {
            let b = metamoran_bundle::Bundle::open(&dir.join(p.id), Default::default()).unwrap();
            (p.pose(), b.truth.unwrap())
        })
        .collect();
    let mut seen_by: BTreeMap<u16, usize> = BTreeMap::new();
    let frames: Vec<FrameObjects> = (0..report.frames)
        .map(|f| {
            let mut objects: BTreeMap<u16, [f64; 2]> = BTreeMap::new();
            for (pose, truth) in &truths {
                for t in &truth.frames[f].objects {
                    if !OBJECTS_OF_INTEREST.contains(&t.class.as_str()) {
                        continue;
                    }
                    let a = t.azimuth_deg.to_radians();
                    let plan = pose.to_world([t.depth_m * a.sin(), t.depth_m * a.cos()]);
                    objects.entry(t.identity()).or_insert(plan);
                    *seen_by.entry(t.identity()).or_default() += 1;
                }
            }
            FrameObjects {
                truth: objects
                    .into_iter()
                    .map(|(id, p)| (u32::from(id), p))
                    .collect(),
                tracks: report.tracks[f]
                    .iter()
                    .map(|t| (t.id, t.position_m))
                    .collect(),
            }
        })
        .collect();
    let clear = score(&frames, 2.0);
    eprintln!("site, cascade, seed 11, three poles: {clear}");
    eprintln!("{report}");
    // Two people and a car, each seen by more than one pole in most frames.
    assert_eq!(seen_by.len(), 3, "{seen_by:?}");
    assert!(seen_by.values().all(|&n| n > 40), "{seen_by:?}");
    // Measured (README, "Site"): the misses are the confirmation delay; most false tracks are
    // one pole's track of the hidden person on depths 3–4 m off after an occlusion (#17).
    assert!(clear.id_switches <= 2, "{clear}");
    assert!(clear.false_tracks <= 15, "duplicates across poles: {clear}");
    assert!(clear.mota() > 0.75, "{clear}");
    // The yard: each person enters once on a track two poles or more see.
    let enters: Vec<_> = report
        .alerts
        .iter()
        .filter(|a| a.alert.kind == AlertKind::Enter && a.sensors.len() >= 2)
        .collect();
    assert_eq!(enters.len(), 2, "{:?}", report.alerts);
    assert!(enters.iter().all(|a| a.alert.class == "person"));
    assert_ne!(enters[0].alert.track, enters[1].alert.track);
    assert!(
        report
            .health
            .iter()
            .all(|(_, h)| h.accepted == 40 && h.rejected == 0)
    );
}
