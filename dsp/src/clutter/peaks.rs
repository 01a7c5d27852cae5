//! The frame's strongest reflectors: one pass over the range–azimuth map (a zero-padded Q15
//! azimuth FFT per range bin), keeping the [`MAX_PEAKS`] strongest local maxima. Shared by every
//! object of the frame; SIC takes its candidates from here.
//!
//! Memory: the azimuth FFT buffer and three rows of powers (caller-owned); the map itself is
//! never stored. O(bins · Nₐ log Nₐ).

use crate::fixed::CQ15;
use crate::range::Spectra;
use crate::range::frame_sum::unpack;
use heapless::Vec;

/// Most peaks kept per frame.
pub const MAX_PEAKS: usize = 64;

/// A local maximum of the range–azimuth power map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Peak {
    /// Range bin.
    pub bin: u16,
    /// Azimuth FFT bin (natural order; `sin θ = 2·signed(bin)/Nₐ`).
    pub az: u16,
    /// `|B|²` in the spectra's stored units.
    pub power: u64,
}

impl Peak {
    /// sin(azimuth) of the peak's bin for an `na`-point azimuth FFT.
    pub fn sin_az(&self, na: usize) -> f32 {
        2.0 * crate::units::signed_bin(self.az as usize, na) as f32 / na as f32
    }
}

/// Why the scan could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ScanError {
    /// The azimuth FFT length is unsupported or shorter than the array span.
    AzimuthLen(usize),
    /// The power rows hold fewer than `3·Nₐ` values.
    Rows(usize),
}

impl core::error::Error for ScanError {}

impl core::fmt::Display for ScanError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::AzimuthLen(n) => write!(
                f,
                "azimuth FFT of {n} points: use a supported length at least the array span"
            ),
            Self::Rows(n) => write!(
                f,
                "power rows hold {n} values: give 3 × the azimuth FFT length"
            ),
        }
    }
}

/// Scans range bins `1..max_bin` and returns the strongest local maxima (3 × 3 neighbourhood,
/// azimuth circular), strongest first; ties keep the earlier peak. `fft` is the azimuth FFT
/// buffer (its length is Nₐ), `rows` scratch of `3·Nₐ` powers.
///
/// # Errors
/// [`ScanError`] for an unusable buffer.
pub fn scan(
    spectra: &Spectra<'_>,
    positions: &[u16],
    max_bin: usize,
    fft: &mut [CQ15],
    rows: &mut [u64],
) -> Result<Vec<Peak, MAX_PEAKS>, ScanError> {
    let na = fft.len();
    let span = positions
        .iter()
        .copied()
        .max()
        .map_or(0, |p| p as usize + 1);
    if !crate::fft::is_supported_len(na) || na < span {
        return Err(ScanError::AzimuthLen(na));
    }
    let have = rows.len();
    let rows = rows.get_mut(..3 * na).ok_or(ScanError::Rows(have))?;
    rows.fill(0);
    let mut out: Vec<Peak, MAX_PEAKS> = Vec::new();
    let last = max_bin.min(spectra.bins());
    let filled = is_filled(positions);
    // Row of bin k lives at slot k % 3; bin 0 and bin `last` count as empty rows.
    for k in 1..=last {
        let slot = k % 3;
        if k < last {
            load_column(spectra.column(k), positions, filled, fft);
            let shift = crate::fft::cfft_q15_bit_reversed(fft).map_or(0, |e| 2 * e.0);
            power_row(&mut rows[slot * na..(slot + 1) * na], fft, shift);
        } else {
            rows[slot * na..(slot + 1) * na].fill(0);
        }
        if k >= 2 {
            find_maxima(rows, na, k - 1, &mut out);
        }
    }
    Ok(out)
}

/// Whether elements sit at positions 0, 1, 2, … (a filled aperture). O(E).
pub(crate) fn is_filled(positions: &[u16]) -> bool {
    positions.iter().enumerate().all(|(e, &p)| p as usize == e)
}

/// One bin's `column` (a word per element) placed at the elements' positions in `fft`, zero
/// elsewhere: the input of an azimuth FFT. A `filled` aperture ([`is_filled`]) is a word copy.
/// O(len).
pub(crate) fn load_column(column: &[u32], positions: &[u16], filled: bool, fft: &mut [CQ15]) {
    match (
        filled,
        crate::fixed::words_mut(fft).split_at_mut_checked(column.len()),
    ) {
        (true, Some((head, tail))) => {
            head.copy_from_slice(column);
            tail.fill(0);
        }
        _ => {
            fft.fill(CQ15::default());
            for (&p, &w) in positions.iter().zip(column) {
                if let Some(slot) = fft.get_mut(p as usize) {
                    *slot = unpack(w);
                }
            }
        }
    }
}

/// `|X|² · 2^shift` of a bit-reversed azimuth spectrum, in natural order: natural bin `i` is read
/// from its reversed index (no reorder pass). `|X|² ≤ 2³¹` fits a `u32` (`SMUAD` of the word
/// with itself, exact as unsigned) and `shift = 2·exponent ≤ 22` keeps the result below 2⁵⁴;
/// the 64-bit shift is three 32-bit ones, valid for any `shift < 32`. O(Nₐ), about 13
/// instructions per cell on the M7.
fn power_row(row: &mut [u64], fft: &[CQ15], shift: u32) {
    let (na, words) = (fft.len(), crate::fixed::words(fft));
    let (up, down) = (shift.min(31), 31 - shift.min(31));
    for (i, o) in row.iter_mut().enumerate() {
        let w = words
            .get(crate::fft::bit_reversed(i, na))
            .copied()
            .unwrap_or(0);
        let p = crate::fft::simd::smuad(w, w);
        *o = (((p >> 1) >> down) as u64) << 32 | (p << up) as u64;
    }
}

/// Local maxima of the row of bin `k` (its neighbours are the rows of `k ± 1`). Once `out` is
/// full, a cell at or below its weakest peak could not enter it, so one comparison rejects it:
/// the scan then costs a load and a compare for almost every cell.
fn find_maxima(rows: &[u64], na: usize, k: usize, out: &mut Vec<Peak, MAX_PEAKS>) {
    let row = |kk: usize| rows.get((kk % 3) * na..(kk % 3 + 1) * na);
    let (Some(prev), Some(cur), Some(next)) = (row(k.wrapping_sub(1)), row(k), row(k + 1)) else {
        return;
    };
    let at = |row: &[u64], i: usize| row.get(i).copied().unwrap_or(0);
    let mut floor = weakest(out);
    for (j, &v) in cur.iter().enumerate() {
        // `insert` keeps a peak only if it is stronger than the weakest of a full list.
        if v <= floor {
            continue;
        }
        let (l, r) = (
            if j == 0 { na - 1 } else { j - 1 },
            if j + 1 == na { 0 } else { j + 1 },
        );
        // Strictly above what comes earlier in scan order, at least what comes later. The row's
        // own neighbours first: they reject most cells before the other rows are read.
        let is_peak = v > at(cur, l)
            && v >= at(cur, r)
            && v > at(prev, j)
            && v >= at(next, j)
            && v > at(prev, l)
            && v > at(prev, r)
            && v >= at(next, l)
            && v >= at(next, r);
        if is_peak {
            insert(
                out,
                Peak {
                    bin: k as u16,
                    az: j as u16,
                    power: v,
                },
            );
            floor = weakest(out);
        }
    }
}

/// The power a cell must exceed to enter `out`: the weakest kept once it is full (else 0, so
/// empty cells are skipped too).
fn weakest(out: &Vec<Peak, MAX_PEAKS>) -> u64 {
    if out.is_full() {
        out.last().map_or(0, |p| p.power)
    } else {
        0
    }
}

/// Inserts keeping `out` sorted by falling power and at most [`MAX_PEAKS`] long.
fn insert(out: &mut Vec<Peak, MAX_PEAKS>, p: Peak) {
    let at = out.partition_point(|q| q.power >= p.power);
    if at >= MAX_PEAKS {
        return;
    }
    if out.is_full() {
        out.pop();
    }
    let _ = out.insert(at, p);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::range::frame_sum::pack;

    /// The kept peaks are the [`MAX_PEAKS`] strongest of every local maximum of the stored map,
    /// listed by a plain sort (stable: ties keep scan order).
    #[test]
    fn keeps_the_strongest_of_all_maxima() {
        // A filled aperture (copied) and a gapped one (scattered).
        keeps_the_strongest_of(&[0, 1, 2, 3, 4, 5, 6, 7]);
        keeps_the_strongest_of(&[0, 1, 2, 4, 5, 8, 9, 13]);
    }

    fn keeps_the_strongest_of(pos: &[u16]) {
        let (el, m, na) = (pos.len(), 96usize, 16usize);
        let mut x = 99u64;
        let words: std::vec::Vec<u32> = (0..el * m)
            .map(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                pack(CQ15::from_raw(
                    (x >> 52) as i16 - 2048,
                    (x >> 36) as i16 >> 4,
                ))
            })
            .collect();
        let spec = Spectra::from_words(&words, el, m, 0).unwrap();
        let last = 90usize;
        // The whole map, row 0 and row `last` empty.
        let mut map = std::vec![std::vec![0u64; na]; last + 1];
        for (k, row) in map.iter_mut().enumerate().take(last).skip(1) {
            let mut fft = std::vec![CQ15::default(); na];
            for (&p, &w) in pos.iter().zip(spec.column(k)) {
                fft[p as usize] = unpack(w);
            }
            let shift = crate::fft::cfft_q15(&mut fft).map_or(0, |e| 2 * e.0);
            for (o, z) in row.iter_mut().zip(&fft) {
                *o = (z.norm_sqr_raw() as u64) << shift;
            }
        }
        let mut all = std::vec::Vec::new();
        for k in 1..last {
            for j in 0..na {
                let v = map[k][j];
                let (l, r) = ((j + na - 1) % na, (j + 1) % na);
                let earlier = [map[k][l], map[k - 1][j], map[k - 1][l], map[k - 1][r]];
                let later = [map[k][r], map[k + 1][j], map[k + 1][l], map[k + 1][r]];
                if v > 0 && earlier.iter().all(|&e| v > e) && later.iter().all(|&e| v >= e) {
                    all.push(Peak {
                        bin: k as u16,
                        az: j as u16,
                        power: v,
                    });
                }
            }
        }
        assert!(all.len() > 2 * MAX_PEAKS, "{} maxima", all.len());
        all.sort_by_key(|p| core::cmp::Reverse(p.power));
        all.truncate(MAX_PEAKS);
        let mut fft = [CQ15::default(); 16];
        let mut rows = [0u64; 48];
        let peaks = scan(&spec, pos, last, &mut fft, &mut rows).unwrap();
        assert_eq!(peaks.as_slice(), all.as_slice());
        // The power row at full scale, where |X|² = 2³¹ no longer fits an i32.
        let mut row = [0u64; 16];
        let mut full = [CQ15::from_raw(i16::MIN, i16::MIN); 16];
        full[3] = CQ15::from_raw(i16::MAX, i16::MIN);
        power_row(&mut row, &full, 22);
        for (i, &v) in row.iter().enumerate() {
            let z = full[crate::fft::bit_reversed(i, 16)];
            assert_eq!(v, (z.norm_sqr_raw() as u64) << 22, "cell {i}");
        }
    }

    #[test]
    fn finds_two_reflectors_strongest_first() {
        // Elements 0..8, 32 bins; tones at (bin 10, sin 0.25) and (bin 20, sin −0.5), weaker.
        let (el, m, na) = (8usize, 32usize, 16usize);
        let pos: std::vec::Vec<u16> = (0..el as u16).collect();
        let mut words = std::vec![0u32; el * m];
        for (bin, s, a) in [(10usize, 0.25f64, 8000.0f64), (20, -0.5, 3000.0)] {
            for e in 0..el {
                let ph = core::f64::consts::PI * e as f64 * s;
                let at = Spectra::word_index(e, bin, el);
                let z = unpack(words[at]);
                words[at] = pack(CQ15::from_raw(
                    z.re.0 + (a * libm::cos(ph)) as i16,
                    z.im.0 + (a * libm::sin(ph)) as i16,
                ));
            }
        }
        let spec = Spectra::from_words(&words, el, m, 0).unwrap();
        let mut fft = [CQ15::default(); 16];
        let mut rows = [0u64; 48];
        let peaks = scan(&spec, &pos, 30, &mut fft, &mut rows).unwrap();
        // Azimuth side lobes of the 8-element aperture are local maxima too, 13 dB down.
        assert!(peaks.len() >= 2, "{peaks:?}");
        assert_eq!((peaks[0].bin, peaks[0].sin_az(na)), (10, 0.25));
        assert_eq!((peaks[1].bin, peaks[1].sin_az(na)), (20, -0.5));
        assert!(peaks[0].power > peaks[1].power);
        assert!(peaks[2..].iter().all(|p| p.power * 10 < peaks[0].power));
        assert_eq!(
            scan(&spec, &pos, 30, &mut fft[..4], &mut rows),
            Err(ScanError::AzimuthLen(4))
        );
    }
}
