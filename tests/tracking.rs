//! The tracker on the simulator's perimeter scene (issue #20 part 1): the Metamoran estimates of
//! 22 frames, tracked in the ground plane without the camera's instance ids, scored against the
//! truth with CLEAR-MOT (misses, false tracks, id switches).

use metamoran_bundle::OBJECTS_OF_INTEREST;
use metamoran_operator::tracking::score::{FrameObjects, score};
use metamoran_operator::tracking::{Detection, Tracker, TrackerConfig};
use metamoran_process::{Mode, ProcessOptions, process};
use metamoran_sim::radar::RadarKind;
use metamoran_sim::{layout::Preset, simulate};

fn ground(depth_m: f64, azimuth_deg: f64) -> [f64; 2] {
    let a = azimuth_deg.to_radians();
    [depth_m * a.sin(), depth_m * a.cos()]
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
    let out = process(bundle, &ProcessOptions::mode(Mode::Metamoran)).unwrap();
    let b = metamoran_bundle::Bundle::open(bundle, Default::default()).unwrap();
    let (truth, period) = (b.truth.clone().unwrap(), b.scene.radar.frame_period_s);
    let mut tracker = Tracker::new(TrackerConfig::default());
    let mut frames = Vec::new();
    for (f, result) in out.frames.iter().enumerate() {
        // The tracker never sees an instance id: renumbering the camera's changes nothing.
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
                .map(|t| (u32::from(t.instance), ground(t.depth_m, t.azimuth_deg)))
                .collect(),
            tracks: tracker.confirmed().map(|t| (t.id, t.position_m)).collect(),
        });
    }
    let clear = score(&frames, 2.0);
    eprintln!("perimeter scene, cascade, seed 3: {clear}");
    assert_eq!(clear.truth, 44, "a car and a person over 22 frames");
    assert_eq!(clear.id_switches, 0, "{clear}");
    assert!(clear.false_tracks <= 2, "{clear}");
    // Two frames per object go by before a track is confirmed.
    assert!(clear.mota() > 0.8, "{clear}");
    assert!(clear.motp_m < 0.5, "{clear}");
}
