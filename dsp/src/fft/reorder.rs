//! Bit-reversal reordering from a swap table built by the compiler.
//!
//! A DIF FFT leaves its output in bit-reversed order. Instead of reversing every index at run
//! time, the table lists the `(i, rev(i))` pairs with `i < rev(i)` for every supported length
//! (1,950 pairs, 7.8 KiB of flash); reordering is one load and two swaps per pair.

use super::{MAX_LEN, MIN_LEN};

const MIN_BITS: u32 = MIN_LEN.trailing_zeros();
const MAX_BITS: u32 = MAX_LEN.trailing_zeros();

/// Pairs to swap for a length of `2^bits`: all indices minus the palindromes, halved.
const fn pairs(bits: u32) -> usize {
    ((1usize << bits) - (1usize << bits.div_ceil(2))) / 2
}

const fn total() -> usize {
    let mut t = 0;
    let mut b = MIN_BITS;
    while b <= MAX_BITS {
        t += pairs(b);
        b += 1;
    }
    t
}

const TOTAL: usize = total();

/// Every length's pairs, packed `i | rev(i) << 16`, lengths in increasing order.
static SWAPS: [u32; TOTAL] = {
    let mut t = [0u32; TOTAL];
    let mut at = 0;
    let mut b = MIN_BITS;
    while b <= MAX_BITS {
        let mut i = 0u32;
        while i < (1 << b) {
            let r = i.reverse_bits() >> (32 - b);
            if i < r {
                t[at] = i | (r << 16);
                at += 1;
            }
            i += 1;
        }
        b += 1;
    }
    t
};

/// The swap pairs of a supported length `n`.
fn swaps(n: usize) -> &'static [u32] {
    let bits = n.trailing_zeros();
    let mut start = 0;
    let mut b = MIN_BITS;
    while b < bits {
        start += pairs(b);
        b += 1;
    }
    SWAPS.get(start..start + pairs(bits)).unwrap_or(&[])
}

/// Reorders a bit-reversed sequence of supported length into natural order.
pub fn bit_reverse<T>(buf: &mut [T]) {
    for &pair in swaps(buf.len()) {
        let (i, r) = ((pair & 0xFFFF) as usize, (pair >> 16) as usize);
        // `i < r` in every table entry: split there and swap across the halves.
        if let Some((lo, hi)) = buf.split_at_mut_checked(r)
            && let (Some(a), Some(b)) = (lo.get_mut(i), hi.first_mut())
        {
            core::mem::swap(a, b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_index_reversal() {
        for bits in MIN_BITS..=MAX_BITS {
            let n = 1usize << bits;
            let mut v: std::vec::Vec<usize> = (0..n).collect();
            bit_reverse(&mut v);
            for (i, &x) in v.iter().enumerate() {
                assert_eq!(x, i.reverse_bits() >> (usize::BITS - bits), "n={n} i={i}");
            }
        }
        assert_eq!(TOTAL, 1950);
    }
}
