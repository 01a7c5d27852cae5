//! The periodic sinc that interpolates a zero-padded DFT exactly.

use crate::trig::cos_sin_pi;

/// `D(x) = (1/M) Σ_{n<N} exp(j2π·x·n/M)`: the weight of bin `k` in the spectrum of N samples
/// (zero-padded to M points) evaluated at the fractional bin `k + x`. Returns `(re, im)`.
/// Three [`cos_sin_pi`]; O(1).
pub fn dirichlet(x: f32, n: usize, m: usize) -> (f32, f32) {
    let (nf, mf) = (n as f32, m as f32);
    let den = cos_sin_pi(x / mf).1;
    let mag = if den.abs() < 1e-7 {
        nf / mf
    } else {
        cos_sin_pi(x * nf / mf).1 / (mf * den)
    };
    let (c, s) = cos_sin_pi(x * (nf - 1.0) / mf);
    (mag * c, mag * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_sum() {
        for &(x, n, m) in &[
            (0.3f32, 8usize, 16usize),
            (-2.7, 100, 128),
            (5.0, 64, 64),
            (0.0, 10, 16),
        ] {
            let (mut re, mut im) = (0.0f64, 0.0f64);
            for k in 0..n {
                let a = 2.0 * core::f64::consts::PI * x as f64 * k as f64 / m as f64;
                re += libm::cos(a) / m as f64;
                im += libm::sin(a) / m as f64;
            }
            let (r, i) = dirichlet(x, n, m);
            assert!(
                (r as f64 - re).abs() < 1e-5 && (i as f64 - im).abs() < 1e-5,
                "x={x} n={n} m={m}"
            );
        }
    }
}
