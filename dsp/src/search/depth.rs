//! The depth search: brute force over every candidate depth (the reference) and decimated
//! coarse-to-fine (production). Both evaluate `P(d) = Σᵢ |Bᵢ(d + relᵢ)|²` (see [`super`]) on the
//! same fine grid of [`FINE_STEPS_PER_BIN`] steps per range bin, and count their complex
//! multiply-accumulates.
//!
//! * [`brute_force`]: for every fine depth and contour point, the matched filter on the raw
//!   (windowed, static) samples of every channel: `C·N` MACs each, `D·K·C·N` in all.
//! * [`coarse_to_fine`]: beamform the range spectra toward each point once (`K·C·M` MACs for M
//!   bins), score every depth on the bin grid (`K` lookups each), then evaluate `P` exactly on
//!   the fine grid (Dirichlet interpolation of the zero-padded spectrum, `M` MACs per point)
//!   only within ±1 bin of the best [`CANDIDATES`] coarse depths.
//!
//! Arithmetic is `f32` (the M7 has a single-precision FPU; IEEE operations and `libm` give the
//! same bits on every platform).

use super::contour::Contour;
use super::dirichlet::dirichlet;
pub use crate::fft::C32;
use core::fmt;

/// Fine depth steps per range bin.
pub const FINE_STEPS_PER_BIN: usize = 4;
/// Coarse candidates refined.
pub const CANDIDATES: usize = 3;

/// What the search needs to know about the radar.
#[derive(Clone, Copy, Debug)]
pub struct Geometry<'a> {
    /// Virtual position of each channel, half-wavelengths.
    pub positions: &'a [f32],
    /// ADC samples per chirp (N).
    pub samples: usize,
    /// Range FFT length (M ≥ N).
    pub fft_len: usize,
    /// Metres per range bin of the M-point FFT.
    pub bin_m: f32,
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
    /// Complex multiply-accumulates spent.
    pub macs: u64,
}

/// Why a search could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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
/// exclusive end) from the raw samples, `channels × samples` complex values, already windowed
/// and summed over loops.
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
                acc += sum * steer(geo.positions[ch], pt.sin_az);
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
        macs,
    })
}

/// Fine steps in `bins`, if the range is valid for an `m`-bin spectrum.
fn fine_steps(bins: (f32, f32), m: usize) -> Result<usize, SearchError> {
    let (lo, hi) = bins;
    if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi > lo && hi <= m as f32) {
        return Err(SearchError::Range);
    }
    Ok(((hi - lo) * FINE_STEPS_PER_BIN as f32) as usize)
}

/// Production search from the range spectra (`channels × fft_len`, windowed, summed over loops).
/// `profiles` is scratch of `contour.points().len() × fft_len`, `scores` of `fft_len`.
///
/// # Errors
/// [`SearchError`] for an empty contour, an empty range or a wrong buffer size.
pub fn coarse_to_fine(
    spectra: &[C32],
    geo: &Geometry<'_>,
    contour: &Contour,
    bins: (f32, f32),
    profiles: &mut [C32],
    scores: &mut [f32],
) -> Result<SearchResult, SearchError> {
    let (c, m) = (geo.positions.len(), geo.fft_len);
    let k = contour.points().len();
    check("spectra", c * m, spectra.len())?;
    if k == 0 {
        return Err(SearchError::EmptyContour);
    }
    check("profiles", k * m, profiles.len())?;
    check("scores", m, scores.len())?;
    fine_steps(bins, m)?;
    let mut macs = 0u64;
    // 1. Beamform toward each contour point: K·C·M.
    for (pt, prof) in contour.points().iter().zip(profiles.chunks_exact_mut(m)) {
        prof.fill(C32::new(0.0, 0.0));
        for (ch, row) in spectra.chunks_exact(m).enumerate() {
            let w = steer(geo.positions[ch], pt.sin_az);
            for (o, &x) in prof.iter_mut().zip(row) {
                *o += x * w;
            }
        }
        macs += (c * m) as u64;
    }
    // 2. Coarse scores on the bin grid.
    let offsets = |pt: &super::ContourPoint| libm::roundf(pt.rel_range_m / geo.bin_m) as usize;
    let (lo, hi) = (
        libm::ceilf(bins.0) as usize,
        (libm::floorf(bins.1) as usize).min(m - 1),
    );
    scores.fill(0.0);
    for d in lo..=hi {
        let mut p = 0.0;
        for (pt, prof) in contour.points().iter().zip(profiles.chunks_exact(m)) {
            if let Some(z) = prof.get(d + offsets(pt)) {
                p += norm2(*z);
            }
        }
        scores[d] = p;
        macs += k as u64;
    }
    // 3. Best coarse candidates (local maxima), then exact P on the fine grid around them.
    let mut cands = [usize::MAX; CANDIDATES];
    for d in lo..=hi {
        let v = scores[d];
        let is_peak = (d == lo || scores[d - 1] <= v) && (d == hi || scores[d + 1] <= v);
        if !is_peak {
            continue;
        }
        if let Some(slot) =
            (0..CANDIDATES).find(|&i| cands[i] == usize::MAX || scores[cands[i]] < v)
        {
            for i in (slot + 1..CANDIDATES).rev() {
                cands[i] = cands[i - 1];
            }
            cands[slot] = d;
        }
    }
    let mut best = (f32::NEG_INFINITY, 0.0f32);
    let fine = FINE_STEPS_PER_BIN as f32;
    for &cand in cands.iter().filter(|&&d| d != usize::MAX) {
        // Fine grid points within ±1 bin, aligned with brute_force's grid from bins.0.
        let first = libm::ceilf((cand as f32 - 1.0 - bins.0) * fine).max(0.0) as usize;
        let last = libm::floorf((cand as f32 + 1.0 - bins.0) * fine) as usize;
        for s in first..=last {
            let d = bins.0 + s as f32 / fine;
            if d >= bins.1 {
                break;
            }
            let mut p = 0.0;
            for (pt, prof) in contour.points().iter().zip(profiles.chunks_exact(m)) {
                let f = d + pt.rel_range_m / geo.bin_m;
                let mut z = C32::new(0.0, 0.0);
                for (b, &x) in prof.iter().enumerate() {
                    let (re, im) = dirichlet(b as f32 - f, geo.samples, m);
                    z += x * C32::new(re, im);
                }
                macs += m as u64;
                p += norm2(z);
            }
            if p > best.0 {
                best = (p, d);
            }
        }
    }
    // 4. The runner-up away from d*, then the floor: median coarse score over the searched range.
    let guard = (contour.depth_extent() / geo.bin_m) as usize + 2;
    let centre = libm::roundf(best.1) as usize;
    let runner_up = (lo..=hi)
        .filter(|&d| d + guard < centre || d > centre + guard)
        .map(|d| scores[d])
        .fold(0.0, f32::max);
    let window = &mut scores[lo..=hi];
    let mid = window.len() / 2;
    let floor = *window.select_nth_unstable_by(mid, f32::total_cmp).1;
    Ok(SearchResult {
        depth_bins: best.1,
        depth_m: best.1 * geo.bin_m,
        peak: best.0,
        floor,
        runner_up,
        macs,
    })
}
