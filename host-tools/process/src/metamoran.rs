//! The Metamoran method on the host: per frame, the static sums and spectra (module code in
//! `dsp`); per object, its contour from the camera, clutter cancellation outside its span,
//! the depth search, and depth imaging (Sec. IV).

use super::ObjectEstimate;
use super::camera_points::CameraObject;
use crate::ProcessError;
use crate::lead::{HannLobe, Lead, leading_edge};
use crate::trust::{Candidate, Evidence};
use metamoran_bundle::geometry::{Point, azimuth, range_xz};
use metamoran_dsp::clutter::peaks::{MAX_PEAKS, Peak};
use metamoran_dsp::clutter::sic::{MAX_REFLECTORS, Reflector};
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::fft::C32;
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::pipeline::{Edge, FrameScene, ObjectHint, ObjectReport};
use metamoran_dsp::range::calibration::AppliedCalibration;
use metamoran_dsp::range::{Spectra, StaticSum};
use metamoran_dsp::search::Contour;
use metamoran_dsp::search::depth::{SearchResult, brute_force, coarse_to_fine, profile_words};
use metamoran_dsp::window::{WindowKind, coefficient_f64};
use metamoran_dsp::wire::{Hint, ObjectResult as WireResult};

/// Width of the azimuth bins that build the contour and reject edge outliers, rad.
const AZ_BIN: f64 = 0.25 * std::f64::consts::PI / 180.0;
/// Azimuth bins of the depth image with fewer points than this fraction of the fullest bin are
/// edge outliers (the paper's per-azimuth-bin point-count threshold).
const EDGE_FRACTION: f64 = 0.25;

/// A frame's static scene through the module's pipeline ([`metamoran_dsp::pipeline`]): the arena with the
/// frame's fixed-point spectra and peak list, plus the `f32` sums the reference search needs.
pub struct StaticScene {
    edge: Edge,
    arena: Vec<u32>,
    exponent: i32,
    peaks: heapless::Vec<Peak, MAX_PEAKS>,
    /// Windowed `f32` sums per element (`elements × N`), for the reference search only.
    samples: Vec<C32>,
    window: Vec<f32>,
}

impl StaticScene {
    /// Streams `frame` (`[chirp][rx][sample]`) through the module's frame stage.
    ///
    /// # Errors
    /// [`ProcessError`] if the frame does not match the configuration.
    pub fn new(config: &RadarConfig, frame: &[CQ15]) -> Result<Self, ProcessError> {
        Self::calibrated(config, frame, None)
    }

    /// [`Self::new`] of a frame as recorded, calibrated by `calibration` the way the module
    /// does it (block coefficients multiplied as chirps are summed), so that the in-process
    /// answer is the module's bit for bit; the reference sums take the per-sample calibration.
    ///
    /// # Errors
    /// [`ProcessError`] if the frame does not match the configuration or the calibration.
    pub fn calibrated(
        config: &RadarConfig,
        frame: &[CQ15],
        calibration: Option<&AppliedCalibration>,
    ) -> Result<Self, ProcessError> {
        let edge = Edge::new(config)?;
        let mut table = vec![0u32; edge.calibration_words()];
        let coefficients = calibration
            .map(|c| edge.calibrate(c, &mut table))
            .transpose()?;
        let mut calibrated_chirp = vec![CQ15::default(); config.adc_samples as usize];
        let (n, m, rx) = (
            config.adc_samples as usize,
            edge.fft_len(),
            config.rx_count(),
        );
        let elements = edge.array().elements();
        let mut arena = vec![0u32; edge.arena_words()];
        let mut samples = vec![C32::new(0.0, 0.0); elements * n];
        let mut sum = StaticSum::new(&mut samples, n)?;
        let (exponent, peaks) = {
            let mut frame_sum = match &coefficients {
                None => edge.start(&mut arena)?,
                Some(k) => edge.start_calibrated(&mut arena, k)?,
            };
            for (chirp, rows) in frame.chunks_exact(rx * n).enumerate() {
                for (r, s) in rows.chunks_exact(n).enumerate() {
                    let slot = chirp % config.slots();
                    let element = edge
                        .array()
                        .element_of(slot * rx + r)
                        .ok_or(ProcessError::Channel)?;
                    match (&coefficients, calibration) {
                        (Some(k), Some(c)) => {
                            edge.push_calibrated(&mut frame_sum, chirp, r, s, k)?;
                            let tx = config.tx_order.get(slot).copied().unwrap_or(u8::MAX);
                            c.apply(usize::from(tx), r, s, &mut calibrated_chirp)?;
                            sum.push(element, &calibrated_chirp)?;
                        }
                        _ => {
                            edge.push(&mut frame_sum, chirp, r, s)?;
                            sum.push(element, s)?;
                        }
                    }
                }
            }
            let mut row = vec![CQ15::default(); m];
            let mut az = vec![CQ15::default(); edge.azimuth_len()];
            let mut powers = vec![0u64; 3 * edge.azimuth_len()];
            let scene = edge.finish(frame_sum, &mut row, &mut az, &mut powers)?;
            (scene.spectra.exponent(), scene.peaks)
        };
        let window: Vec<f32> = (0..n)
            .map(|i| coefficient_f64(Edge::WINDOW, i, n) as f32)
            .collect();
        sum.finish(&window)?;
        Ok(Self {
            edge,
            arena,
            exponent,
            peaks,
            samples,
            window,
        })
    }

    /// SIC for `hint`, on the module's view of the frame.
    fn cancel(
        &mut self,
        hint: &ObjectHint,
    ) -> Result<heapless::Vec<Reflector, MAX_REFLECTORS>, ProcessError> {
        let view = resume(&self.edge, &mut self.arena, self.exponent, &self.peaks)?;
        Ok(self.edge.cancel(&view, hint))
    }

    /// The depth search for `hint` with `reflectors` cancelled, on the module's view of the frame.
    fn search(
        &mut self,
        hint: &ObjectHint,
        reflectors: &[Reflector],
    ) -> Result<ObjectReport, ProcessError> {
        self.search_scored(hint, reflectors).map(|(r, _)| r)
    }

    /// `Self::search`, also returning the coarse score `P(d)` per range bin (0 outside the
    /// searched bins).
    pub fn search_scored(
        &mut self,
        hint: &ObjectHint,
        reflectors: &[Reflector],
    ) -> Result<(ObjectReport, Vec<f32>), ProcessError> {
        let mut scores = vec![0.0f32; self.edge.fft_len()];
        let mut view = resume(&self.edge, &mut self.arena, self.exponent, &self.peaks)?;
        let report = self.edge.search(&mut view, hint, reflectors, &mut scores)?;
        Ok((report, scores))
    }

    /// The range–azimuth power map, dB (arbitrary reference), with `reflectors` subtracted:
    /// one row of range bins `0..bins` per entry of `sin_grid` (row-major). The beams are the
    /// module's (its fixed-point spectra, its SIC residual). O(grid · bins · E).
    ///
    /// # Errors
    /// [`ProcessError`] if the frame's spectra cannot be read back.
    pub fn range_azimuth_db(
        &mut self,
        reflectors: &[Reflector],
        sin_grid: &[f32],
        bins: usize,
    ) -> Result<Vec<f32>, ProcessError> {
        let view = resume(&self.edge, &mut self.arena, self.exponent, &self.peaks)?;
        let geo = self.edge.geometry();
        let mut row = vec![C32::new(0.0, 0.0); bins];
        let mut out = Vec::with_capacity(sin_grid.len() * bins);
        for &s in sin_grid {
            row.fill(C32::new(0.0, 0.0));
            metamoran_dsp::clutter::sic::Residual::new(&view.spectra, &geo, reflectors, s)
                .fill(0, &mut row);
            out.extend(row.iter().map(|b| 10.0 * (b.norm_sqr() + 1e-12).log10()));
        }
        Ok(out)
    }

    /// The pipeline.
    pub fn edge(&self) -> &Edge {
        &self.edge
    }
}

/// The module's view of a frame already finished in `arena` (see [`FrameScene::resume`]).
fn resume<'a>(
    edge: &Edge,
    arena: &'a mut [u32],
    exponent: i32,
    peaks: &heapless::Vec<Peak, MAX_PEAKS>,
) -> Result<FrameScene<'a>, ProcessError> {
    Ok(FrameScene::resume(edge, arena, exponent, peaks.clone())?)
}

/// A frame's moving scene: static clutter removed (mean over loops), then one range spectrum per
/// Doppler bin and channel; `None` for frames with fewer than [`MIN_DOPPLER_LOOPS`] loops.
pub struct MovingScene {
    /// `[doppler][channel][bin]`, Doppler in natural FFT order (bin 0 is empty after clutter removal).
    spectra: Vec<Vec<C32>>,
    edge: Edge,
    /// Position of each channel, half-wavelengths.
    positions: Vec<f32>,
    m: usize,
    rx: usize,
    slots: usize,
    /// Radial velocity of one Doppler bin, m/s (λ / (2 · loop period · Doppler length)).
    bin_mps: f64,
    /// The range window's main lobe in range bins (wider where the range FFT zero-pads).
    lobe: HannLobe,
}

/// Doppler bins searched per object: the strongest toward its span (another mover's energy can
/// outweigh it there).
pub const DOPPLER_BINS: usize = 3;

/// One Doppler bin focused for an object: the bin, the alias chosen and the channel spectra
/// compensated for it (`channels × m`).
struct Focus {
    q: usize,
    alias: i32,
    spectra: Vec<C32>,
}

impl MovingScene {
    /// Steering phasors of every channel toward `s`.
    fn steering(&self, s: f32) -> Vec<C32> {
        self.positions
            .iter()
            .map(|&p| {
                let a = -std::f32::consts::PI * p * s;
                C32::new(a.cos(), a.sin())
            })
            .collect()
    }

    /// The [`DOPPLER_BINS`] strongest local maxima of the Doppler energy toward `s_mid` over
    /// range bins `first..max_bin`, strongest first: energy beamformed within each slot's
    /// receivers and summed over slots (insensitive to the alias).
    /// O(Doppler · bins · channels).
    fn doppler_bins(&self, s_mid: f32, first: usize, max_bin: usize) -> Vec<usize> {
        let (m, rx) = (self.m, self.rx);
        let steer = self.steering(s_mid);
        let incoherent = |sp: &[C32]| -> f32 {
            (first..max_bin)
                .map(|k| {
                    (0..self.slots)
                        .map(|t| {
                            let z: C32 = (t * rx..(t + 1) * rx)
                                .map(|ch| sp[ch * m + k] * steer[ch])
                                .sum();
                            z.norm_sqr()
                        })
                        .sum::<f32>()
                })
                .sum()
        };
        let nd = self.spectra.len();
        let energy: Vec<f32> = (0..nd)
            .map(|q| {
                if q == 0 {
                    0.0
                } else {
                    incoherent(&self.spectra[q])
                }
            })
            .collect();
        // Local maxima over the (circular) Doppler axis: one per mover, not its main lobe's
        // neighbours.
        let mut peaks: Vec<usize> = (1..nd)
            .filter(|&q| {
                let (l, r) = (energy[(q + nd - 1) % nd], energy[(q + 1) % nd]);
                energy[q] >= l && energy[q] >= r
            })
            .collect();
        peaks.sort_by(|&a, &b| energy[b].total_cmp(&energy[a]).then(a.cmp(&b)));
        peaks.truncate(DOPPLER_BINS);
        peaks
    }

    /// Doppler bin `q` compensated for the TDM slot delays with the alias that makes the virtual
    /// array most coherent toward `s_mid` over range bins `first..max_bin` (12-TX TDM leaves
    /// ±1.4 m/s unambiguous, so fast movers alias).
    fn focus(&self, q: usize, s_mid: f32, first: usize, max_bin: usize) -> Focus {
        let (m, c) = (self.m, self.positions.len());
        let steer = self.steering(s_mid);
        let sp = &self.spectra[q];
        let coherent = |comp: &[C32]| -> f32 {
            (first..max_bin)
                .map(|k| {
                    let z: C32 = (0..c).map(|ch| sp[ch * m + k] * steer[ch] * comp[ch]).sum();
                    z.norm_sqr()
                })
                .sum()
        };
        let alias = self
            .aliases()
            .max_by(|&a, &b| {
                coherent(&self.compensation(q, a)).total_cmp(&coherent(&self.compensation(q, b)))
            })
            .unwrap_or(0);
        let comp = self.compensation(q, alias);
        Focus {
            q,
            alias,
            spectra: sp
                .iter()
                .enumerate()
                .map(|(i, &z)| z * comp[i / m])
                .collect(),
        }
    }

    /// The Doppler aliases TDM can tell apart: a slot's phase advances by a whole turn every
    /// `slots` aliases, so only `slots` consecutive ones differ (centred on 0).
    fn aliases(&self) -> std::ops::RangeInclusive<i32> {
        let half = (self.slots / 2) as i32;
        -half..=(self.slots as i32 - 1 - half)
    }

    /// Radial velocity of Doppler bin `q` taken `alias` unambiguous intervals further, m/s
    /// (positive away from the radar): unique within ± slots · Doppler length · bin / 2
    /// (±16 m/s for the cascade's 12 slots of 60 µs), folded into that interval beyond it.
    fn velocity_mps(&self, q: usize, alias: i32) -> f64 {
        let nd = self.spectra.len();
        let qs = metamoran_dsp::units::signed_bin(q, nd) as f64;
        (qs + f64::from(alias) * nd as f64) * self.bin_mps
    }

    /// The TDM slot phases of Doppler bin `q` taken `alias` unambiguous intervals further.
    fn compensation(&self, q: usize, alias: i32) -> Vec<C32> {
        let nd = self.spectra.len();
        let qs = metamoran_dsp::units::signed_bin(q, nd) as f32;
        let f = (qs + (alias * nd as i32) as f32) / (nd * self.slots) as f32;
        (0..self.positions.len())
            .map(|ch| {
                let a = -2.0 * std::f32::consts::PI * f * (ch / self.rx) as f32;
                C32::new(a.cos(), a.sin())
            })
            .collect()
    }
}

/// Fewest loops for the Doppler path.
pub const MIN_DOPPLER_LOOPS: u16 = 8;

impl MovingScene {
    /// Builds the Doppler spectra of the frame through the module's fixed-point cube.
    ///
    /// # Errors
    /// [`ProcessError`] if the frame does not match the configuration.
    pub fn new(config: &RadarConfig, frame: &[CQ15]) -> Result<Option<Self>, ProcessError> {
        if config.chirps_per_tx < MIN_DOPPLER_LOOPS {
            return Ok(None);
        }
        let options = crate::frame::FrameOptions {
            range_window: WindowKind::Hann,
            doppler_window: WindowKind::Rectangular,
            remove_static: true,
        };
        let mut proc = crate::frame::FrameProcessor::new(config, options)?;
        proc.process(frame)?;
        let (c, m, nd) = (
            config.channels(),
            config.range_fft_len(),
            config.doppler_fft_len(),
        );
        let mut spectra = vec![vec![C32::new(0.0, 0.0); c * m]; nd];
        for k in 0..m {
            for (ch, (exp, column)) in proc.doppler_spectra(k, true)?.into_iter().enumerate() {
                let scale = exp.scale_f32();
                for (s, z) in spectra.iter_mut().zip(&column) {
                    s[ch * m + k] = C32::new(z.re.to_f32() * scale, z.im.to_f32() * scale);
                }
            }
        }
        let edge = Edge::new(config)?;
        let positions = (0..c)
            .map(|ch| edge.array().position(ch).unwrap_or(0) as f32)
            .collect();
        Ok(Some(Self {
            spectra,
            edge,
            positions,
            m,
            rx: config.rx_count(),
            slots: config.slots(),
            bin_mps: config.wavelength_m() / (2.0 * config.loop_period_s() * nd as f64),
            lobe: HannLobe::new(usize::from(config.adc_samples), m),
        }))
    }

    /// The depth search on each of the [`DOPPLER_BINS`] Doppler bins holding most energy at the
    /// object's azimuth, as the module would report it, without the candidates that are another
    /// direction's reflection ([`Self::reflects_elsewhere`]); each with the radial velocity of
    /// its bin and alias, m/s, and, given the object's depth extent `lead_within_m`, the
    /// mover's leading edge within it in front of its strongest return ([`leading_edge`]).
    fn search(&self, hint: &ObjectHint, lead_within_m: Option<f64>) -> Vec<DopplerAnswer> {
        let bins = self.edge.bins(hint);
        let s_mid = (hint.span.0 + hint.span.1) / 2.0;
        let (first, last) = (bins.0 as usize, bins.1 as usize);
        self.doppler_bins(s_mid, first, last)
            .into_iter()
            .filter_map(|q| {
                let focus = self.focus(q, s_mid, first, last);
                let (result, lead) = self.search_focused(hint, bins, &focus, lead_within_m)?;
                Some(DopplerAnswer {
                    result,
                    velocity_mps: self.velocity_mps(focus.q, focus.alias),
                    lead,
                })
            })
            .collect()
    }

    /// The search on one focused Doppler bin, and the leading edge of its strongest candidate
    /// within `lead_within_m` (none without).
    fn search_focused(
        &self,
        hint: &ObjectHint,
        bins: (f32, f32),
        focus: &Focus,
        lead_within_m: Option<f64>,
    ) -> Option<(WireResult, Option<Lead>)> {
        let (words, exponent) = pack_elements(&self.edge, &focus.spectra, self.m);
        let spectra =
            Spectra::from_words(&words, self.edge.array().elements(), self.m, exponent).ok()?;
        let mut profiles = vec![0u32; profile_words(hint.contour.points().len(), self.m)];
        let mut scores = vec![0.0f32; self.m];
        let mut search = coarse_to_fine(
            &spectra,
            &self.edge.geometry(),
            &hint.contour,
            bins,
            &[],
            &mut profiles,
            &mut scores,
        )
        .ok()?;
        // A candidate whose energy is another direction's reflection is withdrawn (its peak
        // zeroed): the wire's ranking then puts the next one first and measures the others
        // from it, as for any candidate without a peak.
        let bin_m = self.edge.geometry().bin_m;
        let elsewhere = |depth_m: f32| {
            let bin = (depth_m / bin_m).round().max(0.0) as usize;
            self.reflects_elsewhere(focus.q, bin, hint.span)
        };
        // The mover's range profile over its span: the contour's directions without their
        // relative ranges (with them, the template moved forward by its own depth extent
        // lines its far points up with the closest return, a ghost in front).
        let lead = lead_within_m.and_then(|extent_m| {
            let flat = Contour::new(hint.contour.points().iter().map(|p| (p.sin_az, 0.0)));
            coarse_to_fine(
                &spectra,
                &self.edge.geometry(),
                &flat,
                bins,
                &[],
                &mut profiles,
                &mut scores,
            )
            .ok()?;
            leading_edge(&scores, &search, bin_m, self.lobe, extent_m)
                .filter(|l| !elsewhere(l.depth_m as f32))
        });
        if search.peak > 0.0 && elsewhere(search.depth_m) {
            search.peak = 0.0;
        }
        for o in &mut search.others {
            if o.peak > 0.0 && elsewhere(o.depth_m) {
                o.peak = 0.0;
            }
        }
        let found = search.peak > 0.0 || search.others.iter().any(|o| o.peak > 0.0);
        // Not measured here (every candidate survives): a mover's direction is checked by
        // `reflects_elsewhere` instead.
        let mut result = ObjectReport {
            id: hint.id,
            class: hint.class,
            search,
            cancelled: 0,
            survival: Default::default(),
        }
        .to_wire();
        if !found {
            result.depth_mm = 0;
        }
        Some((result, lead.filter(|_| search.peak > 0.0)))
    }

    /// Whether the energy of Doppler bin `q` at range bin `bin` comes from outside the
    /// sin-azimuth `span` widened by a beamwidth: focused with the Doppler alias that
    /// concentrates it best (with TDM a wrong alias steers and spreads a beam), its strongest
    /// direction lies outside and is [`ELSEWHERE_RATIO`] stronger than anything inside:
    /// another mover's side lobes, which no SIC removes on this path.
    /// O(aliases · 4·span · channels).
    fn reflects_elsewhere(&self, q: usize, bin: usize, span: (f32, f32)) -> bool {
        let Some(sp) = self.spectra.get(q).filter(|_| bin < self.m) else {
            return false;
        };
        let span_len = self.edge.array().span().max(1) as f32;
        let guard = 2.0 / span_len;
        let steps = (4.0 * span_len) as usize;
        let steer: Vec<Vec<C32>> = (0..=steps)
            .map(|i| self.steering(-1.0 + 2.0 * i as f32 / steps as f32))
            .collect();
        // Per alias: the strongest direction inside and outside; the alias that focuses the
        // energy best decides.
        let mut focus = (0.0f32, 0.0f32);
        for alias in self.aliases() {
            let column: Vec<C32> = self
                .compensation(q, alias)
                .iter()
                .enumerate()
                .map(|(ch, &c)| sp[ch * self.m + bin] * c)
                .collect();
            let (mut inside, mut outside) = (0.0f32, 0.0f32);
            for (i, st) in steer.iter().enumerate() {
                let s = -1.0 + 2.0 * i as f32 / steps as f32;
                let z: C32 = column.iter().zip(st).map(|(&x, &w)| x * w).sum();
                let power = z.norm_sqr();
                if s >= span.0 - guard && s <= span.1 + guard {
                    inside = inside.max(power);
                } else {
                    outside = outside.max(power);
                }
            }
            if inside.max(outside) > focus.0.max(focus.1) {
                focus = (inside, outside);
            }
        }
        let (inside, outside) = focus;
        outside > ELSEWHERE_RATIO * inside
    }

    /// sin(azimuth) of the strongest direction of the reflection at `depth_m` in the Doppler bin
    /// of `velocity_mps`, whatever its alias: the bin compensated for each alias TDM can tell
    /// apart and steered over a grid of 32 steps per beamwidth, on the range bin of the depth
    /// and its two neighbours; the strongest cell decides (a wrong alias spreads the beam and
    /// steers it, which would put a mover where it is not). `None` for a depth outside the
    /// frame. O(aliases · 3 · 32·span · channels).
    pub fn direction(&self, velocity_mps: f64, depth_m: f64) -> Option<f32> {
        let nd = self.spectra.len();
        let n = (velocity_mps / self.bin_mps).round();
        let bin = (depth_m / f64::from(self.edge.geometry().bin_m)).round();
        if !(n.is_finite() && (0.0..self.m as f64).contains(&bin)) {
            return None;
        }
        let q = (n.rem_euclid(nd as f64) as usize).min(nd - 1);
        let sp = &self.spectra[q];
        let centre = bin as usize;
        let bins = centre.saturating_sub(1)..=(centre + 1).min(self.m - 1);
        let steps = 32 * self.edge.array().span().max(1);
        let steering: Vec<(f32, Vec<C32>)> = (0..=steps)
            .map(|i| {
                let s = -1.0 + 2.0 * i as f32 / steps as f32;
                (s, self.steering(s))
            })
            .collect();
        let mut best = (f32::NEG_INFINITY, None);
        for alias in self.aliases() {
            let comp = self.compensation(q, alias);
            for k in bins.clone() {
                let column: Vec<C32> = comp
                    .iter()
                    .enumerate()
                    .map(|(ch, &c)| sp[ch * self.m + k] * c)
                    .collect();
                for (s, steer) in &steering {
                    let z: C32 = column.iter().zip(steer).map(|(&x, &w)| x * w).sum();
                    if z.norm_sqr() > best.0 {
                        best = (z.norm_sqr(), Some(*s));
                    }
                }
            }
        }
        best.1
    }

    /// The span of radial velocities one Doppler bin's aliases repeat over, m/s (Doppler length
    /// · bin): two velocities this far apart are one bin's, told apart only by TDM's phases.
    pub fn fold_mps(&self) -> f64 {
        self.spectra.len() as f64 * self.bin_mps
    }
}

/// How much stronger than inside an object's span the Doppler energy at a candidate's range must
/// be elsewhere for the candidate to count as another direction's reflection (6 dB).
pub const ELSEWHERE_RATIO: f32 = 4.0;

/// Channel spectra (`channels × m`, `f32`) summed into the array's elements and quantized to
/// packed Q15 words with one block exponent.
fn pack_elements(edge: &Edge, channels: &[C32], m: usize) -> (Vec<u32>, i32) {
    let array = edge.array();
    let mut sums = vec![C32::new(0.0, 0.0); array.elements() * m];
    for (ch, row) in channels.chunks_exact(m).enumerate() {
        if let Some(e) = array.element_of(ch) {
            for (o, &z) in sums[e * m..(e + 1) * m].iter_mut().zip(row) {
                *o += z;
            }
        }
    }
    let peak = sums
        .iter()
        .map(|z| z.re.abs().max(z.im.abs()))
        .fold(0.0f32, f32::max);
    let exponent = if peak > 0.0 {
        (peak / 16383.0).log2().ceil() as i32
    } else {
        0
    };
    let scale = 2f32.powi(-exponent);
    let mut words = vec![0u32; sums.len()];
    for (i, z) in sums.iter().enumerate() {
        let at = Spectra::word_index(i / m, i % m, array.elements());
        words[at] = metamoran_dsp::range::frame_sum::pack(CQ15::from_raw(
            (z.re * scale).round() as i16,
            (z.im * scale).round() as i16,
        ));
    }
    (words, exponent)
}

/// The contour of an object: per azimuth bin, the median monocular range of its points;
/// bins far from the object's near surface (bleed into the background) are dropped. Empty for
/// an object whose points do not describe its shape ([`CameraObject::has_shape`]).
pub fn contour(obj: &CameraObject) -> Contour {
    if !obj.has_shape() {
        return Contour::default();
    }
    let mut bins: std::collections::BTreeMap<i64, Vec<f64>> = std::collections::BTreeMap::new();
    for p in &obj.points {
        bins.entry((azimuth(p) / AZ_BIN).floor() as i64)
            .or_default()
            .push(range_xz(p));
    }
    let med = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let mut cols: Vec<(f64, f64)> = bins
        .into_iter()
        .map(|(b, mut v)| ((b as f64 + 0.5) * AZ_BIN, med(&mut v)))
        .collect();
    if cols.is_empty() {
        return Contour::default();
    }
    let mut ranges: Vec<f64> = cols.iter().map(|c| c.1).collect();
    ranges.sort_by(f64::total_cmp);
    let near = ranges[ranges.len() / 5];
    cols.retain(|&(_, r)| r >= near - 1.0 && r <= near + 6.0);
    Contour::new(cols.into_iter().map(|(a, r)| (a.sin() as f32, r as f32)))
}

/// Keeps depth-image points of azimuth bins holding at least [`EDGE_FRACTION`] of the fullest
/// bin's count.
fn reject_edges(points: Vec<Point>) -> Vec<Point> {
    let mut counts = std::collections::HashMap::new();
    let bin = |p: &Point| (azimuth(p) / AZ_BIN).floor() as i64;
    for p in &points {
        *counts.entry(bin(p)).or_insert(0usize) += 1;
    }
    let max = counts.values().copied().max().unwrap_or(0);
    points
        .into_iter()
        .filter(|p| counts[&bin(p)] as f64 >= EDGE_FRACTION * max as f64)
        .collect()
}

/// Class code of the telemetry protocol: 1 + the index in the objects of interest, then 64 +
/// the index in the clutter classes; 0 for anything else.
pub fn class_code(class: &str) -> u8 {
    use metamoran_bundle::{CLUTTER_CLASSES, OBJECTS_OF_INTEREST};
    if let Some(i) = OBJECTS_OF_INTEREST.iter().position(|c| *c == class) {
        1 + i as u8
    } else if let Some(i) = CLUTTER_CLASSES.iter().position(|c| *c == class) {
        64 + i as u8
    } else {
        0
    }
}

/// The module's hint for `obj` as it arrives over the link ([`ObjectHint::from_wire`] of its wire
/// form): id, class, sin-azimuth span, monocular prior and contour (a flat one across the span
/// where the mask has no usable shape, e.g. beyond the 256 m a depth PNG holds).
pub fn hint(obj: &CameraObject) -> Option<ObjectHint> {
    wire_hint(0, obj).map(|h| ObjectHint::from_wire(&h))
}

/// The wire form of `obj`'s hint for frame `frame`.
pub fn wire_hint(frame: u32, obj: &CameraObject) -> Option<Hint> {
    let (lo, hi) = obj.span?;
    let mut c = contour(obj);
    if c.is_empty() {
        c = Contour::new((0..9).map(|i| ((lo + (hi - lo) * i as f64 / 8.0).sin() as f32, 0.0f32)));
    }
    let exact = ObjectHint {
        id: obj.instance,
        class: class_code(&obj.class),
        span: (lo.sin() as f32, hi.sin() as f32),
        prior_m: obj.closest_range().unwrap_or(0.0) as f32,
        window_m: crate::trust::search_window_m(obj),
        contour: c,
    };
    Some(exact.to_wire(frame))
}

/// An object's search problem after clutter cancellation: what both searches run on.
pub struct Prepared {
    /// The module's hint.
    pub hint: ObjectHint,
    /// What SIC cancelled.
    pub reflectors: heapless::Vec<Reflector, MAX_REFLECTORS>,
    /// First and last range bin searched.
    pub bins: (f32, f32),
}

/// Builds the hint and cancels clutter outside the object's span.
pub fn prepare(scene: &mut StaticScene, obj: &CameraObject) -> Option<Prepared> {
    let hint = hint(obj)?;
    let reflectors = scene.cancel(&hint).ok()?;
    Some(Prepared {
        bins: scene.edge.bins(&hint),
        hint,
        reflectors,
    })
}

/// The production search on a prepared object (the module's code).
///
/// # Errors
/// [`ProcessError`] if the search cannot run.
pub fn fast_search(scene: &mut StaticScene, p: &Prepared) -> Result<ObjectReport, ProcessError> {
    scene.search(&p.hint, &p.reflectors)
}

/// Both searches on a prepared object: (production coarse-to-fine, brute-force reference on the
/// `f32` sums with the same reflectors subtracted in the time domain).
///
/// # Errors
/// [`ProcessError`] if a search cannot run.
pub fn both_searches(
    scene: &mut StaticScene,
    p: &Prepared,
) -> Result<(SearchResult, SearchResult), ProcessError> {
    let fast = fast_search(scene, p)?.search;
    let geo = scene.edge.geometry();
    let mut samples = scene.samples.clone();
    for r in &p.reflectors {
        r.subtract_from(&mut samples, &geo, &scene.window, scene.exponent);
    }
    let contour = scene.edge.contour(&p.hint);
    let reference = brute_force(&samples, &geo, &contour, p.bins)?;
    Ok((fast, reference))
}

/// The Metamoran estimate for one object of a frame: the module's static search after
/// clutter cancellation, in process (see [`merge`]).
pub fn estimate(
    scene: &mut StaticScene,
    moving: Option<&MovingScene>,
    obj: &CameraObject,
) -> ObjectEstimate {
    let Some(p) = prepare(scene, obj) else {
        return ObjectEstimate::missed(obj);
    };
    let on_module = fast_search(scene, &p).ok().map(|r| r.to_wire());
    merge(
        obj,
        &p.hint,
        on_module,
        moving,
        beamwidth_deg(scene.edge.array()),
    )
}

/// Combines the module's answer for `obj` (in process or from the edge; `hint` as the module
/// received it) with the host's search on the Doppler bin holding most of the energy at the
/// object's azimuth, where the frame has Doppler: every candidate depth of both goes to the
/// trust test ([`crate::trust`]), which weighs them against the camera's cues (the same bits
/// from either edge).
pub fn merge(
    obj: &CameraObject,
    hint: &ObjectHint,
    on_module: Option<WireResult>,
    moving: Option<&MovingScene>,
    beamwidth_deg: f64,
) -> ObjectEstimate {
    let lead_within_m =
        crate::lead::moves(&obj.class).then(|| crate::camera_points::depth_extent(&obj.class));
    let found = moving.map_or_else(Vec::new, |mv| mv.search(hint, lead_within_m));
    conclude(
        obj,
        evidence(obj, on_module.as_ref(), &found, beamwidth_deg),
    )
}

/// The estimate the trust test's verdict on `evidence` gives `obj`: its depth image when the
/// depth is trusted, "not detected" otherwise; the confidence and the evidence kept for `eval`.
pub fn conclude(obj: &CameraObject, evidence: Evidence) -> ObjectEstimate {
    let verdict = evidence.judge();
    let mut estimate = match verdict {
        Some(v) if v.detected() => {
            let points = reject_edges(obj.anchored(v.depth_m));
            ObjectEstimate {
                confidence_db: Some(v.features.over_floor_db),
                radial_velocity_mps: v.velocity_mps.map(|x| (x * 100.0).round() / 100.0),
                ..ObjectEstimate::found(obj, v.depth_m, obj.median_azimuth(), points)
            }
        }
        _ => ObjectEstimate::missed(obj),
    };
    estimate.confidence = verdict.map(|v| (v.confidence * 1000.0).round() / 1000.0);
    estimate.evidence = Some(Box::new((evidence, verdict)));
    estimate
}

/// What the trust test weighs for `obj`: the candidates of the module's answer and of the
/// Doppler path's answers (each with its velocity, m/s, and its leading edge), and the camera's
/// three cues.
pub fn evidence(
    obj: &CameraObject,
    on_module: Option<&WireResult>,
    doppler: &[DopplerAnswer],
    beamwidth_deg: f64,
) -> Evidence {
    Evidence {
        candidates: on_module
            .into_iter()
            .flat_map(|r| candidates(r, None))
            .chain(doppler.iter().flat_map(DopplerAnswer::candidates))
            .collect(),
        monocular_m: obj.closest_range(),
        height: obj
            .extent
            .and_then(|e| crate::trust::HeightCue::of(&obj.class, &e)),
        ground: obj.contact,
        beamwidth_deg,
        extent_m: crate::camera_points::depth_extent(&obj.class),
    }
}

/// The Doppler path's answer on one focused Doppler bin.
pub struct DopplerAnswer {
    /// The search's result, in the module's form.
    pub result: WireResult,
    /// Radial velocity of the bin (with its alias), m/s.
    pub velocity_mps: f64,
    /// The mover's leading edge in front of the strongest candidate, if its profile shows one.
    pub lead: Option<Lead>,
}

impl DopplerAnswer {
    /// The trust test's candidates: the result's depth and alternatives, then the leading
    /// edge, each at the bin's velocity.
    fn candidates(&self) -> impl Iterator<Item = Candidate> + '_ {
        let v = self.velocity_mps;
        candidates(&self.result, Some(v)).chain(self.lead.map(|l| Candidate {
            depth_m: l.depth_m,
            over_floor_db: l.over_floor_db,
            survives: true,
            velocity_mps: Some(v),
        }))
    }
}

/// The array's azimuth beamwidth at boresight, degrees (2 / aperture in sin θ).
pub fn beamwidth_deg(array: &metamoran_dsp::array::VirtualArray) -> f64 {
    (2.0 / array.span().max(1) as f64).asin().to_degrees()
}

/// The candidate depths of one answer (of the Doppler path at `velocity_mps` m/s if given): its
/// depth, then its alternatives.
fn candidates(r: &WireResult, velocity_mps: Option<f64>) -> impl Iterator<Item = Candidate> + '_ {
    let best = (r.depth_mm > 0).then_some((r.depth_m(), r.score));
    best.into_iter()
        .chain(r.alternatives())
        .map(move |(depth_m, score)| Candidate {
            depth_m,
            over_floor_db: score.over_floor_db(),
            survives: score.survives(),
            velocity_mps,
        })
}
