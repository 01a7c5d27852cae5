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
    /// element on the M7 (`SMLSLD`, `SMLALDX`) over the contiguous column, exact in `i64`. O(E).
    #[inline]
    pub fn beam(&self, spectra: &Spectra<'_>, k: usize) -> C32 {
        self.beam_of(spectra.column(k))
    }

    /// The beam of one column (bin) of packed words.
    #[inline(always)]
    fn beam_of(&self, column: &[u32]) -> C32 {
        let (re, im) = simd::complex_mac(column, &self.weights);
        C32::new(q15_to_f32(re), q15_to_f32(im))
    }

    /// Calls `each(k, beam(k))` for bins `first..first + len` (clipped to the spectrum): one walk
    /// over their contiguous columns, without a bounds check or call per bin. O(E·len).
    #[inline]
    pub fn run(
        &self,
        spectra: &Spectra<'_>,
        first: usize,
        len: usize,
        mut each: impl FnMut(usize, C32),
    ) {
        let block = spectra.columns(first..first.saturating_add(len));
        for (i, column) in block.chunks_exact(spectra.elements().max(1)).enumerate() {
            each(first + i, self.beam_of(column));
        }
    }
}

/// `x / 2¹⁵ as f32` (round to nearest, ties to even) for `|x| < 2⁴⁸`, through two exact
/// `i32 → f32` conversions and one rounding addition: hardware instructions on the M7 instead of
/// the `__aeabi_l2f` call. Beams stay below 2⁴⁰ (E ≤ 256 products below 2³¹). Both terms are
/// exact multiples of powers of two, so this is `(x as f32) / 32768.0`, bit for bit.
#[inline]
fn q15_to_f32(x: i64) -> f32 {
    let hi = (x >> 24) as i32 as f32 * 512.0; // exact: at most 24 significant bits
    let lo = (x & 0xFF_FFFF) as i32 as f32 * (1.0 / 32768.0); // exact: below 2²⁴
    hi + lo
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
        let mut words = std::vec![0u32; vals.len()];
        for (i, &z) in vals.iter().enumerate() {
            words[Spectra::word_index(i / 4, i % 4, pos.len())] = pack(z);
        }
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
        // The run gives the single-bin beams, clipped to the spectrum.
        for (first, len) in [(0usize, 4usize), (1, 3), (0, 3), (3, 9)] {
            let mut seen = 0;
            st.run(&spec, first, len, |k, z| {
                assert_eq!(z, st.beam(&spec, k), "k={k}");
                seen += 1;
            });
            assert_eq!(seen, len.min(4usize.saturating_sub(first)));
        }
    }

    #[test]
    fn q15_to_f32_rounds_like_a_cast() {
        let mut x = 1i64;
        for i in 0..200_000i64 {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let v = (x >> (16 + i % 24)) % (1i64 << 47);
            assert_eq!(
                q15_to_f32(v).to_bits(),
                (v as f32 / 32768.0).to_bits(),
                "{v}"
            );
        }
        for v in [0i64, -1, (1 << 24) + 1, -(1 << 40) - 3, (1 << 47) - 1] {
            assert_eq!(
                q15_to_f32(v).to_bits(),
                (v as f32 / 32768.0).to_bits(),
                "{v}"
            );
        }
    }
}
