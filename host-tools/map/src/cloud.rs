//! Radar point clouds of a bundle's frames, with the module's `dsp` processing.

use crate::MapError;
use metamoran_bundle::Bundle;
use metamoran_dsp::detect::{Boundary, Cfar, Cfar2d, CfarKind};
use metamoran_dsp::points::{ArrayGeometry, CloudOptions, Peaks, RadarPoint, Screen};
use metamoran_dsp::window::WindowKind;
use metamoran_process::frame::{FrameOptions, FrameProcessor, FrameSpectra};

/// The detector settings for mapping with the map's local maxima ([`Peaks::RangeDoppler`], the
/// module's rule): [`options`] of it.
pub fn default_options() -> CloudOptions {
    options(Peaks::RangeDoppler)
}

/// The detector settings for mapping with `peaks`: CA-CFAR 9.5 dB over magnitude (×3), 2 guard
/// and 8 training range bins, 1 guard and 4 training Doppler bins (wrapping); azimuth peaks
/// within 8 dB; nothing nearer than 1.5 m or more than 80 dB below the strongest cell; no
/// [`Screen`] (the imaging board's submaps and `map --screen` add [`DIRECTION_SCREEN`]).
///
/// ```
/// use metamoran_dsp::points::Peaks;
/// let direction = metamoran_map::cloud::options(Peaks::Direction);
/// assert_eq!(direction.peaks, Peaks::Direction);
/// assert_eq!(direction.screen, None);
/// assert_eq!(
///     metamoran_map::cloud::options(Peaks::RangeDoppler),
///     metamoran_map::cloud::default_options()
/// );
/// ```
pub fn options(peaks: Peaks) -> CloudOptions {
    let axis = |guard, train, boundary| Cfar {
        guard,
        train,
        scale: 3.0,
        kind: CfarKind::CellAveraging,
        boundary,
    };
    CloudOptions {
        cfar: Cfar2d {
            rows: axis(2, 8, Boundary::Truncate),
            cols: axis(1, 4, Boundary::Wrap),
        },
        direction_floor_db: 8.0,
        min_range_m: 1.5,
        dynamic_range_db: 80.0,
        screen: None,
        velocity_prior: None,
        peaks,
    }
}

/// How far over the map's median magnitude (its noise, where noise fills most of the map)
/// [`DIRECTION_SCREEN`] asks a cell to be, dB. The imaging map's noise cells spread about 1 dB
/// from the 5th to the 75th percentile, so 6 dB over the median passes few of them; a real
/// capture's returns stand 55 dB over it (OpenRadar `doppler_example_1`), the simulator's 86 dB.
pub const NOISE_MARGIN_DB: f32 = 6.0;

/// The cells the imaging board's submaps (and `map --screen`) also test (for
/// [`Peaks::Direction`], whose own test of each direction's peak in range and Doppler decides
/// what is a point): louder than their training cells' mean (×1), within 40 dB of the
/// strongest cell and [`NOISE_MARGIN_DB`] over the map's median. At 9.5 dB over the summed
/// map's neighbourhood the rule lost reflectors whose cell other directions' returns crowd;
/// below 40 dB, with no margin over the neighbourhood asked, lie mostly the range and Doppler
/// side lobes of the strongest reflectors (Hann: −31 dB and falling). Picked on 12 fresh
/// imaging scenes (seeds 9510–9810) from scales 0–3 and ranges 40–80 dB and checked on 12
/// others (README "the direction rule's screen"). The imaging board's default since its
/// network takes IP-Basic's completion as a guide (README "a network that corrects
/// IP-Basic"); retrained on such submaps without the guide it did worse in the held-out
/// tunnel. In the simulator the noise lies lower still (62 dB of processing gain over thermal
/// noise near one LSB), so the median test changes nothing there; a capture whose noise comes
/// within 40 dB of its strongest return needs it (README "the screen keeps over the noise").
pub const DIRECTION_SCREEN: Screen = Screen {
    scale: 1.0,
    dynamic_range_db: 40.0,
    noise_margin_db: NOISE_MARGIN_DB,
};

/// The antenna array of `bundle`'s radar with its antennas' elevations, as the point clouds
/// use it.
///
/// # Errors
/// [`MapError::Geometry`] naming `scene.toml` if the array cannot give point clouds.
pub fn geometry(bundle: &Bundle) -> Result<ArrayGeometry, MapError> {
    let scene = &bundle.scene;
    ArrayGeometry::new(&scene.radar, &scene.tx_elevation, &scene.rx_elevation).map_err(|source| {
        MapError::Geometry {
            scene: bundle.dir().join("scene.toml"),
            source,
        }
    })
}

/// Turns a bundle's frames into point clouds, one at a time.
pub struct Clouds {
    processor: FrameProcessor,
    geometry: ArrayGeometry,
    options: CloudOptions,
    samples: Vec<metamoran_dsp::fixed::CQ15>,
    max_velocity: f32,
}

impl Clouds {
    /// For `bundle`'s radar, its antennas' elevations and `options`.
    ///
    /// # Errors
    /// [`MapError`] if the array or configuration cannot give point clouds.
    pub fn new(bundle: &Bundle, options: CloudOptions) -> Result<Self, MapError> {
        let scene = &bundle.scene;
        let geometry = geometry(bundle)?;
        let processor = FrameProcessor::new(
            &scene.radar,
            FrameOptions {
                range_window: WindowKind::Hann,
                doppler_window: WindowKind::Hann,
                remove_static: false,
            },
        )?
        .keeping_doppler_spectra();
        Ok(Self {
            processor,
            geometry,
            options,
            samples: Vec::new(),
            max_velocity: scene.radar.max_velocity(),
        })
    }

    /// The points of frame `frame`, their radial velocities unfolded towards a static world
    /// seen at radar velocity `prior` (m/s, radar frame) where given
    /// ([`CloudOptions::velocity_prior`]).
    ///
    /// # Errors
    /// [`MapError`] naming the file if the frame cannot be read.
    pub fn frame(
        &mut self,
        bundle: &mut Bundle,
        frame: u32,
        prior: Option<[f32; 2]>,
    ) -> Result<Vec<RadarPoint>, MapError> {
        bundle.read_radar_frame(frame, &mut self.samples)?;
        let spectra = self.processor.process(&self.samples)?;
        self.points(&spectra, prior)
    }

    /// The points of the processed `spectra` unfolded towards `prior`.
    fn points(
        &mut self,
        spectra: &FrameSpectra,
        prior: Option<[f32; 2]>,
    ) -> Result<Vec<RadarPoint>, MapError> {
        let options = CloudOptions {
            velocity_prior: prior,
            ..self.options
        };
        Ok(self.processor.points(spectra, &self.geometry, &options)?)
    }

    /// [`Self::frame`] without a prior, then, if `choose` finds one in those folded points,
    /// the points again with it: the frame is read and transformed once, only its cloud is
    /// formed twice.
    ///
    /// # Errors
    /// [`MapError`] naming the file if the frame cannot be read.
    pub fn frame_unfolded(
        &mut self,
        bundle: &mut Bundle,
        frame: u32,
        choose: impl FnOnce(&[RadarPoint]) -> Option<[f32; 2]>,
    ) -> Result<Vec<RadarPoint>, MapError> {
        bundle.read_radar_frame(frame, &mut self.samples)?;
        let spectra = self.processor.process(&self.samples)?;
        let folded = self.points(&spectra, None)?;
        match choose(&folded) {
            Some(prior) => self.points(&spectra, Some(prior)),
            None => Ok(folded),
        }
    }

    /// The span of radial velocity the board measures unambiguously, m/s (twice its largest
    /// unambiguous speed).
    pub fn velocity_span_mps(&self) -> f32 {
        2.0 * self.max_velocity
    }
}
