//! The Metamoran method on the host: per frame, the static sums and spectra (module code in
//! `dsp`); per object, its contour from the camera, clutter cancellation outside its span,
//! the depth search, and depth imaging (Sec. IV).

use super::ObjectResult;
use super::camera_points::{CameraObject, shift_to_depth};
use crate::geometry::{Point, azimuth, range_xz};
use dsp::clutter::sic::{self, SicScratch};
use dsp::config::RadarConfig;
use dsp::fft::C32;
use dsp::range::StaticSum;
use dsp::search::Contour;
use dsp::search::depth::{Geometry, SearchResult, brute_force, coarse_to_fine};
use dsp::window::{WindowKind, coefficient_f64};

/// Width of the azimuth bins that build the contour and reject edge outliers, rad.
const AZ_BIN: f64 = 0.25 * std::f64::consts::PI / 180.0;
/// SIC goes on while a reflector outside the span has more than this fraction of the power of
/// the strongest cell inside it.
const SIC_STOP_RATIO: f32 = 0.05;
/// The search starts at this fraction of the monocular depth: monocular depth is metres off, but
/// not by a factor of 2.5 (the paper's Table I: 19 m median error at 40–60 m).
const PRIOR_FRACTION: f64 = 0.4;
/// `P(d*)` must also exceed the best score elsewhere (beyond the contour's depth extent) by this
/// factor: two comparable explanations of the data mean the answer is a guess.
pub const UNIQUENESS_RATIO: f32 = 1.3;
/// `P(d*)` must exceed the median of `P` by this factor to be trusted.
pub const DETECTION_RATIO: f32 = 6.0;
/// Azimuth bins of the depth image with fewer points than this fraction of the fullest bin are
/// edge outliers (the paper's per-azimuth-bin point-count threshold).
const EDGE_FRACTION: f64 = 0.25;

/// A frame's static scene, ready for the per-object search.
pub struct StaticScene {
    positions: Vec<f32>,
    window: Vec<f32>,
    samples: Vec<C32>,
    spectra: Vec<C32>,
    n: usize,
    m: usize,
    bin_m: f32,
    span: usize,
}

impl StaticScene {
    /// Sums `frame` (`[chirp][rx][sample]`) over loops per channel, Hann-windows and transforms it.
    ///
    /// # Errors
    /// A message if the frame does not match the configuration.
    pub fn new(config: &RadarConfig, frame: &[dsp::fixed::CQ15]) -> Result<Self, String> {
        let (n, m, rx, slots) = (
            config.adc_samples as usize,
            config.range_fft_len(),
            config.rx_count(),
            config.slots(),
        );
        let channels = config.channels();
        let mut samples = vec![C32::new(0.0, 0.0); channels * n];
        let mut sum = StaticSum::new(&mut samples, n).map_err(|e| e.to_string())?;
        for (chirp, rows) in frame.chunks_exact(rx * n).enumerate() {
            for (r, s) in rows.chunks_exact(n).enumerate() {
                sum.push((chirp % slots) * rx + r, s)
                    .map_err(|e| e.to_string())?;
            }
        }
        let window: Vec<f32> = (0..n)
            .map(|i| coefficient_f64(WindowKind::Hann, i, n) as f32)
            .collect();
        let mut spectra = vec![C32::new(0.0, 0.0); channels * m];
        sum.finish(&window, &mut spectra)
            .map_err(|e| e.to_string())?;
        let positions: Vec<f32> = (0..channels)
            .map(|ch| config.channel_position(ch).unwrap_or(0) as f32)
            .collect();
        let span = (positions.iter().copied().fold(f32::MIN, f32::max)
            - positions.iter().copied().fold(f32::MAX, f32::min)) as usize
            + 1;
        Ok(Self {
            positions,
            window,
            samples,
            spectra,
            n,
            m,
            bin_m: config.range_bin_size(m).0,
            span,
        })
    }

    fn geometry(&self) -> Geometry<'_> {
        Geometry {
            positions: &self.positions,
            samples: self.n,
            fft_len: self.m,
            bin_m: self.bin_m,
        }
    }
}

/// A frame's moving scene: static clutter removed (mean over loops), then one range spectrum per
/// Doppler bin and channel; `None` for frames with fewer than [`MIN_DOPPLER_LOOPS`] loops.
pub struct MovingScene {
    /// `[doppler][channel][bin]`, Doppler in natural FFT order (bin 0 is empty after clutter removal).
    spectra: Vec<Vec<C32>>,
    scene: StaticScene,
    rx: usize,
    slots: usize,
}

/// Most Doppler aliases tried each way (±`MAX_ALIAS` unambiguous intervals).
const MAX_ALIAS: i32 = 25;

impl MovingScene {
    /// The Doppler spectra of the bin holding most energy toward `s_mid` from range bin `first`
    /// on, compensated for the TDM slot delays with the Doppler alias that makes the virtual
    /// array most coherent (12-TX TDM leaves ±1.4 m/s unambiguous, so fast movers alias).
    fn focused(&self, s_mid: f32, first: usize, max_bin: usize) -> Vec<C32> {
        let (m, nd, rx) = (self.scene.m, self.spectra.len(), self.rx);
        let c = self.scene.positions.len();
        let steer: Vec<C32> = self
            .scene
            .positions
            .iter()
            .map(|&p| {
                let a = -std::f32::consts::PI * p * s_mid;
                C32::new(a.cos(), a.sin())
            })
            .collect();
        // Doppler bin: energy beamformed within each slot's receivers, summed over slots
        // (insensitive to the alias).
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
        let q = (1..nd)
            .max_by(|&a, &b| incoherent(&self.spectra[a]).total_cmp(&incoherent(&self.spectra[b])))
            .unwrap_or(0);
        let sp = &self.spectra[q];
        let qs = dsp::units::signed_bin(q, nd) as f32;
        let compensation = |alias: i32| -> Vec<C32> {
            let f = (qs + (alias * nd as i32) as f32) / (nd * self.slots) as f32;
            (0..c)
                .map(|ch| {
                    let a = -2.0 * std::f32::consts::PI * f * (ch / rx) as f32;
                    C32::new(a.cos(), a.sin())
                })
                .collect()
        };
        let coherent = |comp: &[C32]| -> f32 {
            (first..max_bin)
                .map(|k| {
                    let z: C32 = (0..c).map(|ch| sp[ch * m + k] * steer[ch] * comp[ch]).sum();
                    z.norm_sqr()
                })
                .sum()
        };
        let alias = (-MAX_ALIAS..=MAX_ALIAS)
            .max_by(|&a, &b| coherent(&compensation(a)).total_cmp(&coherent(&compensation(b))))
            .unwrap_or(0);
        let comp = compensation(alias);
        sp.iter()
            .enumerate()
            .map(|(i, &z)| z * comp[i / m])
            .collect()
    }
}

/// Fewest loops for the Doppler path.
pub const MIN_DOPPLER_LOOPS: u16 = 8;

impl MovingScene {
    /// Builds the Doppler spectra of the frame through the module's fixed-point cube.
    ///
    /// # Errors
    /// A message if the frame does not match the configuration.
    pub fn new(
        config: &RadarConfig,
        frame: &[dsp::fixed::CQ15],
        scene: &StaticScene,
    ) -> Result<Option<Self>, String> {
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
        let (c, m, nd) = (config.channels(), scene.m, config.doppler_fft_len());
        let mut spectra = vec![vec![C32::new(0.0, 0.0); c * m]; nd];
        for k in 0..m {
            for (ch, (exp, column)) in proc.doppler_spectra(k, true)?.into_iter().enumerate() {
                let scale = exp.scale_f32();
                for (s, z) in spectra.iter_mut().zip(&column) {
                    s[ch * m + k] = C32::new(z.re.to_f32() * scale, z.im.to_f32() * scale);
                }
            }
        }
        Ok(Some(Self {
            spectra,
            scene: scene.clone_geometry(),
            rx: config.rx_count(),
            slots: config.slots(),
        }))
    }
}

impl StaticScene {
    fn clone_geometry(&self) -> Self {
        Self {
            positions: self.positions.clone(),
            window: self.window.clone(),
            samples: Vec::new(),
            spectra: Vec::new(),
            n: self.n,
            m: self.m,
            bin_m: self.bin_m,
            span: self.span,
        }
    }
}

/// The contour of an object: per azimuth bin, the median monocular range of its points;
/// bins far from the object's near surface (bleed into the background) are dropped.
pub fn contour(obj: &CameraObject) -> Contour {
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

/// The best depth of `contour` in `spectra` from range bin `first` on: (depth m, peak/floor).
fn search(
    scene: &StaticScene,
    spectra: &[C32],
    contour: &Contour,
    first: f32,
    max_bin: usize,
) -> Option<(f64, f32, f32)> {
    let found = run_search(scene, spectra, contour, (first, max_bin as f32)).ok()?;
    Some((
        found.depth_m as f64,
        found.peak / found.floor.max(f32::MIN_POSITIVE),
        found.peak / found.runner_up.max(f32::MIN_POSITIVE),
    ))
}

/// `coarse_to_fine` with its scratch buffers.
fn run_search(
    scene: &StaticScene,
    spectra: &[C32],
    contour: &Contour,
    bins: (f32, f32),
) -> Result<SearchResult, String> {
    let mut profiles = vec![C32::new(0.0, 0.0); contour.points().len() * scene.m];
    let mut scores = vec![0.0; scene.m];
    coarse_to_fine(
        spectra,
        &scene.geometry(),
        contour,
        bins,
        &mut profiles,
        &mut scores,
    )
    .map_err(|e| e.to_string())
}

/// An object's search problem after clutter cancellation: what both searches run on.
pub struct Prepared {
    /// The contour.
    pub contour: Contour,
    /// Windowed static samples with the cancelled reflectors removed (`channels × N`).
    pub samples: Vec<C32>,
    /// Their spectra (`channels × M`).
    pub spectra: Vec<C32>,
    /// First and last range bin searched.
    pub bins: (f32, f32),
}

/// Builds the contour, cancels clutter outside the object's span, and sets the search range.
pub fn prepare(scene: &StaticScene, obj: &CameraObject) -> Option<Prepared> {
    let (lo, hi) = obj.span?;
    let mut c = contour(obj);
    if c.is_empty() {
        // No monocular depth (e.g. beyond the 256 m a depth PNG holds): a flat contour across
        // the mask's azimuth span.
        c = Contour::new((0..9).map(|i| ((lo + (hi - lo) * i as f64 / 8.0).sin() as f32, 0.0f32)));
    }
    let geo = scene.geometry();
    let (mut samples, mut spectra) = (scene.samples.clone(), scene.spectra.clone());
    // Keep the object's span plus a main lobe (first null of the array at sin = 2/span).
    let guard = 2.0 / scene.span as f32;
    let keep = [((lo.sin() as f32) - guard, (hi.sin() as f32) + guard)];
    let max_bin = (0.92 * scene.m as f32) as usize;
    let mut elements =
        vec![C32::new(0.0, 0.0); dsp::fft::padded_len(4 * scene.span).unwrap_or(dsp::fft::MAX_LEN)];
    let mut tone = vec![C32::new(0.0, 0.0); scene.m];
    sic::cancel(
        &mut spectra,
        &mut samples,
        &geo,
        &scene.window,
        &keep,
        max_bin,
        SIC_STOP_RATIO,
        SicScratch {
            elements: &mut elements,
            tone: &mut tone,
        },
    );
    let first = obj
        .closest_range()
        .map_or(1.0, |r| (PRIOR_FRACTION * r) as f32 / scene.bin_m)
        .clamp(1.0, max_bin as f32 - 2.0);
    Some(Prepared {
        contour: c,
        samples,
        spectra,
        bins: (first, max_bin as f32),
    })
}

/// The production search on a prepared object.
///
/// # Errors
/// A message if the search cannot run.
pub fn fast_search(scene: &StaticScene, p: &Prepared) -> Result<SearchResult, String> {
    run_search(scene, &p.spectra, &p.contour, p.bins)
}

/// Both searches on a prepared object: (production coarse-to-fine, brute-force reference).
///
/// # Errors
/// A message if a search cannot run.
pub fn both_searches(
    scene: &StaticScene,
    p: &Prepared,
) -> Result<(SearchResult, SearchResult), String> {
    let fast = fast_search(scene, p)?;
    let reference = brute_force(&p.samples, &scene.geometry(), &p.contour, p.bins)
        .map_err(|e| e.to_string())?;
    Ok((fast, reference))
}

/// The Metamoran estimate for one object of a frame: the static search after clutter
/// cancellation and, where the frame has Doppler, the search on the Doppler bin holding most of
/// the energy at the object's azimuth; the more confident of the two wins.
pub fn estimate(
    scene: &StaticScene,
    moving: Option<&MovingScene>,
    obj: &CameraObject,
) -> ObjectResult {
    let Some((lo, hi)) = obj.span else {
        return ObjectResult::missed(obj);
    };
    let Some(p) = prepare(scene, obj) else {
        return ObjectResult::missed(obj);
    };
    let (c, first_bin, max_bin) = (&p.contour, p.bins.0, p.bins.1 as usize);
    let mut best = search(scene, &p.spectra, c, first_bin, max_bin);
    if let Some(mv) = moving {
        let focused = mv.focused(((lo + hi) / 2.0).sin() as f32, first_bin as usize, max_bin);
        if let Some(found) = search(&mv.scene, &focused, c, first_bin, max_bin) {
            if best.is_none_or(|b| found.1 > b.1) {
                best = Some(found);
            }
        }
    }
    match best {
        Some((depth, ratio, unique)) if ratio >= DETECTION_RATIO && unique >= UNIQUENESS_RATIO => {
            let points = reject_edges(shift_to_depth(&obj.points, depth));
            ObjectResult::found(obj, depth, obj.median_azimuth(), points)
        }
        _ => ObjectResult::missed(obj),
    }
}
