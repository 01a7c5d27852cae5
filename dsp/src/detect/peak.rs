//! Sub-bin peak position by a parabola through three bins.

/// Offset in bins (−0.5..=0.5) of the vertex of the parabola through `(−1, left)`,
/// `(0, centre)`, `(1, right)`; 0 when the three points are not a peak. For a windowed FFT peak,
/// pass magnitudes in dB for the smallest bias.
// The negated comparisons are deliberate: a NaN anywhere fails them and gives 0.
#[allow(clippy::neg_cmp_op_on_partial_ord, clippy::nonminimal_bool)]
pub fn quadratic_offset(left: f32, centre: f32, right: f32) -> f32 {
    let denom = left - 2.0 * centre + right;
    if !(denom < 0.0) || !(centre >= left && centre >= right) {
        return 0.0;
    }
    (0.5 * (left - right) / denom).clamp(-0.5, 0.5)
}

/// Whether `x[i]` is at least each existing neighbour and strictly above one of them.
pub fn is_local_max(x: &[f32], i: usize) -> bool {
    let Some(&v) = x.get(i) else { return false };
    let left = i.checked_sub(1).and_then(|j| x.get(j)).copied();
    let right = x.get(i + 1).copied();
    let ge = |n: Option<f32>| n.is_none_or(|n| v >= n);
    let gt = |n: Option<f32>| n.is_some_and(|n| v > n);
    ge(left) && ge(right) && (gt(left) || gt(right) || x.len() == 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_on_a_parabola() {
        // y = −(x − 0.3)² + 5 sampled at −1, 0, 1
        let f = |x: f32| -(x - 0.3) * (x - 0.3) + 5.0;
        assert!((quadratic_offset(f(-1.0), f(0.0), f(1.0)) - 0.3).abs() < 1e-6);
        assert_eq!(quadratic_offset(1.0, 0.0, 1.0), 0.0);
        assert_eq!(quadratic_offset(f32::NAN, 1.0, 0.0), 0.0);
    }

    #[test]
    fn local_max() {
        let x = [1.0, 3.0, 3.0, 0.0, 2.0];
        assert!(is_local_max(&x, 1) && is_local_max(&x, 2) && is_local_max(&x, 4));
        assert!(!is_local_max(&x, 0) && !is_local_max(&x, 3) && !is_local_max(&x, 9));
    }
}
