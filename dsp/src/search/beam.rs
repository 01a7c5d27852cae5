//! Beams: a frame's range spectra steered toward one direction, in fixed point.
//!
//! `B(k, s) = Σₑ Xₑ[k]·exp(−jπ·pₑ·s)` with Q15 spectra and Q15 weights, summed exactly in `i64`
//! (no rounding until the one conversion to `f32` per bin). This is the hot loop of the search:
//! K contour points × E elements × the searched bins.

use super::kernel::half_turns;
use crate::array::MAX_CHANNELS;
use crate::fft::C32;
use crate::fft::simd;
use crate::range::Spectra;
use crate::range::frame_sum::pack;
use crate::trig::{Phase, expj_neg};
use heapless::Vec;

/// Steering weights toward one direction.
#[derive(Clone, Debug)]
pub struct Steering {
    /// Packed Q15 weights (see [`crate::range::frame_sum::pack`]).
    weights: Vec<u32, MAX_CHANNELS>,
}

impl Steering {
    /// Weights `exp(−jπ·p·sin θ)` for the element positions `positions` (half-wavelengths).
    pub fn new(positions: &[u16], sin_az: f32) -> Self {
        let step = half_turns(sin_az);
        Self {
            weights: positions
                .iter()
                .take(MAX_CHANNELS)
                .map(|&p| pack(expj_neg(Phase(step.wrapping_mul(p as u32)))))
                .collect(),
        }
    }

    /// The beam at bin `k`, in the spectra's stored units: two dual-MAC instructions per
    /// element on the M7 (`SMLSLD`, `SMLALDX`), exact in `i64`. O(E).
    #[inline]
    pub fn beam(&self, spectra: &Spectra<'_>, k: usize) -> C32 {
        let (mut re, mut im) = (0i64, 0i64);
        for (&w, &x) in self.weights.iter().zip(spectra.column(k)) {
            re = simd::smlsld(x, w, re);
            im = simd::smlaldx(x, w, im);
        }
        C32::new(re as f32 / 32768.0, im as f32 / 32768.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::CQ15;

    #[test]
    fn beam_matches_f64() {
        let pos = [0u16, 1, 3, 4, 7];
        let vals: std::vec::Vec<CQ15> = (0..pos.len() * 4)
            .map(|i| {
                CQ15::from_raw(
                    (i as i16 * 997) % 30000 - 15000,
                    (i as i16 * 331) % 20000 - 9000,
                )
            })
            .collect();
        let words: std::vec::Vec<u32> = vals.iter().map(|&z| pack(z)).collect();
        let spec = Spectra::from_words(&words, pos.len(), 4, 0).unwrap();
        let s = 0.31f32;
        let st = Steering::new(&pos, s);
        for k in 0..4 {
            let (mut re, mut im) = (0.0f64, 0.0f64);
            for (e, &p) in pos.iter().enumerate() {
                let z = vals[e * 4 + k];
                let a = -core::f64::consts::PI * p as f64 * s as f64;
                let (c, sn) = (libm::cos(a), libm::sin(a));
                re += z.re.0 as f64 * c - z.im.0 as f64 * sn;
                im += z.re.0 as f64 * sn + z.im.0 as f64 * c;
            }
            let b = st.beam(&spec, k);
            assert!(
                (b.re as f64 - re).abs() < 5.0 && (b.im as f64 - im).abs() < 5.0,
                "k={k}"
            );
        }
    }
}
