//! A mover's leading edge: on the Doppler path (after the search on a focused Doppler bin, before
//! the trust test), where the mover's range profile first rises in front of its strongest
//! return.
//!
//! ```text
//! Doppler bin ─▶ template search ─▶ strongest return d*
//!             └▶ range profile over the span ─▶ nearest peak within LEAD_DB, ≤ extent in front ─▶ lead
//!                                              └▶ (no peak) −6 dB edge of a return too wide ─▶ lead
//! ```
//!
//! The depth is about the object's closest point. A far car's mask is a few pixels, so its
//! contour says little, and the strongest return in its Doppler bin is often its body, 1–5 m
//! behind; the search keeps its candidates farther apart than that, so the trust test could not
//! see the closest return ([`crate::trust::Evidence::judge`] takes the lead when the mover's
//! bin offers one). The profile is the contour's directions without their relative ranges: with
//! them, the template moved forward by its own depth extent lines its far points up with the
//! closest return, a ghost in front.
//!
//! When the body is shallower than the range window's main lobe (a car's 3 m side at the
//! far-moving boards' 1.3 m bins), its near end shows no peak of its own but widens the return:
//! the shoulder reads the near end from where the profile falls 6 dB under the peak.

use metamoran_dsp::search::depth::SearchResult;
use metamoran_dsp::wire::Score;

/// A mover's closest return: where its Doppler bin's range profile first rises within
/// [`crate::trust::LEAD_DB`] of its strongest return ([`leading_edge`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lead {
    /// Depth, m.
    pub depth_m: f64,
    /// Its score over the search floor, dB: the strongest return's less what the profile drops
    /// by (half-dB steps, as the wire's).
    pub over_floor_db: f64,
}

/// Whether an object of `class` can move, so that its Doppler bin's leading edge can be its
/// own: not a sign (a sign's span holds other movers only). Classes the camera carries through
/// unknown may.
pub fn moves(class: &str) -> bool {
    class != "sign"
}

/// The Hann range window's main lobe as the profile's bins see it: `samples` ADC samples
/// transformed with `fft_len` points, so one resolution cell (the lobe's unit) spans
/// `fft_len / samples` bins (1 without zero-padding: a power-of-two sample count).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HannLobe {
    bins_per_cell: f32,
}

impl HannLobe {
    /// Without zero-padding: one bin per resolution cell.
    pub const UNPADDED: Self = Self { bins_per_cell: 1.0 };

    /// The lobe of `samples` ADC samples padded to an FFT of `fft_len` points (no padding is
    /// assumed when `fft_len < samples` or `samples` is 0).
    pub fn new(samples: usize, fft_len: usize) -> Self {
        if samples == 0 {
            return Self::UNPADDED;
        }
        Self {
            bins_per_cell: (fft_len as f32 / samples as f32).max(1.0),
        }
    }

    /// Range bins in front of the strongest return a leading edge must be at least: the main
    /// lobe (±2 cells) is the strongest return's own, one bin past it. 3 without padding.
    pub fn lead_min_bins(self) -> usize {
        ((2.0 * self.bins_per_cell).ceil() as usize).saturating_add(1)
    }

    /// Half the width of a point reflector's return at a quarter of its power (−6 dB), bins:
    /// the Hann window's amplitude is half its peak one cell off.
    pub fn point_half_width_bins(self) -> f32 {
        self.bins_per_cell
    }

    /// How far in front of the choice, bins, a shoulder's edge must lie to be a lead: half a
    /// cell. A point reflector's measured −6 dB edge (interpolated in dB between bins) lies
    /// within a fifth of a cell of it wherever it falls between bins.
    pub fn shoulder_min_bins(self) -> f32 {
        0.5 * self.bins_per_cell
    }
}

/// The mover's leading edge in front of the search's choice: the nearest local maximum of its
/// range profile `profile` (one value per range bin of `bin_m` m, the range window's main lobe
/// `lobe` wide) at least [`HannLobe::lead_min_bins`] in front of the choice, at most `extent_m` in front of the mover's strongest return (the
/// profile's largest value from the choice to `extent_m` behind it: the choice is the closest
/// point's estimate, the body lies behind) and within [`crate::trust::LEAD_DB`] of it,
/// refined by a parabola through its neighbours. A far car's strongest return is often its
/// body, metres behind the closest point the depth is about, and the search's candidates are
/// kept farther apart than that. `None` where the profile rises nowhere in front.
/// O(extent in bins).
pub fn leading_edge(
    profile: &[f32],
    search: &SearchResult,
    bin_m: f32,
    lobe: HannLobe,
    extent_m: f64,
) -> Option<Lead> {
    if !(search.peak > 0.0 && search.floor > 0.0 && bin_m > 0.0 && search.depth_bins >= 0.0) {
        return None;
    }
    let d = search.depth_bins.round() as usize;
    if d >= profile.len() {
        return None;
    }
    // (A reach past the profile reads zeros; NaN casts to 0: no overflow below.)
    let reach = ((extent_m / f64::from(bin_m)).ceil() as usize).min(profile.len());
    let at = |b: usize| profile.get(b).copied().unwrap_or(0.0);
    let strongest = (d..=d + reach).max_by(|&a, &b| at(a).total_cmp(&at(b)))?;
    let peak = Some(at(strongest)).filter(|&p| p > 0.0)?;
    let least = peak * 10f32.powf(-(crate::trust::LEAD_DB as f32) / 10.0);
    let first = strongest.saturating_sub(reach).max(1);
    let (depth_bins, v) = match (first..d.saturating_sub(lobe.lead_min_bins() - 1)).find(|&b| {
        let v = at(b);
        v >= least && v >= at(b - 1) && v >= at(b + 1)
    }) {
        Some(b) => (b as f32 + vertex(at(b - 1), at(b), at(b + 1)), at(b)),
        None => shoulder(&at, strongest, first, lobe)
            .filter(|&(edge, _)| edge <= search.depth_bins - lobe.shoulder_min_bins())?,
    };
    // As far over the floor as the choice, less what the profile drops by from its peak.
    let db = 10.0 * (search.peak / search.floor).log10() - 10.0 * (peak / v).log10();
    Some(Lead {
        depth_m: f64::from(depth_bins * bin_m),
        over_floor_db: Score::new(db, true).over_floor_db(),
    })
}

/// How far the vertex of the parabola through `l`, `v`, `r` (at −1, 0, +1) lies from the
/// middle, bins (0 where they do not curve down; at most half a bin).
fn vertex(l: f32, v: f32, r: f32) -> f32 {
    let curve = l - 2.0 * v + r;
    if curve < 0.0 {
        (0.5 * (l - r) / curve).clamp(-0.5, 0.5)
    } else {
        0.0
    }
}

/// The closest point of a return too wide for one reflector, when the body in front of the
/// strongest return lies within its main lobe and shows no peak of its own: where the profile
/// `at` first falls under a quarter of the strongest return's power in front of bin
/// `strongest` (searching no nearer than bin `first`, interpolated in dB between bins),
/// [`HannLobe::point_half_width_bins`] back: the nearest point a reflector as strong as the peak would
/// put that edge at. With its profile value there. `None` if the profile does not fall by
/// then. O(bins in front).
fn shoulder(
    at: &impl Fn(usize) -> f32,
    strongest: usize,
    first: usize,
    lobe: HannLobe,
) -> Option<(f32, f32)> {
    let quarter = at(strongest) / 4.0;
    let b = (first..strongest).rev().find(|&b| at(b) < quarter)?;
    let (below, above) = (at(b), at(b + 1));
    let db = |p: f32| 10.0 * p.max(f32::MIN_POSITIVE).log10();
    let crossing = b as f32 + ((db(quarter) - db(below)) / (db(above) - db(below))).clamp(0.0, 1.0);
    let edge = crossing + lobe.point_half_width_bins();
    // The profile at the edge, interpolated in dB between its bins.
    let k = edge.floor() as usize;
    let t = edge - k as f32;
    let value = 10f32.powf((db(at(k)) * (1.0 - t) + db(at(k + 1)) * t) / 10.0);
    Some((edge, value))
}

#[cfg(test)]
mod tests {
    use super::*;
    use metamoran_dsp::search::depth::Candidate;

    const BIN_M: f32 = 0.5;

    /// The search's choice at `bin`, 30 dB over its floor.
    fn choice(bin: f32) -> SearchResult {
        SearchResult {
            depth_bins: bin,
            depth_m: bin * BIN_M,
            peak: 1000.0,
            floor: 1.0,
            runner_up: 0.0,
            others: [Candidate::default(); 2],
            macs: 0,
        }
    }

    /// A profile of 200 bins: a noise floor of 1, and a parabolic peak of `height` at each of
    /// `peaks` (bin, height), one bin wide on each side.
    fn profile(peaks: &[(usize, f32)]) -> Vec<f32> {
        let mut p = vec![1.0; 200];
        for &(b, h) in peaks {
            p[b] = h;
            p[b - 1] = p[b - 1].max(0.75 * h);
            p[b + 1] = p[b + 1].max(0.75 * h);
        }
        p
    }

    #[test]
    fn the_nearest_return_within_lead_db_in_front_is_the_lead() {
        // The body at bin 100, two returns in front: 5 dB down at bin 92 (4 m), 3 dB down at 96.
        let p = profile(&[(100, 1000.0), (92, 316.0), (96, 500.0)]);
        let lead = leading_edge(&p, &choice(100.0), BIN_M, HannLobe::UNPADDED, 6.0).unwrap();
        // The nearest, not the strongest; symmetric neighbours: no offset.
        assert!((lead.depth_m - 92.0 * 0.5).abs() < 1e-6, "{lead:?}");
        // 30 dB less 5 dB, in half-dB steps.
        assert!((lead.over_floor_db - 25.0).abs() <= 0.25, "{lead:?}");
    }

    #[test]
    fn the_profile_is_measured_against_the_movers_strongest_return_behind_the_choice() {
        // The template put the closest point at bin 94, in front of the strongest return at
        // 100 (its contour reaches 3 m behind): the noise in front is 30 dB under that return,
        // no lead, however it compares with the profile at the choice.
        let noisy = profile(&[(100, 1000.0), (60, 2.0), (70, 3.0), (80, 2.0)]);
        assert_eq!(
            leading_edge(&noisy, &choice(94.0), BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
        // A return 3 dB under it, 5 m in front of it (2 m in front of the choice): the lead.
        let lead = profile(&[(100, 1000.0), (90, 500.0)]);
        let got = leading_edge(&lead, &choice(94.0), BIN_M, HannLobe::UNPADDED, 6.0).unwrap();
        assert!((got.depth_m - 45.0).abs() < 1e-6, "{got:?}");
        // Within the choice's own main lobe: the choice already is the closest return.
        assert_eq!(
            leading_edge(&lead, &choice(92.0), BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
    }

    #[test]
    fn a_lead_is_refined_between_bins() {
        // Neighbours 0.9 and 0.5 of the peak: the parabola's vertex 0.5·(0.9 − 0.5)/(2 − 1.4)
        // = 1/3 bin toward the stronger one.
        let mut p = profile(&[(100, 1000.0)]);
        p[89] = 450.0;
        p[90] = 900.0;
        p[91] = 810.0;
        let lead = leading_edge(&p, &choice(100.0), BIN_M, HannLobe::UNPADDED, 6.0).unwrap();
        let vertex = 90.0 + 0.5 * (450.0 - 810.0) / (450.0 - 1800.0 + 810.0);
        assert!(
            (lead.depth_m - vertex * 0.5).abs() < 1e-4,
            "{lead:?} vs {vertex}"
        );
        assert!(vertex > 90.0 && vertex < 90.5);
    }

    #[test]
    fn no_lead_beyond_the_extent_or_lead_db_or_inside_the_main_lobe() {
        // 11 dB down: not the same mover's.
        let weak = profile(&[(100, 1000.0), (94, 79.0)]);
        assert_eq!(
            leading_edge(&weak, &choice(100.0), BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
        // 7 m in front of a car 6 m long.
        let far = profile(&[(100, 1000.0), (86, 500.0)]);
        assert_eq!(
            leading_edge(&far, &choice(100.0), BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
        // A return two bins in front is no peak of its own, inside the strongest return's
        // main lobe; the shoulder puts the lead at it (below).
        let lobe = profile(&[(100, 1000.0), (98, 900.0)]);
        let got = leading_edge(&lobe, &choice(100.0), BIN_M, HannLobe::UNPADDED, 6.0).unwrap();
        assert!(
            (got.depth_m / f64::from(BIN_M) - 98.0).abs() < 0.25,
            "{got:?}"
        );
        // A profile that only falls toward the radar.
        let clean = profile(&[(100, 1000.0)]);
        assert_eq!(
            leading_edge(&clean, &choice(100.0), BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
    }

    /// Power of the Hann range window's response `offset` bins from a point reflector (1 at
    /// 0, a quarter at ±1, 0 from ±2), in f64 from its closed form.
    fn hann_power(offset: f64) -> f64 {
        let x = offset.abs();
        if x < 1e-9 {
            return 1.0;
        }
        if (x - 1.0).abs() < 1e-9 {
            return 0.25;
        }
        let sinc = (std::f64::consts::PI * x).sin() / (std::f64::consts::PI * x);
        (sinc / (1.0 - x * x)).powi(2)
    }

    /// A profile of 200 bins: a floor of 1 and the power of reflectors at fractional bins
    /// `(bin, power)`, added (the directions' powers add; their phases do not meet).
    fn hann_profile(reflectors: &[(f64, f64)]) -> Vec<f32> {
        padded_profile(reflectors, 1.0)
    }

    /// [`hann_profile`] through a zero-padded range FFT: one resolution cell spans `cell` bins.
    fn padded_profile(reflectors: &[(f64, f64)], cell: f64) -> Vec<f32> {
        (0..200)
            .map(|b| {
                let p: f64 = reflectors
                    .iter()
                    .map(|&(at, h)| h * hann_power((b as f64 - at) / cell))
                    .sum();
                (1.0 + p) as f32
            })
            .collect()
    }

    #[test]
    fn one_reflector_has_no_shoulder_wherever_it_falls_between_bins() {
        for k in 0..8 {
            let at = 100.0 + f64::from(k) / 8.0;
            let p = hann_profile(&[(at, 1.0e5)]);
            let strongest = (0..200).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap();
            let got = leading_edge(&p, &choice(at as f32), BIN_M, HannLobe::UNPADDED, 6.0);
            assert_eq!(got, None, "reflector at {at} (strongest bin {strongest})");
            // The edge the shoulder would give is within a fifth of a bin of it.
            let at_fn = |b: usize| p.get(b).copied().unwrap_or(0.0);
            let (edge, _) = shoulder(&at_fn, strongest, 80, HannLobe::UNPADDED).unwrap();
            assert!((f64::from(edge) - at).abs() < 0.2, "{edge} for {at}");
        }
    }

    #[test]
    fn a_zero_padded_lobe_is_as_many_cells_wide() {
        // 136 samples into a 256-point FFT: a cell is 1.88 bins.
        let lobe = HannLobe::new(136, 256);
        assert_eq!(HannLobe::new(256, 256), HannLobe::UNPADDED);
        assert_eq!(HannLobe::new(0, 256), HannLobe::UNPADDED);
        assert_eq!(HannLobe::new(256, 128), HannLobe::UNPADDED);
        assert_eq!(
            (HannLobe::UNPADDED.lead_min_bins(), lobe.lead_min_bins()),
            (3, 5)
        );
        let cell = 256.0 / 136.0;
        let mut unpadded_leads = 0;
        for k in 0..8 {
            let at = 100.0 + f64::from(k) / 8.0;
            let p = padded_profile(&[(at, 1.0e5)], cell);
            let strongest = (0..200).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap();
            let got = leading_edge(&p, &choice(at as f32), BIN_M, lobe, 6.0);
            assert_eq!(got, None, "reflector at {at} (strongest bin {strongest})");
            let at_fn = |b: usize| p.get(b).copied().unwrap_or(0.0);
            let (edge, _) = shoulder(&at_fn, strongest, 80, lobe).unwrap();
            assert!((f64::from(edge) - at).abs() < 0.2 * cell, "{edge} for {at}");
            // Read as unpadded, the lobe's own flank is a lead ~0.9 bins in front.
            unpadded_leads += usize::from(
                leading_edge(&p, &choice(at as f32), BIN_M, HannLobe::UNPADDED, 6.0).is_some(),
            );
        }
        assert_eq!(unpadded_leads, 8);
    }

    #[test]
    fn a_body_wider_than_one_reflector_leads_from_its_near_end() {
        // A car's side 2.6 bins deep (3.3 m at the far-moving 8-element board's 1.29 m bins),
        // its strongest scatterer at the back: no peak in front, but a return too wide for one
        // reflector. The lead is near its near end: a front scatterer 5 dB weaker than the
        // peak puts the −6 dB edge nearer to itself, so the lead is up to a bin behind it.
        let body = [(97.4, 3.0e4), (98.3, 5.0e4), (99.1, 4.0e4), (100.0, 1.0e5)];
        let p = hann_profile(&body);
        let got = leading_edge(&p, &choice(100.0), BIN_M, HannLobe::UNPADDED, 6.0).unwrap();
        let bins = got.depth_m / f64::from(BIN_M);
        assert!((97.4..98.4).contains(&bins), "{got:?}");
        // Within LEAD_DB of the choice: the trust test can take it.
        assert!(got.over_floor_db >= 30.0 - crate::trust::LEAD_DB, "{got:?}");
    }

    #[test]
    fn no_lead_without_a_choice_or_a_profile() {
        let p = profile(&[(100, 1000.0), (92, 500.0)]);
        let none = SearchResult {
            peak: 0.0,
            ..choice(100.0)
        };
        assert_eq!(
            leading_edge(&p, &none, BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
        // The choice at the profile's first bins or past its end: nothing to read, no panic.
        assert_eq!(
            leading_edge(&p, &choice(1.0), BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
        assert_eq!(
            leading_edge(&p, &choice(500.0), BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
        assert_eq!(
            leading_edge(&[], &choice(100.0), BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
        assert_eq!(
            leading_edge(&p, &choice(f32::NAN), BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
        assert_eq!(
            leading_edge(&p, &choice(100.0), 0.0, HannLobe::UNPADDED, 6.0),
            None
        );
        assert_eq!(
            leading_edge(&p, &choice(f32::MAX), BIN_M, HannLobe::UNPADDED, 6.0),
            None
        );
        // An extent without bound reads the whole profile in front: the nearest rise.
        let got =
            leading_edge(&p, &choice(100.0), BIN_M, HannLobe::UNPADDED, f64::INFINITY).unwrap();
        assert!((got.depth_m - 46.0).abs() < 1e-6, "{got:?}");
        assert_eq!(
            leading_edge(&p, &choice(100.0), BIN_M, HannLobe::UNPADDED, f64::NAN),
            None
        );
    }
}
