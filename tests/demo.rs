//! `metamoran demo`: the whole system on the built-in scene. Checked against the scene's truth,
//! not against the code's own output: the objects inside the built-in perimeter's zones (by the
//! truth positions) must raise exactly those alerts, and the KITTI depth PNG, decoded by the `png`
//! decoder, must hold the objects' true camera depths.

use metamoran::demo::{DemoEdge, DemoOptions, run};
use metamoran_e2e::{firmware_dir, oracles_required, qemu_available, run_oracle};
use metamoran_operator::geofence::AlertKind;

#[test]
fn demo_alerts_images_and_points_match_the_truth() {
    let edge = if qemu_available() {
        DemoEdge::Qemu
    } else {
        assert!(!oracles_required(), "qemu-system-arm is required");
        DemoEdge::InProcess
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let options = |edge| DemoOptions {
        edge,
        firmware: Some(firmware_dir()),
        ..DemoOptions::default()
    };
    let report = run(&out, &options(edge)).unwrap();
    // Safe to run twice into the same folder.
    let again = run(&out, &options(DemoEdge::InProcess)).unwrap();
    assert_eq!(again.alerts, report.alerts, "the in-process edge disagrees");

    let scene = std::fs::read_dir(out.join("scene"))
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let truth: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(scene.join("truth.json")).unwrap()).unwrap();
    let frames = truth["frames"].as_array().unwrap();
    assert_eq!(report.frames, frames.len());
    assert!(frames.len() >= 10, "the demo is a multi-frame scene");
    // Expected alerts, without the code under test (issue #18: this test used to run a copy
    // of the geofence's rule): the built-in zones are axis-aligned rectangles, so the truth
    // position's signed distance to each has a closed form; the scene's story gives the events.
    let zones = [
        ("far lot", [-10.0, 30.0, 20.0, 55.0]),
        ("gate", [-3.0, 8.0, 3.0, 16.0]),
    ];
    let perimeter = std::fs::read_to_string(out.join("perimeter.toml")).unwrap();
    assert!(perimeter.contains("[[-3.0, 8.0], [3.0, 8.0], [3.0, 16.0], [-3.0, 16.0]]"));
    assert!(perimeter.contains("[[-10.0, 30.0], [20.0, 30.0], [20.0, 55.0], [-10.0, 55.0]]"));
    assert!(perimeter.contains("hysteresis_m = 1.0"));
    // Positive inside (distance to the nearest side), negative outside (to the rectangle).
    let signed = |[x0, z0, x1, z1]: [f64; 4], x: f64, z: f64| {
        if (x0..=x1).contains(&x) && (z0..=z1).contains(&z) {
            (x - x0).min(x1 - x).min(z - z0).min(z1 - z)
        } else {
            let dx = (x0 - x).max(x - x1).max(0.0);
            let dz = (z0 - z).max(z - z1).max(0.0);
            -dx.hypot(dz)
        }
    };
    // Per (instance, zone): the truth's signed distance in every frame.
    let track = |instance: u64, rect: [f64; 4]| -> Vec<f64> {
        frames
            .iter()
            .map(|f| {
                let o = f["objects"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .find(|o| o["instance"] == instance)
                    .unwrap();
                let (d, az) = (
                    o["depth_m"].as_f64().unwrap(),
                    o["azimuth_deg"].as_f64().unwrap().to_radians(),
                );
                signed(rect, d * az.sin(), d * az.cos())
            })
            .collect()
    };
    let (car, person) = (1u64, 2u64);
    let car_far = track(car, zones[0].1);
    let person_gate = track(person, zones[1].1);
    // The story: the car is parked inside the far lot from the start; the person walks into
    // the gate, lingers just outside its border (less than the 1 m hysteresis) and leaves.
    assert!(car_far.iter().all(|&s| s > 0.0), "{car_far:?}");
    assert!(track(person, zones[0].1).iter().all(|&s| s < 0.0));
    assert!(track(car, zones[1].1).iter().all(|&s| s < 0.0));
    let enter = person_gate.iter().position(|&s| s >= 0.0).unwrap();
    let left = person_gate.iter().rposition(|&s| s >= 0.0).unwrap();
    let gone = (left..frames.len())
        .find(|&f| person_gate[f] < -1.0)
        .unwrap();
    let lingers = (enter..left).any(|f| person_gate[f] < 0.0 && person_gate[f] > -1.0);
    assert!(
        lingers,
        "the scene does not test hysteresis: {person_gate:?}"
    );
    // Alerts follow tracks, so an object's first alert waits for its track's confirmation:
    // the tracker's third detection (frame 2).
    let confirmed = 2u32;
    let want = [
        (car, "far lot", AlertKind::Enter, 0u32),
        (person, "gate", AlertKind::Enter, enter as u32),
        (person, "gate", AlertKind::Exit, gone as u32),
    ];
    // The truth object of an alert: the one with the alert's camera instance in its frame.
    let truth_of = |a: &metamoran_operator::geofence::Alert| {
        let instance = a.instance.expect("an enter or exit comes with a detection");
        let o = frames[a.frame as usize]["objects"]
            .as_array()
            .unwrap()
            .iter()
            .find(|o| o["instance"] == instance)
            .unwrap()
            .clone();
        let identity = o.get("object").unwrap_or(&o["instance"]).as_u64().unwrap();
        (identity, o)
    };
    let got: Vec<_> = report
        .alerts
        .iter()
        .map(|a| (truth_of(a).0, a.zone.as_str(), a.kind))
        .collect();
    let want_kinds: Vec<_> = want.iter().map(|w| (w.0, w.1, w.2)).collect();
    assert_eq!(got, want_kinds, "alerts {:?}", report.alerts);
    // One track per object.
    let tracks: Vec<u32> = report.alerts.iter().map(|a| a.track).collect();
    assert!(
        tracks[1] == tracks[2] && tracks[0] != tracks[1],
        "{tracks:?}"
    );
    for (a, e) in report.alerts.iter().zip(&want) {
        // Within a frame of the truth crossing (the radar depth and camera azimuth are close to,
        // not exactly, the truth) or of the confirmation, with the object's depth then.
        let due = e.3.max(confirmed);
        assert!(a.frame.abs_diff(due) <= 1, "{a:?} vs frame {due}");
        let t = truth_of(a).1;
        assert!(
            (a.depth_m - t["depth_m"].as_f64().unwrap()).abs() < 1.0,
            "{a:?}"
        );
    }

    // A segmenter that numbers its instances afresh every frame changes no track and no alert.
    let renumbered_out = dir.path().join("renumbered");
    let renumbered = run(
        &renumbered_out,
        &DemoOptions {
            renumber_instances: true,
            ..options(DemoEdge::InProcess)
        },
    )
    .unwrap();
    let masks_differ = (0..frames.len()).any(|f| {
        let read = |out: &std::path::Path| {
            let scene = std::fs::read_dir(out.join("scene"))
                .unwrap()
                .next()
                .unwrap()
                .unwrap();
            std::fs::read(metamoran_bundle::CameraPaths::new(&scene.path(), f as u32).instances)
                .unwrap()
        };
        read(&out) != read(&renumbered_out)
    });
    assert!(
        masks_differ,
        "the renumbered scene has the same instance ids"
    );
    let without_instance = |alerts: &[metamoran_operator::geofence::Alert]| {
        alerts
            .iter()
            .map(|a| (a.kind, a.zone.clone(), a.track, a.frame, a.class.clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        without_instance(&renumbered.alerts),
        without_instance(&report.alerts)
    );
    for (r, a) in renumbered.alerts.iter().zip(&report.alerts) {
        assert!((r.depth_m - a.depth_m).abs() < 1e-9, "{r:?} vs {a:?}");
    }
    let objects = frames[0]["objects"].as_array().unwrap();
    assert!(objects.len() >= 2);

    // The depth PNG: 16-bit grey, KITTI scale; each object's pixels near its true depth.
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(out.join("depth_0.png")).unwrap(),
    ));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0u8; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(
        (info.color_type, info.bit_depth),
        (png::ColorType::Grayscale, png::BitDepth::Sixteen)
    );
    let depths: Vec<f64> = buf[..info.buffer_size()]
        .chunks_exact(2)
        .map(|b| u16::from_be_bytes([b[0], b[1]]) as f64 / 256.0)
        .filter(|&d| d > 0.0)
        .collect();
    assert!(depths.len() > 50, "{} valid pixels", depths.len());
    let nearest = objects
        .iter()
        .map(|o| o["depth_m"].as_f64().unwrap())
        .fold(f64::MAX, f64::min);
    let farthest = objects
        .iter()
        .map(|o| o["depth_m"].as_f64().unwrap())
        .fold(0.0, f64::max);
    // Camera depth is range × cos(azimuth) (the camera sits at the radar, facing forward); a few
    // mask-edge pixels of the fusion keep background depths, so 95% rather than all.
    let within = depths
        .iter()
        .filter(|&&d| d > 0.9 * nearest - 1.0 && d < farthest + 5.0)
        .count();
    assert!(
        within as f64 >= 0.95 * depths.len() as f64,
        "{within} of {} pixels within the objects' depths",
        depths.len()
    );

    // The PLY holds every point of results.json.
    let results: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let n: usize = results["frames"][0]["objects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["points"].as_array().unwrap().len())
        .sum();
    let ply = std::fs::read_to_string(out.join("points_0.ply")).unwrap();
    assert!(ply.contains(&format!("element vertex {n}\n")));
    assert_eq!(
        ply.lines().skip_while(|l| *l != "end_header").count() - 1,
        n
    );
    assert!(
        std::fs::read_to_string(out.join("operator.txt"))
            .unwrap()
            .contains("far lot")
    );
    check_recording(&out, &results);
}

/// `recording.mcap`, read by Foxglove's `mcap` package from PyPI (the test venv): one objects
/// message and one point cloud per frame with results.json's depths and points, and every alert
/// of alerts.jsonl, each with a JSON Schema and JSON messages.
fn check_recording(out: &std::path::Path, results: &serde_json::Value) {
    let mcap = out.join("recording.mcap");
    let Some(stdout) = run_oracle("read_mcap.py", &[mcap.as_os_str()], "the mcap reader") else {
        return;
    };
    let messages: Vec<serde_json::Value> = serde_json::from_slice(&stdout).unwrap();
    let on = |topic: &str| -> Vec<&serde_json::Value> {
        messages.iter().filter(|m| m["topic"] == topic).collect()
    };
    assert!(
        messages
            .iter()
            .all(|m| m["schema_encoding"] == "jsonschema" && m["message_encoding"] == "json")
    );
    let frames = results["frames"].as_array().unwrap();
    let objects = on("/metamoran/objects");
    assert_eq!(objects.len(), frames.len());
    for (message, frame) in objects.iter().zip(frames) {
        let recorded = message["body"]["objects"].as_array().unwrap();
        let wanted = frame["objects"].as_array().unwrap();
        assert_eq!(recorded.len(), wanted.len());
        for (rec, want) in recorded.iter().zip(wanted) {
            assert_eq!(rec["instance"], want["instance"]);
            assert_eq!(rec["depth_m"], want["depth_m"]);
            assert_eq!(rec["points"], want["points"].as_array().unwrap().len());
        }
    }
    let frame = &frames[0];
    let clouds = on("/metamoran/points");
    assert_eq!(clouds.len(), frames.len());
    assert_eq!(clouds[0]["schema"], "foxglove.PointCloud");
    let got = clouds[0]["points"].as_array().unwrap();
    let want: Vec<(f64, f64, f64, f64)> = frame["objects"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|o| {
            let id = o["instance"].as_f64().unwrap();
            o["points"].as_array().unwrap().iter().map(move |p| {
                let c = |i: usize| p[i].as_f64().unwrap();
                (c(0), c(1), c(2), id)
            })
        })
        .collect();
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(&want) {
        let g: Vec<f64> = g
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let err = (g[0] - w.0).abs() + (g[1] - w.1).abs() + (g[2] - w.2).abs();
        assert!(
            err < 1e-4 * (1.0 + w.2.abs()) && g[3] == w.3,
            "{g:?} vs {w:?}"
        );
    }
    let alerts: Vec<serde_json::Value> = std::fs::read_to_string(out.join("alerts.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let recorded: Vec<&serde_json::Value> =
        on("/metamoran/alerts").iter().map(|m| &m["body"]).collect();
    assert!(!alerts.is_empty());
    assert_eq!(recorded, alerts.iter().collect::<Vec<_>>());
}
