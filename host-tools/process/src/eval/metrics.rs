//! Error statistics and the modified Hausdorff distance of the Metamoran paper.

use nalgebra::Vector3;

/// Median of `v` (NaN-free), `None` when empty.
pub fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let m = s.len() / 2;
    Some(if s.len() % 2 == 1 {
        s[m]
    } else {
        (s[m - 1] + s[m]) / 2.0
    })
}

/// Population standard deviation.
pub fn std_dev(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    Some((v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64).sqrt())
}

/// The `q`-quantile (nearest rank).
pub fn quantile(v: &[f64], q: f64) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    Some(s[((q * s.len() as f64).ceil() as usize).clamp(1, s.len()) - 1])
}

/// Median over `a` of the distance to the nearest point of `b`.
fn directed_median(a: &[[f64; 3]], b: &[[f64; 3]]) -> Option<f64> {
    let nearest: Vec<f64> = a
        .iter()
        .map(|p| {
            let p = Vector3::from(*p);
            b.iter()
                .map(|q| (Vector3::from(*q) - p).norm_squared())
                .fold(f64::INFINITY, f64::min)
                .sqrt()
        })
        .collect();
    median(&nearest)
}

/// Modified Hausdorff distance as the paper defines it: the smaller of the two directed medians
/// of nearest-neighbour distances. O(|a|·|b|).
pub fn modified_hausdorff(a: &[[f64; 3]], b: &[[f64; 3]]) -> Option<f64> {
    if a.is_empty() || b.is_empty() {
        return None;
    }
    Some(directed_median(a, b)?.min(directed_median(b, a)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_forms() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(std_dev(&[1.0, 3.0]), Some(1.0));
        assert_eq!(
            quantile(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0], 0.9),
            Some(9.0)
        );
        // b is a copy of a shifted by 0.5 m in z plus one far outlier: a→b median 0.5, b→a 0.5.
        let a: Vec<[f64; 3]> = (0..5).map(|i| [i as f64, 0.0, 10.0]).collect();
        let mut b: Vec<[f64; 3]> = a.iter().map(|p| [p[0], p[1], p[2] + 0.5]).collect();
        b.push([0.0, 0.0, 100.0]);
        assert!((modified_hausdorff(&a, &b).unwrap() - 0.5).abs() < 1e-12);
        assert_eq!(modified_hausdorff(&a, &[]), None);
    }
}
