//! The directions present in one range–Doppler cell: peaks of a zero-padded FFT over the base
//! row give azimuths (two walls at the same range and radial velocity, left and right, are two
//! peaks); at each, beams of the elevated channels and of the base channels at the same azimuth
//! positions differ in phase by `π · e · sin φ`, which gives the elevation `φ`.
//!
//! Phase convention (bundle.md, extended): channel `(p, e)` sees `exp(jπ(p·sin θ + e·sin φ))`
//! for azimuth θ (positive right) and elevation φ (positive up).

use super::geometry::{AZIMUTH_FFT, ArrayGeometry};
use crate::detect::quadratic_offset;
use crate::fft::{Complex32, cfft_f32};
use libm::{asinf, atan2f, log10f, sincosf};

/// Most directions reported per cell.
pub const MAX_DIRECTIONS: usize = 4;

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

/// Power (dB) of the base row steered to `sin θ = s`: how strong direction θ is in a cell.
/// O(channels).
pub fn steered_power_db(values: &[Complex32], geom: &ArrayGeometry, s: f32) -> f32 {
    db(beam(values, geom, s, |c| geom.elevation(c) == 0))
}

/// Calls `emit` for each direction in the cell with channel values `values` (one per virtual
/// channel): azimuth peaks within `floor_db` of the strongest, strongest first, at most
/// [`MAX_DIRECTIONS`]. Returns how many. O(channels + L log L) plus O(channels) per direction.
pub fn cell_directions(
    values: &[Complex32],
    geom: &ArrayGeometry,
    floor_db: f32,
    mut emit: impl FnMut(Direction),
) -> usize {
    let n = geom.channels().min(values.len());
    let mut row = [Complex32::new(0.0, 0.0); AZIMUTH_FFT];
    let mut count = [0u8; AZIMUTH_FFT];
    for (ch, v) in values.iter().enumerate().take(n) {
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
    if cfft_f32(&mut row).is_err() {
        return 0;
    }
    let mags: [f32; AZIMUTH_FFT] = core::array::from_fn(|k| db(row[k]));
    let top = mags.iter().copied().fold(f32::MIN, f32::max);
    let mut peaks: heapless::Vec<usize, AZIMUTH_FFT> = heapless::Vec::new();
    for k in 0..AZIMUTH_FFT {
        let (l, r) = (
            mags[(k + AZIMUTH_FFT - 1) % AZIMUTH_FFT],
            mags[(k + 1) % AZIMUTH_FFT],
        );
        if mags[k] >= l && mags[k] > r && mags[k] >= top - floor_db {
            let _ = peaks.push(k);
        }
    }
    peaks.sort_unstable_by(|&a, &b| mags[b].total_cmp(&mags[a]));
    let elevated = (0..n)
        .find(|&c| geom.elevation(c) != 0)
        .map(|c| geom.elevation(c));
    let mut emitted = 0;
    for &k in peaks.iter().take(MAX_DIRECTIONS) {
        let signed = if k >= AZIMUTH_FFT / 2 {
            k as f32 - AZIMUTH_FFT as f32
        } else {
            k as f32
        };
        let offset = quadratic_offset(
            mags[(k + AZIMUTH_FFT - 1) % AZIMUTH_FFT],
            mags[k],
            mags[(k + 1) % AZIMUTH_FFT],
        );
        let s = 2.0 * (signed + offset) / AZIMUTH_FFT as f32;
        if !(-1.0..=1.0).contains(&s) {
            continue;
        }
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
        emit(Direction {
            azimuth: asinf(s),
            elevation,
            power_db: mags[k],
        });
        emitted += 1;
    }
    emitted
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
