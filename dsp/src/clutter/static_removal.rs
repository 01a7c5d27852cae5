//! Static clutter removal: subtract the mean over chirps from each (channel, range bin).
//!
//! A static reflector has the same phase in every chirp, so its energy sits in the mean; what
//! remains is what moved. Done after the range FFT it is the same linear operation as the
//! per-sample mean the TI recipes subtract before it.

use crate::fixed::CQ15;

/// Subtracts the mean of `column` from every value. If the difference could exceed Q15 the
/// column is halved first; returns the added exponent (0 or 1). O(N).
pub fn remove_mean(column: &mut [CQ15]) -> u32 {
    if column.is_empty() {
        return 0;
    }
    let n = column.len() as i64;
    let (sr, si) = column.iter().fold((0i64, 0i64), |(r, i), z| {
        (r + z.re.0 as i64, i + z.im.0 as i64)
    });
    let mean = |s: i64| libm::round(s as f64 / n as f64) as i32;
    let (mr, mi) = (mean(sr), mean(si));
    let fits = column.iter().all(|z| {
        let (dr, di) = (z.re.0 as i32 - mr, z.im.0 as i32 - mi);
        (-32768..=32767).contains(&dr) && (-32768..=32767).contains(&di)
    });
    let shift = u32::from(!fits);
    let half = |v: i32| if shift == 1 { (v + 1) >> 1 } else { v };
    for z in column.iter_mut() {
        let r = half(z.re.0 as i32 - mr);
        let i = half(z.im.0 as i32 - mi);
        *z = CQ15::from_raw(r as i16, i as i16);
    }
    shift
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removes_constant_and_keeps_variation() {
        let mut c: std::vec::Vec<CQ15> = (0..8)
            .map(|k| CQ15::from_raw(1000 + if k % 2 == 0 { 50 } else { -50 }, -300))
            .collect();
        assert_eq!(remove_mean(&mut c), 0);
        assert_eq!(c[0], CQ15::from_raw(50, 0));
        assert_eq!(c[1], CQ15::from_raw(-50, 0));
    }

    #[test]
    fn halves_instead_of_overflowing() {
        let mut c = [
            CQ15::from_raw(32767, 0),
            CQ15::from_raw(-32768, 0),
            CQ15::from_raw(-32768, 0),
        ];
        assert_eq!(remove_mean(&mut c), 1);
        // mean −10923; 32767 + 10923 = 43690 → 21845
        assert_eq!(c[0].re.0, 21845);
    }
}
