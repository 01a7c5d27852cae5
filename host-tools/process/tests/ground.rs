//! The ground-contact cue on simulated parking lots against their truth: the plane fitted on the
//! near monocular depths and the ray under each car's and person's mask give its range within
//! a few per cent, independently of the monocular estimate at that range.

use metamoran_bundle::CameraFrame;
use metamoran_bundle::geometry::CameraModel;
use metamoran_process::camera_points::objects_of_interest;
use metamoran_process::ground::stands_on_ground;
use metamoran_sim::layout::Preset;
use metamoran_sim::radar::RadarKind;
use metamoran_sim::simulate_scene;

#[test]
fn cars_and_people_stand_where_the_truth_puts_them() {
    let (mut errors, mut without) = (Vec::new(), 0);
    for index in 0..16 {
        let scene = simulate_scene(Preset::ParkingLot, RadarKind::Xwr18xx, 23, index);
        let shot = &scene.shots[0];
        let frame = CameraFrame {
            width: scene.camera.width,
            height: scene.camera.height,
            mask: shot.products.mask.clone(),
            depth: shot.products.depth_png.clone(),
            instances: shot.instances.clone(),
        };
        let truth = &scene.truth.frames[0].objects;
        for obj in objects_of_interest(&CameraModel::new(&scene.camera), &frame) {
            let Some(t) = truth.iter().find(|t| t.instance == obj.instance) else {
                continue;
            };
            match (stands_on_ground(&obj.class), obj.contact) {
                (true, Some(c)) => errors.push((c.range_m / t.depth_m).ln().abs()),
                (true, None) => without += 1,
                (false, c) => assert_eq!(c, None, "a {} has no contact", obj.class),
            }
        }
    }
    errors.sort_by(f64::total_cmp);
    let n = errors.len();
    assert!(
        n >= 15 && without * 5 <= n,
        "{n} with a contact, {without} without"
    );
    let (median, p90) = (errors[n / 2], errors[n * 9 / 10]);
    // Segmentation and the depth PNG's steps: within 8 % typically, 20 % at worst but one in ten.
    assert!(
        median < 0.08 && p90 < 0.2,
        "median {median}, 90th percentile {p90}: {errors:?}"
    );
}
