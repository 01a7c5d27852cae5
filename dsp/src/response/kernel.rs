//! Closed forms the search and SIC use to synthesize a point reflector without an FFT: the
//! range spectrum of a windowed tone, the array factor, and a row of interpolation weights.
//!
//! A reflector at fractional range bin `r` and direction `sin θ = s` with amplitude `α` adds
//! `α · T(k − r) · AF(s − s')` to the beam toward `s'` at bin `k`, where `T` is the window's
//! transform and `AF` the array factor of the (possibly overlapping) virtual elements. Both are
//! `f32` with `libm`, so every platform computes the same bits.

use super::dirichlet::dirichlet;
use crate::fft::C32;
use crate::trig::cos_sin_pi;
use crate::window::{WindowKind, cosine_terms_f32};

/// Bins on each side of a reflector's range that its synthesized spectrum covers. Hann side
/// lobes are below −75 dB this far out.
pub const SPREAD: usize = 16;

/// `T(x) = Σₙ w[n]·exp(−j2π·x·n/M)`: the M-point spectrum of an N-sample window at offset `x`
/// bins from the tone, for any cosine-sum window (closed form, no FFT). O(1).
pub fn window_transform(kind: WindowKind, x: f32, n: usize, m: usize) -> C32 {
    let a = cosine_terms_f32(kind);
    let (mf, period) = (m as f32, n.saturating_sub(1).max(1) as f32);
    // Σₙ exp(−j2π·y·n/M) = M·D(−y) with D the periodic sinc of `dirichlet`.
    let g = |y: f32| {
        let (re, im) = dirichlet(-y, n, m);
        C32::new(re * mf, im * mf)
    };
    let mut t = g(x) * a[0];
    for (q, &aq) in a.iter().enumerate().skip(1) {
        if aq == 0.0 {
            continue;
        }
        let sign = if q % 2 == 1 { -0.5 } else { 0.5 };
        let shift = q as f32 * mf / period;
        t += (g(x - shift) + g(x + shift)) * (sign * aq);
    }
    t
}

/// The phase step `sin θ / 2` turns as a binary angle (`exp(−jπ·p·sin θ)` is the weight of the
/// element at `p` half-wavelengths).
pub fn half_turns(sin_az: f32) -> u32 {
    // Scaling by 2³¹ is exact in f32: the same value as through f64, without soft f64.
    (sin_az * 2147483648.0) as i64 as u32
}

/// `AF(u) = Σₑ cₑ·exp(jπ·pₑ·u)` for element positions `p` (ascending) and channel counts `c`,
/// as a polynomial in `z = exp(jπu)` by Horner's rule in `f32`: one `sincos` and one complex
/// multiply per half-wavelength of aperture, O(span).
pub fn array_factor(positions: &[u16], counts: &[u8], u: f32) -> C32 {
    let (c, s) = cos_sin_pi(u);
    let z = C32::new(c, s);
    let mut acc = C32::new(0.0, 0.0);
    let mut above = None;
    for (&p, &n) in positions.iter().zip(counts).rev() {
        // Multiply by z once per half-wavelength down to this element.
        for _ in p..above.unwrap_or(p) {
            acc *= z;
        }
        acc.re += n as f32;
        above = Some(p);
    }
    for _ in 0..above.unwrap_or(0) {
        acc *= z;
    }
    acc
}

/// Interpolation weights of a zero-padded spectrum (N samples, M bins): the per-bin rotations
/// are computed once, so each interpolation costs three `sincos` for its start angles.
#[derive(Clone, Copy, Debug)]
pub struct Interpolator {
    n: usize,
    m: usize,
    /// Rotations by πN/M, π/M and π(N−1)/M: one bin's step of each angle.
    steps: [C32; 3],
}

/// `exp(jπx)` for `x` in half-turns.
fn rot(x: f32) -> C32 {
    let (c, s) = cos_sin_pi(x);
    C32::new(c, s)
}

impl Interpolator {
    /// For `n` samples in an `m`-point spectrum.
    pub fn new(n: usize, m: usize) -> Self {
        let (nf, mf) = (n as f32, m as f32);
        Self {
            n,
            m,
            steps: [rot(nf / mf), rot(1.0 / mf), rot((nf - 1.0) / mf)],
        }
    }

    /// Calls `each(b, D(b − f))` (see [`dirichlet`]) for bins `first..first + len`, the sines
    /// advanced by rotation instead of evaluated per bin. O(len).
    pub fn for_each(&self, f: f32, first: usize, len: usize, mut each: impl FnMut(usize, C32)) {
        let (nf, mf) = (self.n as f32, self.m as f32);
        let x0 = first as f32 - f;
        // Angles πxN/M (numerator), πx/M (denominator), πx(N−1)/M (phase), stepped by x += 1.
        let (mut num, mut den, mut ph) =
            (rot(x0 * nf / mf), rot(x0 / mf), rot(x0 * (nf - 1.0) / mf));
        let [dn, dd, dp] = self.steps;
        for t in 0..len {
            let w = if den.im.abs() < 2e-3 {
                let (re, im) = dirichlet(x0 + t as f32, self.n, self.m);
                C32::new(re, im)
            } else {
                ph * (num.im / (mf * den.im))
            };
            each(first + t, w);
            num *= dn;
            den *= dd;
            ph *= dp;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::window::coefficient_f64;

    #[test]
    fn window_transform_matches_the_sum() {
        for kind in [
            WindowKind::Hann,
            WindowKind::BlackmanHarris,
            WindowKind::Rectangular,
        ] {
            for &(x, n, m) in &[
                (0.0f32, 64usize, 64usize),
                (0.37, 64, 64),
                (-3.6, 48, 64),
                (7.25, 512, 512),
            ] {
                let (mut re, mut im) = (0.0f64, 0.0f64);
                for i in 0..n {
                    let w = coefficient_f64(kind, i, n);
                    let a = -2.0 * core::f64::consts::PI * x as f64 * i as f64 / m as f64;
                    re += w * libm::cos(a);
                    im += w * libm::sin(a);
                }
                let t = window_transform(kind, x, n, m);
                let err = ((t.re as f64 - re).powi(2) + (t.im as f64 - im).powi(2)).sqrt();
                assert!(
                    err < 2e-4 * n as f64,
                    "{kind:?} x={x}: {t:?} vs ({re}, {im})"
                );
            }
        }
    }

    #[test]
    fn array_factor_matches_the_sum() {
        // A small irregular array, and a cascade-like one: 86 elements over 250 half-wavelengths.
        let wide: (std::vec::Vec<u16>, std::vec::Vec<u8>) = (
            (0..86u16).map(|i| i * 3 - i / 7).collect(),
            (0..86u8).map(|i| 1 + i % 3).collect(),
        );
        for (p, c) in [
            (&[0u16, 1, 2, 5, 9][..], &[1u8, 2, 1, 1, 3][..]),
            (&wide.0, &wide.1),
        ] {
            let total: f64 = c.iter().map(|&n| n as f64).sum();
            for u in [0.0f32, 0.1, -0.37, 0.9, 0.0123, -1.7] {
                let (mut re, mut im) = (0.0f64, 0.0f64);
                for (&pp, &cc) in p.iter().zip(c) {
                    let a = core::f64::consts::PI * pp as f64 * u as f64;
                    re += cc as f64 * libm::cos(a);
                    im += cc as f64 * libm::sin(a);
                }
                let af = array_factor(p, c, u);
                let tol = 2e-5 * total;
                assert!(
                    (af.re as f64 - re).abs() < tol && (af.im as f64 - im).abs() < tol,
                    "u={u}: {af:?} vs ({re}, {im})"
                );
            }
        }
    }

    #[test]
    fn rotated_weights_match_dirichlet() {
        let (n, m) = (400usize, 512usize);
        for f in [100.0f32, 100.3, 117.77] {
            Interpolator::new(n, m).for_each(f, 80, 48, |b, w| {
                let (re, im) = dirichlet(b as f32 - f, n, m);
                assert!(
                    (w.re - re).abs() < 1e-4 && (w.im - im).abs() < 1e-4,
                    "f={f} b={b}"
                );
            });
        }
    }
}
