//! The firmware under QEMU (mps2-an500, Cortex-M7): it must boot, run the self-test, and
//! compute exactly the bits the host computes with the same `dsp` code.

use metamoran_e2e::{oracles_required, qemu_available};
use metamoran_edge::qemu;
use std::time::Duration;

#[test]
fn firmware_self_test_matches_host_bit_for_bit() {
    if !qemu_available() {
        assert!(
            !oracles_required(),
            "qemu-system-arm is required (apt-get install -y qemu-system-arm)"
        );
        eprintln!("SKIPPED: qemu-system-arm not installed");
        return;
    }
    let elf = qemu::build(&metamoran_e2e::firmware_dir(), "firmware", None).unwrap();
    let out = qemu::run(&elf, false, Duration::from_secs(60)).unwrap();
    let module: Vec<&str> = out
        .lines()
        .filter(|l| l.starts_with("SELFTEST ") && !l.ends_with("done"))
        .collect();
    let mut host = Vec::new();
    firmware::selftest::run(|o| {
        host.push(format!(
            "SELFTEST {} exp={} hash={:08x}",
            o.name, o.exponent, o.hash
        ));
    });
    assert!(
        out.contains("SELFTEST done"),
        "self-test did not finish:\n{out}"
    );
    assert_eq!(module, host, "the module and the host disagree");
}

/// The module pipeline on the cascade-86 budget scene (4 objects, 3 clutter reflectors), on a
/// perfect board and on an imperfect one calibrated in the range stage: the M7 must report
/// exactly what the host computes, both must find every object within 5 cm (the imperfect board
/// uncalibrated does not), and each frame must stay within the 24 M-instruction budget.
#[test]
fn pipeline_on_the_m7_matches_host_and_truth() {
    use firmware::bench_scene::{self, N};
    use metamoran_dsp::fixed::CQ15;
    use metamoran_dsp::pipeline::Edge;
    if !qemu_available() {
        assert!(!oracles_required(), "qemu-system-arm is required");
        eprintln!("SKIPPED: qemu-system-arm not installed");
        return;
    }
    let elf = qemu::build(&metamoran_e2e::firmware_dir(), "pipeline-icount", None).unwrap();
    let out = qemu::run(&elf, true, Duration::from_secs(120)).unwrap();
    let module: Vec<&str> = out.lines().filter(|l| l.starts_with("PIPELINE ")).collect();
    // The same pipeline on the host: the perfect board, then the imperfect board calibrated as
    // the module sums it.
    let config = bench_scene::config();
    let edge = Edge::new(&config).unwrap();
    let calibration = bench_scene::calibration().unwrap();
    let mut table = vec![0u32; edge.calibration_words()];
    let coefficients = edge.calibrate(&calibration, &mut table).unwrap();
    let mut host = Vec::new();
    for (prefix, calibrated) in [("", false), ("calibrated_", true)] {
        let mut arena = vec![0u32; bench_scene::ARENA_WORDS];
        let mut frame = if calibrated {
            edge.start_calibrated(&mut arena, &coefficients).unwrap()
        } else {
            edge.start(&mut arena).unwrap()
        };
        let mut chirp = [CQ15::default(); N];
        for c in 0..config.chirps_per_frame() {
            for rx in 0..config.rx_count() {
                if calibrated {
                    bench_scene::chirp_on_board(&config, c, rx, &mut chirp);
                    edge.push_calibrated(&mut frame, c, rx, &chirp, &coefficients)
                } else {
                    bench_scene::chirp(&config, c, rx, &mut chirp);
                    edge.push(&mut frame, c, rx, &chirp)
                }
                .unwrap();
            }
        }
        let (mut row, mut az, mut pw) = ([CQ15::default(); N], [CQ15::default(); 256], [0u64; 768]);
        let mut scene = edge.finish(frame, &mut row, &mut az, &mut pw).unwrap();
        let mut scores = [0.0f32; N];
        for (i, hint) in bench_scene::hints().iter().enumerate() {
            let r = edge.object(&mut scene, hint, &mut scores).unwrap();
            assert!(
                (r.search.depth_m - bench_scene::truth_m(i)).abs() < 0.05 && r.detected(),
                "{prefix}object {i}: {r:?}"
            );
            host.push(format!(
                "PIPELINE {prefix}object={} depth_mm={} cancelled={} detected={} macs={}",
                i,
                (r.search.depth_m * 1000.0) as i32,
                r.cancelled,
                r.detected(),
                r.search.macs
            ));
        }
    }
    // The board as recorded, not calibrated, misses: the calibration is what finds them.
    {
        let mut arena = vec![0u32; bench_scene::ARENA_WORDS];
        let mut frame = edge.start(&mut arena).unwrap();
        let mut chirp = [CQ15::default(); N];
        for c in 0..config.chirps_per_frame() {
            for rx in 0..config.rx_count() {
                bench_scene::chirp_on_board(&config, c, rx, &mut chirp);
                edge.push(&mut frame, c, rx, &chirp).unwrap();
            }
        }
        let (mut row, mut az, mut pw) = ([CQ15::default(); N], [CQ15::default(); 256], [0u64; 768]);
        let mut scene = edge.finish(frame, &mut row, &mut az, &mut pw).unwrap();
        let mut scores = [0.0f32; N];
        let found = bench_scene::hints()
            .iter()
            .enumerate()
            .filter(|(i, hint)| {
                let r = edge.object(&mut scene, hint, &mut scores).unwrap();
                (r.search.depth_m - bench_scene::truth_m(*i)).abs() < 0.05 && r.detected()
            })
            .count();
        assert!(
            found < 4,
            "the imperfect board needs no calibration: {found} of 4 found"
        );
    }
    assert_eq!(module, host, "the module and the host disagree:\n{out}");
    // The firmware issue's budget, counted (deterministic under -icount, not timed).
    let frame: u64 = out
        .lines()
        .find_map(|l| l.strip_prefix("ICOUNT stage=frame instructions="))
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or_else(|| panic!("no frame count in:\n{out}"));
    let calibrated: u64 = out
        .lines()
        .find_map(|l| l.strip_prefix("ICOUNT stage=calibrated_frame instructions="))
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or_else(|| panic!("no calibrated frame count in:\n{out}"));
    for (what, n) in [("frame", frame), ("calibrated frame", calibrated)] {
        assert!(
            n <= metamoran::bench::budget::INSTRUCTION_BUDGET,
            "{n} instructions per {what}, over the budget (scripts/profile-m7 shows where)"
        );
    }
}
