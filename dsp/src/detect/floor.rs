//! The noise level of a whole detection map, beside the CFAR's local one: the median of its
//! magnitudes, which is the receiver's noise wherever noise fills most of the map. A screen
//! that lets cells through below the CFAR's threshold (`points::Screen`) keeps above it.
//!
//! The median is bounded from a histogram of the values' float bit patterns (eight buckets
//! per octave, their edges the floats with three mantissa bits), so it needs no sorting, no
//! buffer and no floating-point arithmetic: the same bits on every target. The depth search's
//! exact median (`search::depth`) is not shared: its 16-bit counts would saturate on a map of
//! more than 65,535 cells, and widening them changes the module's golden instruction counts.

/// Buckets of [`median_floor`]'s histogram, eight per octave (each at most 1/8 wider than its
/// lower edge, 1.02 dB of magnitude): 16 octaves (96 dB) under the map's largest value.
pub const FLOOR_BUCKETS: usize = 128;

/// Bits of an `f32` under its bucket's: the 23 mantissa bits less the 3 kept.
const SHIFT: u32 = 20;

/// A lower bound of the median of `map`'s values (magnitudes), within an eighth of itself:
/// `floor ≤ median < 1.125 · floor` (1.02 dB). The median is the ⌈n/2⌉-th smallest value.
/// Values that are not positive and finite count as the smallest. When the median lies more
/// than 96 dB ([`FLOOR_BUCKETS`]) under the largest value, the result is the lowest bucket's
/// edge, which is above it; 0 for a map without a positive value.
/// O(n), no allocation; the result is exact to the bit on every target.
///
/// ```
/// use metamoran_dsp::detect::median_floor;
/// // Mostly noise near 1.0, a few strong returns.
/// let mut map = [1.0f32; 100];
/// map[3] = 5000.0;
/// map[40] = 900.0;
/// let floor = median_floor(&map);
/// assert!(floor <= 1.0 && 1.0 < floor * 1.125);
/// ```
pub fn median_floor(map: &[f32]) -> f32 {
    let valid = |v: f32| v.is_finite() && v > 0.0;
    let Some(top) = map
        .iter()
        .filter(|&&v| valid(v))
        .map(|v| v.to_bits() >> SHIFT)
        .max()
    else {
        return 0.0;
    };
    // Bucket 0 holds the largest values; positive floats' bits order as the values do.
    let mut counts = [0usize; FLOOR_BUCKETS];
    for &v in map {
        let below = if valid(v) {
            (top - (v.to_bits() >> SHIFT)) as usize
        } else {
            FLOOR_BUCKETS
        };
        counts[below.min(FLOOR_BUCKETS - 1)] += 1;
    }
    let rank = map.len().div_ceil(2);
    let mut seen = 0;
    // From the smallest values up: the bucket that holds the rank-th smallest.
    let below = (0..FLOOR_BUCKETS)
        .rev()
        .find(|&b| {
            seen += counts[b];
            seen >= rank
        })
        .unwrap_or(0);
    f32::from_bits(top.saturating_sub(below as u32) << SHIFT)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    /// The exact median (the ⌈n/2⌉-th smallest), non-positive values as the smallest.
    fn exact(map: &[f32]) -> f32 {
        let mut v: Vec<f32> = map.iter().map(|&x| x.max(0.0)).collect();
        v.sort_by(f32::total_cmp);
        v[map.len().div_ceil(2) - 1]
    }

    #[test]
    fn bounds_the_median_within_an_eighth_of_itself() {
        // Log-uniform values over 60 dB and an outlier 20 dB over them, odd and even lengths (a
        // xorshift generator, so the test needs no crate).
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [1usize, 2, 3, 10, 101, 1000, 4096] {
            for _ in 0..20 {
                let mut map: Vec<f32> = (0..n).map(|_| 10f64.powf(3.0 * next()) as f32).collect();
                map[0] = 1e4;
                let (floor, median) = (median_floor(&map), exact(&map));
                let ratio = f64::from(median) / f64::from(floor);
                assert!(
                    (1.0..1.125).contains(&ratio),
                    "n {n}: floor {floor}, median {median}"
                );
            }
        }
    }

    #[test]
    fn counts_what_is_not_a_magnitude_as_the_smallest() {
        assert_eq!(median_floor(&[]), 0.0);
        assert_eq!(median_floor(&[0.0, -1.0, f32::NAN]), 0.0);
        // Three of five are not magnitudes: the median is the lowest bucket's edge, 96 dB under.
        let map = [4.0, 4.0, 0.0, f32::NAN, f32::INFINITY];
        let floor = median_floor(&map);
        assert!(
            floor > 0.0 && floor < 4.0 * 10f32.powf(-95.0 / 20.0),
            "{floor}"
        );
        // Two of five: the median is 4.
        let map = [4.0, 4.0, 4.0, 0.0, f32::NAN];
        assert_eq!(median_floor(&map), 4.0);
    }
}
