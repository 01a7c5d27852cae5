//! The module's per-frame job, end to end: chirps stream into per-element sums, the sums become
//! Q15 range spectra in place, one range–azimuth pass lists the strong reflectors, and each
//! object the camera reported gets SIC and the depth search. The firmware runs exactly this; the
//! host's in-process pipeline calls the same functions, so both produce the same bits.
//!
//! ```text
//! chirps ─▶ FrameSum ─▶ Spectra ─▶ peaks::scan ─┬▶ sic::cancel ─▶ coarse_to_fine ─▶ ObjectReport
//!                                               └▶ (next object)
//! ```
//!
//! Memory is the caller's: one arena of [`Edge::arena_words`] words (sums, then spectra and
//! the search's beams) and small scratch buffers sized by [`Edge`].

use crate::array::{ArrayError, VirtualArray};
use crate::clutter::peaks::{self, MAX_PEAKS, Peak, ScanError};
use crate::clutter::sic::{self, MAX_REFLECTORS, Reflector};
use crate::config::RadarConfig;
use crate::fixed::{CQ15, Q15};
use crate::range::calibration::{self as cal, AppliedCalibration, CalibrationError};
use crate::range::{FrameSum, RangeError, Spectra};
use crate::response::Geometry;
use crate::search::Contour;
use crate::search::depth::{self, CANDIDATES, Candidate, SearchError, SearchResult};
use crate::search::survival::{self, Survival};
use crate::window::{self, WindowKind};
use crate::wire::message::{WirePoint, m_to_mm, q15_to_sin, sin_to_q15};
use crate::wire::{ALTERNATIVES, Alternative, Hint, ObjectResult, Score};
use core::fmt;
use heapless::Vec;

/// SIC goes on while a reflector outside the span has more than this fraction of the power of
/// the strongest peak inside it.
pub const SIC_STOP_RATIO: f32 = 0.05;
/// The search starts at this fraction of the monocular depth: monocular depth is metres off, but
/// not by a factor of 2.5 (the paper's Table I: 19 m median error at 40–60 m).
pub const PRIOR_FRACTION: f32 = 0.4;
/// `P(d*)` must exceed the median of `P` by this factor to be trusted.
pub const DETECTION_RATIO: f32 = 6.0;
/// `P(d*)` must also exceed the best score elsewhere (beyond the contour's depth extent) by this
/// factor: two comparable explanations of the data mean the answer is a guess.
pub const UNIQUENESS_RATIO: f32 = 1.3;
/// Fewest range bins a camera window may leave to search; narrower windows are ignored.
pub const MIN_WINDOW_BINS: f32 = 8.0;
/// The search and SIC stay below this fraction of the unambiguous range (the IF filter's
/// roll-off makes the last bins unreliable).
pub const MAX_RANGE_FRACTION: f32 = 0.92;

/// What the camera tells the module about one object.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectHint {
    /// Instance id.
    pub id: u16,
    /// Class code (see the telemetry protocol).
    pub class: u8,
    /// sin(azimuth) of the mask's left and right edges.
    pub span: (f32, f32),
    /// Monocular range of the object's closest point, m (0 when unknown).
    pub prior_m: f32,
    /// Near and far bound on that range from the camera's other cues (the mask's apparent
    /// size), m; 0 where unknown. The search stays inside them.
    pub window_m: (f32, f32),
    /// The contour.
    pub contour: Contour,
}

/// The module's answer for one object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectReport {
    /// Instance id.
    pub id: u16,
    /// Class code.
    pub class: u8,
    /// The search's result.
    pub search: SearchResult,
    /// Reflectors SIC cancelled.
    pub cancelled: u8,
    /// The survival of each refined candidate: the best, then `search.others` (a candidate that
    /// was not measured, or not found, has the default: it survives, nothing lost).
    pub survival: [Survival; CANDIDATES],
}

impl ObjectHint {
    /// The wire form of this hint for `frame`, quantized as the link carries it. O(contour).
    pub fn to_wire(&self, frame: u32) -> Hint {
        Hint {
            frame,
            instance: self.id,
            class: self.class,
            span: (sin_to_q15(self.span.0), sin_to_q15(self.span.1)),
            prior_mm: m_to_mm(self.prior_m),
            window_mm: (m_to_mm(self.window_m.0), m_to_mm(self.window_m.1)),
            contour: self
                .contour
                .points()
                .iter()
                .map(|p| WirePoint {
                    sin_az: sin_to_q15(p.sin_az),
                    rel_mm: m_to_mm(p.rel_range_m).min(u16::MAX as u32) as u16,
                })
                .collect(),
        }
    }

    /// The hint a wire [`Hint`] carries. O(contour).
    pub fn from_wire(hint: &Hint) -> Self {
        Self {
            id: hint.instance,
            class: hint.class,
            span: (q15_to_sin(hint.span.0), q15_to_sin(hint.span.1)),
            prior_m: hint.prior_mm as f32 / 1000.0,
            window_m: (
                hint.window_mm.0 as f32 / 1000.0,
                hint.window_mm.1 as f32 / 1000.0,
            ),
            contour: Contour::new(
                hint.contour
                    .iter()
                    .map(|p| (q15_to_sin(p.sin_az), p.rel_mm as f32 / 1000.0)),
            ),
        }
    }
}

impl ObjectReport {
    /// The search's refined candidates with their survival, survivors first (see
    /// [`crate::search::survival`]), each group strongest first; candidates the search did not
    /// find come last. O(1).
    pub fn ranked(&self) -> [(Candidate, Survival); CANDIDATES] {
        let s = &self.search;
        let first = Candidate {
            depth_bins: s.depth_bins,
            depth_m: s.depth_m,
            peak: s.peak,
        };
        let mut all = [(first, self.survival[0]); CANDIDATES];
        for (slot, (&c, &v)) in all
            .iter_mut()
            .skip(1)
            .zip(s.others.iter().zip(self.survival.iter().skip(1)))
        {
            *slot = (c, v);
        }
        // 0: a survivor, 1: a candidate that does not survive, 2: none. Stable insertion sort
        // of three (no panic path).
        let rank = |(c, v): &(Candidate, Survival)| match (c.peak > 0.0, v.survives()) {
            (true, true) => 0,
            (true, false) => 1,
            (false, _) => 2,
        };
        for i in 1..CANDIDATES {
            for j in (1..=i).rev() {
                if rank(&all[j]) < rank(&all[j - 1]) {
                    all.swap(j - 1, j);
                }
            }
        }
        all
    }

    /// The wire form of this report: the best of [`Self::ranked`]'s candidates as the depth in
    /// millimetres, the others as offsets in centimetres, each with its [`Score`].
    pub fn to_wire(&self) -> ObjectResult {
        let floor = self.search.floor.max(f32::MIN_POSITIVE);
        let score = |(c, v): &(Candidate, Survival)| {
            Score::new(
                10.0 * libm::log10f(c.peak.max(f32::MIN_POSITIVE) / floor),
                v.survives(),
            )
        };
        let [best, rest @ ..] = self.ranked();
        let mut others = [Alternative::default(); ALTERNATIVES];
        for (slot, other) in others.iter_mut().zip(&rest) {
            let offset_cm = libm::roundf(100.0 * (other.0.depth_m - best.0.depth_m));
            if other.0.peak > 0.0 && libm::fabsf(offset_cm) <= i16::MAX as f32 {
                *slot = Alternative {
                    offset_cm: offset_cm as i16,
                    // An alternative's score is never 0 (that means none).
                    score: Score(score(other).0.max(2)),
                };
            }
        }
        ObjectResult {
            instance: self.id,
            depth_mm: m_to_mm(best.0.depth_m),
            score: score(&best),
            others,
        }
    }

    /// `P(d*) / median P`.
    pub fn floor_ratio(&self) -> f32 {
        self.search.peak / self.search.floor.max(f32::MIN_POSITIVE)
    }

    /// `P(d*) / best P elsewhere`.
    pub fn uniqueness(&self) -> f32 {
        self.search.peak / self.search.runner_up.max(f32::MIN_POSITIVE)
    }

    /// Whether the peak is trustworthy: [`DETECTION_RATIO`] above the floor and
    /// [`UNIQUENESS_RATIO`] above any other explanation.
    pub fn detected(&self) -> bool {
        self.floor_ratio() >= DETECTION_RATIO && self.uniqueness() >= UNIQUENESS_RATIO
    }
}

/// Why the pipeline could not run.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PipelineError {
    /// The radar configuration cannot be processed.
    Array(ArrayError),
    /// Range stage (sizes, arena).
    Range(RangeError),
    /// Range–azimuth scan.
    Scan(ScanError),
    /// Depth search.
    Search(SearchError),
    /// The channel calibration cannot be applied.
    Calibration(CalibrationError),
    /// A chirp addressed a slot or receiver the configuration does not have.
    Chirp {
        /// Chirp index in the frame.
        chirp: usize,
        /// Receiver.
        rx: usize,
    },
}

impl core::error::Error for PipelineError {}

impl fmt::Display for PipelineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Array(e) => e.fmt(f),
            Self::Range(e) => e.fmt(f),
            Self::Scan(e) => e.fmt(f),
            Self::Search(e) => e.fmt(f),
            Self::Calibration(e) => e.fmt(f),
            Self::Chirp { chirp, rx } => write!(
                f,
                "chirp {chirp}, receiver {rx} is not in the radar configuration: check the capture layout"
            ),
        }
    }
}

macro_rules! from_errors {
    ($($v:ident($t:ty)),*) => {$(
        impl From<$t> for PipelineError {
            fn from(e: $t) -> Self {
                Self::$v(e)
            }
        }
    )*};
}
from_errors!(
    Array(ArrayError),
    Range(RangeError),
    Scan(ScanError),
    Search(SearchError),
    Calibration(CalibrationError)
);

/// The per-configuration state: array, window, sizes. About 7 KiB.
pub struct Edge {
    array: VirtualArray,
    window: Vec<Q15, { crate::fft::MAX_LEN }>,
    n: usize,
    m: usize,
    rx: usize,
    slots: usize,
    chirps: usize,
    bin_m: f32,
    /// TX of each slot.
    tx_order: Vec<u8, { crate::config::MAX_SLOTS }>,
    tx: usize,
}

/// The most chirps one virtual element may take per frame when the module calibrates:
/// coefficients then keep 15 − 8 = 7 fraction bits (gain steps under 0.4 %, phase under 0.5°).
pub const MAX_CALIBRATED_CHIRPS: usize = 255;

/// A calibration in the module's form: every channel's block coefficients
/// ([`AppliedCalibration::block_coefficients`]), channel-major in capture order (slot · RX +
/// RX), over caller-owned words ([`Edge::calibration_words`]).
pub struct ChannelCoefficients<'t> {
    words: &'t [u32],
    blocks: usize,
    headroom: u32,
}

impl fmt::Debug for ChannelCoefficients<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ChannelCoefficients")
            .field("channels", &(self.words.len() / self.blocks.max(1)))
            .field("blocks", &self.blocks)
            .field("headroom", &self.headroom)
            .finish()
    }
}

impl ChannelCoefficients<'_> {
    /// Fraction bits the coefficients give up so that an element's sums stay inside `i32`.
    pub fn headroom(&self) -> u32 {
        self.headroom
    }
}

/// A frame after the range stage: spectra, the strongest reflectors, and the arena's free words.
pub struct FrameScene<'a> {
    /// The range spectra.
    pub spectra: Spectra<'a>,
    /// The strongest reflectors, strongest first.
    pub peaks: Vec<Peak, MAX_PEAKS>,
    free: &'a mut [u32],
}

impl<'a> FrameScene<'a> {
    /// The scene of a frame already finished in `arena` (spectra with block exponent `exponent`
    /// in its first words), e.g. kept by the host while it works through the objects.
    ///
    /// # Errors
    /// [`PipelineError::Range`] if the arena is smaller than [`Edge::arena_words`].
    pub fn resume(
        edge: &Edge,
        arena: &'a mut [u32],
        exponent: i32,
        peaks: Vec<Peak, MAX_PEAKS>,
    ) -> Result<Self, PipelineError> {
        let (e, m) = (edge.array.elements(), edge.m);
        if arena.len() < edge.arena_words() {
            return Err(RangeError::Buffer {
                what: "frame arena (u32 words)",
                expected: edge.arena_words(),
                got: arena.len(),
            }
            .into());
        }
        let (spec, free) = arena.split_at_mut(e * m);
        Ok(Self {
            spectra: Spectra::from_words(spec, e, m, exponent)?,
            peaks,
            free,
        })
    }
}

impl Edge {
    /// Range window of the pipeline.
    pub const WINDOW: WindowKind = WindowKind::Hann;

    /// The pipeline for `config`.
    ///
    /// # Errors
    /// [`PipelineError::Array`] if the configuration has no usable array.
    ///
    /// # Example
    /// A 2 TX × 4 RX board: 8 virtual elements, 256 samples per chirp; the frame arena holds
    /// one range spectrum per element.
    /// ```
    /// use metamoran_dsp::config::RadarConfig;
    /// use metamoran_dsp::pipeline::Edge;
    ///
    /// let config = RadarConfig {
    ///     start_frequency_hz: 77e9,
    ///     slope_hz_per_s: 30e12,
    ///     sample_rate_hz: 10e6,
    ///     adc_samples: 256,
    ///     chirp_period_s: 60e-6,
    ///     chirps_per_tx: 16,
    ///     frames: 1,
    ///     frame_period_s: 0.1,
    ///     tx_positions: heapless::Vec::from_slice(&[0, 4]).unwrap(),
    ///     rx_positions: heapless::Vec::from_slice(&[0, 1, 2, 3]).unwrap(),
    ///     tx_order: heapless::Vec::from_slice(&[0, 1]).unwrap(),
    /// };
    /// let edge = Edge::new(&config)?;
    /// assert_eq!((edge.samples(), edge.rows_per_frame()), (256, 2 * 4 * 16));
    /// assert!(edge.arena_words() >= 8 * 256);
    /// # Ok::<(), metamoran_dsp::pipeline::PipelineError>(())
    /// ```
    pub fn new(config: &RadarConfig) -> Result<Self, PipelineError> {
        let n = config.adc_samples as usize;
        let mut w = Vec::new();
        let _ = w.resize(n.min(crate::fft::MAX_LEN), Q15::ZERO);
        window::fill(Self::WINDOW, &mut w);
        Ok(Self {
            array: VirtualArray::new(config)?,
            window: w,
            n,
            m: config.range_fft_len(),
            rx: config.rx_count(),
            slots: config.slots(),
            chirps: config.chirps_per_frame(),
            bin_m: config.range_bin_size(config.range_fft_len()),
            tx_order: config.tx_order.clone(),
            tx: config.tx_positions.len(),
        })
    }

    /// Words of a [`ChannelCoefficients`] table for this configuration: channels × blocks (24
    /// KiB for a 12 TX × 16 RX, 512-sample cascade).
    pub fn calibration_words(&self) -> usize {
        self.array.channels() * cal::blocks(self.n)
    }

    /// Chirps the busiest virtual element takes per frame (loops × its channels).
    fn chirps_per_element(&self) -> usize {
        let loops = self.chirps / self.slots.max(1);
        let most = self
            .array
            .element_counts()
            .iter()
            .copied()
            .max()
            .unwrap_or(0);
        loops * usize::from(most)
    }

    /// `calibration` (by TX and RX index) in the module's form over `words`: each channel's
    /// block coefficients with the headroom this configuration's sums need. O(channels ·
    /// blocks), about 30 instructions per coefficient; once per configuration.
    ///
    /// # Errors
    /// [`PipelineError::Calibration`] if `calibration` does not cover a channel, `words` is
    /// short, or an element takes more than [`MAX_CALIBRATED_CHIRPS`] chirps per frame.
    pub fn calibrate<'t>(
        &self,
        calibration: &AppliedCalibration,
        words: &'t mut [u32],
    ) -> Result<ChannelCoefficients<'t>, PipelineError> {
        let per_element = self.chirps_per_element();
        if per_element > MAX_CALIBRATED_CHIRPS {
            return Err(CalibrationError::Chirps {
                per_element,
                max: MAX_CALIBRATED_CHIRPS,
            }
            .into());
        }
        // 2^headroom − 1 ≥ chirps per element.
        let headroom = usize::BITS - per_element.leading_zeros();
        let (blocks, need) = (cal::blocks(self.n), self.calibration_words());
        let Some(words) = words.get_mut(..need) else {
            return Err(CalibrationError::Length.into());
        };
        for (channel, row) in words.chunks_exact_mut(blocks.max(1)).enumerate() {
            let (slot, rx) = (channel / self.rx.max(1), channel % self.rx.max(1));
            let tx = self
                .tx_order
                .get(slot)
                .map_or(usize::MAX, |&t| usize::from(t));
            calibration.block_coefficients(tx, rx, self.n, headroom, row)?;
        }
        Ok(ChannelCoefficients {
            words,
            blocks,
            headroom,
        })
    }

    /// The search geometry.
    pub fn geometry(&self) -> Geometry<'_> {
        Geometry {
            positions: self.array.element_positions(),
            counts: self.array.element_counts(),
            samples: self.n,
            fft_len: self.m,
            window: Self::WINDOW,
            bin_m: self.bin_m,
        }
    }

    /// The virtual array.
    pub fn array(&self) -> &VirtualArray {
        &self.array
    }

    /// ADC samples per chirp N.
    pub fn samples(&self) -> u16 {
        self.n as u16
    }

    /// Transmitters of the board (`tx_positions`).
    pub fn tx_count(&self) -> usize {
        self.tx
    }

    /// Receivers per chirp.
    pub fn rx_count(&self) -> usize {
        self.rx
    }

    /// (chirp, receiver) rows in a frame, in capture order: chirp-major, then receiver.
    pub fn rows_per_frame(&self) -> usize {
        self.chirps * self.rx
    }

    /// Range FFT length M.
    pub fn fft_len(&self) -> usize {
        self.m
    }

    /// Azimuth FFT length of the range–azimuth scan: the span rounded up to a power of two (at
    /// least 16), so the sin-azimuth grid step 2/Nₐ is at most one beamwidth (2/span); SIC refines
    /// between grid points. (Twice the span cost 5 M instructions per cascade frame and found no
    /// better reflectors on the fresh-seed evaluation.)
    pub fn azimuth_len(&self) -> usize {
        crate::fft::padded_len(self.array.span()).unwrap_or(crate::fft::MAX_LEN)
    }

    /// Highest range bin searched (exclusive).
    pub fn max_bin(&self) -> usize {
        (MAX_RANGE_FRACTION * self.m as f32) as usize
    }

    /// Arena words a frame needs: the sums, or the spectra plus the beams of a full contour.
    pub fn arena_words(&self) -> usize {
        let e = self.array.elements();
        let search = e * self.m + depth::profile_words(crate::search::MAX_CONTOUR, self.m);
        FrameSum::words_needed(e, self.n, self.m).max(search)
    }

    /// Starts a frame in `arena`.
    ///
    /// # Errors
    /// [`PipelineError::Range`] if the arena is too small.
    pub fn start<'a>(&self, arena: &'a mut [u32]) -> Result<FrameSum<'a>, PipelineError> {
        let need = self.arena_words();
        if arena.len() < need {
            return Err(RangeError::Buffer {
                what: "frame arena (u32 words)",
                expected: need,
                got: arena.len(),
            }
            .into());
        }
        Ok(FrameSum::new(arena, self.array.elements(), self.n, self.m)?)
    }

    /// The table [`Self::calibrate`] filled (`words`, with the headroom it chose), viewed again
    /// for a later frame.
    ///
    /// # Errors
    /// [`PipelineError::Calibration`] if `words` is shorter than [`Self::calibration_words`]
    /// or `headroom` is not this configuration's.
    pub fn coefficients<'t>(
        &self,
        words: &'t [u32],
        headroom: u32,
    ) -> Result<ChannelCoefficients<'t>, PipelineError> {
        let per_element = self.chirps_per_element();
        let expected = usize::BITS - per_element.leading_zeros();
        let Some(words) = words.get(..self.calibration_words()) else {
            return Err(CalibrationError::Length.into());
        };
        if headroom != expected || per_element > MAX_CALIBRATED_CHIRPS {
            return Err(CalibrationError::Chirps {
                per_element,
                max: MAX_CALIBRATED_CHIRPS,
            }
            .into());
        }
        Ok(ChannelCoefficients {
            words,
            blocks: cal::blocks(self.n),
            headroom,
        })
    }

    /// Starts a frame in `arena` whose chirps are calibrated by `coefficients` as they are
    /// summed ([`Self::push_calibrated`]).
    ///
    /// # Errors
    /// [`PipelineError::Range`] if the arena is too small.
    pub fn start_calibrated<'a>(
        &self,
        arena: &'a mut [u32],
        coefficients: &ChannelCoefficients<'_>,
    ) -> Result<FrameSum<'a>, PipelineError> {
        let need = self.arena_words();
        if arena.len() < need {
            return Err(RangeError::Buffer {
                what: "frame arena (u32 words)",
                expected: need,
                got: arena.len(),
            }
            .into());
        }
        Ok(FrameSum::new_calibrated(
            arena,
            self.array.elements(),
            self.n,
            self.m,
            coefficients.headroom,
        )?)
    }

    /// [`Self::push`] of a frame from [`Self::start_calibrated`]: the chirp multiplied by its
    /// channel's block coefficients as it is summed. O(N), as many instructions as `push` on
    /// the M7 plus one load per block.
    ///
    /// # Errors
    /// As [`Self::push`].
    pub fn push_calibrated(
        &self,
        frame: &mut FrameSum<'_>,
        chirp: usize,
        rx: usize,
        samples: &[CQ15],
        coefficients: &ChannelCoefficients<'_>,
    ) -> Result<(), PipelineError> {
        let channel = chirp.checked_rem(self.slots).unwrap_or(usize::MAX) * self.rx + rx;
        let (element, row) = match (
            self.array.element_of(channel),
            coefficients
                .words
                .get(channel * coefficients.blocks..(channel + 1) * coefficients.blocks),
        ) {
            (Some(e), Some(row)) if rx < self.rx => (e, row),
            _ => return Err(PipelineError::Chirp { chirp, rx }),
        };
        Ok(frame.add_calibrated(element, samples, row)?)
    }

    /// Adds chirp `chirp` of the frame (loop-major: slot `chirp % slots`) of receiver `rx`. O(N).
    ///
    /// # Errors
    /// [`PipelineError`] for a receiver out of range or a wrong sample count.
    pub fn push(
        &self,
        frame: &mut FrameSum<'_>,
        chirp: usize,
        rx: usize,
        samples: &[CQ15],
    ) -> Result<(), PipelineError> {
        let channel = chirp.checked_rem(self.slots).unwrap_or(usize::MAX) * self.rx + rx;
        let element = match self.array.element_of(channel) {
            Some(e) if rx < self.rx => e,
            _ => return Err(PipelineError::Chirp { chirp, rx }),
        };
        Ok(frame.add(element, samples)?)
    }

    /// Ends the frame: range spectra in place, then the range–azimuth scan. `row` holds M
    /// values, `azimuth` [`Edge::azimuth_len`], `powers` three times that.
    ///
    /// # Errors
    /// [`PipelineError`] for wrong scratch sizes.
    pub fn finish<'a>(
        &self,
        frame: FrameSum<'a>,
        row: &mut [CQ15],
        azimuth: &mut [CQ15],
        powers: &mut [u64],
    ) -> Result<FrameScene<'a>, PipelineError> {
        let (spectra, free) = frame.finish(&self.window, row)?;
        let na = self.azimuth_len();
        let have = azimuth.len();
        let azimuth = azimuth.get_mut(..na).ok_or(ScanError::AzimuthLen(have))?;
        let peaks = peaks::scan(
            &spectra,
            self.array.element_positions(),
            self.max_bin(),
            azimuth,
            powers,
        )?;
        Ok(FrameScene {
            spectra,
            peaks,
            free,
        })
    }

    /// The range bins searched for `hint`: from [`PRIOR_FRACTION`] of its monocular range (bin 1
    /// when unknown) or the window's near bound, whichever is farther, to [`Edge::max_bin`] or
    /// the window's far bound, whichever is nearer; the whole range beyond the first when the
    /// window leaves fewer than [`MIN_WINDOW_BINS`]. The window's near bound is taken down to a
    /// whole bin.
    pub fn bins(&self, hint: &ObjectHint) -> (f32, f32) {
        let max_bin = self.max_bin() as f32;
        let bin = |m: f32| m / self.bin_m;
        let mut first = if hint.prior_m > 0.0 {
            PRIOR_FRACTION * bin(hint.prior_m)
        } else {
            1.0
        };
        let (near, far) = (bin(hint.window_m.0), bin(hint.window_m.1));
        let last = if far > 0.0 { far.min(max_bin) } else { max_bin };
        if near.max(first) + MIN_WINDOW_BINS <= last {
            // The window's start on a whole bin, so the fine grid does not move with a mask
            // one pixel taller.
            first = libm::floorf(near).max(first);
            // max/min rather than clamp: no panic path even for a radar too short to search.
            return (first.max(1.0), last);
        }
        (first.min(max_bin - 2.0).max(1.0), max_bin)
    }

    /// The contour the search uses for `hint`: directions rounded to a quarter of the array's
    /// beamwidth (sin step 1/(2·span)), so nearby points share a beam at a loss below 0.2 dB.
    pub fn contour(&self, hint: &ObjectHint) -> Contour {
        hint.contour.snapped(0.5 / self.array.span() as f32)
    }

    /// SIC for one object: the reflectors outside its span, strongest first.
    pub fn cancel(
        &self,
        scene: &FrameScene<'_>,
        hint: &ObjectHint,
    ) -> Vec<Reflector, MAX_REFLECTORS> {
        // Keep the object's span plus a main lobe (first null of the array at sin = 2/span).
        let guard = 2.0 / self.array.span() as f32;
        let keep = [(hint.span.0 - guard, hint.span.1 + guard)];
        sic::cancel(
            &scene.spectra,
            &self.geometry(),
            &scene.peaks,
            self.azimuth_len(),
            &keep,
            SIC_STOP_RATIO,
        )
    }

    /// The depth search for one object with `reflectors` cancelled. `scores` holds M values.
    ///
    /// # Errors
    /// [`PipelineError::Search`] if the search cannot run (empty contour, range, buffers).
    pub fn search(
        &self,
        scene: &mut FrameScene<'_>,
        hint: &ObjectHint,
        reflectors: &[Reflector],
        scores: &mut [f32],
    ) -> Result<ObjectReport, PipelineError> {
        let geo = self.geometry();
        let search = depth::coarse_to_fine(
            &scene.spectra,
            &geo,
            &self.contour(hint),
            self.bins(hint),
            reflectors,
            scene.free,
            scores,
        )?;
        // The search's beams are done with: the survival test's FFT takes the free words.
        let need = survival::fft_len(self.array.span()).unwrap_or(0);
        let have = scene.free.len();
        let fft = scene
            .free
            .get_mut(..need)
            .map(crate::fixed::from_words_mut)
            .ok_or(SearchError::Buffer {
                what: "survival FFT (free arena words)",
                expected: need,
                got: have,
            })?;
        let mut survival = [Survival::default(); CANDIDATES];
        let candidates = core::iter::once(search.depth_bins)
            .zip(core::iter::once(search.peak))
            .chain(search.others.iter().map(|c| (c.depth_bins, c.peak)));
        for (slot, (bins, peak)) in survival.iter_mut().zip(candidates) {
            if peak > 0.0 {
                let bin = libm::roundf(bins).max(0.0) as usize;
                *slot = survival::survival(&scene.spectra, &geo, bin, hint.span, fft)?;
            }
        }
        Ok(ObjectReport {
            id: hint.id,
            class: hint.class,
            search,
            cancelled: reflectors.len() as u8,
            survival,
        })
    }

    /// SIC, then the depth search, for one object. `scores` holds M values.
    ///
    /// # Errors
    /// [`PipelineError::Search`] if the search cannot run (empty contour, range, buffers).
    pub fn object(
        &self,
        scene: &mut FrameScene<'_>,
        hint: &ObjectHint,
        scores: &mut [f32],
    ) -> Result<ObjectReport, PipelineError> {
        let reflectors = self.cancel(scene, hint);
        self.search(scene, hint, &reflectors, scores)
    }
}
