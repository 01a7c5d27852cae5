//! The range → Doppler → azimuth chain on signals synthesized from the bundle format's signal
//! model (`shared/spec/bundle.md`), checked against the closed-form bins of each reflector.

use heapless::Vec as HVec;
use metamoran_dsp::array::VirtualArray;
use metamoran_dsp::azimuth::{azimuth_spectrum, beamform};
use metamoran_dsp::config::{RadarConfig, SPEED_OF_LIGHT, azimuth_bin_to_angle};
use metamoran_dsp::doppler::{
    DopplerOptions, doppler_column, magnitude, range_doppler_map, range_doppler_rows,
    range_doppler_rows_keeping,
};
use metamoran_dsp::fft::Exponent;
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::range::{RangeCube, RangeProcessor};
use metamoran_dsp::units::signed_bin;
use std::f64::consts::PI;

fn config() -> RadarConfig {
    RadarConfig {
        start_frequency_hz: 77.0e9,
        slope_hz_per_s: 29.982e12,
        sample_rate_hz: 10.0e6,
        adc_samples: 256,
        chirp_period_s: 60.0e-6,
        chirps_per_tx: 16,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: HVec::from_slice(&[0, 4]).unwrap(),
        rx_positions: HVec::from_slice(&[0, 1, 2, 3]).unwrap(),
        tx_order: HVec::from_slice(&[0, 1]).unwrap(),
    }
}

/// A point reflector: range (m), sin(azimuth), radial velocity (m/s), amplitude (full scale).
struct Reflector {
    range: f64,
    sin_az: f64,
    velocity: f64,
    amplitude: f64,
}

/// One frame `[chirp][rx][sample]` per the spec's signal model.
fn synthesize(c: &RadarConfig, reflectors: &[Reflector]) -> Vec<CQ15> {
    let lambda = c.wavelength_m();
    let n = c.adc_samples as usize;
    let mut out = Vec::new();
    for chirp in 0..c.chirps_per_frame() {
        let slot = chirp % c.slots();
        let t = chirp as f64 * c.chirp_period_s;
        for rx in 0..c.rx_count() {
            let p = c.channel_position(slot * c.rx_count() + rx).unwrap() as f64;
            for s in 0..n {
                let (mut re, mut im) = (0.0, 0.0);
                for r in reflectors {
                    let beat = 2.0 * c.slope_hz_per_s * r.range / SPEED_OF_LIGHT;
                    let phase = 4.0 * PI * r.range / lambda
                        + 2.0 * PI * beat * s as f64 / c.sample_rate_hz
                        + PI * p * r.sin_az
                        + 4.0 * PI * r.velocity * t / lambda;
                    re += r.amplitude * phase.cos();
                    im += r.amplitude * phase.sin();
                }
                out.push(CQ15::from_f32(re as f32, im as f32));
            }
        }
    }
    out
}

fn cube_of(c: &RadarConfig, frame: &[CQ15]) -> RangeCube<Vec<CQ15>, Vec<Exponent>> {
    let (n, nr, loops) = (
        c.adc_samples as usize,
        c.range_fft_len(),
        c.chirps_per_tx as usize,
    );
    let rows = c.channels() * loops;
    let mut cube = RangeCube::new(
        vec![CQ15::default(); rows * nr],
        vec![Exponent::default(); rows],
        c.slots(),
        c.rx_count(),
        loops,
        nr,
    )
    .unwrap();
    let proc = RangeProcessor::new(n, nr, None).unwrap();
    for (chirp, rows) in frame.chunks_exact(c.rx_count() * n).enumerate() {
        for (rx, s) in rows.chunks_exact(n).enumerate() {
            cube.push_chirp(&proc, chirp, rx, s).unwrap();
        }
    }
    cube
}

/// Index of the largest value.
fn argmax(x: &[f32]) -> usize {
    (0..x.len()).max_by(|&a, &b| x[a].total_cmp(&x[b])).unwrap()
}

/// The range–Doppler map of `cube` without windows.
fn rd_map(cube: &RangeCube<Vec<CQ15>, Vec<Exponent>>, remove_static: bool) -> Vec<f32> {
    let nd = cube.loops().next_power_of_two().max(16);
    let mut scratch = vec![CQ15::default(); nd];
    let mut map = vec![0f32; cube.bins() * nd];
    let options = DopplerOptions {
        remove_static,
        window: None,
    };
    range_doppler_map(cube, &options, &mut scratch, &mut map).unwrap();
    map
}

#[test]
fn mover_lands_in_its_range_and_doppler_bin_and_static_is_removed() {
    let c = config();
    let (nr, nd) = (c.range_fft_len(), c.doppler_fft_len());
    // On-grid: range bin 40, Doppler bin −3 (approaching), broadside; a strong static target at bin 90.
    let range = c.bin_to_range(40.0, nr) as f64;
    let v = c.doppler_to_velocity(-3.0, nd) as f64;
    let frame = synthesize(
        &c,
        &[
            Reflector {
                range,
                sin_az: 0.0,
                velocity: v,
                amplitude: 0.02,
            },
            Reflector {
                range: c.bin_to_range(90.0, nr) as f64,
                sin_az: 0.3,
                velocity: 0.0,
                amplitude: 0.2,
            },
        ],
    );
    let cube = cube_of(&c, &frame);
    let map = rd_map(&cube, true);
    let arg = argmax(&map);
    assert_eq!((arg / nd, signed_bin(arg % nd, nd)), (40, -3));
    // The static reflector is ten times stronger, yet after clutter removal it is at the noise floor.
    let static_cell = map[90 * nd];
    assert!(
        static_cell < 1e-3 * map[arg],
        "static residue {static_cell} vs mover {}",
        map[arg]
    );
    // Amplitude: 8 channels × |0.02 · 256 samples · 16 loops| = 655.36 (full scale 1).
    assert!(
        (map[arg] as f64 - 8.0 * 0.02 * 256.0 * 16.0).abs() / 655.36 < 0.01,
        "{}",
        map[arg]
    );
    // Without clutter removal the static target dominates Doppler bin 0.
    let map = rd_map(&cube, false);
    let arg = argmax(&map);
    assert_eq!((arg / nd, arg % nd), (90, 0));
}

/// The host fills the cube's rows and the map's range bins in two halves, one per thread: the
/// rows `rows_mut` names hold the same bits as `push_chirp` writes, and two parts of
/// `range_doppler_rows` are the whole map.
#[test]
fn rows_and_map_filled_in_parts_are_the_same_bits() {
    let c = config();
    let (n, nr) = (c.adc_samples as usize, c.range_fft_len());
    let frame = synthesize(
        &c,
        &[Reflector {
            range: 12.3,
            sin_az: 0.2,
            velocity: 1.7,
            amplitude: 0.05,
        }],
    );
    let whole = cube_of(&c, &frame);
    let mut parts = cube_of(&c, &vec![CQ15::default(); frame.len()]);
    let proc = RangeProcessor::new(n, nr, None).unwrap();
    let mut rows: Vec<_> = parts.rows_mut().collect();
    assert_eq!(rows.len(), c.channels() * c.chirps_per_tx as usize);
    // In reverse, so an order the mapping got wrong cannot pass by writing the same row twice.
    for (chirp, rx, out, exp) in rows.iter_mut().rev() {
        let start = (*chirp * c.rx_count() + *rx) * n;
        **exp = proc.process(&frame[start..start + n], out).unwrap();
    }
    drop(rows);
    assert!(whole.rows().eq(parts.rows()), "rows differ");

    let map = rd_map(&whole, true);
    let nd = map.len() / nr;
    let options = DopplerOptions {
        remove_static: true,
        window: None,
    };
    let mut split = vec![0f32; map.len()];
    let half = nr / 2 + 3;
    let (lower, upper) = split.split_at_mut(half * nd);
    let mut scratch = vec![CQ15::default(); nd];
    range_doppler_rows(&whole, &options, &mut scratch, 0, lower).unwrap();
    range_doppler_rows(&whole, &options, &mut scratch, half, upper).unwrap();
    assert!(
        map.iter()
            .zip(&split)
            .all(|(a, b)| a.to_bits() == b.to_bits()),
        "maps differ"
    );
    // A part reaching past the last bin, or not whole rows, is refused.
    let mut long = vec![0f32; (nr - half + 1) * nd];
    assert!(range_doppler_rows(&whole, &options, &mut scratch, half, &mut long).is_err());
    let mut ragged = vec![0f32; nd + 1];
    assert!(range_doppler_rows(&whole, &options, &mut scratch, 0, &mut ragged).is_err());
}

/// The map's rows are each bin's channels summed in channel order, bit for bit, and `keep`
/// sees every (bin, channel)'s spectrum once: checked from `doppler_column` bin by bin, over a
/// part of the map that starts and ends at odd bins.
#[test]
fn map_rows_are_each_bins_channels_summed_in_order() {
    let c = config();
    let frame = synthesize(
        &c,
        &[Reflector {
            range: 20.1,
            sin_az: -0.4,
            velocity: -2.3,
            amplitude: 0.08,
        }],
    );
    let cube = cube_of(&c, &frame);
    let nd = c.doppler_fft_len();
    let options = DopplerOptions {
        remove_static: true,
        window: None,
    };
    let (first, rows) = (5, 37);
    let mut scratch = vec![CQ15::default(); nd];
    let mut map = vec![0f32; rows * nd];
    let mut seen = vec![0u32; rows * c.channels()];
    let mut mismatched = 0;
    let mut column = vec![CQ15::default(); nd];
    range_doppler_rows_keeping(
        &cube,
        &options,
        &mut scratch,
        first,
        &mut map,
        |bin, ch, e, z| {
            seen[(bin - first) * c.channels() + ch] += 1;
            let expected = doppler_column(&cube, ch, bin, &options, &mut column).unwrap();
            mismatched += usize::from(e != expected || z != column.as_slice());
        },
    )
    .unwrap();
    assert!(seen.iter().all(|&n| n == 1), "each (bin, channel) once");
    assert_eq!(mismatched, 0, "kept spectra");
    for (i, row) in map.chunks_exact(nd).enumerate() {
        let mut expected = vec![0f32; nd];
        for ch in 0..c.channels() {
            let e = doppler_column(&cube, ch, first + i, &options, &mut column).unwrap();
            for (o, &z) in expected.iter_mut().zip(&column) {
                *o += magnitude(z, e);
            }
        }
        let same = row
            .iter()
            .zip(&expected)
            .all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "row of bin {}", first + i);
    }
}

#[test]
fn azimuth_fft_and_beamformer_find_the_arrival_angle() {
    let c = config();
    let nr = c.range_fft_len();
    let array = VirtualArray::new(&c).unwrap();
    // sin θ = 2·5/64: exactly bin 5 of a 64-point azimuth FFT; range bin 60.
    let sin_az = 2.0 * 5.0 / 64.0;
    let range = c.bin_to_range(60.0, nr) as f64;
    let frame = synthesize(
        &c,
        &[Reflector {
            range,
            sin_az,
            velocity: 0.0,
            amplitude: 0.1,
        }],
    );
    let cube = cube_of(&c, &frame);
    // Channel values at range bin 60, loop 0 (same exponent across a static frame's rows).
    let mut values = Vec::new();
    let mut exps = Vec::new();
    for ch in 0..c.channels() {
        let (row, e) = cube.row(ch, 0).unwrap();
        values.push(row[60]);
        exps.push(e);
    }
    assert!(exps.iter().all(|&e| e == exps[0]));
    let mut spec = vec![CQ15::default(); 64];
    azimuth_spectrum(&array, &values, &mut spec).unwrap();
    let mags: Vec<f32> = spec.iter().map(|&z| magnitude(z, Exponent(0))).collect();
    let k = argmax(&mags);
    assert_eq!(signed_bin(k, 64), 5);
    let angle = azimuth_bin_to_angle(5.0, 64).unwrap();
    assert!((angle as f64 - sin_az.asin()).abs() < 1e-6);
    // The beamformer over the same elements peaks at the same direction and falls off away from it.
    let mut elements = vec![CQ15::default(); array.span()];
    array.gather(&values, &mut elements).unwrap();
    let power = |s: f32| {
        let (r, i) = beamform(&array, &elements, s).to_f64();
        r * r + i * i
    };
    let on = power(sin_az as f32);
    assert!(
        on > power(sin_az as f32 + 0.1)
            && on > power(sin_az as f32 - 0.1)
            && on > 10.0 * power(-0.5)
    );
}
