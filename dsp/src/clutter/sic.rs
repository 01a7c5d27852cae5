//! Successive interference cancellation (Metamoran, Sec. III-B): strong reflectors outside the
//! object's azimuth span are estimated as point reflectors — range, azimuth, and a complex
//! amplitude fitted to the data (the paper's "α equal to the peak") — their synthesized signal
//! (Eq. 1) is subtracted, and the next strongest is taken, until what is left outside the span
//! is weak next to the strongest return inside it (the caller's ratio; inside the span at short
//! range, that "return" is often itself the side lobes being cancelled), or [`MAX_REFLECTORS`]
//! are gone.
//!
//! It works on a frame's static sums ([`crate::range::StaticSum`]): the windowed samples and
//! their spectra are both updated, so a matched filter on either sees the cleaned scene. The
//! static sums fill chirp by chirp as the frame streams in; cancellation then runs once per
//! frame. Memory: the caller's `channels × (N + M)` sums plus `M + Nₐ` scratch values and at most
//! [`MAX_REFLECTORS`] estimates: bounded by the configuration, not by the scene.

use crate::fft::{C32, cfft_f32};
use crate::search::depth::Geometry;
use heapless::Vec;

/// Most reflectors cancelled per object.
pub const MAX_REFLECTORS: usize = 32;

/// A cancelled reflector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reflector {
    /// Range, bins of the M-point FFT (fractional).
    pub range_bins: f32,
    /// sin(azimuth).
    pub sin_az: f32,
    /// Fitted complex amplitude (windowed-sum units).
    pub amplitude: C32,
}

/// Scratch for [`cancel`]: `elements` of the azimuth FFT length (a power of two ≥ the array
/// span), `tone` of M.
pub struct SicScratch<'a> {
    /// Azimuth FFT buffer.
    pub elements: &'a mut [C32],
    /// One reflector's spectrum.
    pub tone: &'a mut [C32],
}

fn steer(p: f32, s: f32) -> C32 {
    let a = -core::f32::consts::PI * p * s;
    C32::new(libm::cosf(a), libm::sinf(a))
}

fn norm2(z: C32) -> f32 {
    z.re * z.re + z.im * z.im
}

/// Beamformed value of bin `k` toward `s`.
fn beam(spectra: &[C32], geo: &Geometry<'_>, k: usize, s: f32) -> C32 {
    let m = geo.fft_len;
    let mut acc = C32::new(0.0, 0.0);
    for (ch, &p) in geo.positions.iter().enumerate() {
        acc += spectra[ch * m + k] * steer(p, s);
    }
    acc
}

fn quad(l: f32, c: f32, r: f32) -> f32 {
    let db = |x: f32| libm::log10f(x.max(1e-30));
    crate::detect::quadratic_offset(db(l), db(c), db(r))
}

/// Cancels reflectors outside the sin-azimuth intervals `keep` (the object's span, widened by
/// the caller by a main-lobe width) from range bins `1..max_bin`, strongest first, while the
/// strongest one left outside has more than `stop_ratio` times the power of the strongest cell
/// inside. Returns what it cancelled. O(iterations · M · (C + Nₐ log Nₐ)).
#[allow(clippy::too_many_arguments)]
pub fn cancel(
    spectra: &mut [C32],
    samples: &mut [C32],
    geo: &Geometry<'_>,
    window: &[f32],
    keep: &[(f32, f32)],
    max_bin: usize,
    stop_ratio: f32,
    scratch: SicScratch<'_>,
) -> Vec<Reflector, MAX_REFLECTORS> {
    let (c, n, m) = (geo.positions.len(), geo.samples, geo.fft_len);
    let mut out = Vec::new();
    let na = scratch.elements.len();
    if spectra.len() != c * m
        || samples.len() != c * n
        || window.len() != n
        || scratch.tone.len() != m
        || c == 0
    {
        return out;
    }
    let pmin = geo.positions.iter().copied().fold(f32::INFINITY, f32::min);
    let index: Vec<usize, 256> = geo
        .positions
        .iter()
        .map(|&p| libm::roundf(p - pmin) as usize)
        .take(256)
        .collect();
    if index.iter().any(|&i| i >= na) {
        return out;
    }
    let inside = |s: f32| keep.iter().any(|&(lo, hi)| s >= lo && s <= hi);
    let sin_of = |j: usize| 2.0 * crate::units::signed_bin(j, na) as f32 / na as f32;
    while out.len() < MAX_REFLECTORS {
        let (mut best_out, mut best_in) = ((0.0f32, 0usize, 0usize), 0.0f32);
        for k in 1..max_bin.min(m) {
            scratch.elements.fill(C32::new(0.0, 0.0));
            for (ch, &i) in index.iter().enumerate() {
                scratch.elements[i] += spectra[ch * m + k];
            }
            if cfft_f32(scratch.elements).is_err() {
                return out;
            }
            // The FFT computes Σ x·exp(−j2πjp/Nₐ): direction sin θ = 2j/Nₐ.
            for (j, z) in scratch.elements.iter().enumerate() {
                let s = sin_of(j);
                if s.abs() > 1.0 {
                    continue;
                }
                let pw = norm2(*z);
                if inside(s) {
                    best_in = best_in.max(pw);
                } else if pw > best_out.0 {
                    best_out = (pw, k, j);
                }
            }
        }
        let (pw, k, j) = best_out;
        if pw <= stop_ratio * best_in || pw == 0.0 {
            break;
        }
        // Refine range and azimuth by parabolas through the neighbours (in dB).
        let s0 = sin_of(j);
        let ds = 2.0 / na as f32;
        let at = |kk: usize, s: f32| norm2(beam(spectra, geo, kk, s));
        let dr = if k + 1 < m {
            quad(at(k - 1, s0), pw, at(k + 1, s0))
        } else {
            0.0
        };
        let da = quad(at(k, s0 - ds), pw, at(k, s0 + ds));
        let (r, s) = (k as f32 + dr, (s0 + da * ds).clamp(-1.0, 1.0));
        // The reflector's spectrum: window · exp(j2π r n / M), transformed.
        let w = 2.0 * core::f32::consts::PI * r / m as f32;
        scratch.tone.fill(C32::new(0.0, 0.0));
        for (nn, (t, &wv)) in scratch.tone.iter_mut().zip(window).enumerate() {
            let a = w * nn as f32;
            *t = C32::new(libm::cosf(a), libm::sinf(a)) * wv;
        }
        if cfft_f32(scratch.tone).is_err() {
            return out;
        }
        // Least-squares amplitude over the main lobe (±6 bins) of every channel.
        let (lo, hi) = (k.saturating_sub(6), (k + 7).min(m));
        let (mut num, mut den) = (C32::new(0.0, 0.0), 0.0f32);
        for (ch, &p) in geo.positions.iter().enumerate() {
            let e = steer(p, s).conj(); // exp(+jπ p s)
            for kk in lo..hi {
                let model = e * scratch.tone[kk];
                num += model.conj() * spectra[ch * m + kk];
                den += norm2(model);
            }
        }
        if den <= 0.0 {
            break;
        }
        let alpha = num / den;
        // Subtract from spectra and samples.
        for (ch, &p) in geo.positions.iter().enumerate() {
            let e = steer(p, s).conj() * alpha;
            for (x, &t) in spectra[ch * m..(ch + 1) * m]
                .iter_mut()
                .zip(scratch.tone.iter())
            {
                *x -= e * t;
            }
            for (nn, (x, &wv)) in samples[ch * n..(ch + 1) * n]
                .iter_mut()
                .zip(window)
                .enumerate()
            {
                let a = w * nn as f32;
                *x -= e * C32::new(libm::cosf(a), libm::sinf(a)) * wv;
            }
        }
        if out
            .push(Reflector {
                range_bins: r,
                sin_az: s,
                amplitude: alpha,
            })
            .is_err()
        {
            break;
        }
    }
    out
}
