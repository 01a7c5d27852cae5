//! Submaps that keep only what the last frame sees again (issue #21, part 2): on a parking area
//! seen by the 4D imaging board, the earlier frames' points the last frame no longer sees (since
//! hidden by something the radar does not report, or ghosts) are what make the all-points
//! submap worse than its own frame. Judged against the lidar truth's image, which the submap
//! never sees.

use metamoran_map::cylinder::Visibility;
use metamoran_map::depth::{SubmapOptions, last_with};
use metamoran_map::odometry;
use metamoran_map::report::{Pixels, errors};
use metamoran_map::submap::{Keep, density_growth};
use metamoran_sim::drive::MOUNT;
use metamoran_sim::{layout::Preset, radar::RadarKind, simulate};

#[test]
fn keeping_what_the_frame_sees_again_makes_the_submap_more_accurate() {
    let dir = tempfile::tempdir().unwrap();
    // Seed 45: not among the training (6000–6115) or the README's (6500–6702) seeds.
    let bundles = simulate(
        Preset::ParkingArea,
        RadarKind::Imaging,
        45,
        1,
        dir.path(),
        &|| (),
    )
    .unwrap();
    let o = odometry::run(&bundles[0], &MOUNT).unwrap();
    let mae = |keep| {
        let options = SubmapOptions {
            keep,
            visibility: Some(Visibility::IMAGING_BEAM),
            ..SubmapOptions::default()
        };
        let images = last_with(&bundles[0], &o, None, &options).unwrap().unwrap();
        let growth = density_growth(&images.frame, &images.submap).unwrap();
        let both = errors(&images, Pixels::Both).unwrap().mae_m;
        let own = errors(&images, Pixels::Own).unwrap().mae_m;
        eprintln!(
            "{keep:?}: MAE over both frame {:?} submap {:?}, over own {:?}, growth {:?}",
            both.frame, both.submap, own.submap, growth
        );
        (
            both.frame.unwrap(),
            both.submap.unwrap(),
            own.submap.unwrap(),
            growth,
        )
    };
    let (frame, all, all_own, _) = mae(Keep::All);
    let (frame_again, again, again_own, growth) = mae(Keep::SEEN_AGAIN);
    // The last frame's own image does not depend on what the submap keeps.
    assert_eq!(frame, frame_again);
    // Over the pixels the submap and the lidar both fill, and over the submap's own pixels.
    assert!(again < 0.7 * all, "seen again {again} m, all {all} m");
    // And here the submap is more accurate than its frame alone, which all points are not.
    assert!(
        again < frame && all > frame,
        "frame {frame} m, seen again {again} m, all {all} m"
    );
    assert!(
        again_own < 0.7 * all_own,
        "seen again {again_own} m, all {all_own} m"
    );
    // It still adds to the frame: earlier sightings of what the frame sees fill more pixels.
    assert!(growth > 1.5, "density growth {growth}");
}
