//! The point cloud of one frame: CFAR over the range–Doppler map, then the directions of each
//! detected cell from its channel values. Which detections are points is [`Peaks`]'s choice:
//! the map's local maxima (the module's way), or every cell, each direction kept where its own
//! beam peaks in range and Doppler (a peak of the 4D range–Doppler–direction cube). A
//! [`Screen`] lets cells the CFAR misses through to that test too.
//!
//! Range is interpolated between bins (parabola through the dB values of the map). Radial
//! velocity is found per direction: the base row steered to the direction's azimuth is
//! evaluated in the neighbouring Doppler bins, climbed to its peak and interpolated, so two
//! walls that share a cell (left and right at mirror azimuths) each get their own velocity.
//! Channel values are compensated for TDM-MIMO: each TX slot transmits later in the loop, so a
//! moving target's phase advances from slot to slot, which would otherwise bias its azimuth in
//! proportion to its Doppler. The power is the direction's beam power, and `rcs_db` adds `40·log10(range)` (the radar
//! equation's spreading loss) for a relative, uncalibrated RCS.

use super::angles::{BaseSteering, Direction, MAX_DIRECTIONS, cell_directions_where};
use super::geometry::ArrayGeometry;
use crate::config::{MAX_SLOTS, RadarConfig};
use crate::detect::{Cfar2d, CfarError, median_floor, quadratic_offset};
use crate::doppler::{DopplerError, DopplerOptions, doppler_column};
use crate::fft::{Complex32, Exponent};
use crate::fixed::CQ15;
use crate::range::RangeCube;

use core::fmt;
use libm::{cosf, fabsf, log10f, sinf};

/// How close to the unambiguous speed a static point's radial velocity may come before its
/// measurement is unfolded towards the prior, m/s (Doppler noise could fold it already).
pub const FOLD_MARGIN_MPS: f32 = 0.5;

/// Which CFAR detections become points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Peaks {
    /// Only local maxima of the range–Doppler map (summed over channels), each cell's
    /// directions from its channel values: one [`DopplerSpectra::load`] per range bin with a
    /// peak. A weaker reflector in another direction one range or Doppler bin from a stronger
    /// one is not a maximum of the map and is lost; from a moving platform, where every
    /// azimuth of a static street has its own Doppler and walls fill range bin after range bin,
    /// that is most of them.
    #[default]
    RangeDoppler,
    /// Every detected cell, each of its directions kept only where that direction's own beam
    /// power peaks over the neighbouring range bins and Doppler bins (the same direction
    /// steered in each): a reflector is one point, at its own cell, however strong its
    /// neighbours in other directions are. A range bin with a detection needs its two
    /// neighbours' spectra too (`spectra` holds three bins; each is loaded once in a run of
    /// detected bins), and each direction a few more beams; elevations are searched only for
    /// the directions whose point forms in the cell.
    Direction,
}

impl Peaks {
    /// Range bins of Doppler spectra [`frame_points`] needs at once.
    pub const fn bins_held(self) -> usize {
        match self {
            Self::RangeDoppler => 1,
            Self::Direction => 3,
        }
    }
}

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
    /// A second, looser test cells may pass instead of the detector's: `None` for the detector
    /// alone.
    pub screen: Option<Screen>,
    /// The radar's velocity `[v_x, v_z]` (m/s, radar frame) expected this frame, for a board
    /// whose unambiguous velocity a static world can exceed (a 4D imaging board's twelve TX
    /// slots give ±5 m/s). In directions where a static point's radial velocity comes within
    /// [`FOLD_MARGIN_MPS`] of the unambiguous speed or beyond, each direction's radial velocity
    /// is unfolded to the alias nearest a static point's, and its channels are compensated for
    /// the unfolded Doppler's TDM phase before its azimuth and elevation are found; elsewhere
    /// it stands as measured. `None`: as measured, within ±[`RadarConfig::max_velocity`].
    pub velocity_prior: Option<[f32; 2]>,
    /// Which detections become points.
    pub peaks: Peaks,
}

/// A looser test for the cells the detector ([`CloudOptions::cfar`] within
/// [`CloudOptions::dynamic_range_db`]) misses: a cell passes where it exceeds `scale` times the
/// detector's estimate of its training cells, lies within `dynamic_range_db` of the map's
/// strongest cell and `noise_margin_db` or more over the map's median ([`median_floor`]: the
/// noise, where noise fills most of the map; O(n) per frame, `n` the map's cells). For
/// [`Peaks::Direction`], whose own test of each direction's peak in range and Doppler decides
/// what is a point: cells whose training window other directions' returns crowd are tested
/// too. Never fewer cells than the detector alone: a frame whose strongest return
/// is so strong that the near dynamic range holds little else keeps the detector's cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Screen {
    /// CFAR scale over the training cells' estimate, at most the detector's (1: louder than
    /// the estimate).
    pub scale: f32,
    /// Cells more than this far below the map's strongest fail, dB.
    pub dynamic_range_db: f32,
    /// Cells less than this far over the map's median magnitude fail, dB: in a capture whose
    /// noise comes within `dynamic_range_db` of its strongest return, the noise's own cells
    /// would pass the other two tests about half the time.
    pub noise_margin_db: f32,
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

/// Where [`frame_points`] reads the Doppler spectra of a range bin's channels: formed from the
/// range cube when asked ([`CubeSpectra`]: one column of scratch, the module's way), or kept
/// from the pass that formed the range–Doppler map (the host's, which has the memory).
pub trait DopplerSpectra {
    /// Channels per range bin.
    fn channels(&self) -> usize;

    /// The Doppler spectrum of every channel at range bin `bin` into `out` (`channels × nd`,
    /// natural FFT order, full scale 1: [`spectrum_f32`] of each block-floating-point column).
    ///
    /// # Errors
    /// [`PointsError`] if the bin or `out` does not fit.
    fn load(&mut self, bin: usize, out: &mut [Complex32]) -> Result<(), PointsError>;
}

/// A block-floating-point spectrum (`column · 2^exponent`, Q15) as `f32` into `out`, full
/// scale 1. O(len).
pub fn spectrum_f32(exponent: Exponent, column: &[CQ15], out: &mut [Complex32]) {
    let scale = (1.0 / 32768.0) * exponent.scale_f32();
    for (o, z) in out.iter_mut().zip(column) {
        *o = Complex32::new(f32::from(z.re.0) * scale, f32::from(z.im.0) * scale);
    }
}

/// Doppler spectra formed from a frame's range cube when [`frame_points`] asks for a bin
/// ([`doppler_column`] per channel, through `scratch`). O(channels · nd log nd) per bin.
pub struct CubeSpectra<'a, D, E> {
    /// The frame's range cube.
    pub cube: &'a RangeCube<D, E>,
    /// How the range–Doppler map's spectra were formed.
    pub doppler: DopplerOptions<'a>,
    /// One column: its length is the Doppler FFT length `nd`.
    pub scratch: &'a mut [CQ15],
}

impl<D: AsRef<[CQ15]>, E: AsRef<[Exponent]>> DopplerSpectra for CubeSpectra<'_, D, E> {
    fn channels(&self) -> usize {
        self.cube.channels()
    }

    fn load(&mut self, bin: usize, out: &mut [Complex32]) -> Result<(), PointsError> {
        let nd = self.scratch.len();
        if nd == 0 || out.len() != self.cube.channels() * nd {
            return Err(PointsError::Buffer("spectra"));
        }
        for (ch, o) in out.chunks_exact_mut(nd).enumerate() {
            let e = doppler_column(self.cube, ch, bin, &self.doppler, self.scratch)
                .map_err(PointsError::Doppler)?;
            spectrum_f32(e, self.scratch, o);
        }
        Ok(())
    }
}

/// Calls `emit` for every point of a frame. `map` is its range–Doppler map (`bins × nd`, from
/// [`crate::doppler::range_doppler_map`]), `source` gives the Doppler spectra that map was
/// formed from, one range bin at a time, into `spectra` (`channels × nd` values for each of
/// [`Peaks::bins_held`] bins of `options.peaks`). Only
/// detections at range bins in `bins_in` become points (`0..usize::MAX` for all): parts of the
/// bins give the same points in the same order, so the host can split a frame among threads and
/// concatenate. Returns the number of points. O(cells · window) for CFAR plus at most
/// [`Peaks::bins_held`] [`DopplerSpectra::load`]s per range bin with a detection (a bin still
/// held from the bin before is not loaded again) and O(channels) per direction.
///
/// # Errors
/// [`PointsError`] on size mismatches.
#[allow(clippy::too_many_arguments)]
pub fn frame_points(
    source: &mut (impl DopplerSpectra + ?Sized),
    config: &RadarConfig,
    geom: &ArrayGeometry,
    map: &[f32],
    options: &CloudOptions,
    bins_in: core::ops::Range<usize>,
    spectra: &mut [Complex32],
    mut emit: impl FnMut(RadarPoint),
) -> Result<usize, PointsError> {
    let (channels, rx) = (geom.channels(), config.rx_count());
    let held = options.peaks.bins_held();
    if channels == 0
        || !spectra.len().is_multiple_of(channels * held)
        || source.channels() != channels
        || channels != config.slots() * rx
    {
        return Err(PointsError::Buffer("spectra"));
    }
    let (nr, nd) = (config.range_fft_len(), spectra.len() / (channels * held));
    let block = channels * nd;
    let bins = nr;
    if nd == 0 || map.len() != bins * nd {
        return Err(PointsError::Buffer("range-Doppler map"));
    }
    let at = |b: usize, d: usize| map[b * nd + d % nd];
    // The range bin each block of `spectra` holds: bin `n` in block `n % held`, so a bin's
    // neighbours are never in its block and a run of detected bins loads each bin once.
    let mut loaded = [usize::MAX; Peaks::Direction.bins_held()];
    let mut failed = None;
    let mut count = 0;
    let mut values = [Complex32::new(0.0, 0.0); crate::array::MAX_CHANNELS];
    let peak = map.iter().copied().fold(0.0f32, f32::max);
    let below_peak = |db: f32| peak * libm::powf(10.0, -db / 20.0);
    let floor = below_peak(options.dynamic_range_db);
    // With a screen, the CFAR runs at the lower of the two scales and each test is applied to
    // its estimate (the threshold over that scale: exact at scale 1).
    let mut run = *options;
    let screen = options.screen.map(|s| {
        let scale = s.scale.min(run.cfar.rows.scale);
        let detector = run.cfar.rows.scale;
        run.cfar.rows.scale = scale;
        let over_noise = median_floor(map) * libm::powf(10.0, s.noise_margin_db / 20.0);
        (
            scale,
            detector,
            below_peak(s.dynamic_range_db).max(over_noise),
            s.scale,
        )
    });
    run.cfar
        .detect_rows(map, bins, nd, bins_in, |det| {
            if failed.is_some() {
                return;
            }
            let (b, d) = (det.index / nd, det.index % nd);
            let v = det.value;
            let passes = match screen {
                None => v >= floor,
                Some((scale, detector, near_floor, loose)) => {
                    let level = det.threshold / scale;
                    (v > detector * level && v >= floor) || (v > loose * level && v >= near_floor)
                }
            };
            if !passes {
                return;
            }
            // Local maxima of the map only (Doppler wraps, range truncates), or every cell with
            // each direction's own peak tested below.
            let by_direction = options.peaks == Peaks::Direction;
            if !by_direction && !is_map_peak(map, (bins, nd), (b, d)) {
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
            // This bin, and by direction the bins below and above it, each unless held already.
            for n in [Some(b), b.checked_sub(1), Some(b + 1).filter(|&n| n < bins)]
                .into_iter()
                .take(held)
                .flatten()
            {
                let slot = n % held;
                if loaded[slot] != n {
                    loaded[slot] = usize::MAX;
                    if let Err(e) = source.load(n, &mut spectra[slot * block..][..block]) {
                        failed = Some(e);
                        return;
                    }
                    loaded[slot] = n;
                }
            }
            // Where bin `n`'s spectra start.
            let at_bin = |n: usize| (n % held) * block;
            let here = at_bin(b);
            let spectra: &[Complex32] = spectra;
            let slots = config.slots();
            // Channel values of Doppler bin `k` unfolded by `alias` periods, TDM-MIMO Doppler
            // phase removed.
            let cell_at = |k: usize, alias: i32, out: &mut [Complex32]| {
                let turns = slot_phasors((nd, slots), (k, alias));
                let k = k % nd;
                for (ch, o) in out.iter_mut().enumerate() {
                    *o = rotate(spectra[here + ch * nd + k], turns[ch / rx]);
                }
            };
            // The direction's power in Doppler bin `k`: the base row of that cell, TDM phase
            // removed, steered to it (only the channels the power reads are compensated).
            let power = |k: usize, alias: i32, steering: &BaseSteering| {
                let turns = slot_phasors((nd, slots), (k, alias));
                let k = k % nd;
                steering.power_db(|ch| rotate(spectra[here + ch * nd + k], turns[ch / rx]))
            };
            // A direction's measured radial velocity (its own Doppler peak near `d`), and the
            // aliases to add to reach the prior's static point in that direction.
            let span = config.doppler_to_velocity(nd as f32, nd);
            let measure = |azimuth: f32, steering: &BaseSteering, alias: i32| {
                let (k, off) = doppler_peak(|k| power(k, alias, steering), d + nd);
                let k = k % nd;
                let own = k == d;
                let signed = if k >= nd / 2 {
                    k as f32 - nd as f32
                } else {
                    k as f32
                };
                let folded = config.doppler_to_velocity(signed + off, nd);
                let wanted = options.velocity_prior.map_or(0, |v| {
                    let static_vr = -(sinf(azimuth) * v[0] + cosf(azimuth) * v[1]);
                    // Where a static point does not fold, the measurement stands: a mover's
                    // alias cannot be known.
                    if fabsf(static_vr) <= 0.5 * span - FOLD_MARGIN_MPS {
                        0
                    } else {
                        libm::roundf((static_vr - folded) / span) as i32
                    }
                });
                (folded, wanted, own)
            };
            // By direction: its range where its own beam at Doppler bin `d` peaks over the
            // bins below and above (interpolated as the map's range is); `None` where a
            // neighbour is stronger, or its Doppler peak is another bin's (`own`): that
            // direction's point is formed there.
            let own_range = |steering: &BaseSteering, alias: i32, own: bool| -> Option<f32> {
                if !by_direction {
                    return Some(range);
                }
                if !own {
                    return None;
                }
                let turns = slot_phasors((nd, slots), (d, alias));
                let beam = |n: usize| {
                    let at = at_bin(n);
                    steering.power_db(|ch| rotate(spectra[at + ch * nd + d], turns[ch / rx]))
                };
                let centre = beam(b);
                let below = (b > 0).then(|| beam(b - 1));
                let above = (b + 1 < bins).then(|| beam(b + 1));
                if below.is_some_and(|p| p > centre) || above.is_some_and(|p| p > centre) {
                    return None;
                }
                let off = match (below, above) {
                    (Some(l), Some(r)) => quadratic_offset(l, centre, r),
                    _ => 0.0,
                };
                Some(config.bin_to_range(b as f32 + off, nr))
            };
            cell_at(d, 0, &mut values[..channels]);
            // An azimuth's point in this cell, in the cell compensated for `alias`: its range
            // and radial velocity (m, m/s), `Ok(None)` if it forms in another cell, or
            // `Err(wanted)` if the prior asks for another alias. Each azimuth is judged so
            // before its elevations are searched: only the azimuths whose point forms here are.
            let form = |azimuth: f32, alias: i32| {
                let steering = BaseSteering::new(geom, sinf(azimuth));
                let (folded, wanted, own) = measure(azimuth, &steering, alias);
                if wanted != alias {
                    return Err(wanted);
                }
                // (As measured, the velocity is `folded` itself, −0 kept.)
                let velocity = match alias {
                    0 => folded,
                    _ => folded + alias as f32 * span,
                };
                Ok(own_range(&steering, alias, own).map(|range| (range, velocity)))
            };
            let mut point = |(range, velocity): (f32, f32), dir: Direction| {
                emit(RadarPoint::new(range, velocity, dir));
                count += 1;
            };
            // First as measured; a direction whose prior asks for another alias is found again
            // in the cell compensated for it.
            let mut others: heapless::Vec<i32, MAX_DIRECTIONS> = heapless::Vec::new();
            let floor_db = options.direction_floor_db;
            cell_directions_where(
                &values[..channels],
                geom,
                floor_db,
                |azimuth| {
                    form(azimuth, 0).unwrap_or_else(|wanted| {
                        if !others.contains(&wanted) {
                            let _ = others.push(wanted);
                        }
                        None
                    })
                },
                &mut point,
            );
            for &alias in &others {
                cell_at(d, alias, &mut values[..channels]);
                let formed = |azimuth| form(azimuth, alias).ok().flatten();
                cell_directions_where(&values[..channels], geom, floor_db, formed, &mut point);
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

/// The phasor `exp(−jφ_s)` that removes the TDM-MIMO phase of the Doppler at bin `k` (wrapping)
/// of `nd`, unfolded by `alias` periods, from each of the `slots` slots: slot `s` transmits `s`
/// chirp periods into the loop, so a target at signed Doppler bin `b` (the measured bin plus
/// `alias` periods of `nd`) has advanced `φ_s = 2π·b·s / (nd·slots)` there. Channel `ch` of
/// `rx` receivers is in slot `ch / rx`. O(slots).
fn slot_phasors((nd, slots): (usize, usize), (k, alias): (usize, i32)) -> [Complex32; MAX_SLOTS] {
    let k = k % nd;
    let signed = if k >= nd / 2 {
        k as f32 - nd as f32
    } else {
        k as f32
    } + alias as f32 * nd as f32;
    let mut turns = [Complex32::new(1.0, 0.0); MAX_SLOTS];
    for (slot, t) in turns.iter_mut().enumerate().take(slots) {
        let phi = -core::f32::consts::TAU * signed * slot as f32 / (nd as f32 * slots as f32);
        *t = Complex32::new(cosf(phi), sinf(phi));
    }
    turns
}

/// `z` rotated by the unit phasor `w` (`z · w`, written out).
fn rotate(z: Complex32, w: Complex32) -> Complex32 {
    Complex32::new(z.re * w.re - z.im * w.im, z.re * w.im + z.im * w.re)
}

/// Climbs from Doppler bin `k` (offset by one period so `k − 1` does not wrap) to the
/// direction's own peak of `power` (at most two bins); the peak's bin and its parabolic
/// sub-bin offset. Each bin's power is evaluated once (3 to 5 evaluations).
fn doppler_peak(power: impl Fn(usize) -> f32, mut k: usize) -> (usize, f32) {
    let mut here = power(k);
    let (mut l, mut r) = (power(k - 1), power(k + 1));
    for _ in 0..2 {
        if l > here && l >= r {
            k -= 1;
            (r, here, l) = (here, l, power(k - 1));
        } else if r > here {
            k += 1;
            (l, here, r) = (here, r, power(k + 1));
        } else {
            break;
        }
    }
    (k, quadratic_offset(l, here, r))
}
