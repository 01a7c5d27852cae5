//! The baselines on fresh simulated scenes (seeds no other test uses) show what the Metamoran
//! paper reports: naive fusion has a long error tail in clutter, and monocular depth error grows
//! with range. Also checks `process --json` against the shape of shared/spec/cli.md.

use metamoran_process::Mode;
use metamoran_process::eval;
use metamoran_sim::{layout::Preset, radar::RadarKind, simulate};

#[test]
fn naive_has_a_long_tail_and_monocular_error_grows_with_range() {
    let tmp = tempfile::tempdir().unwrap();
    simulate(
        Preset::ParkingLot,
        RadarKind::Cascade,
        20_261_122,
        40,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    let (report, samples) = eval::run(tmp.path(), &[Mode::Naive, Mode::Monocular], &|| ()).unwrap();
    assert!(report.failed.is_empty(), "{:?}", report.failed);
    assert!(samples.len() >= 40);
    let naive = &report.modes["naive"].all;
    println!("{report}");
    assert!(
        naive.over_1m.unwrap() > 0.2,
        "naive errors over 1 m: {:?}",
        naive.over_1m
    );
    assert!(naive.p90_m.unwrap() > 3.0);
    let mono = &report.modes["monocular"].by_range;
    let mae = |k: &str| mono[k].mae_m.unwrap();
    assert!(
        mae("0-20") < mae("20-40") && mae("20-40") < mae("40-60"),
        "monocular MAE by range: {} {} {}",
        mae("0-20"),
        mae("20-40"),
        mae("40-60")
    );
    assert!(mae("0-20") < 2.0 && mae("40-60") > 5.0);
}

#[test]
fn process_json_has_the_cli_shape() {
    let tmp = tempfile::tempdir().unwrap();
    let dirs = simulate(
        Preset::LongRange,
        RadarKind::Xwr18xx,
        5,
        1,
        tmp.path(),
        &|| (),
    )
    .unwrap();
    let truth = metamoran_bundle::Truth::read(&dirs[0].join("truth.json"), 1).unwrap();
    for mode in [Mode::Naive, Mode::Monocular] {
        let out =
            metamoran_process::process(&dirs[0], &metamoran_process::ProcessOptions::mode(mode))
                .unwrap();
        let v = serde_json::to_value(&out).unwrap();
        assert_eq!(v["mode"], mode.name());
        let objects = v["frames"][0]["objects"].as_array().unwrap();
        assert_eq!(v["frames"][0]["frame"], 0);
        // One entry per object of interest, in id order, with the documented keys.
        let ids: Vec<u64> = objects
            .iter()
            .map(|o| o["instance"].as_u64().unwrap())
            .collect();
        let mut sorted = ids.clone();
        sorted.sort();
        assert_eq!(ids, sorted);
        assert_eq!(ids.len(), truth.frames[0].objects.len());
        for o in objects {
            for key in [
                "instance",
                "class",
                "detected",
                "depth_m",
                "azimuth_deg",
                "points",
            ] {
                assert!(o.get(key).is_some(), "missing {key}");
            }
            assert_eq!(o["detected"].as_bool().unwrap(), o["depth_m"].is_number());
            assert!(
                o["points"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .all(|p| p.as_array().unwrap().len() == 3)
            );
        }
    }
}
