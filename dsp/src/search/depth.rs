//! The depth search: brute force over every candidate depth (the reference) and decimated
//! coarse-to-fine (production). Both evaluate `P(d) = Σᵢ |Bᵢ(d + relᵢ)|²` (see [`super`]) on the
//! same fine grid of [`FINE_STEPS_PER_BIN`] steps per range bin, and count their complex
//! multiply-accumulates.
//!
//! * [`brute_force`]: for every fine depth and contour point, the matched filter on the windowed
//!   samples of every element: `E·N` MACs each, `D·K·E·N` in all (`f32`; the reference).
//! * [`coarse_to_fine`]: beamform the fixed-point range spectra toward each point once, in exact
//!   integer arithmetic, over the bins the search can reach ([`crate::response::beam`]), with the cancelled
//!   reflectors' responses subtracted; score every depth on the bin grid (`K` lookups each);
//!   then evaluate `P` on the fine grid (Dirichlet interpolation of the zero-padded spectrum
//!   over ±[`INTERP_HALF_WIDTH`] bins) only within ±1 bin of the best [`CANDIDATES`] coarse
//!   depths.
//!
//! The hot loop (beams: `K·E·bins` MACs) is integer; the few scores and interpolations are
//! `f32` with `libm` (the M7 has a single-precision FPU; IEEE operations give the same bits on
//! every platform).

use super::contour::{Contour, MAX_CONTOUR};
use crate::clutter::sic::{Reflector, Residual};
pub use crate::fft::C32;
use crate::range::Spectra;
use crate::response::Geometry;
use crate::response::kernel::Interpolator;
use core::fmt;

/// Fine depth steps per range bin.
pub const FINE_STEPS_PER_BIN: usize = 4;
/// Coarse candidates refined.
pub const CANDIDATES: usize = 3;
/// Bins on each side of a fractional bin that its interpolation uses. The kernel weighs under 4%
/// beyond 8 bins, where it mostly carries other reflectors' leakage; ±24 gave the same eval rows.
pub const INTERP_HALF_WIDTH: usize = 8;
/// Bins one interpolation reads.
const INTERP_WIDTH: usize = 2 * INTERP_HALF_WIDTH + 2;
/// Fine points the refinement can visit: ±1 bin around each candidate.
const FINE_POINTS: usize = CANDIDATES * (2 * FINE_STEPS_PER_BIN + 1);

/// A local maximum of `P` refined on the fine grid: one explanation of the data.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Candidate {
    /// Depth of the contour's closest point, range bins (fractional).
    pub depth_bins: f32,
    /// The same in metres.
    pub depth_m: f32,
    /// `P` there (0: no such candidate).
    pub peak: f32,
}

/// The chosen depth and the evidence for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchResult {
    /// Depth of the contour's closest point, range bins (fractional).
    pub depth_bins: f32,
    /// The same in metres.
    pub depth_m: f32,
    /// `P(d*)`.
    pub peak: f32,
    /// Median of `P` over the searched depths on the bin grid (the floor a real object must clear).
    pub floor: f32,
    /// Best bin-grid score more than the contour's depth extent + 2 bins away from `d*`: a
    /// second explanation of the data (0 where none was computed).
    pub runner_up: f32,
    /// The other refined candidates, each more than the contour's depth extent + 2 bins from
    /// `d*` and from each other, strongest first (peak 0 where there are fewer): what a trust
    /// test with other evidence (the camera's) can choose instead.
    pub others: [Candidate; CANDIDATES - 1],
    /// Complex multiply-accumulates spent.
    pub macs: u64,
}

/// Why a search could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SearchError {
    /// The contour has no points.
    EmptyContour,
    /// The depth range is empty or beyond the spectrum.
    Range,
    /// A buffer has the wrong length (names it).
    Buffer {
        /// Which buffer.
        what: &'static str,
        /// Length needed.
        expected: usize,
        /// Length given.
        got: usize,
    },
}

impl core::error::Error for SearchError {}

impl fmt::Display for SearchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::EmptyContour => write!(
                f,
                "the contour has no points: the object's mask has no usable depth row"
            ),
            Self::Range => write!(
                f,
                "the depth range is empty or lies beyond the radar's range"
            ),
            Self::Buffer {
                what,
                expected,
                got,
            } => write!(f, "{what} holds {got} entries but {expected} are needed"),
        }
    }
}

fn check(what: &'static str, expected: usize, got: usize) -> Result<(), SearchError> {
    if expected == got {
        Ok(())
    } else {
        Err(SearchError::Buffer {
            what,
            expected,
            got,
        })
    }
}

/// Steering phasor `exp(−jπ·p·s)`.
fn steer(p: f32, s: f32) -> C32 {
    let a = -core::f32::consts::PI * p * s;
    C32::new(libm::cosf(a), libm::sinf(a))
}

fn norm2(z: C32) -> f32 {
    z.re * z.re + z.im * z.im
}

/// Brute-force reference: `P` at every fine depth in `bins` (range bins, inclusive start,
/// exclusive end) from the samples, `elements × N` complex values summed over loops and the
/// channels of each element, windowed, with any cancelled reflectors already subtracted.
///
/// # Errors
/// [`SearchError`] for an empty contour, an empty range or a wrong buffer size.
pub fn brute_force(
    samples: &[C32],
    geo: &Geometry<'_>,
    contour: &Contour,
    bins: (f32, f32),
) -> Result<SearchResult, SearchError> {
    let (c, n, m) = (geo.positions.len(), geo.samples, geo.fft_len);
    check("samples", c * n, samples.len())?;
    if contour.is_empty() {
        return Err(SearchError::EmptyContour);
    }
    let steps = fine_steps(bins, m)?;
    let mut macs = 0u64;
    let mut best = (f32::NEG_INFINITY, 0.0f32);
    for s in 0..steps {
        let d = bins.0 + s as f32 / FINE_STEPS_PER_BIN as f32;
        let mut p = 0.0f32;
        for pt in contour.points() {
            let f = d + pt.rel_range_m / geo.bin_m;
            // The template exp(−j2π f n / M), advanced by rotation (renormalized every 64).
            let w = -2.0 * core::f32::consts::PI * f / m as f32;
            let step = C32::new(libm::cosf(w), libm::sinf(w));
            let mut acc = C32::new(0.0, 0.0);
            for (ch, row) in samples.chunks_exact(n).enumerate() {
                let mut sum = C32::new(0.0, 0.0);
                let mut t = C32::new(1.0, 0.0);
                for (k, &x) in row.iter().enumerate() {
                    sum += x * t;
                    t *= step;
                    if k % 64 == 63 {
                        let a = w * (k + 1) as f32;
                        t = C32::new(libm::cosf(a), libm::sinf(a));
                    }
                }
                acc += sum * steer(geo.positions[ch] as f32, pt.sin_az);
            }
            macs += (c * n) as u64;
            p += norm2(acc);
        }
        if p > best.0 {
            best = (p, d);
        }
    }
    Ok(SearchResult {
        depth_bins: best.1,
        depth_m: best.1 * geo.bin_m,
        peak: best.0,
        floor: 0.0,
        runner_up: 0.0,
        others: [Candidate::default(); CANDIDATES - 1],
        macs,
    })
}

/// The upper median of `values` (the element at sorted position `len / 2` under
/// [`f32::total_cmp`]; 0 for none) by a four-pass radix select on the order-preserving bit
/// keys: O(len), no reordering, no panic path.
fn median(values: &[f32]) -> f32 {
    // Flip the sign bit of positives, every bit of negatives: unsigned order = total order.
    let key = |v: f32| {
        let b = v.to_bits();
        if b >> 31 == 1 { !b } else { b | 0x8000_0000 }
    };
    let (mut prefix, mut rank) = (0u32, values.len() / 2);
    for shift in [24u32, 16, 8, 0] {
        // Keys agreeing with `prefix` above this byte, counted per value of the byte.
        let above = |k: u32| {
            if shift == 24 {
                true
            } else {
                k >> (shift + 8) == prefix >> (shift + 8)
            }
        };
        let mut counts = [0u16; 256];
        for &v in values {
            let k = key(v);
            if above(k) {
                let c = &mut counts[((k >> shift) & 0xFF) as usize];
                *c = c.saturating_add(1);
            }
        }
        let mut byte = 0u32;
        for (b, &c) in counts.iter().enumerate() {
            if rank < c as usize {
                byte = b as u32;
                break;
            }
            rank -= c as usize;
        }
        prefix |= byte << shift;
    }
    if values.is_empty() {
        return 0.0;
    }
    let bits = if prefix >> 31 == 1 {
        prefix & 0x7FFF_FFFF
    } else {
        !prefix
    };
    f32::from_bits(bits)
}

/// Fine steps in `bins`, if the range is valid for an `m`-bin spectrum.
fn fine_steps(bins: (f32, f32), m: usize) -> Result<usize, SearchError> {
    let (lo, hi) = bins;
    if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi > lo && hi <= m as f32) {
        return Err(SearchError::Range);
    }
    Ok(((hi - lo) * FINE_STEPS_PER_BIN as f32) as usize)
}

/// Where one direction's beams are stored and which bins they cover.
#[derive(Clone, Copy, Debug, Default)]
struct Row {
    /// Index of its first beam in the storage.
    at: usize,
    /// Bin of its first beam.
    first: usize,
    /// Beams (bins) in the row.
    len: usize,
}

/// Beams toward each contour direction, each over the bins its points can read, in
/// caller-owned words (so the firmware can lend the frame arena's free words).
struct Profiles<'w> {
    beams: &'w mut [C32],
    rows: [Row; MAX_CONTOUR],
}

impl Profiles<'_> {
    /// Direction `dir`'s beams from bin `bin` to the end of its row (empty outside it).
    fn from(&self, dir: usize, bin: usize) -> &[C32] {
        let Some(r) = self.rows.get(dir) else {
            return &[];
        };
        match (self.beams.get(r.at..r.at + r.len), bin.checked_sub(r.first)) {
            (Some(row), Some(i)) => row.get(i..).unwrap_or(&[]),
            _ => &[],
        }
    }

    /// Direction `dir`'s first bin and whole row, to fill.
    fn row_mut(&mut self, dir: usize) -> (usize, &mut [C32]) {
        let r = self.rows.get(dir).copied().unwrap_or_default();
        (
            r.first,
            self.beams.get_mut(r.at..r.at + r.len).unwrap_or(&mut []),
        )
    }
}

/// Words of scratch [`coarse_to_fine`] needs for `points` contour points and an `m`-bin spectrum
/// (an upper bound: the beams of every point over every bin).
pub const fn profile_words(points: usize, m: usize) -> usize {
    2 * points * m
}

/// Production search from the fixed-point range spectra (windowed, summed over loops), with the
/// `reflectors` SIC cancelled subtracted from every beam. `profiles` is scratch of
/// [`profile_words`] words, `scores` of `M` values.
///
/// # Errors
/// [`SearchError`] for an empty contour, an empty range or a wrong buffer size.
pub fn coarse_to_fine(
    spectra: &Spectra<'_>,
    geo: &Geometry<'_>,
    contour: &Contour,
    bins: (f32, f32),
    reflectors: &[Reflector],
    profiles: &mut [u32],
    scores: &mut [f32],
) -> Result<SearchResult, SearchError> {
    let (e, m) = (geo.positions.len(), geo.fft_len);
    let k = contour.points().len();
    check("spectra bins", m, spectra.bins())?;
    check("spectra elements", e, spectra.elements())?;
    if k == 0 {
        return Err(SearchError::EmptyContour);
    }
    check("scores", m, scores.len())?;
    fine_steps(bins, m)?;
    let offset = |rel_m: f32| libm::roundf(rel_m / geo.bin_m) as usize;
    // Each point's coarse offset and fractional offset in bins, computed once.
    let mut offsets = [(0usize, 0.0f32); MAX_CONTOUR];
    for (o, pt) in offsets.iter_mut().zip(contour.points()) {
        *o = (offset(pt.rel_range_m), pt.rel_range_m / geo.bin_m);
    }
    let (lo, hi) = (
        libm::ceilf(bins.0) as usize,
        (libm::floorf(bins.1) as usize).min(m - 1),
    );
    // Points in the same direction share one beam (see `Contour::snapped`).
    let mut dirs: heapless::Vec<f32, MAX_CONTOUR> = heapless::Vec::new();
    let mut beam_of = [0usize; MAX_CONTOUR];
    // Per direction: the smallest and largest coarse offset of its points.
    let mut spread = [(usize::MAX, 0usize); MAX_CONTOUR];
    for ((slot, pt), &(o, _)) in beam_of.iter_mut().zip(contour.points()).zip(&offsets) {
        let s = pt.sin_az;
        *slot = match dirs.iter().position(|&d| d == s) {
            Some(i) => i,
            None => {
                let _ = dirs.push(s);
                dirs.len() - 1
            }
        };
        if let Some(r) = spread.get_mut(*slot) {
            *r = (r.0.min(o), r.1.max(o));
        }
    }
    // Bins a direction's points read: coarse d + o for d in lo..=hi; fine f = d + rel with
    // |rel − o| ≤ ½ and d within ±1 of a candidate, so ⌊f⌋ ∈ [lo + o − 2, hi + o + 1], each
    // interpolation ± the half width around it.
    let mut rows = [Row::default(); MAX_CONTOUR];
    let mut need = 0;
    for (row, &(lo_o, hi_o)) in rows.iter_mut().zip(&spread).take(dirs.len()) {
        let first = (lo + lo_o).saturating_sub(INTERP_HALF_WIDTH + 2);
        let end = (hi + hi_o + INTERP_HALF_WIDTH + 3).min(m);
        *row = Row {
            at: need,
            first,
            len: end.saturating_sub(first),
        };
        need += row.len;
    }
    let Some(words) = profiles.get_mut(..2 * need) else {
        return Err(SearchError::Buffer {
            what: "profiles",
            expected: 2 * need,
            got: profiles.len(),
        });
    };
    // SAFETY: `C32` is `repr(C)` of two `f32` (8 bytes, 4-aligned, like two `u32` words) and
    // every bit pattern is a valid `f32`; the cast slice covers exactly `words`.
    #[allow(unsafe_code)] // the word arena viewed as beams: see the SAFETY note
    let beams = unsafe { core::slice::from_raw_parts_mut(words.as_mut_ptr().cast::<C32>(), need) };
    let mut prof = Profiles { beams, rows };
    let mut macs = 0u64;
    // 1. Beamform toward each distinct direction over its bins: E·Σ len, integer.
    for (i, &s) in dirs.iter().enumerate() {
        let (first, beams) = prof.row_mut(i);
        macs += (e * beams.len()) as u64;
        Residual::new(spectra, geo, reflectors, s).fill(first, beams);
    }
    // 2. Coarse scores on the bin grid.
    // Point-outer, depth-inner: each score still adds its points in contour order from 0.
    // `win[i]` is the score of depth bin `lo + i`.
    scores.fill(0.0);
    let Some(win) = scores.get_mut(lo..=hi) else {
        return Err(SearchError::Range);
    };
    for (&b, &(o, _)) in beam_of.iter().zip(&offsets).take(k) {
        for (p, z) in win.iter_mut().zip(prof.from(b, lo + o)) {
            *p += z.norm_sqr();
        }
    }
    macs += (k * win.len()) as u64;
    // 3. Best coarse candidates: local maxima, strongest first, each more than `guard` bins
    //    from a stronger one (distinct explanations), then P on the fine grid around them.
    let guard = (contour.depth_extent() / geo.bin_m) as usize + 2;
    let mut cands: [Option<(usize, f32)>; CANDIDATES] = [None; CANDIDATES];
    for slot in 0..CANDIDATES {
        let mut pick: Option<(usize, f32)> = None;
        for (i, &v) in win.iter().enumerate() {
            let left = i.checked_sub(1).and_then(|j| win.get(j));
            let is_peak = left.is_none_or(|&l| l <= v) && win.get(i + 1).is_none_or(|&r| r <= v);
            let d = lo + i;
            let free = cands[..slot]
                .iter()
                .flatten()
                .all(|&(c, _)| d.abs_diff(c) > guard);
            if is_peak && free && pick.is_none_or(|(_, s)| s < v) {
                pick = Some((d, v));
            }
        }
        cands[slot] = pick;
    }
    // The fine points within ±1 bin of each candidate (strongest first), each listed once,
    // aligned with brute_force's grid from bins.0.
    let fine = FINE_STEPS_PER_BIN as f32;
    let mut steps: heapless::Vec<usize, FINE_POINTS> = heapless::Vec::new();
    for &(cand, _) in cands.iter().flatten() {
        let from = libm::ceilf((cand as f32 - 1.0 - bins.0) * fine).max(0.0) as usize;
        let to = libm::floorf((cand as f32 + 1.0 - bins.0) * fine) as usize;
        for s in from..=to {
            if bins.0 + s as f32 / fine >= bins.1 {
                break;
            }
            if !steps.contains(&s) {
                let _ = steps.push(s);
            }
        }
    }
    // P at each of them. The weights of a point depend only on its fractional bin, which
    // repeats every FINE_STEPS_PER_BIN steps: one row of weights serves every step of a phase.
    let mut power = [0.0f32; FINE_POINTS];
    let interp = Interpolator::new(geo.samples, m);
    let mut weights = [C32::new(0.0, 0.0); INTERP_WIDTH];
    for phase in 0..FINE_STEPS_PER_BIN {
        for (&beam, &(_, rel)) in beam_of.iter().zip(&offsets).take(k) {
            // Offset of the first weight's bin from the point (bins), once computed.
            let mut row_x0 = None;
            for (&s, p) in steps.iter().zip(power.iter_mut()) {
                if s % FINE_STEPS_PER_BIN != phase {
                    continue;
                }
                let f = bins.0 + s as f32 / fine + rel;
                let b0 = (libm::floorf(f) as usize).saturating_sub(INTERP_HALF_WIDTH);
                let x0 = b0 as f32 - f;
                // Rounding moves x0 by ~1e-5 bins between steps; a clipped start moves it by 1.
                if row_x0.is_none_or(|r: f32| libm::fabsf(r - x0) > 1e-3) {
                    interp.for_each(f, b0, INTERP_WIDTH, |b, w| {
                        if let Some(slot) = weights.get_mut(b - b0) {
                            *slot = w;
                        }
                    });
                    row_x0 = Some(x0);
                }
                let width = INTERP_WIDTH.min(m - b0.min(m));
                let mut z = C32::new(0.0, 0.0);
                for (&b, &w) in prof.from(beam, b0).iter().zip(&weights[..width]) {
                    z += b * w;
                }
                macs += width as u64;
                *p += z.norm_sqr();
            }
        }
    }
    // Each candidate's best fine point (its ±1 bin), then the strongest is d*.
    let mut refined = [Candidate::default(); CANDIDATES];
    for (r, &(cand, _)) in refined.iter_mut().zip(cands.iter().flatten()) {
        let mut best = (f32::NEG_INFINITY, 0.0f32);
        for (&s, &p) in steps.iter().zip(&power) {
            let d = bins.0 + s as f32 / fine;
            if libm::fabsf(d - cand as f32) <= 1.0 && p > best.0 {
                best = (p, d);
            }
        }
        if best.0 > 0.0 {
            *r = Candidate {
                depth_bins: best.1,
                depth_m: best.1 * geo.bin_m,
                peak: best.0,
            };
        }
    }
    // Strongest first (insertion sort of three: stable, no panic path).
    for i in 1..CANDIDATES {
        for j in (1..=i).rev() {
            if refined[j - 1].peak < refined[j].peak {
                refined.swap(j - 1, j);
            }
        }
    }
    let [first, others @ ..] = refined;
    let best = (first.peak, first.depth_bins);
    // 4. The runner-up away from d*, then the floor: median coarse score over the searched range.
    let centre = libm::roundf(best.1) as usize;
    let runner_up = (lo..)
        .zip(win.iter())
        .filter(|&(d, _)| d + guard < centre || d > centre + guard)
        .map(|(_, &v)| v)
        .fold(0.0, f32::max);
    let floor = median(win);
    Ok(SearchResult {
        depth_bins: best.1,
        depth_m: best.1 * geo.bin_m,
        peak: best.0,
        floor,
        runner_up,
        others,
        macs,
    })
}

#[cfg(test)]
mod tests {
    use super::median;

    #[test]
    fn median_matches_select_nth() {
        let mut x = 12345u64;
        for len in [0usize, 1, 2, 3, 10, 255, 256, 257, 511] {
            let values: std::vec::Vec<f32> = (0..len)
                .map(|i| {
                    x = x
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    match i % 7 {
                        0 => 0.0,
                        1 => -0.0,
                        2 => -((x >> 40) as f32),
                        3 => 1.5, // ties
                        _ => (x >> 20) as f32 * 1e-3,
                    }
                })
                .collect();
            let mut sorted = values.clone();
            let expected = if len == 0 {
                0.0
            } else {
                *sorted.select_nth_unstable_by(len / 2, f32::total_cmp).1
            };
            assert_eq!(median(&values).to_bits(), expected.to_bits(), "len {len}");
        }
    }
}
