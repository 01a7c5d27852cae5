//! Property tests: no input makes the DSP panic, and the fixed-point FFT stays close to an f64
//! reference for any Q15 input, including full-scale worst cases.

use metamoran_dsp::capture::{IqOrder, deinterleave_bytes};
use metamoran_dsp::clutter::remove_mean;
use metamoran_dsp::detect::{Boundary, Cfar, CfarKind, quadratic_offset};
use metamoran_dsp::fft::cfft_q15;
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::range::RangeProcessor;
use proptest::prelude::*;
use rustfft::{FftPlanner, num_complex::Complex64};

fn any_len() -> impl Strategy<Value = usize> {
    (4u32..=11).prop_map(|k| 1usize << k)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn q15_fft_tracks_f64_for_any_input(n in any_len(), seed in any::<u64>(), scale in 0u32..16) {
        let mut s = seed | 1;
        let mut buf: Vec<CQ15> = (0..n).map(|_| {
            s ^= s << 13; s ^= s >> 7; s ^= s << 17;
            CQ15::from_raw((s as i16) >> scale, ((s >> 16) as i16) >> scale)
        }).collect();
        let input: Vec<Complex64> = buf.iter().map(|z| Complex64::new(z.re.0 as f64, z.im.0 as f64) / 32768.0).collect();
        let mut reference = input.clone();
        FftPlanner::<f64>::new().plan_fft_forward(n).process(&mut reference);
        let k = cfft_q15(&mut buf).unwrap().scale_f64() / 32768.0;
        let sig: f64 = reference.iter().map(rustfft::num_complex::Complex::norm_sqr).sum();
        let err: f64 = reference.iter().zip(&buf).map(|(r, z)| (r - Complex64::new(z.re.0 as f64 * k, z.im.0 as f64 * k)).norm_sqr()).sum();
        // Inputs down to 1 LSB wide have little to resolve; above ~5 bits of input we need ≥ 40 dB.
        if sig > 0.0 && scale <= 10 {
            prop_assert!(10.0 * (sig / err.max(1e-300)).log10() > 40.0, "n={} scale={} sqnr={}", n, scale, 10.0 * (sig / err).log10());
        }
    }

    #[test]
    fn deinterleave_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..64), n in 0usize..20) {
        let mut out = vec![CQ15::default(); n];
        let ok = deinterleave_bytes(&bytes, IqOrder::Qqii, &mut out).is_ok();
        prop_assert_eq!(ok, n % 2 == 0 && bytes.len() == 4 * n);
    }

    #[test]
    fn cfar_never_panics(x in proptest::collection::vec(prop_oneof![any::<f32>(), Just(f32::NAN), Just(f32::INFINITY)], 0..100),
                         guard in 0usize..5, train in 0usize..40, os in any::<bool>(), wrap in any::<bool>()) {
        let kind = if os { CfarKind::OrderedStatistic { rank: 0.75 } } else { CfarKind::CellAveraging };
        let boundary = if wrap { Boundary::Wrap } else { Boundary::Truncate };
        let _ = Cfar { guard, train, scale: 3.0, kind, boundary }.detect(&x, |_| ());
    }

    #[test]
    fn clutter_removal_and_range_never_panic(v in proptest::collection::vec(any::<(i16, i16)>(), 0..300), fft_pow in 0u32..13) {
        let mut col: Vec<CQ15> = v.iter().map(|&(a, b)| CQ15::from_raw(a, b)).collect();
        remove_mean(&mut col);
        let fft_len = 1usize << fft_pow;
        if let Ok(p) = RangeProcessor::new(col.len(), fft_len, None) {
            let mut out = vec![CQ15::default(); fft_len];
            prop_assert!(p.process(&col, &mut out).is_ok());
        }
    }

    #[test]
    fn peak_offset_is_bounded(a in any::<f32>(), b in any::<f32>(), c in any::<f32>()) {
        let o = quadratic_offset(a, b, c);
        prop_assert!((-0.5..=0.5).contains(&o));
    }
}
