//! The directions present in one range–Doppler cell: peaks of a zero-padded FFT over the base
//! row give azimuths (two walls at the same range and radial velocity, left and right, are two
//! peaks). At each azimuth the elevation comes from the rows above the base row:
//! - one elevated row (the xWR1843's raised TX): its beam and the base channels' beam at the
//!   same azimuth positions differ in phase by `π · e · sin φ`, which gives `φ`;
//! - two or more (a 4D imaging array): each row's beam over the azimuth positions all rows
//!   share, steered to the azimuth, is one element of an elevation aperture, beamformed on a
//!   grid of [`ELEVATION_GRID`] sines over the unambiguous range; up to
//!   [`ELEVATIONS_PER_AZIMUTH`] peaks (the ground and a wall in the same cell) are directions.
//!
//! Phase convention (bundle.md, extended): channel `(p, e)` sees `exp(jπ(p·sin θ + e·sin φ))`
//! for azimuth θ (positive right) and elevation φ (positive up).

use super::geometry::{AZIMUTH_FFT, ArrayGeometry, MAX_AZIMUTH_FFT, MAX_ROWS};
use crate::detect::quadratic_offset;
use crate::fft::{Complex32, cfft_f32};
use libm::{asinf, atan2f, log10f, sincosf};

/// Most azimuths reported per cell.
pub const MAX_DIRECTIONS: usize = 4;
/// Most elevations reported per azimuth (arrays with two or more elevated rows).
pub const ELEVATIONS_PER_AZIMUTH: usize = 2;
/// Points of the elevation beamformer's grid over `|sin φ| < 1 / row spacing`.
pub const ELEVATION_GRID: usize = 64;

/// One direction in a cell.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Direction {
    /// Azimuth, rad, positive right.
    pub azimuth: f32,
    /// Elevation, rad, positive up (0 for an array without elevated channels).
    pub elevation: f32,
    /// Beam power, dB relative to a full-scale unit on every base channel.
    pub power_db: f32,
}

fn db(z: Complex32) -> f32 {
    10.0 * log10f((z.re * z.re + z.im * z.im).max(1e-30))
}

/// Steered sum `Σ v_ch · exp(−jπ·p_ch·s)` over the channels `pick` selects.
fn beam(
    values: &[Complex32],
    geom: &ArrayGeometry,
    s: f32,
    pick: impl Fn(usize) -> bool,
) -> Complex32 {
    let mut acc = Complex32::new(0.0, 0.0);
    for (ch, v) in values.iter().enumerate().take(geom.channels()) {
        if pick(ch) {
            let (si, co) = sincosf(-core::f32::consts::PI * geom.azimuth(ch) as f32 * s);
            acc.re += v.re * co - v.im * si;
            acc.im += v.re * si + v.im * co;
        }
    }
    acc
}

/// The base row's steering toward one azimuth, `exp(−jπ·p_ch·sin θ)` per base channel, for a
/// direction whose power is taken in several cells (its Doppler peak is climbed bin by bin):
/// each phasor is computed once, as [`beam`] computes it.
pub(crate) struct BaseSteering {
    phasors: heapless::Vec<(u16, Complex32), { crate::array::MAX_CHANNELS }>,
}

impl BaseSteering {
    /// The base row of `geom` steered to `sin θ = s`. O(channels).
    pub(crate) fn new(geom: &ArrayGeometry, s: f32) -> Self {
        let phasors = (0..geom.channels())
            .filter(|&ch| geom.elevation(ch) == 0)
            .map(|ch| {
                let (si, co) = sincosf(-core::f32::consts::PI * geom.azimuth(ch) as f32 * s);
                (ch as u16, Complex32::new(co, si))
            })
            .collect();
        Self { phasors }
    }

    /// Power (dB) of the steered sum `Σ value(ch) · exp(−jπ·p_ch·s)` over the base row, channels
    /// in increasing order: how strong the direction is in the cell whose channel values
    /// `value` gives. The same bits as [`beam`] over those values. O(base channels).
    pub(crate) fn power_db(&self, value: impl Fn(usize) -> Complex32) -> f32 {
        let mut acc = Complex32::new(0.0, 0.0);
        for &(ch, w) in &self.phasors {
            let v = value(usize::from(ch));
            acc.re += v.re * w.re - v.im * w.im;
            acc.im += v.re * w.im + v.im * w.re;
        }
        db(acc)
    }
}

/// Each azimuth's share of each elevation row. The rows' channels at the shared columns are
/// fitted by least squares with the steering vectors of the azimuths `sines` the base row found,
/// so a weak direction does not take its elevation from a stronger one that the shared columns'
/// wider beam (16 columns: 7°) cannot tell from it. Returns, per direction, one value per row of
/// [`ArrayGeometry::rows`]. O(channels + rows · columns · directions + directions³).
fn separate(
    values: &[Complex32],
    geom: &ArrayGeometry,
    sines: &[f32],
) -> [[Complex32; MAX_ROWS]; MAX_DIRECTIONS] {
    let zero = Complex32::new(0.0, 0.0);
    let rows = geom.rows();
    let k = sines.len().min(MAX_DIRECTIONS);
    let mut cols: heapless::Vec<usize, AZIMUTH_FFT> = heapless::Vec::new();
    let mut index = [usize::MAX; AZIMUTH_FFT];
    for p in (0..AZIMUTH_FFT).filter(|&p| geom.shared(p)) {
        index[p] = cols.len();
        let _ = cols.push(p);
    }
    // Each row's value per shared column (duplicates averaged).
    let mut y = [[zero; AZIMUTH_FFT]; MAX_ROWS];
    let mut n = [[0u8; AZIMUTH_FFT]; MAX_ROWS];
    for (ch, v) in values.iter().enumerate().take(geom.channels()) {
        let c = index[geom.azimuth(ch)];
        if let (true, Ok(r)) = (c != usize::MAX, rows.binary_search(&geom.elevation(ch))) {
            y[r][c] += *v;
            n[r][c] = n[r][c].saturating_add(1);
        }
    }
    for (yr, nr) in y.iter_mut().zip(&n) {
        for (z, &m) in yr.iter_mut().zip(nr) {
            if m > 1 {
                *z /= f32::from(m);
            }
        }
    }
    // The steering vectors, each phasor computed once (the normal equations and the
    // right-hand sides read them `k + rows` times).
    let mut steering = [[zero; MAX_DIRECTIONS]; AZIMUTH_FFT];
    for (c, row) in steering.iter_mut().enumerate().take(cols.len()) {
        for (w, &s) in row.iter_mut().zip(sines).take(k) {
            let (si, co) = sincosf(core::f32::consts::PI * cols[c] as f32 * s);
            *w = Complex32::new(co, si);
        }
    }
    let steer = |c: usize, d: usize| steering[c][d];
    // Normal equations AᴴA x = Aᴴ y, with a small ridge for azimuths closer than the columns
    // resolve; unused directions keep an identity row.
    let mut g = nalgebra::SMatrix::<Complex32, MAX_DIRECTIONS, MAX_DIRECTIONS>::identity();
    for i in 0..k {
        for j in 0..k {
            let mut acc = zero;
            for c in 0..cols.len() {
                acc += steer(c, i).conj() * steer(c, j);
            }
            g[(i, j)] = acc;
        }
        g[(i, i)] += Complex32::new(1e-3 * cols.len() as f32, 0.0);
    }
    let lu = g.lu();
    let mut out = [[zero; MAX_ROWS]; MAX_DIRECTIONS];
    for (r, yr) in y.iter().enumerate().take(rows.len()) {
        let mut b = nalgebra::SVector::<Complex32, MAX_DIRECTIONS>::zeros();
        for i in 0..k {
            for (c, &v) in yr.iter().enumerate().take(cols.len()) {
                b[i] += steer(c, i).conj() * v;
            }
        }
        if let Some(x) = lu.solve(&b) {
            for (o, &xi) in out.iter_mut().zip(x.iter()).take(k) {
                o[r] = xi;
            }
        }
    }
    out
}

/// Elevation peaks of one direction from its value on each elevation row (`beams`, one per
/// [`ArrayGeometry::rows`]), beamformed over the rows on [`ELEVATION_GRID`] sines spanning the
/// unambiguous `±1 / spacing` (the spectrum is periodic there). Peaks within `floor_db` of the
/// strongest, strongest first, as (elevation rad, dB relative to the strongest).
/// O(rows · grid).
fn elevation_peaks(
    beams: &[Complex32],
    geom: &ArrayGeometry,
    floor_db: f32,
) -> heapless::Vec<(f32, f32), ELEVATIONS_PER_AZIMUTH> {
    let rows = geom.rows();
    let spacing = f32::from(geom.row_spacing().max(1));
    // Grid point g is sin φ = (g − G/2) · step; each row's steering phase advances by a fixed
    // rotation from one point to the next.
    let step = 2.0 / (spacing * ELEVATION_GRID as f32);
    let half = (ELEVATION_GRID / 2) as f32;
    let mut phasor = [Complex32::new(0.0, 0.0); MAX_ROWS];
    let mut turn = [Complex32::new(0.0, 0.0); MAX_ROWS];
    for (r, &e) in rows.iter().enumerate() {
        let (si, co) = sincosf(core::f32::consts::PI * f32::from(e) * half * step);
        phasor[r] = Complex32::new(co, si);
        let (si, co) = sincosf(-core::f32::consts::PI * f32::from(e) * step);
        turn[r] = Complex32::new(co, si);
    }
    let mut spectrum = [0.0f32; ELEVATION_GRID];
    for p in &mut spectrum {
        let mut acc = Complex32::new(0.0, 0.0);
        for r in 0..rows.len() {
            let (b, w) = (beams[r], phasor[r]);
            acc.re += b.re * w.re - b.im * w.im;
            acc.im += b.re * w.im + b.im * w.re;
            let t = turn[r];
            phasor[r] = Complex32::new(w.re * t.re - w.im * t.im, w.re * t.im + w.im * t.re);
        }
        *p = db(acc);
    }
    let top = spectrum.iter().copied().fold(f32::MIN, f32::max);
    let at = |g: usize| spectrum[g % ELEVATION_GRID];
    let mut peaks: heapless::Vec<usize, ELEVATION_GRID> = heapless::Vec::new();
    for (g, &here) in spectrum.iter().enumerate() {
        let (l, r) = (at(g + ELEVATION_GRID - 1), at(g + 1));
        if here >= l && here > r && here >= top - floor_db {
            let _ = peaks.push(g);
        }
    }
    peaks.sort_unstable_by(|&a, &b| spectrum[b].total_cmp(&spectrum[a]));
    peaks
        .iter()
        .take(ELEVATIONS_PER_AZIMUTH)
        .map(|&g| {
            let off = quadratic_offset(at(g + ELEVATION_GRID - 1), spectrum[g], at(g + 1));
            let t = (g as f32 + off - half) * step;
            (asinf(t.clamp(-1.0, 1.0)), spectrum[g] - top)
        })
        .collect()
}

/// Calls `emit` for each direction in the cell with channel values `values` (one per virtual
/// channel): azimuth peaks within `floor_db` of the strongest, strongest first, at most
/// [`MAX_DIRECTIONS`], each with its elevation (or, on an array of several elevated rows, its
/// elevation peaks within `floor_db`, at most [`ELEVATIONS_PER_AZIMUTH`]). Returns how many.
/// O(channels + L log L) plus O(channels + rows · [`ELEVATION_GRID`]) per azimuth.
///
/// [`cell_directions_where`] with every azimuth wanted.
pub fn cell_directions(
    values: &[Complex32],
    geom: &ArrayGeometry,
    floor_db: f32,
    mut emit: impl FnMut(Direction),
) -> usize {
    cell_directions_where(values, geom, floor_db, |_| Some(()), |(), d| emit(d))
}

/// [`cell_directions`] for a caller that rejects some azimuths on its own grounds (a point
/// formed in another cell): `wanted(azimuth)` (rad) is asked once per azimuth, strongest first,
/// before any elevation is searched, and only the azimuths it answers `Some(tag)` have theirs
/// searched; `emit(tag, direction)` gets each of their directions, in the order
/// [`cell_directions`] emits them, with that azimuth's tag. The directions are the same bits as
/// [`cell_directions`]' for those azimuths (on an array of several elevated rows the fit that
/// shares the rows among the azimuths still sees every azimuth). Returns how many were emitted.
pub fn cell_directions_where<T: Copy>(
    values: &[Complex32],
    geom: &ArrayGeometry,
    floor_db: f32,
    mut wanted: impl FnMut(f32) -> Option<T>,
    mut emit: impl FnMut(T, Direction),
) -> usize {
    let n = geom.channels().min(values.len());
    let found = azimuths(&values[..n], geom, floor_db);
    let mut keep: [Option<T>; MAX_DIRECTIONS] = [None; MAX_DIRECTIONS];
    for (k, &(s, _)) in keep.iter_mut().zip(&found) {
        *k = wanted(asinf(s));
    }
    if keep.iter().all(Option::is_none) {
        return 0;
    }
    let mut emitted = 0;
    if geom.rows().len() > 2 {
        let sines: heapless::Vec<f32, MAX_DIRECTIONS> = found.iter().map(|f| f.0).collect();
        let rows = separate(values, geom, &sines);
        for ((&(s, power_db), beams), &tag) in found.iter().zip(&rows).zip(&keep) {
            let Some(tag) = tag else { continue };
            for (elevation, below_db) in
                elevation_peaks(&beams[..geom.rows().len()], geom, floor_db)
            {
                emit(
                    tag,
                    Direction {
                        azimuth: asinf(s),
                        elevation,
                        power_db: power_db + below_db,
                    },
                );
                emitted += 1;
            }
        }
        return emitted;
    }
    let elevated = (0..n)
        .find(|&c| geom.elevation(c) != 0)
        .map(|c| geom.elevation(c));
    for (&(s, power_db), &tag) in found.iter().zip(&keep) {
        let Some(tag) = tag else { continue };
        let elevation = match elevated {
            Some(e) => {
                let up = beam(values, geom, s, |c| geom.elevation(c) == e);
                // The base channels at the elevated channels' azimuth positions.
                let base = beam(values, geom, s, |c| {
                    geom.elevation(c) == 0
                        && (0..n)
                            .any(|u| geom.elevation(u) == e && geom.azimuth(u) == geom.azimuth(c))
                });
                let dphi = atan2f(
                    up.im * base.re - up.re * base.im,
                    up.re * base.re + up.im * base.im,
                );
                asinf((dphi / (core::f32::consts::PI * f32::from(e))).clamp(-1.0, 1.0))
            }
            None => 0.0,
        };
        emit(
            tag,
            Direction {
                azimuth: asinf(s),
                elevation,
                power_db,
            },
        );
        emitted += 1;
    }
    emitted
}

/// The cell's azimuths: peaks of the zero-padded FFT over the base row within `floor_db` of
/// the strongest, strongest first, at most [`MAX_DIRECTIONS`], each as (sin θ, dB).
/// O(channels + L log L).
fn azimuths(
    values: &[Complex32],
    geom: &ArrayGeometry,
    floor_db: f32,
) -> heapless::Vec<(f32, f32), MAX_DIRECTIONS> {
    let len = geom.azimuth_fft_len();
    let mut buf = [Complex32::new(0.0, 0.0); MAX_AZIMUTH_FFT];
    let row = &mut buf[..len];
    let mut count = [0u8; AZIMUTH_FFT];
    for (ch, v) in values.iter().enumerate() {
        if geom.elevation(ch) == 0 {
            let p = geom.azimuth(ch);
            row[p].re += v.re;
            row[p].im += v.im;
            count[p] = count[p].saturating_add(1);
        }
    }
    // Duplicate positions are averaged, so each position weighs once.
    for (z, &c) in row.iter_mut().zip(&count) {
        if c > 1 {
            z.re /= f32::from(c);
            z.im /= f32::from(c);
        }
    }
    let mut found = heapless::Vec::new();
    if cfft_f32(row).is_err() {
        return found;
    }
    let mut mags = [f32::MIN; MAX_AZIMUTH_FFT];
    for (m, z) in mags.iter_mut().zip(row.iter()) {
        *m = db(*z);
    }
    let top = mags.iter().copied().fold(f32::MIN, f32::max);
    let mut peaks: heapless::Vec<usize, MAX_AZIMUTH_FFT> = heapless::Vec::new();
    for k in 0..len {
        let (l, r) = (mags[(k + len - 1) % len], mags[(k + 1) % len]);
        if mags[k] >= l && mags[k] > r && mags[k] >= top - floor_db {
            let _ = peaks.push(k);
        }
    }
    peaks.sort_unstable_by(|&a, &b| mags[b].total_cmp(&mags[a]));
    for &k in peaks.iter().take(MAX_DIRECTIONS) {
        let signed = if k >= len / 2 {
            k as f32 - len as f32
        } else {
            k as f32
        };
        let offset = quadratic_offset(mags[(k + len - 1) % len], mags[k], mags[(k + 1) % len]);
        let s = 2.0 * (signed + offset) / len as f32;
        if (-1.0..=1.0).contains(&s) {
            let _ = found.push((s, mags[k]));
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::tests::example;

    fn geometry() -> ArrayGeometry {
        let mut c = example();
        c.tx_positions = heapless::Vec::from_slice(&[0, 4, 2]).unwrap();
        c.tx_order = heapless::Vec::from_slice(&[0, 1, 2]).unwrap();
        ArrayGeometry::new(&c, &[0, 0, 1], &[]).unwrap()
    }

    /// Channel values of unit targets at (azimuth, elevation, amplitude), in f64 then rounded.
    fn values(g: &ArrayGeometry, targets: &[(f64, f64, f64)]) -> std::vec::Vec<Complex32> {
        (0..g.channels())
            .map(|ch| {
                let (mut re, mut im) = (0.0, 0.0);
                for &(az, el, a) in targets {
                    let phi = core::f64::consts::PI
                        * (g.azimuth(ch) as f64 * az.sin() + f64::from(g.elevation(ch)) * el.sin());
                    re += a * phi.cos();
                    im += a * phi.sin();
                }
                Complex32::new(re as f32, im as f32)
            })
            .collect()
    }

    #[test]
    fn one_target_gives_its_azimuth_and_elevation() {
        let g = geometry();
        for &(az, el) in &[(0.3f64, 0.1f64), (-0.6, -0.2), (0.05, 0.35)] {
            let mut got = std::vec::Vec::new();
            cell_directions(&values(&g, &[(az, el, 1.0)]), &g, 6.0, |d| got.push(d));
            assert_eq!(got.len(), 1, "{got:?}");
            // 8 channels, 64-point FFT: quadratic interpolation is within a few tenths of a
            // degree; the elevation is exact up to the azimuth error's effect on the beams.
            assert!(
                (f64::from(got[0].azimuth) - az).abs() < 0.01,
                "{az} {got:?}"
            );
            assert!(
                (f64::from(got[0].elevation) - el).abs() < 0.01,
                "{el} {got:?}"
            );
        }
    }

    /// A T-shaped 12 × 16 imaging array: four TX fill a 64-element azimuth row, eight more at
    /// azimuth 24 raised 3, 6, …, 24 half-wavelengths.
    fn imaging() -> ArrayGeometry {
        let mut c = example();
        c.tx_positions =
            heapless::Vec::from_slice(&[0, 16, 32, 48, 24, 24, 24, 24, 24, 24, 24, 24]).unwrap();
        c.rx_positions = (0..16).collect();
        c.tx_order = (0..12).collect();
        ArrayGeometry::new(&c, &[0, 0, 0, 0, 3, 6, 9, 12, 15, 18, 21, 24], &[]).unwrap()
    }

    #[test]
    fn an_imaging_array_has_nine_rows_over_sixteen_shared_columns() {
        let g = imaging();
        assert_eq!(g.channels(), 192);
        assert_eq!(g.rows(), [0, 3, 6, 9, 12, 15, 18, 21, 24]);
        assert_eq!(g.row_spacing(), 3);
        let shared: std::vec::Vec<usize> = (0..AZIMUTH_FFT).filter(|&p| g.shared(p)).collect();
        assert_eq!(shared, (24..40).collect::<std::vec::Vec<_>>());
        assert_eq!(geometry().row_spacing(), 1);
    }

    #[test]
    fn an_imaging_array_beamforms_its_elevation_rows() {
        let g = imaging();
        // Within the unambiguous ±19.5°, on and off grid points.
        for &(az, el) in &[(0.0f64, 0.0f64), (0.3, 0.1), (-0.5, -0.25), (0.6, 0.31)] {
            let mut got = std::vec::Vec::new();
            cell_directions(&values(&g, &[(az, el, 1.0)]), &g, 6.0, |d| got.push(d));
            assert_eq!(got.len(), 1, "{az} {el}: {got:?}");
            // The 64-point FFT of a 64-element row is not zero-padded: quadratic
            // interpolation is within a third of the 1.8° beam.
            assert!(
                (f64::from(got[0].azimuth) - az).abs() < 0.01,
                "{az} {got:?}"
            );
            assert!(
                (f64::from(got[0].elevation) - el).abs() < 0.006,
                "{el} {got:?}"
            );
        }
    }

    #[test]
    fn the_ground_and_a_wall_in_one_cell_are_two_elevations() {
        let g = imaging();
        // Same azimuth, 14° apart in elevation (the beam is 4.2° wide), the wall 2 dB weaker.
        let v = values(&g, &[(0.4, -0.17, 1.0), (0.4, 0.08, 0.8)]);
        let mut got = std::vec::Vec::new();
        assert_eq!(cell_directions(&v, &g, 6.0, |d| got.push(d)), 2);
        assert!((f64::from(got[0].elevation) + 0.17).abs() < 0.01, "{got:?}");
        assert!((f64::from(got[1].elevation) - 0.08).abs() < 0.01, "{got:?}");
        assert!(
            got.iter()
                .all(|d| (f64::from(d.azimuth) - 0.4).abs() < 0.01)
        );
        let below = got[0].power_db - got[1].power_db;
        assert!((below - 1.94).abs() < 0.5, "{below} dB");
    }

    #[test]
    fn a_weak_direction_keeps_its_own_elevation_beside_a_strong_one() {
        let g = imaging();
        // 2.9° apart in azimuth: two beams of the 64-element row, but inside one beam of the
        // 16 shared columns; the pole 5 dB stronger and 11° higher than the kerb beside it.
        let v = values(&g, &[(0.30, 0.15, 1.0), (0.25, -0.05, 0.56)]);
        let mut got = std::vec::Vec::new();
        cell_directions(&v, &g, 8.0, |d| got.push(d));
        let near = |az: f64| {
            got.iter()
                .find(|d| (f64::from(d.azimuth) - az).abs() < 0.01)
                .unwrap_or_else(|| panic!("{az}: {got:?}"))
        };
        assert!(
            (f64::from(near(0.30).elevation) - 0.15).abs() < 0.01,
            "{got:?}"
        );
        assert!(
            (f64::from(near(0.25).elevation) + 0.05).abs() < 0.01,
            "{got:?}"
        );
    }

    #[test]
    fn a_rejected_azimuth_is_not_searched_and_the_others_are_unchanged() {
        // Two azimuths, the first with two elevations: reject each in turn; the rest come back with
        // the same bits and their own tags, and `wanted` is asked once per azimuth.
        let g = imaging();
        let v = values(
            &g,
            &[(0.4, -0.17, 1.0), (0.4, 0.08, 0.8), (-0.3, 0.05, 1.2)],
        );
        let mut all = std::vec::Vec::new();
        assert_eq!(cell_directions(&v, &g, 6.0, |d| all.push(d)), 3);
        for reject in [0.4f32, -0.3] {
            let (mut asked, mut got) = (0, std::vec::Vec::new());
            let n = cell_directions_where(
                &v,
                &g,
                6.0,
                |az| {
                    asked += 1;
                    ((az.sin() - reject).abs() > 0.05).then_some(az.to_bits())
                },
                |tag, d| got.push((tag, d)),
            );
            assert_eq!(asked, 2);
            let kept: std::vec::Vec<Direction> = all
                .iter()
                .copied()
                .filter(|d| (d.azimuth.sin() - reject).abs() > 0.05)
                .collect();
            assert_eq!(n, kept.len());
            assert!(!kept.is_empty() && kept.len() < all.len());
            assert_eq!(got.iter().map(|g| g.1).collect::<std::vec::Vec<_>>(), kept);
            assert!(got.iter().all(|(tag, d)| *tag == d.azimuth.to_bits()));
        }
    }

    #[test]
    fn two_walls_at_mirror_azimuths_are_two_directions() {
        let g = geometry();
        let mut got = std::vec::Vec::new();
        let v = values(&g, &[(-0.7, 0.0, 1.0), (0.7, 0.0, 0.8)]);
        assert_eq!(cell_directions(&v, &g, 6.0, |d| got.push(d)), 2);
        assert!((f64::from(got[0].azimuth) + 0.7).abs() < 0.02, "{got:?}");
        assert!((f64::from(got[1].azimuth) - 0.7).abs() < 0.02, "{got:?}");
        assert!(got[0].power_db > got[1].power_db);
    }
}
