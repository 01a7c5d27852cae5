//! The simulator against closed forms: a single point reflector lands in its predicted range
//! bin, azimuth and Doppler bin for both boards, and a written bundle reads back exactly.

use dsp::capture::{IqOrder, deinterleave_bytes};
use dsp::fixed::CQ15;
use dsp::units::{DopplerBin, RangeBin, signed_bin};
use dsp::window::WindowKind;
use host_tools::frame::{FrameOptions, FrameProcessor};
use host_tools::sim::radar::{RadarKind, config};
use host_tools::sim::signal::{Echo, synthesize};
use rand::SeedableRng;

fn frame(kind: RadarKind, loops: u16, echo: Echo) -> (dsp::config::RadarConfig, Vec<CQ15>) {
    let c = config(kind, 59.4, loops);
    let bytes = synthesize(&c, &[echo], &mut rand_pcg::Pcg64Mcg::seed_from_u64(5));
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
            let predicted = c.range_to_bin(dsp::units::Meters(range as f32), nr).0;
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
            let _ = RangeBin(0.0);
        }
    }
}

#[test]
fn moving_reflector_lands_in_its_doppler_bin() {
    for kind in [RadarKind::Xwr18xx, RadarKind::Cascade] {
        let c = config(kind, 59.4, 16);
        let nd = c.doppler_fft_len();
        for bin in [-5.0f32, 3.0] {
            let v = c.doppler_to_velocity(DopplerBin(bin), nd).0 as f64;
            let (c, s) = frame(
                kind,
                16,
                Echo {
                    range: 30.0,
                    sin_az: 0.1,
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
