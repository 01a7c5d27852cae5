//! Steering-vector (Bartlett) beamforming at an arbitrary angle.

use crate::array::VirtualArray;
use crate::fixed::{CQ15, CQ31, Complex, Q31};
use crate::trig::{Phase, expj_neg};

/// Response of the gathered element values (see [`VirtualArray::gather`]) towards sin θ:
/// `(1/E) Σₚ x[p] · exp(−jπ·p·sin θ)` over the E occupied positions, in Q31.
///
/// The phase steps are exact binary angles, so the result is the same on every platform.
/// O(span).
pub fn beamform(array: &VirtualArray, elements: &[CQ15], sin_theta: f32) -> CQ31 {
    let step = Phase::from_turns(sin_theta as f64 / 2.0).0;
    let (mut re, mut im) = (0i64, 0i64);
    for (p, x) in elements.iter().enumerate().take(array.span()) {
        if !array.occupied(p) {
            continue;
        }
        let w = expj_neg(Phase(step.wrapping_mul(p as u32)));
        let (xr, xi, wr, wi) = (x.re.0 as i64, x.im.0 as i64, w.re.0 as i64, w.im.0 as i64);
        re += xr * wr - xi * wi;
        im += xr * wi + xi * wr;
    }
    let e = array.elements().max(1) as i64;
    // Sum of Q30 products / E is Q30; one more bit makes Q31.
    let q31 = |v: i64| Q31(((2 * v) / e).clamp(i32::MIN as i64, i32::MAX as i64) as i32);
    Complex::new(q31(re), q31(im))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::tests::example;

    /// A plane wave from sin θ = s on every element, amplitude 0.5.
    fn wave(array: &VirtualArray, s: f64) -> std::vec::Vec<CQ15> {
        (0..array.span())
            .map(|p| {
                let ph = core::f64::consts::PI * p as f64 * s;
                CQ15::from_f32((0.5 * libm::cos(ph)) as f32, (0.5 * libm::sin(ph)) as f32)
            })
            .collect()
    }

    #[test]
    fn peaks_at_the_arrival_angle() {
        let a = VirtualArray::new(&example()).unwrap();
        let x = wave(&a, 0.3);
        let on = beamform(&a, &x, 0.3);
        let (r, i) = on.to_f64();
        assert!(((r * r + i * i).sqrt() - 0.5).abs() < 1e-3, "coherent gain");
        let off = beamform(&a, &x, -0.5).to_f64();
        assert!((off.0 * off.0 + off.1 * off.1).sqrt() < 0.2);
    }
}
