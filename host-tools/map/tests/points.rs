//! Radar point clouds (`metamoran_dsp::points` through `FrameProcessor::points`) against closed forms:
//! point reflectors synthesized with the simulator's signal model (bundle.md's, plus the
//! README's elevation term) at known range, azimuth, elevation and radial velocity, on the
//! drive preset's boards: the xWR1843-like one (3 TX, one of them half a wavelength up, TDM) and
//! the 4D imaging one (12 TX × 16 RX, nine elevation rows, radial velocities that fold).

use metamoran_dsp::capture::{IqOrder, deinterleave_bytes};
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::points::{ArrayGeometry, CloudOptions, Peaks, RadarPoint};
use metamoran_dsp::window::WindowKind;
use metamoran_process::frame::{FrameOptions, FrameProcessor};
use metamoran_sim::radar::{RadarKind, drive_config};
use metamoran_sim::signal::{Echo, synthesize};
use rand::{Rng, SeedableRng};

/// A target: (range m, azimuth °, elevation °, radial velocity m/s).
type Target = (f64, f64, f64, f64);

#[test]
fn point_reflectors_come_back_where_they_are() {
    // Fast movers on both sides, one high, one low, one receding; moving targets test the
    // TDM-MIMO compensation.
    let targets = [
        (12.3, -35.0, 0.0, -7.3),
        (20.7, 20.0, 8.0, -4.1),
        (31.1, 5.0, -6.0, 2.6),
        (8.4, 48.0, 3.0, -1.2),
    ];
    for peaks in [Peaks::RangeDoppler, Peaks::Direction] {
        check(RadarKind::Xwr18xx, &targets, None, (0.5, 1.5), peaks);
    }
}

#[test]
fn the_imaging_board_unfolds_a_street_and_resolves_its_elevations() {
    // A static street seen at 8.5 m/s forward: radial velocities to −8.5 m/s, folded by the
    // board's ±5.1 m/s; the prior (the last frame's velocity) unfolds them. Elevations to
    // ±15° over the nine rows.
    let v = 8.5;
    let targets: Vec<Target> = [
        (12.3, -35.0, 0.0),
        (20.7, 20.0, 8.0),
        (31.1, 5.0, -6.0),
        (8.4, 48.0, 3.0),
        (17.2, -12.0, 15.0),
        (25.6, -3.0, -11.0),
    ]
    .iter()
    .map(|&(r, az, el): &(f64, f64, f64)| {
        let (a, e) = (az.to_radians(), el.to_radians());
        (r, az, el, -v * a.cos() * e.cos())
    })
    .collect();
    for peaks in [Peaks::RangeDoppler, Peaks::Direction] {
        check(
            RadarKind::Imaging,
            &targets,
            Some([0.0, v as f32]),
            (0.5, 1.0),
            peaks,
        );
    }
}

#[test]
fn a_weak_reflector_beside_a_strong_one_in_range_is_its_own_peak_by_direction() {
    // Two static reflectors on the imaging board, each at a range bin's centre: a strong one at
    // −20° and, one bin farther, one 8 dB weaker at +25°. The strong one's range main lobe
    // (−6 dB a bin away) makes the weak one's cell no maximum of the range–Doppler map, so the
    // map's peaks lose it; by direction its own beam peaks there, and each is one point.
    let (config, _) = drive_config(RadarKind::Imaging);
    let bin = f64::from(config.range_bin_size(config.range_fft_len()));
    let strong = (86.0 * bin, -20.0, 0.0, 0.0);
    let weak = (87.0 * bin, 25.0, 0.0, 0.0);
    let targets = [(strong, 3000.0), (weak, 3000.0 * 10f64.powf(-8.0 / 20.0))];
    let (_, by_map) = cloud(RadarKind::Imaging, &targets, None, Peaks::RangeDoppler);
    assert_eq!(
        near(&by_map, strong, (2.0 * bin, 3.0)).len(),
        1,
        "{by_map:?}"
    );
    assert!(
        near(&by_map, weak, (2.0 * bin, 3.0)).is_empty(),
        "{by_map:?}"
    );
    let (_, by_direction) = cloud(RadarKind::Imaging, &targets, None, Peaks::Direction);
    for (r, az, _, _) in [strong, weak] {
        let found = near(&by_direction, (r, az, 0.0, 0.0), (2.0 * bin, 3.0));
        assert_eq!(found.len(), 1, "{r} m, {az}°: {by_direction:?}");
        let p = found[0];
        assert!((f64::from(p.range_m) - r).abs() < bin / 4.0, "{p:?}");
        assert!(
            (f64::from(p.azimuth).to_degrees() - az).abs() < 0.5,
            "{p:?}"
        );
    }
}

#[test]
fn the_direction_rule_screens_a_reflector_its_neighbours_crowd() {
    // Static reflectors on the imaging board: twelve strong ones at −20°, three to eight range
    // bins on either side of a weak one at +25°, 14 dB weaker. The strong ones fill the
    // zero-Doppler row of the weak one's CFAR training window, so its cell is no 9.5 dB over
    // their mean (the detector, ×3) but is over it (`DIRECTION_SCREEN`, ×1); its own
    // beam then peaks there, and it is one point. (The strong ones and their Doppler main
    // lobes put the training mean about 19 dB under one of them: 9.5 dB over it is −9.5 dB.)
    let (config, _) = drive_config(RadarKind::Imaging);
    let bin = f64::from(config.range_bin_size(config.range_fft_len()));
    let weak = (86.0 * bin, 25.0, 0.0, 0.0);
    let mut targets = vec![(weak, 3000.0 * 10f64.powf(-14.0 / 20.0))];
    for off in (3..=8).flat_map(|k| [-k, k]) {
        targets.push((((86 + off) as f64 * bin, -20.0, 0.0, 0.0), 3000.0));
    }
    let at_weak = |points: &[RadarPoint]| near(points, weak, (2.0 * bin, 3.0));
    let direction = screened();
    let (_, screened) = cloud_with(RadarKind::Imaging, &targets, &direction);
    let found = at_weak(&screened);
    assert_eq!(found.len(), 1, "{screened:?}");
    assert!(
        (f64::from(found[0].range_m) - weak.0).abs() < bin / 4.0,
        "{found:?}"
    );
    // The same rule with the map's 9.5 dB CFAR alone loses it.
    let unscreened_options = CloudOptions {
        screen: None,
        ..direction
    };
    let (_, unscreened) = cloud_with(RadarKind::Imaging, &targets, &unscreened_options);
    assert!(at_weak(&unscreened).is_empty(), "{unscreened:?}");
}

#[test]
fn the_direction_rule_keeps_what_the_map_detector_finds_under_a_strong_return() {
    // A reflector 50 dB under a strong one, 40 range bins away: beyond the screen's 40 dB but
    // well over its own neighbourhood, so the 9.5 dB detector finds it, and the screen must
    // not lose it (with the 40 dB test alone, two frames of a street kept 20 and 22 points,
    // the frames around them 47–95, and odometry failed on them).
    let (config, _) = drive_config(RadarKind::Imaging);
    let bin = f64::from(config.range_bin_size(config.range_fft_len()));
    let strong = (40.0 * bin, -10.0, 0.0, 0.0);
    let faint = (80.0 * bin, 15.0, 0.0, 0.0);
    let targets = [(strong, 3000.0), (faint, 3000.0 * 10f64.powf(-50.0 / 20.0))];
    let (_, points) = cloud_with(RadarKind::Imaging, &targets, &screened());
    for t in [strong, faint] {
        let found = near(&points, t, (bin / 4.0, 1.0));
        assert_eq!(found.len(), 1, "{t:?}: {points:?}");
    }
}

#[test]
fn the_screen_keeps_over_a_capture_s_noise() {
    // Four static reflectors on the imaging board in receiver noise of σ = NOISE LSB per I/Q
    // component, so the map's median (the noise) lies within the screen's 40 dB of its
    // strongest cell (the simulator's own noise lies 86 dB under on a street). The screen
    // asks `NOISE_MARGIN_DB` over the median: it keeps the reflectors and adds few noise
    // cells to what the detector alone finds; without that floor (the screen before it) half
    // the noise cells within 40 dB of the peak pass its ×1 test, and each gives points.
    const NOISE: f64 = 1500.0;
    let (config, _) = drive_config(RadarKind::Imaging);
    let bin = f64::from(config.range_bin_size(config.range_fft_len()));
    let targets = [
        ((40.0 * bin, -20.0, 0.0, 0.0), 3000.0),
        ((75.0 * bin, 10.0, 5.0, 0.0), 2000.0),
        ((110.0 * bin, 30.0, -5.0, 0.0), 2000.0),
        ((150.0 * bin, -5.0, 0.0, 0.0), 1500.0),
    ];
    let stray = |points: &[RadarPoint]| {
        points
            .iter()
            .filter(|p| {
                targets
                    .iter()
                    .all(|&(t, _)| near(&[**p], t, (3.0 * bin, 10.0)).is_empty())
            })
            .count()
    };
    let with_screen = |noise_margin_db| CloudOptions {
        screen: Some(metamoran_dsp::points::Screen {
            noise_margin_db,
            ..metamoran_map::cloud::DIRECTION_SCREEN
        }),
        ..screened()
    };
    let floored = with_screen(metamoran_map::cloud::NOISE_MARGIN_DB);
    let (_, screen) = cloud_in_noise(RadarKind::Imaging, &targets, &floored, NOISE);
    for &(t, _) in &targets {
        assert!(
            !near(&screen, t, (bin, 2.0)).is_empty(),
            "{t:?}: {screen:?}"
        );
    }
    let detector = CloudOptions {
        screen: None,
        ..floored
    };
    let (_, alone) = cloud_in_noise(RadarKind::Imaging, &targets, &detector, NOISE);
    let unfloored = with_screen(f32::NEG_INFINITY);
    let (_, old) = cloud_in_noise(RadarKind::Imaging, &targets, &unfloored, NOISE);
    let (screen, alone, old) = (stray(&screen), stray(&alone), stray(&old));
    println!("stray points: screen {screen}, detector alone {alone}, without the floor {old}");
    assert!(
        screen <= alone + alone / 2 + 2,
        "screen {screen}, detector {alone}"
    );
    assert!(
        old > 5 * screen.max(4),
        "without the floor {old}, with {screen}"
    );
}

/// The points within `range_m` m and `azimuth_deg` degrees of target `t`.
fn near(points: &[RadarPoint], t: Target, (range_m, azimuth_deg): (f64, f64)) -> Vec<RadarPoint> {
    points
        .iter()
        .filter(|p| {
            (f64::from(p.range_m) - t.0).abs() < range_m
                && (f64::from(p.azimuth).to_degrees() - t.1).abs() < azimuth_deg
        })
        .copied()
        .collect()
}

/// The mapping detector by direction with `map --screen`'s screen.
fn screened() -> CloudOptions {
    CloudOptions {
        screen: Some(metamoran_map::cloud::DIRECTION_SCREEN),
        ..metamoran_map::cloud::options(Peaks::Direction)
    }
}

/// Synthesizes `targets` on `kind`'s drive board, forms the cloud (unfolded towards `prior`)
/// and checks each target's strongest point within two range bins against it, to `tolerance`
/// (azimuth, elevation) degrees.
fn check(
    kind: RadarKind,
    targets: &[Target],
    prior: Option<[f32; 2]>,
    tolerance: (f64, f64),
    peaks: Peaks,
) {
    let echoes: Vec<(Target, f64)> = targets.iter().map(|&t| (t, 3000.0)).collect();
    let (config, points) = cloud(kind, &echoes, prior, peaks);
    // With points in both halves of the range bins, both threads had work.
    let half = config.bin_to_range(config.range_fft_len() as f32 / 2.0, config.range_fft_len());
    assert!(
        points.iter().any(|p| p.range_m < half) && points.iter().any(|p| p.range_m > half),
        "all points on one side of {half} m"
    );
    let bin = config.range_bin_size(config.range_fft_len()) as f64;
    for &(r, az, el, v) in targets {
        // The strongest point within two range bins.
        let p = points
            .iter()
            .filter(|p| (f64::from(p.range_m) - r).abs() < 2.0 * bin)
            .max_by(|a, b| a.power_db.total_cmp(&b.power_db))
            .unwrap();
        let deg = |x: f32| f64::from(x).to_degrees();
        assert!(
            (f64::from(p.range_m) - r).abs() < bin / 4.0,
            "range {r}: {p:?}"
        );
        assert!(
            (deg(p.azimuth) - az).abs() < tolerance.0,
            "azimuth {az}: {p:?}"
        );
        assert!(
            (deg(p.elevation) - el).abs() < tolerance.1,
            "elevation {el}: {p:?}"
        );
        assert!(
            (f64::from(p.radial_velocity_mps) - v).abs() < 0.05,
            "velocity {v}: {p:?}"
        );
        // Nothing else there is within 80 dB (the cloud's dynamic range): no sidelobe ghosts.
        assert!(
            points
                .iter()
                .filter(|q| (f64::from(q.range_m) - r).abs() < 2.0 * bin && *q != p)
                .all(|q| q.power_db < p.power_db - 30.0),
            "{points:?}"
        );
        // The position: range in the x–z plane (bundle.md), height from the elevation.
        let (a, e) = (f64::from(p.azimuth), f64::from(p.elevation));
        let want = [r * a.sin(), -r * e.tan(), r * a.cos()];
        for (g, w) in p.position.iter().zip(want) {
            assert!((f64::from(*g) - w).abs() < bin / 4.0 + 0.01, "{p:?}");
        }
    }
}

/// Synthesizes `targets` (each with its amplitude, LSB) on `kind`'s drive board and forms the
/// cloud unfolded towards `prior` with the mapping's detector for `peaks`, checking that the
/// processor's two threads give the one-thread `dsp` cloud bit for bit.
fn cloud(
    kind: RadarKind,
    targets: &[(Target, f64)],
    prior: Option<[f32; 2]>,
    peaks: Peaks,
) -> (RadarConfig, Vec<RadarPoint>) {
    let options = CloudOptions {
        velocity_prior: prior,
        ..metamoran_map::cloud::options(peaks)
    };
    cloud_with(kind, targets, &options)
}

/// [`cloud`] with the detector `options`.
fn cloud_with(
    kind: RadarKind,
    targets: &[(Target, f64)],
    options: &CloudOptions,
) -> (RadarConfig, Vec<RadarPoint>) {
    cloud_in_noise(kind, targets, options, 0.0)
}

/// [`cloud_with`] with extra receiver noise: Gaussian of `sigma_lsb` per I and Q component,
/// added to the synthesized samples (seeded, so the same every run).
fn cloud_in_noise(
    kind: RadarKind,
    targets: &[(Target, f64)],
    options: &CloudOptions,
    sigma_lsb: f64,
) -> (RadarConfig, Vec<RadarPoint>) {
    let peaks = options.peaks;
    let (mut config, tx_elevation) = drive_config(kind);
    config.frames = 1;
    let elevation: Vec<i16> = (0..config.channels())
        .map(|ch| tx_elevation[config.tx_order[ch / config.rx_count()] as usize])
        .collect();
    let echoes: Vec<Echo> = targets
        .iter()
        .map(|&((r, az, el, v), amplitude)| Echo {
            range: r,
            sin_az: f64::sin(az * std::f64::consts::PI / 180.0),
            sin_el: f64::sin(el * std::f64::consts::PI / 180.0),
            velocity: v,
            amplitude,
            phase: 0.3,
        })
        .collect();
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
    let mut bytes = synthesize(&config, &echoes, &elevation, None, &mut rng);
    if sigma_lsb > 0.0 {
        for sample in bytes.chunks_exact_mut(2) {
            let noise: f64 = rng.sample(rand_distr::StandardNormal);
            let v = f64::from(i16::from_le_bytes([sample[0], sample[1]])) + sigma_lsb * noise;
            let v = v.round().clamp(f64::from(i16::MIN), f64::from(i16::MAX)) as i16;
            sample.copy_from_slice(&v.to_le_bytes());
        }
    }
    let mut samples = vec![CQ15::default(); config.samples_per_frame()];
    deinterleave_bytes(&bytes, IqOrder::Iiqq, &mut samples).unwrap();
    let mut proc = FrameProcessor::new(
        &config,
        FrameOptions {
            range_window: WindowKind::Hann,
            doppler_window: WindowKind::Hann,
            remove_static: false,
        },
    )
    .unwrap()
    .keeping_doppler_spectra();
    let spectra = proc.process(&samples).unwrap();
    let geometry = ArrayGeometry::new(&config, &tx_elevation, &[]).unwrap();
    let points = proc.points(&spectra, &geometry, options).unwrap();
    // The processor splits the map and the cloud between two threads, and the cloud reads the
    // Doppler spectra the map's pass kept: both are the one-thread `dsp` results, which form
    // each detected bin's spectra again from the cube, bit for bit.
    let nd = spectra.doppler_len;
    let mut scratch = vec![CQ15::default(); nd];
    let mut map = vec![0f32; spectra.range_bins * nd];
    let doppler = proc.doppler_options(false);
    metamoran_dsp::doppler::range_doppler_map(proc.cube(), &doppler, &mut scratch, &mut map)
        .unwrap();
    assert!(
        map.iter()
            .zip(&spectra.range_doppler)
            .all(|(a, b)| a.to_bits() == b.to_bits()),
        "range-Doppler map differs"
    );
    let mut whole = Vec::new();
    let held = peaks.bins_held();
    let mut values =
        vec![metamoran_dsp::fft::Complex32::new(0.0, 0.0); geometry.channels() * nd * held];
    let mut source = Counted {
        inner: metamoran_dsp::points::CubeSpectra {
            cube: proc.cube(),
            doppler,
            scratch: &mut scratch,
        },
        loads: vec![0; spectra.range_bins],
    };
    metamoran_dsp::points::frame_points(
        &mut source,
        &config,
        &geometry,
        &map,
        options,
        0..usize::MAX,
        &mut values,
        |p| whole.push(p),
    )
    .unwrap();
    assert_eq!(points, whole);
    // Detections come bin by bin, so no bin's spectra are formed twice in a frame (by
    // direction a detected bin needs both neighbours: loading three per detected bin would
    // form most bins three times).
    assert!(source.loads.iter().any(|&n| n > 0), "no bin loaded");
    assert!(
        source.loads.iter().all(|&n| n <= 1),
        "{peaks:?}: a bin loaded again: {:?}",
        source
            .loads
            .iter()
            .enumerate()
            .filter(|e| *e.1 > 1)
            .collect::<Vec<_>>()
    );
    (config, whole)
}

/// A source that counts how often each range bin is loaded.
struct Counted<S> {
    inner: S,
    loads: Vec<u32>,
}

impl<S: metamoran_dsp::points::DopplerSpectra> metamoran_dsp::points::DopplerSpectra
    for Counted<S>
{
    fn channels(&self) -> usize {
        self.inner.channels()
    }

    fn load(
        &mut self,
        bin: usize,
        out: &mut [metamoran_dsp::fft::Complex32],
    ) -> Result<(), metamoran_dsp::points::PointsError> {
        self.loads[bin] += 1;
        self.inner.load(bin, out)
    }
}
