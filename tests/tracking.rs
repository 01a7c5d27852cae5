//! The tracker on the simulator's multi-frame scenes (issue #20 part 1): the Metamoran estimates
//! of every frame, tracked in the ground plane without the camera's instance ids, scored against
//! the truth with CLEAR-MOT (misses, false tracks, id switches).

use metamoran_bundle::OBJECTS_OF_INTEREST;
use metamoran_operator::tracking::score::{Clear, FrameObjects, score};
use metamoran_operator::tracking::{Detection, Tracker, TrackerConfig};
use metamoran_process::{Mode, ProcessOptions, process};
use metamoran_sim::radar::RadarKind;
use metamoran_sim::{Variant, layout::Preset, simulate, simulate_with};

fn ground(depth_m: f64, azimuth_deg: f64) -> [f64; 2] {
    let a = azimuth_deg.to_radians();
    [depth_m * a.sin(), depth_m * a.cos()]
}

/// Tracks the Metamoran estimates of every frame of `bundle` and scores them against its truth
/// (objects of interest, by their identity across frames), gated at 2 m.
fn track_and_score(bundle: &std::path::Path) -> Clear {
    let out = process(bundle, &ProcessOptions::mode(Mode::Metamoran)).unwrap();
    let b = metamoran_bundle::Bundle::open(bundle, Default::default()).unwrap();
    let (truth, period) = (b.truth.clone().unwrap(), b.scene.radar.frame_period_s);
    let mut tracker = Tracker::new(TrackerConfig::default());
    let mut frames = Vec::new();
    for (f, result) in out.frames.iter().enumerate() {
        // The tracker never sees an instance id.
        let detections: Vec<Detection> = result
            .objects
            .iter()
            .filter_map(Detection::from_estimate)
            .collect();
        tracker.update(f as f64 * period, &detections).unwrap();
        frames.push(FrameObjects {
            truth: truth.frames[f]
                .objects
                .iter()
                .filter(|t| OBJECTS_OF_INTEREST.contains(&t.class.as_str()))
                .map(|t| (u32::from(t.identity()), ground(t.depth_m, t.azimuth_deg)))
                .collect(),
            tracks: tracker.confirmed().map(|t| (t.id, t.position_m)).collect(),
        });
    }
    score(&frames, 2.0)
}

#[test]
fn the_perimeter_scene_is_tracked_without_id_switches() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = &simulate(
        Preset::Perimeter,
        RadarKind::Cascade,
        3,
        1,
        dir.path(),
        &|| (),
    )
    .unwrap()[0];
    let clear = track_and_score(bundle);
    eprintln!("perimeter scene, cascade, seed 3: {clear}");
    assert_eq!(clear.truth, 44, "a car and a person over 22 frames");
    assert_eq!(clear.id_switches, 0, "{clear}");
    assert!(clear.false_tracks <= 2, "{clear}");
    // Two frames per object go by before a track is confirmed.
    assert!(clear.mota() > 0.8, "{clear}");
    assert!(clear.motp_m < 0.5, "{clear}");
}

/// Issue #20: two people whose walks cross (one hides the other from the camera for a frame or
/// two) and a car, on fresh scenes with the camera's instances renumbered every frame: the
/// tracks keep their ids. The README's tracking table is this test's output.
#[test]
fn people_crossing_keep_their_ids() {
    let dir = tempfile::tempdir().unwrap();
    let variant = Variant {
        renumber: true,
        ..Variant::default()
    };
    let mut total = Clear::default();
    for (radar, seed) in [(RadarKind::Cascade, 41), (RadarKind::Xwr18xx, 42)] {
        let bundles = simulate_with(
            Preset::Crossing,
            radar,
            variant,
            seed,
            3,
            dir.path(),
            &|| (),
        )
        .unwrap();
        let mut set = Clear::default();
        for b in &bundles {
            let clear = track_and_score(b);
            eprintln!("{}: {clear}", b.file_name().unwrap().to_string_lossy());
            set += clear;
        }
        eprintln!("crossing, {radar:?}, seed {seed}, 3 scenes: {set}");
        total += set;
    }
    assert_eq!(
        total.truth,
        6 * 90,
        "three objects over 30 frames, six scenes"
    );
    assert!(total.id_switches <= 1, "{total}");
    assert!(total.mota() > 0.75, "{total}");
}
