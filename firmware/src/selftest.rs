//! Deterministic DSP workloads and their output fingerprints.
//!
//! The firmware prints one line per workload under QEMU; the host test runs [`run`] natively and
//! requires identical exponents and hashes: the `dsp` crate computes the same bits on the
//! Cortex-M7 as on x86.

use crate::workload::{Fnv, noise_q15, noise_q31};
use metamoran_dsp::array::VirtualArray;
use metamoran_dsp::azimuth::beamform;
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::detect::{Boundary, Cfar, CfarKind};
use metamoran_dsp::fft::{Cfft, Complex32, cfft_f32, cfft_q15};
use metamoran_dsp::fixed::{CQ15, CQ31, Q15};
use metamoran_dsp::range::RangeProcessor;
use metamoran_dsp::window::Window;

/// The result of one workload.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// Workload name.
    pub name: &'static str,
    /// Block exponent (0 where none).
    pub exponent: u32,
    /// FNV-1a of the output.
    pub hash: u32,
}

fn hash_q15(buf: &[CQ15]) -> u32 {
    let mut h = Fnv::default();
    for z in buf {
        h.bytes(&z.re.0.to_le_bytes());
        h.bytes(&z.im.0.to_le_bytes());
    }
    h.0
}

fn hash_q31(buf: &[CQ31]) -> u32 {
    let mut h = Fnv::default();
    for z in buf {
        h.u32(z.re.0 as u32);
        h.u32(z.im.0 as u32);
    }
    h.0
}

/// Runs every workload, calling `emit` with each outcome in a fixed order.
pub fn run(mut emit: impl FnMut(Outcome)) {
    fft_workloads(&mut emit);
    let (range, spectrum) = range_workload();
    emit(range);
    emit(beamform_workload());
    emit(cfar_workload(&spectrum));
    emit(complex_mac_workload());
    emit(frame_sum_workload());
    emit(calibrated_sum_workload());
    emit(search_workload());
}

/// The Q15 FFT at every length (noise at −12 dBFS) and weak noise at 1024 points, the Q31 FFT
/// and microfft's f32 FFT at 256 points.
fn fft_workloads(emit: &mut impl FnMut(Outcome)) {
    const NAMES: [&str; 8] = [
        "q15_fft_16",
        "q15_fft_32",
        "q15_fft_64",
        "q15_fft_128",
        "q15_fft_256",
        "q15_fft_512",
        "q15_fft_1024",
        "q15_fft_2048",
    ];
    let mut buf = [CQ15::default(); 2048];
    for (i, name) in NAMES.iter().enumerate() {
        let n = 16 << i;
        noise_q15(n as u32, Q15(8192), &mut buf[..n]);
        let e = cfft_q15(&mut buf[..n]).map_or(u32::MAX, |e| e.0);
        emit(Outcome {
            name,
            exponent: e,
            hash: hash_q15(&buf[..n]),
        });
    }
    noise_q15(7, Q15(328), &mut buf[..1024]);
    let e = cfft_q15(&mut buf[..1024]).map_or(u32::MAX, |e| e.0);
    emit(Outcome {
        name: "q15_fft_1024_weak",
        exponent: e,
        hash: hash_q15(&buf[..1024]),
    });

    let mut q31 = [CQ31::default(); 256];
    noise_q31(31, Q15(8192), &mut q31);
    let e = Cfft::<256>::q31(&mut q31);
    emit(Outcome {
        name: "q31_fft_256",
        exponent: e.0,
        hash: hash_q31(&q31),
    });

    let mut f = [Complex32::new(0.0, 0.0); 256];
    noise_q15(32, Q15(8192), &mut buf[..256]);
    for (o, z) in f.iter_mut().zip(&buf) {
        *o = Complex32::new(z.re.to_f32(), z.im.to_f32());
    }
    let ok = cfft_f32(&mut f).is_ok();
    let mut h = Fnv::default();
    for z in &f {
        h.u32(z.re.to_bits());
        h.u32(z.im.to_bits());
    }
    emit(Outcome {
        name: "microfft_f32_256",
        exponent: if ok { 0 } else { u32::MAX },
        hash: h.0,
    });
}

/// The range FFT of a Hann-windowed tone at bin 40.5 plus weak noise; also returns the spectrum.
fn range_workload() -> (Outcome, [CQ15; 256]) {
    let window = Window::<200>::HANN;
    let mut samples = [CQ15::default(); 200];
    noise_q15(40, Q15(100), &mut samples);
    for (n, s) in samples.iter_mut().enumerate() {
        let t = metamoran_dsp::trig::expj_neg(metamoran_dsp::trig::Phase::from_turns(
            -(40.5 * n as f64) / 256.0,
        ));
        s.re = Q15(s.re.0.saturating_add(t.re.0 / 4));
        s.im = Q15(s.im.0.saturating_add(t.im.0 / 4));
    }
    let mut out = [CQ15::default(); 256];
    let e = RangeProcessor::new(200, 256, Some(&window))
        .and_then(|p| p.process(&samples, &mut out))
        .map_or(u32::MAX, |e| e.0);
    let outcome = Outcome {
        name: "range_hann_200_in_256",
        exponent: e,
        hash: hash_q15(&out),
    };
    (outcome, out)
}

/// Beamforming over an overlapping, gapped array at several angles.
fn beamform_workload() -> Outcome {
    let config = RadarConfig {
        start_frequency_hz: 77e9,
        slope_hz_per_s: 30e12,
        sample_rate_hz: 10e6,
        adc_samples: 256,
        chirp_period_s: 60e-6,
        chirps_per_tx: 16,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: heapless::Vec::from_slice(&[0, 2, 8]).unwrap_or_default(),
        rx_positions: heapless::Vec::from_slice(&[0, 1, 2, 3]).unwrap_or_default(),
        tx_order: heapless::Vec::from_slice(&[0, 1, 2]).unwrap_or_default(),
    };
    let mut h = Fnv::default();
    // u32::MAX marks a failure `every_workload_succeeds` catches (a hash of nothing would
    // match on both machines).
    let mut exponent = u32::MAX;
    if let Ok(array) = VirtualArray::new(&config) {
        let mut channels = [CQ15::default(); 12];
        noise_q15(12, Q15(16384), &mut channels);
        let mut elements = [CQ15::default(); 16];
        if array.gather(&channels, &mut elements).is_ok() {
            for s in [-0.9f32, -0.3, 0.0, 0.25, 0.8] {
                let b = beamform(&array, &elements, s);
                h.u32(b.re.0 as u32);
                h.u32(b.im.0 as u32);
            }
            exponent = 0;
        }
    }
    Outcome {
        name: "beamform_gapped",
        exponent,
        hash: h.0,
    }
}

/// OS-CFAR on the magnitude profile of `spectrum`.
fn cfar_workload(spectrum: &[CQ15; 256]) -> Outcome {
    let mut profile = [0f32; 256];
    for (p, z) in profile.iter_mut().zip(spectrum) {
        *p = metamoran_dsp::doppler::magnitude(*z, metamoran_dsp::fft::Exponent(0));
    }
    let cfar = Cfar {
        guard: 2,
        train: 8,
        scale: 4.0,
        kind: CfarKind::OrderedStatistic { rank: 0.75 },
        boundary: Boundary::Truncate,
    };
    let mut h = Fnv::default();
    let found = cfar
        .detect(&profile, |d| h.u32(d.index as u32))
        .unwrap_or(usize::MAX);
    Outcome {
        name: "os_cfar_256",
        exponent: found as u32,
        hash: h.0,
    }
}

/// The inputs of [`complex_mac_workload`]: full-scale noise, packed Q15 words.
fn complex_mac_inputs() -> ([CQ15; 48], [CQ15; 48]) {
    let mut x = [CQ15::default(); 48];
    let mut w = [CQ15::default(); 48];
    noise_q15(48, Q15(32767), &mut x);
    noise_q15(49, Q15(32767), &mut w);
    (x, w)
}

/// The beams' dual-MAC loop at every length across its four-pair turns and remainders.
fn complex_mac_workload() -> Outcome {
    let (x, w) = complex_mac_inputs();
    let pack = |z: &[CQ15; 48]| z.map(metamoran_dsp::range::frame_sum::pack);
    let (xw, ww) = (pack(&x), pack(&w));
    let mut h = Fnv::default();
    for len in 0..=xw.len() {
        let (re, im) = metamoran_dsp::fft::complex_mac(&xw[..len], &ww[..len]);
        h.u32(re as u32);
        h.u32((re >> 32) as u32);
        h.u32(im as u32);
        h.u32((im >> 32) as u32);
    }
    Outcome {
        name: "complex_mac_0_to_48",
        exponent: 0,
        hash: h.0,
    }
}

/// Frame sums at every chirp length 1..=9 (the widening loop's pairs and odd word), two
/// elements, three full-scale noise chirps each, then the in-place range spectra.
fn frame_sum_workload() -> Outcome {
    use metamoran_dsp::range::FrameSum;
    let mut h = Fnv::default();
    let mut exponents = 0u32;
    let mut failed = false;
    let mut chirp = [CQ15::default(); 9];
    for n in 1..=9usize {
        let mut arena = [0u32; FrameSum::words_needed(2, 9, 16)];
        let Ok(mut frame) = FrameSum::new(&mut arena, 2, n, 16) else {
            failed = true;
            continue;
        };
        for row in 0..6u32 {
            noise_q15(100 + 10 * n as u32 + row, Q15(32767), &mut chirp[..n]);
            failed |= frame.add(row as usize % 2, &chirp[..n]).is_err();
        }
        let mut scratch = [CQ15::default(); 16];
        failed |= !hash_spectra(
            frame,
            &[Q15(32767); 9][..n],
            &mut scratch,
            &mut h,
            &mut exponents,
        );
    }
    Outcome {
        name: "frame_sum_1_to_9",
        exponent: if failed { u32::MAX } else { exponents },
        hash: h.0,
    }
}

/// Finishes `frame` with `window` and hashes its spectra bin-major into `h` and their exponent
/// into `exponents`; false if the range stage refused.
fn hash_spectra(
    frame: metamoran_dsp::range::FrameSum<'_>,
    window: &[Q15],
    scratch: &mut [CQ15],
    h: &mut Fnv,
    exponents: &mut u32,
) -> bool {
    let Ok((spectra, _)) = frame.finish(window, scratch) else {
        return false;
    };
    *exponents = exponents
        .wrapping_mul(31)
        .wrapping_add(spectra.exponent() as u32);
    for k in 0..spectra.bins() {
        spectra.column(k).iter().for_each(|&w| h.u32(w));
    }
    true
}

/// Calibrated frame sums (`FrameSum::add_calibrated`: the M7's unrolled `SMLSD`/`SMLADX`
/// blocks) at chirp lengths across whole 16-sample blocks and short last ones, full-scale noise
/// times full-scale and noise coefficients, three chirps into each of two elements, then the
/// spectra.
fn calibrated_sum_workload() -> Outcome {
    use metamoran_dsp::range::FrameSum;
    use metamoran_dsp::range::frame_sum::pack;
    const MAX: usize = 40;
    let mut h = Fnv::default();
    let mut exponents = 0u32;
    let mut failed = false;
    let mut chirp = [CQ15::default(); MAX];
    let mut c = [CQ15::default(); 3];
    noise_q15(7, Q15(8192), &mut c);
    c[0] = CQ15::from_raw(-8192, -8192);
    let coefficients = c.map(pack);
    for n in [1usize, 5, 15, 16, 17, 31, 32, 33, 40] {
        let mut arena = [0u32; FrameSum::words_needed(2, MAX, 64)];
        let Ok(mut frame) = FrameSum::new_calibrated(&mut arena, 2, n, 64, 2) else {
            failed = true;
            continue;
        };
        for row in 0..6u32 {
            noise_q15(300 + 10 * n as u32 + row, Q15(32767), &mut chirp[..n]);
            failed |= frame
                .add_calibrated(row as usize % 2, &chirp[..n], &coefficients)
                .is_err();
        }
        let mut scratch = [CQ15::default(); 64];
        failed |= !hash_spectra(
            frame,
            &[Q15(32767); MAX][..n],
            &mut scratch,
            &mut h,
            &mut exponents,
        );
    }
    Outcome {
        name: "calibrated_sum_blocks",
        exponent: if failed { u32::MAX } else { exponents },
        hash: h.0,
    }
}

/// The module pipeline (`metamoran_dsp::pipeline`: frame sums, in-place range spectra, peak scan, SIC,
/// depth search) on a synthetic 2 TX × 4 RX, 64-sample frame: a contour object at bin 20.3 and a
/// strong reflector at bin 9.6, 35° away.
fn search_workload() -> Outcome {
    use metamoran_dsp::pipeline::{Edge, ObjectHint};
    use metamoran_dsp::search::Contour;
    const N: usize = crate::workload::TWO_REFLECTOR_N;
    let failed = |hash| Outcome {
        name: "search_sic",
        exponent: u32::MAX,
        hash,
    };
    let config = crate::workload::two_reflector_config();
    let Ok(edge) = Edge::new(&config) else {
        return failed(0);
    };
    let mut arena = [0u32; 4608];
    let Ok(mut frame) = edge.start(&mut arena) else {
        return failed(1);
    };
    for chirp_no in 0..4 {
        for rx in 0..4 {
            let mut chirp = [CQ15::default(); N];
            crate::workload::two_reflector_row(chirp_no, rx, &[CQ15::default(); N], &mut chirp);
            if edge.push(&mut frame, chirp_no, rx, &chirp).is_err() {
                return failed(2);
            }
        }
    }
    let (mut row, mut az, mut powers) = ([CQ15::default(); N], [CQ15::default(); 16], [0u64; 48]);
    let Ok(mut scene) = edge.finish(frame, &mut row, &mut az, &mut powers) else {
        return failed(3);
    };
    let hint = ObjectHint {
        id: 1,
        class: 0,
        span: (-0.04, 0.04),
        prior_m: 0.0,
        window_m: (0.0, 0.0),
        contour: Contour::new((0..4).map(|i| (-0.03 + 0.02 * i as f32, 5.0 + 0.05 * i as f32))),
    };
    let mut h = Fnv::default();
    let reflectors = edge.cancel(&scene, &hint);
    for r in &reflectors {
        h.u32(r.range_bins.to_bits());
        h.u32(r.amplitude.re.to_bits());
    }
    let mut scores = [0.0f32; N];
    match edge.search(&mut scene, &hint, &reflectors, &mut scores) {
        Ok(r) => {
            h.u32(r.search.depth_bins.to_bits());
            h.u32(r.search.peak.to_bits());
            h.u32(r.search.floor.to_bits());
            Outcome {
                name: "search_sic",
                exponent: reflectors.len() as u32,
                hash: h.0,
            }
        }
        Err(_) => failed(h.0),
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    /// Every workload ran to the end (u32::MAX marks a failure in any of them).
    #[test]
    fn every_workload_succeeds() {
        let mut names = 0;
        run(|o| {
            names += 1;
            assert_ne!(o.exponent, u32::MAX, "{}", o.name);
        });
        assert_eq!(names, 18);
    }

    /// The dual-MAC against the sum of products in i64 (an independent closed form: the
    /// comparison with QEMU only shows both machines agree, not that either is right).
    #[test]
    fn complex_mac_is_the_exact_sum_of_products() {
        let (x, w) = complex_mac_inputs();
        let pack = |z: &[CQ15; 48]| z.map(metamoran_dsp::range::frame_sum::pack);
        let (xw, ww) = (pack(&x), pack(&w));
        for len in 0..=48 {
            let (mut re, mut im) = (0i64, 0i64);
            for (a, b) in x[..len].iter().zip(&w[..len]) {
                let (ar, ai, br, bi) = (a.re.0 as i64, a.im.0 as i64, b.re.0 as i64, b.im.0 as i64);
                re += ar * br - ai * bi;
                im += ar * bi + ai * br;
            }
            assert_eq!(
                metamoran_dsp::fft::complex_mac(&xw[..len], &ww[..len]),
                (re, im),
                "length {len}"
            );
        }
    }

    /// The f32 FFT workload against a direct DFT in f64.
    #[test]
    fn microfft_matches_a_direct_dft() {
        let mut buf = [CQ15::default(); 256];
        noise_q15(32, Q15(8192), &mut buf);
        let mut f = [Complex32::new(0.0, 0.0); 256];
        for (o, z) in f.iter_mut().zip(&buf) {
            *o = Complex32::new(z.re.to_f32(), z.im.to_f32());
        }
        let input = f;
        cfft_f32(&mut f).unwrap();
        for (k, got) in f.iter().enumerate() {
            let (mut re, mut im) = (0f64, 0f64);
            for (n, z) in input.iter().enumerate() {
                let a = -2.0 * core::f64::consts::PI * (k * n % 256) as f64 / 256.0;
                let (s, c) = a.sin_cos();
                re += z.re as f64 * c - z.im as f64 * s;
                im += z.re as f64 * s + z.im as f64 * c;
            }
            assert!(
                (got.re as f64 - re).abs() < 1e-4 && (got.im as f64 - im).abs() < 1e-4,
                "bin {k}: {got:?} vs ({re}, {im})"
            );
        }
    }
}
