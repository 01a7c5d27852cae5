//! The simulator against closed forms: a single point reflector lands in its predicted range
//! bin, azimuth and Doppler bin for both boards, and a written bundle reads back exactly.

use metamoran_dsp::capture::{IqOrder, deinterleave_bytes};
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::units::signed_bin;
use metamoran_dsp::window::WindowKind;
use metamoran_process::frame::{FrameOptions, FrameProcessor};
use metamoran_sim::radar::{RadarKind, config};
use metamoran_sim::signal::{Echo, synthesize};
use rand::SeedableRng;

fn frame(
    kind: RadarKind,
    loops: u16,
    echo: Echo,
) -> (metamoran_dsp::config::RadarConfig, Vec<CQ15>) {
    let c = config(kind, 59.4, loops);
    let bytes = synthesize(
        &c,
        &[echo],
        &[],
        None,
        &mut rand_pcg::Pcg64Mcg::seed_from_u64(5),
    );
    let mut s = vec![CQ15::default(); c.samples_per_frame()];
    deinterleave_bytes(&bytes, IqOrder::Iiqq, &mut s).unwrap();
    (c, s)
}

#[test]
fn point_reflector_lands_in_its_range_bin_and_azimuth() {
    for kind in [RadarKind::Xwr18xx, RadarKind::Cascade] {
        for (range, az_deg) in [(7.3, -20.0), (23.9, 4.0), (41.2, 35.0)] {
            let sin_az = f64::sin(f64::to_radians(az_deg));
            let echo = Echo {
                range,
                sin_az,
                sin_el: 0.0,
                velocity: 0.0,
                amplitude: 200.0,
                phase: 0.3,
            };
            let (c, s) = frame(kind, 2, echo);
            let options = FrameOptions {
                range_window: WindowKind::Hann,
                doppler_window: WindowKind::Rectangular,
                remove_static: false,
            };
            let mut p = FrameProcessor::new(&c, options).unwrap();
            let spectra = p.process(&s).unwrap();
            let nr = spectra.range_bins;
            let k = (0..nr)
                .max_by(|&a, &b| spectra.range_profile[a].total_cmp(&spectra.range_profile[b]))
                .unwrap();
            let predicted = c.range_to_bin(range as f32, nr);
            assert!(
                (k as f32 - predicted).abs() <= 0.5 + 1e-3,
                "{kind:?} {range} m: bin {k}, predicted {predicted}"
            );
            let az = p.azimuth_at(k, 0, false).unwrap().unwrap().to_degrees() as f64;
            let tol = if kind == RadarKind::Cascade { 0.5 } else { 3.0 };
            assert!(
                (az - az_deg).abs() < tol,
                "{kind:?} {range} m: azimuth {az:.2}° for {az_deg}°"
            );
            let _ = 0.0;
        }
    }
}

#[test]
fn moving_reflector_lands_in_its_doppler_bin() {
    for kind in [RadarKind::Xwr18xx, RadarKind::Cascade] {
        let c = config(kind, 59.4, 16);
        let nd = c.doppler_fft_len();
        for bin in [-5.0f32, 3.0] {
            let v = c.doppler_to_velocity(bin, nd) as f64;
            let (c, s) = frame(
                kind,
                16,
                Echo {
                    range: 30.0,
                    sin_az: 0.1,
                    sin_el: 0.0,
                    velocity: v,
                    amplitude: 100.0,
                    phase: 0.0,
                },
            );
            let options = FrameOptions {
                range_window: WindowKind::Hann,
                doppler_window: WindowKind::Rectangular,
                remove_static: true,
            };
            let spectra = FrameProcessor::new(&c, options)
                .unwrap()
                .process(&s)
                .unwrap();
            let map = &spectra.range_doppler;
            let arg = (0..map.len())
                .max_by(|&a, &b| map[a].total_cmp(&map[b]))
                .unwrap();
            assert_eq!(signed_bin(arg % nd, nd) as f32, bin, "{kind:?}");
        }
    }
}

#[test]
fn written_bundle_reads_back_exactly() {
    use metamoran_bundle::{Bundle, OpenOptions};
    use metamoran_sim::{layout::Preset, simulate_one, simulate_scene};
    let tmp = tempfile::tempdir().unwrap();
    for (preset, kind) in [
        (Preset::ParkingLot, RadarKind::Cascade),
        (Preset::Moving, RadarKind::Xwr18xx),
        (Preset::Perimeter, RadarKind::Xwr18xx),
        (Preset::Drive, RadarKind::Xwr18xx),
        // The MMWCAS board's four device files and index files.
        (Preset::LongRange, RadarKind::Mmwcas),
    ] {
        let dir = tmp.path().join(format!("{preset:?}-{kind:?}"));
        simulate_one(preset, kind, 42, 3, &dir).unwrap();
        let scene = simulate_scene(preset, kind, 42, 3); // deterministic: the same scene again
        let mut b = Bundle::open(&dir, OpenOptions::default()).unwrap();
        assert_eq!(b.scene.layout, scene.layout);
        assert_eq!(
            dir.join("master_0000_idx.bin").exists(),
            kind == RadarKind::Mmwcas
        );
        assert_eq!(b.scene.radar, scene.radar);
        assert_eq!(b.scene.tx_elevation, scene.tx_elevation);
        assert_eq!(b.frames() as usize, scene.shots.len());
        let n = scene.radar.samples_per_frame();
        let truth = b.truth.clone().unwrap();
        for f in 0..b.frames() {
            let mut got = Vec::new();
            b.read_radar_frame(f, &mut got).unwrap();
            let mut want = vec![CQ15::default(); n];
            let bytes = &scene.adc[f as usize * n * 4..(f as usize + 1) * n * 4];
            deinterleave_bytes(bytes, IqOrder::Iiqq, &mut want).unwrap();
            assert_eq!(got, want, "{preset:?} frame {f}");
            let cam = b.camera_frame(f).unwrap();
            let shot = &scene.shots[f as usize];
            assert_eq!(cam.mask, shot.products.mask);
            assert_eq!(cam.depth, shot.products.depth_png);
            assert_eq!(
                truth.frames[f as usize].objects.len(),
                scene.truth.frames[f as usize].objects.len()
            );
        }
    }
}

#[test]
fn the_perimeter_walker_moves_at_walking_speed_and_turns_back() {
    use metamoran_sim::{layout::Preset, simulate_scene};
    let scene = simulate_scene(Preset::Perimeter, RadarKind::Xwr18xx, 5, 0);
    assert_eq!(scene.truth.frames.len(), 22);
    let period = scene.radar.frame_period_s;
    // The person's footprint centre from the truth: azimuth of the centre, depth of the
    // closest point (0.25 m in front of the centre of a 0.25 m cylinder).
    let centres: Vec<[f64; 2]> = scene
        .truth
        .frames
        .iter()
        .map(|f| {
            let p = f.objects.iter().find(|o| o.class == "person").unwrap();
            let (r, az) = (p.depth_m + 0.25, p.azimuth_deg.to_radians());
            [r * az.sin(), r * az.cos()]
        })
        .collect();
    let steps: Vec<f64> = centres
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .collect();
    // 1.4 m/s for 0.5 s, less only across a turn or once the walk is over.
    assert!(steps.iter().all(|&s| s <= 1.4 * period + 1e-6), "{steps:?}");
    assert!(steps.iter().filter(|&&s| (s - 0.7).abs() < 1e-6).count() >= 15);
    // It walks right into the gate (x > −3) and back out left of x = −4.
    let x: Vec<f64> = centres.iter().map(|c| c[0]).collect();
    let (lo, hi) = x
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
    assert!(hi > -2.0 && lo < -5.0 && x[21] < -4.0, "{x:?}");
    // The car stays where it is.
    let car: Vec<f64> = scene
        .truth
        .frames
        .iter()
        .map(|f| f.objects.iter().find(|o| o.class == "car").unwrap().depth_m)
        .collect();
    assert!(car.iter().all(|&d| d == car[0] && d > 30.0));
}

#[test]
fn rendered_mask_spans_the_objects_geometry() {
    use metamoran_bundle::geometry::{CameraModel, azimuth};
    use metamoran_sim::{layout::Preset, shape::Shape, simulate_scene};
    let mut checked = 0;
    for index in 0..8 {
        let scene = simulate_scene(Preset::ParkingLot, RadarKind::Cascade, 9, index);
        let model = CameraModel::new(&scene.camera);
        for o in scene
            .objects
            .iter()
            .filter(|o| matches!(o.class, "car" | "person" | "sign"))
        {
            // Azimuth extremes of the footprint (camera and radar share x and z here).
            let footprint: Vec<[f64; 2]> = match o.shape {
                Shape::Cylinder { centre, radius, .. } => (0..360)
                    .map(|d| {
                        let a = f64::to_radians(d as f64);
                        [centre[0] + radius * a.sin(), centre[1] + radius * a.cos()]
                    })
                    .collect(),
                _ => o
                    .shape
                    .segments()
                    .iter()
                    .flat_map(|(a, b)| {
                        (0..=20).map(move |k| {
                            let s = k as f64 / 20.0;
                            [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]
                        })
                    })
                    .collect(),
            };
            let geo: Vec<f64> = footprint.iter().map(|p| p[0].atan2(p[1])).collect();
            let (glo, ghi) = (
                geo.iter().copied().fold(9.0, f64::min),
                geo.iter().copied().fold(-9.0, f64::max),
            );
            let px: Vec<f64> = (0..scene.shots[0].render.ids.len())
                .filter(|&i| scene.shots[0].render.ids[i] == o.id)
                .map(|i| {
                    azimuth(&model.back_project(
                        (i % 640) as u32,
                        (i / 640) as u32,
                        scene.shots[0].render.depth[i],
                    ))
                })
                .collect();
            if px.len() < 20 {
                continue; // partly hidden or tiny: its span is not the footprint's
            }
            let (lo, hi) = (
                px.iter().copied().fold(9.0, f64::min),
                px.iter().copied().fold(-9.0, f64::max),
            );
            let pixel = 1.5 / 500.0; // angular size of 1.5 pixels
            assert!(
                (lo - glo).abs() < pixel && (hi - ghi).abs() < pixel,
                "{} #{}: mask {lo:.4}..{hi:.4} vs geometry {glo:.4}..{ghi:.4}",
                o.class,
                o.id
            );
            checked += 1;
        }
    }
    assert!(checked >= 5, "only {checked} objects checked");
}

/// `MovingScene::direction` against the simulator's own directions: two movers in one Doppler
/// bin at different ranges and azimuths, each moving faster than the board's unambiguous
/// velocity (another alias), are each found where they are, within an eighth of a beamwidth
/// (the contest's margin), whichever of the bin's aliased velocities is asked.
#[test]
fn a_movers_direction_is_measured_whatever_its_alias() {
    use metamoran_process::metamoran::MovingScene;
    for kind in [RadarKind::Xwr18xx, RadarKind::Cascade] {
        let c = config(kind, 59.4, 16);
        let nd = c.doppler_fft_len();
        let bin_mps = f64::from(c.doppler_to_velocity(1.0, nd));
        // Bin 3, one unambiguous interval down (and, on the cascade, two up).
        let alias = if kind == RadarKind::Cascade {
            2.0
        } else {
            -1.0
        };
        let v = (3.0 + alias * nd as f64) * bin_mps;
        let movers = [(21.0, -0.3), (37.5, 0.2)];
        let echoes: Vec<Echo> = movers
            .iter()
            .map(|&(range, sin_az)| Echo {
                range,
                sin_az,
                sin_el: 0.0,
                velocity: v,
                amplitude: 100.0,
                phase: 0.4,
            })
            .collect();
        let bytes = synthesize(
            &c,
            &echoes,
            &[],
            None,
            &mut rand_pcg::Pcg64Mcg::seed_from_u64(6),
        );
        let mut s = vec![CQ15::default(); c.samples_per_frame()];
        deinterleave_bytes(&bytes, IqOrder::Iiqq, &mut s).unwrap();
        let scene = MovingScene::new(&c, &s).unwrap().expect("16 loops");
        // One bin's aliases repeat every λ / (2 · loop period).
        let fold = scene.fold_mps();
        let closed_form = c.wavelength_m() / (2.0 * c.loop_period_s());
        assert!(
            (fold - closed_form).abs() < 1e-6 * closed_form,
            "{kind:?}: fold {fold} m/s, λ / 2T {closed_form} m/s"
        );
        // The beam, sin(az): 2 / the aperture in half-wavelengths.
        let positions: Vec<i32> = (0..c.channels())
            .filter_map(|ch| c.channel_position(ch))
            .collect();
        let span = positions.iter().max().unwrap() - positions.iter().min().unwrap() + 1;
        let tolerance = 0.125 * 2.0 / f64::from(span);
        for &(range, sin_az) in &movers {
            for asked in [v, v - fold, v + 3.0 * fold] {
                let s = scene.direction(asked, range).expect("a depth in the frame");
                assert!(
                    (f64::from(s) - sin_az).abs() <= tolerance,
                    "{kind:?} at {range} m asked at {asked:.1} m/s: sin(az) {s}, truth {sin_az}"
                );
            }
        }
        assert_eq!(
            scene.direction(v, 1.0e4),
            None,
            "{kind:?}: beyond the frame"
        );
    }
}
