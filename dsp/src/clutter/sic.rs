//! Successive interference cancellation (Metamoran, Sec. III-B), in the beam domain.
//!
//! Strong reflectors outside the object's azimuth span are taken from the frame's peak list
//! ([`super::peaks`]), strongest first. Each is estimated as a point reflector: range and
//! azimuth refined by parabolas (in dB) through its neighbours, complex amplitude `α` fitted by
//! least squares over its main lobe (the paper's "α equal to the peak"). Its synthesized
//! response `α·T(k − r)·AF(s_r − s)` ([`crate::response::kernel`]) is then subtracted from every
//! later beam, so the next estimate sees the residual. It stops when the next reflector outside
//! has no more than `stop_ratio` times the power of the strongest peak inside the span, or after
//! [`MAX_REFLECTORS`].
//!
//! Nothing is subtracted from the shared spectra: the search subtracts the same responses from
//! its beams. So objects of one frame never copy the spectra, and the state per object is the
//! reflector list, at most [`MAX_REFLECTORS`] × 280 bytes, whatever the scene.

use super::peaks::Peak;
use crate::fft::C32;
use crate::range::Spectra;
use crate::response::Geometry;
use crate::response::beam::Steering;
use crate::response::kernel::{SPREAD, array_factor, window_transform};
use heapless::Vec;

/// Most reflectors cancelled per object.
pub const MAX_REFLECTORS: usize = 32;

/// Bins on each side of a reflector over which its amplitude is fitted.
const FIT_HALF_WIDTH: usize = 6;

/// Values of a reflector's synthesized spectrum kept (its bin ± [`SPREAD`]).
pub const TONE_LEN: usize = 2 * SPREAD + 1;

/// A cancelled reflector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reflector {
    /// Range, bins of the M-point FFT (fractional).
    pub range_bins: f32,
    /// sin(azimuth).
    pub sin_az: f32,
    /// Fitted complex amplitude, in the spectra's stored units per unit window gain.
    pub amplitude: C32,
    /// First bin of `tone`.
    first: usize,
    /// `α·T(k − r)` for bins `first..first + TONE_LEN`.
    tone: [C32; TONE_LEN],
}

impl Reflector {
    /// A reflector at `range_bins`, `sin_az` with amplitude `amplitude`, its spectrum synthesized
    /// for `geo`. O([`TONE_LEN`]).
    pub fn new(geo: &Geometry<'_>, range_bins: f32, sin_az: f32, amplitude: C32) -> Self {
        let first = (libm::floorf(range_bins) as usize).saturating_sub(SPREAD);
        let mut tone = [C32::new(0.0, 0.0); TONE_LEN];
        for (i, t) in tone.iter_mut().enumerate() {
            let x = (first + i) as f32 - range_bins;
            *t = amplitude * window_transform(geo.window, x, geo.samples, geo.fft_len);
        }
        Self {
            range_bins,
            sin_az,
            amplitude,
            first,
            tone,
        }
    }

    /// Subtracts this reflector from windowed time-domain sums (`elements × N`, the input of
    /// `search::depth::brute_force`) whose spectra have block exponent `exponent`:
    /// element e loses `α·2^exponent·cₑ·exp(jπ·pₑ·s)·w[n]·exp(j2π·r·n/M)`. O(E·N).
    pub fn subtract_from(
        &self,
        samples: &mut [C32],
        geo: &Geometry<'_>,
        window: &[f32],
        exponent: i32,
    ) {
        let scale = libm::powf(2.0, exponent as f32);
        let w = 2.0 * core::f32::consts::PI * self.range_bins / geo.fft_len as f32;
        for ((row, &p), &c) in samples
            .chunks_exact_mut(geo.samples)
            .zip(geo.positions)
            .zip(geo.counts)
        {
            let a = core::f32::consts::PI * p as f32 * self.sin_az;
            let gain = self.amplitude * C32::new(libm::cosf(a), libm::sinf(a)) * (scale * c as f32);
            for (n, (x, &wn)) in row.iter_mut().zip(window).enumerate() {
                let ph = w * n as f32;
                *x -= gain * C32::new(libm::cosf(ph), libm::sinf(ph)) * wn;
            }
        }
    }

    /// `α·T(k − r)`, zero beyond ± [`SPREAD`] bins.
    #[inline]
    pub fn tone_at(&self, k: usize) -> C32 {
        k.checked_sub(self.first)
            .and_then(|i| self.tone.get(i))
            .copied()
            .unwrap_or(C32::new(0.0, 0.0))
    }
}

/// Beams toward one direction with the cancelled reflectors subtracted.
pub struct Residual<'s, 'a> {
    spectra: &'s Spectra<'a>,
    steering: Steering,
    /// `AF(s_r − s)` per reflector.
    gains: Vec<C32, MAX_REFLECTORS>,
    reflectors: &'s [Reflector],
}

impl<'s, 'a> Residual<'s, 'a> {
    /// Toward `sin_az`. O(E·(1 + R)).
    pub fn new(
        spectra: &'s Spectra<'a>,
        geo: &Geometry<'_>,
        reflectors: &'s [Reflector],
        sin_az: f32,
    ) -> Self {
        Self::near(spectra, geo, reflectors, sin_az, 0..=usize::MAX)
    }

    /// Toward `sin_az`, valid only for the bins in `bins`: the array factor is computed only for
    /// the reflectors whose tone reaches them (the others get gain 0). O(E·(1 + R_near)).
    pub fn near(
        spectra: &'s Spectra<'a>,
        geo: &Geometry<'_>,
        reflectors: &'s [Reflector],
        sin_az: f32,
        bins: core::ops::RangeInclusive<usize>,
    ) -> Self {
        let reaches = |r: &Reflector| r.first <= *bins.end() && r.first + TONE_LEN > *bins.start();
        Self {
            spectra,
            steering: Steering::new(geo.positions, sin_az),
            gains: reflectors
                .iter()
                .take(MAX_REFLECTORS)
                .map(|r| {
                    if reaches(r) {
                        array_factor(geo.positions, geo.counts, r.sin_az - sin_az)
                    } else {
                        C32::new(0.0, 0.0)
                    }
                })
                .fold(Vec::new(), |mut v, g| {
                    let _ = v.push(g);
                    v
                }),
            reflectors,
        }
    }

    /// The residual beam at bin `k`. O(E + R).
    #[inline]
    pub fn at(&self, k: usize) -> C32 {
        let mut b = self.steering.beam(self.spectra, k);
        for (r, &g) in self.reflectors.iter().zip(&self.gains) {
            b -= r.tone_at(k) * g;
        }
        b
    }

    /// Writes the residual beams of bins `first..first + out.len()` (clipped to the spectrum)
    /// into `out`: the steered beams, then each reflector's tone subtracted over its own bins
    /// only. Each bin sees the same operations in the same order as in [`Self::at`], so the
    /// values are identical. O(E·len + R·[`TONE_LEN`]).
    pub fn fill(&self, first: usize, out: &mut [C32]) {
        let len = out.len().min(self.spectra.bins().saturating_sub(first));
        let Some(out) = out.get_mut(..len) else {
            return;
        };
        self.steering.run(self.spectra, first, len, |k, b| {
            if let Some(o) = out.get_mut(k - first) {
                *o = b;
            }
        });
        for (r, &g) in self.reflectors.iter().zip(&self.gains) {
            for (i, t) in r.tone.iter().enumerate() {
                if let Some(o) = (r.first + i)
                    .checked_sub(first)
                    .and_then(|j| out.get_mut(j))
                {
                    *o -= *t * g;
                }
            }
        }
    }

    /// Its power at bin `k`.
    pub fn power(&self, k: usize) -> f32 {
        self.at(k).norm_sqr()
    }
}

fn quad(l: f32, c: f32, r: f32) -> f32 {
    let db = |x: f32| libm::log10f(x.max(1e-30));
    crate::detect::quadratic_offset(db(l), db(c), db(r))
}

/// Cancels reflectors from `peaks` (of an `na`-point azimuth FFT, strongest first) that lie
/// outside the sin-azimuth intervals `keep` (the object's span, widened by the caller by a main
/// lobe), while the next one has more than `stop_ratio` times the power of the strongest peak
/// inside. Returns them in the order cancelled. O(R²·E) per frame object.
pub fn cancel(
    spectra: &Spectra<'_>,
    geo: &Geometry<'_>,
    peaks: &[Peak],
    na: usize,
    keep: &[(f32, f32)],
    stop_ratio: f32,
) -> Vec<Reflector, MAX_REFLECTORS> {
    let mut out: Vec<Reflector, MAX_REFLECTORS> = Vec::new();
    let m = spectra.bins();
    let inside = |s: f32| keep.iter().any(|&(lo, hi)| s >= lo && s <= hi);
    let best_in = peaks
        .iter()
        .filter(|p| inside(p.sin_az(na)))
        .map(|p| p.power)
        .max()
        .unwrap_or(0) as f32;
    let threshold = stop_ratio * best_in;
    let channels: f32 = geo.counts.iter().map(|&c| c as f32).sum();
    for peak in peaks {
        let s0 = peak.sin_az(na);
        if inside(s0) {
            continue;
        }
        if peak.power as f32 <= threshold || out.is_full() {
            break;
        }
        let k = peak.bin as usize;
        if k == 0 || k + 1 >= m {
            continue;
        }
        let here = Residual::near(spectra, geo, &out, s0, k - 1..=k + 1);
        let pw = here.power(k);
        if pw <= threshold {
            continue; // it was a side lobe of one already cancelled
        }
        let ds = 2.0 / na as f32;
        let dr = quad(here.power(k - 1), pw, here.power(k + 1));
        let left = Residual::near(spectra, geo, &out, s0 - ds, k..=k).power(k);
        let right = Residual::near(spectra, geo, &out, s0 + ds, k..=k).power(k);
        let da = quad(left, pw, right);
        let (r, s) = (k as f32 + dr, (s0 + da * ds).clamp(-1.0, 1.0));
        // Least squares over the main lobe: α = Σ T*·R(k, s) / (C·Σ|T|²).
        let fit = k.saturating_sub(FIT_HALF_WIDTH)..=(k + FIT_HALF_WIDTH).min(m - 1);
        let at = Residual::near(spectra, geo, &out, s, fit.clone());
        let (mut num, mut den) = (C32::new(0.0, 0.0), 0.0f32);
        for kk in fit {
            let t = window_transform(geo.window, kk as f32 - r, geo.samples, geo.fft_len);
            num += t.conj() * at.at(kk);
            den += t.norm_sqr();
        }
        if den <= 0.0 || channels <= 0.0 {
            break;
        }
        let alpha = num / (den * channels);
        if out.push(Reflector::new(geo, r, s, alpha)).is_err() {
            break;
        }
    }
    out
}
