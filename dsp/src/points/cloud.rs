//! The point cloud of one frame: CFAR over the range–Doppler map, local maxima only, then the
//! directions of each detected cell from its channel values.
//!
//! Range is interpolated between bins (parabola through the dB values of the map). Radial
//! velocity is found per direction: the base row steered to the direction's azimuth is
//! evaluated in the neighbouring Doppler bins, climbed to its peak and interpolated, so two
//! walls that share a cell (left and right at mirror azimuths) each get their own velocity.
//! Channel values are compensated for TDM-MIMO: each TX slot transmits later in the loop, so a
//! moving target's phase advances from slot to slot, which would otherwise bias its azimuth in
//! proportion to its Doppler. The power is the direction's beam power, and `rcs_db` adds `40·log10(range)` (the radar
//! equation's spreading loss) for a relative, uncalibrated RCS.

use super::angles::{Direction, cell_directions, steered_power_db};
use super::geometry::ArrayGeometry;
use crate::config::RadarConfig;
use crate::detect::{Cfar2d, CfarError, quadratic_offset};
use crate::doppler::{DopplerError, DopplerOptions, doppler_column};
use crate::fft::Complex32;
use crate::fixed::CQ15;
use crate::range::RangeCube;

use core::fmt;
use libm::{cosf, fabsf, log10f, sinf};

/// How close to the unambiguous speed a static point's radial velocity may come before its
/// measurement is unfolded towards the prior, m/s (Doppler noise could fold it already).
pub const FOLD_MARGIN_MPS: f32 = 0.5;

/// How a frame becomes points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CloudOptions {
    /// The detector over the range–Doppler map (Doppler wraps, range truncates).
    pub cfar: Cfar2d,
    /// Directions of a cell within this many dB of its strongest are points too.
    pub direction_floor_db: f32,
    /// Nearer detections are dropped (the radar's own leakage), m.
    pub min_range_m: f32,
    /// Cells more than this far below the map's strongest are dropped, dB: the processing's
    /// dynamic range, below which CFAR only finds the range and Doppler side lobes of strong
    /// reflectors (the local noise estimate there is itself side lobes).
    pub dynamic_range_db: f32,
    /// The radar's velocity `[v_x, v_z]` (m/s, radar frame) expected this frame, for a board
    /// whose unambiguous velocity a static world can exceed (a 4D imaging board's twelve TX
    /// slots give ±5 m/s). In directions where a static point's radial velocity comes within
    /// [`FOLD_MARGIN_MPS`] of the unambiguous speed or beyond, each direction's radial velocity
    /// is unfolded to the alias nearest a static point's, and its channels are compensated for
    /// the unfolded Doppler's TDM phase before its azimuth and elevation are found; elsewhere
    /// it stands as measured. `None`: as measured, within ±[`RadarConfig::max_velocity`].
    pub velocity_prior: Option<[f32; 2]>,
}

/// One point of the cloud.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RadarPoint {
    /// Position in the radar frame (x right, y down, z forward), m.
    pub position: [f32; 3],
    /// Range in the x–z plane (bundle.md's range: the radar measures no elevation in range), m.
    pub range_m: f32,
    /// Azimuth, rad, positive right.
    pub azimuth: f32,
    /// Elevation, rad, positive up.
    pub elevation: f32,
    /// Radial velocity, m/s, positive away.
    pub radial_velocity_mps: f32,
    /// Beam power, dB full scale.
    pub power_db: f32,
    /// Relative radar cross section, dB (uncalibrated: power + 40·log10 range).
    pub rcs_db: f32,
}

impl RadarPoint {
    /// A point at `range` (in the x–z plane, as bundle.md measures range) in direction `d`.
    fn new(range: f32, velocity: f32, d: Direction) -> Self {
        Self {
            position: [
                range * sinf(d.azimuth),
                -range * libm::tanf(d.elevation),
                range * cosf(d.azimuth),
            ],
            range_m: range,
            azimuth: d.azimuth,
            elevation: d.elevation,
            radial_velocity_mps: velocity,
            power_db: d.power_db,
            rcs_db: d.power_db + 40.0 * log10f(range.max(1e-3)),
        }
    }
}

/// Why a frame's points could not be formed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PointsError {
    /// The detector could not run.
    Cfar(CfarError),
    /// A Doppler spectrum could not be formed.
    Doppler(DopplerError),
    /// A buffer has the wrong size (names which).
    Buffer(&'static str),
}

impl core::error::Error for PointsError {}

impl fmt::Display for PointsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PointsError::Cfar(e) => write!(f, "CFAR: {e}"),
            PointsError::Doppler(e) => write!(f, "Doppler: {e}"),
            PointsError::Buffer(which) => write!(
                f,
                "the {which} buffer has the wrong size for this configuration"
            ),
        }
    }
}

fn db(v: f32) -> f32 {
    20.0 * log10f(v.max(1e-30))
}

/// Calls `emit` for every point of the frame in `cube`. `map` is its range–Doppler map
/// (`bins × nd`, from [`crate::doppler::range_doppler_map`] with the same `doppler` options),
/// `scratch` has the Doppler length `nd`, `spectra` holds `channels × nd` values (the Doppler
/// spectra of one range bin). Only detections at range bins in `bins_in` become points
/// (`0..usize::MAX` for all): parts of the bins give the same points in the same order, so the
/// host can split a frame among threads and concatenate. Returns the number of points.
/// O(cells · window) for CFAR plus O(channels · nd log nd) per range bin with a detection.
///
/// # Errors
/// [`PointsError`] on size mismatches.
#[allow(clippy::too_many_arguments)]
pub fn frame_points(
    cube: &RangeCube<impl AsRef<[CQ15]>, impl AsRef<[crate::fft::Exponent]>>,
    config: &RadarConfig,
    geom: &ArrayGeometry,
    doppler: &DopplerOptions<'_>,
    map: &[f32],
    options: &CloudOptions,
    bins_in: core::ops::Range<usize>,
    scratch: &mut [CQ15],
    spectra: &mut [Complex32],
    mut emit: impl FnMut(RadarPoint),
) -> Result<usize, PointsError> {
    let (bins, nd, channels) = (cube.bins(), scratch.len(), geom.channels());
    if map.len() != bins * nd {
        return Err(PointsError::Buffer("range-Doppler map"));
    }
    if spectra.len() != channels * nd || cube.channels() != channels {
        return Err(PointsError::Buffer("spectra"));
    }
    let nr = config.range_fft_len();
    let at = |b: usize, d: usize| map[b * nd + d % nd];
    let mut loaded = usize::MAX;
    let mut failed = None;
    let mut count = 0;
    let mut values = [Complex32::new(0.0, 0.0); crate::array::MAX_CHANNELS];
    let peak = map.iter().copied().fold(0.0f32, f32::max);
    let floor = peak * libm::powf(10.0, -options.dynamic_range_db / 20.0);
    options
        .cfar
        .detect(map, bins, nd, |det| {
            if failed.is_some() {
                return;
            }
            let (b, d) = (det.index / nd, det.index % nd);
            if !bins_in.contains(&b) {
                return;
            }
            // Local maxima of the map only (Doppler wraps, range truncates).
            let v = det.value;
            if v < floor {
                return;
            }
            if !is_map_peak(map, (bins, nd), (b, d)) {
                return;
            }
            let range_off = if b > 0 && b + 1 < bins {
                quadratic_offset(db(at(b - 1, d)), db(v), db(at(b + 1, d)))
            } else {
                0.0
            };
            let range = config.bin_to_range(b as f32 + range_off, nr);
            if range < options.min_range_m {
                return;
            }
            if loaded != b {
                if let Err(e) = doppler_spectra(cube, b, doppler, scratch, spectra) {
                    failed = Some(e);
                    return;
                }
                loaded = b;
            }
            let spectra: &[Complex32] = spectra;
            let slots = config.slots() as f32;
            let rx = config.rx_count();
            // Channel values of Doppler bin `k` unfolded by `alias` periods, TDM-MIMO Doppler
            // phase removed.
            let cell_at = |k: usize, alias: i32, out: &mut [Complex32]| {
                compensated_cell(spectra, (nd, rx, slots), (k, alias), out);
            };
            // The direction's power in Doppler bin `k`.
            let power = |k: usize, alias: i32, s: f32| {
                let mut cell = [Complex32::new(0.0, 0.0); crate::array::MAX_CHANNELS];
                cell_at(k, alias, &mut cell[..channels]);
                steered_power_db(&cell[..channels], geom, s)
            };
            // A direction's measured radial velocity (its own Doppler peak near `d`), and the
            // aliases to add to reach the prior's static point in that direction.
            let span = config.doppler_to_velocity(nd as f32, nd);
            let measure = |dir: &Direction, alias: i32| {
                let s = sinf(dir.azimuth);
                let (k, off) = doppler_peak(|k| power(k, alias, s), d + nd);
                let k = k % nd;
                let signed = if k >= nd / 2 {
                    k as f32 - nd as f32
                } else {
                    k as f32
                };
                let folded = config.doppler_to_velocity(signed + off, nd);
                let wanted = options.velocity_prior.map_or(0, |v| {
                    let static_vr = -(sinf(dir.azimuth) * v[0] + cosf(dir.azimuth) * v[1]);
                    // Where a static point does not fold, the measurement stands: a mover's
                    // alias cannot be known.
                    if fabsf(static_vr) <= 0.5 * span - FOLD_MARGIN_MPS {
                        0
                    } else {
                        libm::roundf((static_vr - folded) / span) as i32
                    }
                });
                (folded, wanted)
            };
            cell_at(d, 0, &mut values[..channels]);
            // First as measured; a direction whose prior asks for another alias is found again
            // in the cell compensated for it.
            let mut others: heapless::Vec<
                i32,
                { super::angles::MAX_DIRECTIONS * super::angles::ELEVATIONS_PER_AZIMUTH },
            > = heapless::Vec::new();
            cell_directions(
                &values[..channels],
                geom,
                options.direction_floor_db,
                |dir| {
                    let (folded, wanted) = measure(&dir, 0);
                    if wanted == 0 {
                        emit(RadarPoint::new(range, folded, dir));
                        count += 1;
                    } else if !others.contains(&wanted) {
                        let _ = others.push(wanted);
                    }
                },
            );
            for &alias in &others {
                cell_at(d, alias, &mut values[..channels]);
                cell_directions(
                    &values[..channels],
                    geom,
                    options.direction_floor_db,
                    |dir| {
                        let (folded, wanted) = measure(&dir, alias);
                        if wanted == alias {
                            emit(RadarPoint::new(range, folded + alias as f32 * span, dir));
                            count += 1;
                        }
                    },
                );
            }
        })
        .map_err(PointsError::Cfar)?;
    match failed {
        Some(e) => Err(e),
        None => Ok(count),
    }
}

/// Whether cell `(b, d)` of the `bins × nd` range–Doppler `map` is a local maximum (Doppler
/// wraps, range truncates).
fn is_map_peak(map: &[f32], (bins, nd): (usize, usize), (b, d): (usize, usize)) -> bool {
    let at = |b: usize, d: usize| map[b * nd + d % nd];
    let v = at(b, d);
    !(-1i32..=1).any(|dr| {
        (-1i32..=1).any(|dd| {
            let rb = b as i32 + dr;
            (dr, dd) != (0, 0)
                && rb >= 0
                && (rb as usize) < bins
                && at(rb as usize, (d as i32 + dd + nd as i32) as usize) > v
        })
    })
}

/// The Doppler spectra of range bin `b` of every channel into `spectra` (`channels × nd`,
/// scaled to full scale 1), through `scratch` (`nd` values).
fn doppler_spectra(
    cube: &RangeCube<impl AsRef<[CQ15]>, impl AsRef<[crate::fft::Exponent]>>,
    b: usize,
    doppler: &DopplerOptions<'_>,
    scratch: &mut [CQ15],
    spectra: &mut [Complex32],
) -> Result<(), PointsError> {
    let nd = scratch.len();
    for ch in 0..cube.channels() {
        let e = doppler_column(cube, ch, b, doppler, scratch).map_err(PointsError::Doppler)?;
        let scale = (1.0 / 32768.0) * e.scale_f32();
        for (o, z) in spectra[ch * nd..(ch + 1) * nd].iter_mut().zip(&*scratch) {
            *o = Complex32::new(f32::from(z.re.0) * scale, f32::from(z.im.0) * scale);
        }
    }
    Ok(())
}

/// Channel values of Doppler bin `k` (wrapping) into `out`, with the TDM-MIMO phase of the
/// Doppler removed: slot `s` transmits `s` chirp periods into the loop, so a target at signed
/// Doppler bin `b` (the measured bin plus `alias` periods of `nd`) has advanced
/// `2π·b·s / (nd·slots)` there.
fn compensated_cell(
    spectra: &[Complex32],
    (nd, rx, slots): (usize, usize, f32),
    (k, alias): (usize, i32),
    out: &mut [Complex32],
) {
    let k = k % nd;
    let signed = if k >= nd / 2 {
        k as f32 - nd as f32
    } else {
        k as f32
    } + alias as f32 * nd as f32;
    for (ch, o) in out.iter_mut().enumerate() {
        let slot = (ch / rx) as f32;
        let phi = -core::f32::consts::TAU * signed * slot / (nd as f32 * slots);
        let (si, co) = (sinf(phi), cosf(phi));
        let z = spectra[ch * nd + k];
        *o = Complex32::new(z.re * co - z.im * si, z.re * si + z.im * co);
    }
}

/// Climbs from Doppler bin `k` (offset by one period so `k − 1` does not wrap) to the
/// direction's own peak of `power` (at most two bins); the peak's bin and its parabolic
/// sub-bin offset.
fn doppler_peak(power: impl Fn(usize) -> f32, mut k: usize) -> (usize, f32) {
    let mut here = power(k);
    for _ in 0..2 {
        let (l, r) = (power(k - 1), power(k + 1));
        if l > here && l >= r {
            k -= 1;
            here = l;
        } else if r > here {
            k += 1;
            here = r;
        } else {
            break;
        }
    }
    (k, quadratic_offset(power(k - 1), here, power(k + 1)))
}
