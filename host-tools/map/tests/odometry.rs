//! Doppler odometry on `drive` scenes (the second paper's Sec. 3.2, issue #7's goal): the mean
//! ego-velocity error norm must be at most 0.08 m/s (REVE's published 0.078 m/s), with moving
//! cars among the reflectors. The vehicle's yaw rate is checked against one derived from the
//! truth's poses alone (central differences of the yaw), not from the simulator's motion model;
//! the integrated track against the truth's last pose; the submap must densify the depth image.

use metamoran_map::report::run;
use metamoran_sim::drive::MOUNT;
use metamoran_sim::{layout::Preset, radar::RadarKind, simulate};

#[test]
fn ego_velocity_error_is_within_the_papers_figure() {
    let dir = tempfile::tempdir().unwrap();
    let bundles = simulate(
        Preset::Drive,
        RadarKind::Cascade,
        2026,
        3,
        dir.path(),
        &|| (),
    )
    .unwrap();
    let mut errors = Vec::new();
    for b in &bundles {
        let (report, o, _) = run(b, &MOUNT, None).unwrap();
        let truth: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(b.join("truth.json")).unwrap()).unwrap();
        let yaw: Vec<f64> = truth["frames"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["ego"]["yaw"].as_f64().unwrap())
            .collect();
        let period = 0.1;
        assert!(o.frames.iter().all(|f| f.velocity_mps.is_some()), "{o:?}");
        for f in &o.frames {
            // Most detections are static: walls, poles, parked cars.
            assert!(f.inliers * 2 > f.points, "{f:?}");
            errors.push(f.error_mps.unwrap());
        }
        // The submap of 20 frames fills many more pixels than one frame, and the integrated
        // poses stay on the true track (2 s of driving).
        let growth = report.density_growth_factor.unwrap();
        assert!(growth > 5.0, "density growth factor {growth}");
        assert_eq!(report.ego_velocity_error_mps, o.ego_velocity_error_mps);
        // Depth images against the lidar-like truth: a regression guard at about twice what
        // this first version measures (frame MAE 2–3 m), not a goal.
        let (mae, rmse) = (report.mae_m.unwrap(), report.rmse_m.unwrap());
        let frame = (mae.frame.unwrap(), rmse.frame.unwrap());
        assert!(frame.0 < 5.0 && frame.1 >= frame.0, "{mae:?} {rmse:?}");
        assert_eq!((mae.network, report.network_fps), (None, None));
        let drift = o.final_position_error_m.unwrap();
        assert!(drift < 0.2, "position error {drift} m after 20 frames");
        for k in 1..yaw.len() - 1 {
            let rate = (yaw[k + 1] - yaw[k - 1]) / (2.0 * period);
            let got = o.frames[k].yaw_rate_rps.unwrap();
            assert!(
                (got - rate).abs() < 0.05,
                "frame {k}: {got} vs {rate} rad/s"
            );
        }
    }
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    eprintln!(
        "mean ego-velocity error {mean:.4} m/s over {} frames",
        errors.len()
    );
    assert!(mean <= 0.08, "mean ego-velocity error {mean} m/s");
}
