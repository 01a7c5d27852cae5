//! Range and Doppler windows as Q15 tables.
//!
//! Windows trade resolution for side lobes before an FFT. Coefficients are the symmetric
//! definitions (as `numpy.hanning`, `numpy.hamming`, `scipy.signal.windows.blackmanharris(sym=True)`),
//! computed by the compiler: `Window::<256>::HANN` is a `[Q15; 256]` constant in flash.
//! Lengths known only at run time use [`fill`], which computes the same values.

use crate::fixed::{CQ15, Complex, Q15};
use crate::trig::cos_sin_turn;

/// A window shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WindowKind {
    /// No window (all ones): best resolution, −13 dB side lobes.
    Rectangular,
    /// Hann: −31 dB side lobes.
    Hann,
    /// Hamming: −43 dB side lobes.
    Hamming,
    /// 4-term Blackman–Harris: −92 dB side lobes, widest main lobe.
    BlackmanHarris,
}

/// The window as a cosine sum: `w[n] = a₀ − a₁·cos(2πn/(L−1)) + a₂·cos(4πn/(L−1)) − a₃·cos(6πn/(L−1))`.
/// Every shape here is one, so its transform has a closed form (see `response::kernel`).
pub const fn cosine_terms(kind: WindowKind) -> [f64; 4] {
    match kind {
        WindowKind::Rectangular => [1.0, 0.0, 0.0, 0.0],
        WindowKind::Hann => [0.5, 0.5, 0.0, 0.0],
        WindowKind::Hamming => [0.54, 0.46, 0.0, 0.0],
        WindowKind::BlackmanHarris => [0.35875, 0.48829, 0.14128, 0.01168],
    }
}

/// [`cosine_terms`] rounded to `f32` (constants, so no soft `f64` on the M7).
pub const fn cosine_terms_f32(kind: WindowKind) -> [f32; 4] {
    const fn f32s(a: [f64; 4]) -> [f32; 4] {
        [a[0] as f32, a[1] as f32, a[2] as f32, a[3] as f32]
    }
    match kind {
        WindowKind::Rectangular => const { f32s(cosine_terms(WindowKind::Rectangular)) },
        WindowKind::Hann => const { f32s(cosine_terms(WindowKind::Hann)) },
        WindowKind::Hamming => const { f32s(cosine_terms(WindowKind::Hamming)) },
        WindowKind::BlackmanHarris => const { f32s(cosine_terms(WindowKind::BlackmanHarris)) },
    }
}

/// Coefficient `n` of a symmetric window of length `len` (f64), usable in constant expressions.
pub const fn coefficient_f64(kind: WindowKind, n: usize, len: usize) -> f64 {
    if len <= 1 {
        return 1.0;
    }
    let (n, den) = (n as i64, len as i64 - 1);
    let a = cosine_terms(kind);
    let (c1, c2, c3) = (
        cos_sin_turn(n, den).0,
        cos_sin_turn(2 * n, den).0,
        cos_sin_turn(3 * n, den).0,
    );
    a[0] - a[1] * c1 + a[2] * c2 - a[3] * c3
}

/// Coefficient `n` of a symmetric window of length `len` in Q15 (1.0 saturates to 32767).
pub const fn coefficient(kind: WindowKind, n: usize, len: usize) -> Q15 {
    Q15::from_f64(coefficient_f64(kind, n, len))
}

/// The whole window as a table, for lengths fixed at compile time.
pub const fn table<const N: usize>(kind: WindowKind) -> [Q15; N] {
    let mut t = [Q15::ZERO; N];
    let mut n = 0;
    while n < N {
        t[n] = coefficient(kind, n, N);
        n += 1;
    }
    t
}

/// Compile-time window tables of length `N`.
pub struct Window<const N: usize>;

impl<const N: usize> Window<N> {
    /// Hann window.
    pub const HANN: [Q15; N] = table(WindowKind::Hann);
    /// Hamming window.
    pub const HAMMING: [Q15; N] = table(WindowKind::Hamming);
    /// 4-term Blackman–Harris window.
    pub const BLACKMAN_HARRIS: [Q15; N] = table(WindowKind::BlackmanHarris);
}

/// Fills `out` with the window of length `out.len()`. O(N).
pub fn fill(kind: WindowKind, out: &mut [Q15]) {
    let len = out.len();
    for (n, w) in out.iter_mut().enumerate() {
        *w = coefficient(kind, n, len);
    }
}

/// Multiplies samples by window coefficients pairwise (rounded; |w| < 1 so nothing overflows).
/// Processes `min(samples.len(), window.len())` samples.
pub fn apply(window: &[Q15], samples: &mut [CQ15]) {
    for (z, w) in samples.iter_mut().zip(window) {
        let w = w.0 as i32;
        let mul = |x: Q15| Q15(((x.0 as i32 * w + (1 << 14)) >> 15) as i16);
        *z = Complex::new(mul(z.re), mul(z.im));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_match_closed_forms() {
        use core::f64::consts::PI;
        let n = 64;
        let hann = Window::<64>::HANN;
        let hamming = Window::<64>::HAMMING;
        let bh = Window::<64>::BLACKMAN_HARRIS;
        for i in 0..n {
            let x = 2.0 * PI * i as f64 / (n - 1) as f64;
            let q = |v: f64| (v * 32768.0).round().min(32767.0);
            assert_eq!(hann[i].0 as f64, q(0.5 - 0.5 * libm::cos(x)));
            assert_eq!(hamming[i].0 as f64, q(0.54 - 0.46 * libm::cos(x)));
            let b = 0.35875 - 0.48829 * libm::cos(x) + 0.14128 * libm::cos(2.0 * x)
                - 0.01168 * libm::cos(3.0 * x);
            assert!((bh[i].0 as f64 - q(b)).abs() <= 1.0);
        }
        assert_eq!(hann[0].0, 0);
        assert_eq!(hann[31], hann[32]); // symmetric
    }

    #[test]
    fn fill_equals_table() {
        let mut v = [Q15::ZERO; 100];
        fill(WindowKind::Hann, &mut v);
        assert_eq!(v[0].0, 0);
        assert_eq!(v[1], coefficient(WindowKind::Hann, 1, 100));
        let t: [Q15; 16] = table(WindowKind::Hamming);
        let mut f = [Q15::ZERO; 16];
        fill(WindowKind::Hamming, &mut f);
        assert_eq!(t, f);
    }
}
