//! The 3D-RadarHR network behind `metamoran map` (`metamoran_vision::RadarHr` through tract): a
//! model shipped in the vision crate for the bundle's kind of board, or another ONNX file.
//! Needs the `onnx` feature; without it, loading says how to build with it.

use crate::MapError;
use crate::cloud::DIRECTION_SCREEN;
use crate::cylinder::Visibility;
use crate::depth::SubmapOptions;
use crate::submap::Keep;
use metamoran_bundle::{Bundle, OpenOptions};
use metamoran_dsp::points::Peaks;
use std::path::Path;

/// The kind of radar board a bundle was recorded with, as far as the mapping cares: it picks the
/// shipped network (each was trained on its own board's submaps).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Board {
    /// An array with at most two elevation rows (the xWR1843-like board: elevation from one
    /// phase difference).
    Small,
    /// A 2D aperture of three or more elevation rows (the 4D imaging board). Its network was
    /// trained on submaps cut to what is visible ([`Visibility::IMAGING_BEAM`]) that keep only
    /// the earlier points the frame sees again ([`Keep::SEEN_AGAIN`]), of points at each
    /// direction's own peak ([`Peaks::Direction`]) under the detector's screen
    /// ([`DIRECTION_SCREEN`]), and takes the submap's IP-Basic completion as a guide.
    Imaging,
}

impl Board {
    /// The board of the bundle in `dir`, from its antennas' elevations.
    ///
    /// # Errors
    /// [`MapError`] naming the file of a bad bundle or array.
    pub fn of(dir: &Path) -> Result<Self, MapError> {
        let bundle = Bundle::open(dir, OpenOptions::default())?;
        Ok(if crate::cloud::geometry(&bundle)?.rows().len() > 2 {
            Self::Imaging
        } else {
            Self::Small
        })
    }

    /// The submaps this board's shipped network was trained on: every point and no cut on the
    /// small board; on the imaging board, cut to what the imaging beam sees, keeping
    /// [`IMAGING_KEEP`] of the earlier points, with points at [`IMAGING_PEAKS`] under
    /// [`DIRECTION_SCREEN`].
    pub fn submap_options(self) -> SubmapOptions {
        match self {
            Self::Small => SubmapOptions::default(),
            Self::Imaging => SubmapOptions {
                keep: IMAGING_KEEP,
                visibility: Some(Visibility::IMAGING_BEAM),
                peaks: IMAGING_PEAKS,
                screen: Some(DIRECTION_SCREEN),
            },
        }
    }
}

/// Which detections become the imaging board's points: each direction's own peak in range and
/// Doppler, what its shipped network was trained on (README "the imaging network retrained on
/// each direction's peaks").
pub const IMAGING_PEAKS: Peaks = Peaks::Direction;

/// Which earlier points the imaging board's submaps keep: those the frame sees again (issue
/// #21, part 2; README "Submaps that keep what the frame sees again").
pub const IMAGING_KEEP: Keep = Keep::SEEN_AGAIN;

/// A loaded depth-completion network.
pub struct CompletionNetwork {
    #[cfg(feature = "onnx")]
    inner: metamoran_vision::RadarHr,
    /// Without tract there is no network: the type has no values.
    #[cfg(not(feature = "onnx"))]
    none: std::convert::Infallible,
}

impl CompletionNetwork {
    /// The ONNX model at `path`, or the one shipped for `board`.
    ///
    /// # Errors
    /// [`MapError`] naming the model that cannot be loaded or breaks the contract, or saying how
    /// to build with ONNX support.
    pub fn load(path: Option<&Path>, board: Board) -> Result<Self, MapError> {
        #[cfg(feature = "onnx")]
        {
            let inner = match (path, board) {
                (Some(p), _) => metamoran_vision::RadarHr::load(p),
                (None, Board::Small) => metamoran_vision::RadarHr::shipped(),
                (None, Board::Imaging) => metamoran_vision::RadarHr::shipped_imaging(),
            }
            .map_err(|e| MapError::Network(e.to_string()))?;
            Ok(Self { inner })
        }
        #[cfg(not(feature = "onnx"))]
        {
            let _ = (path, board);
            Err(MapError::NoOnnx)
        }
    }

    /// Completes a 320 × 80 submap depth image (row-major ranges, m, 0 = empty). A model that
    /// takes a guide gets the submap's IP-Basic completion ([`crate::ip_basic::complete`]) as
    /// its second image.
    ///
    /// # Errors
    /// The model's message (wrong size, bad depth, inference failure).
    pub fn complete(&self, range_m: &[f32]) -> Result<Vec<f32>, MapError> {
        #[cfg(feature = "onnx")]
        {
            // An image of another size goes to the model as it is, which refuses it by name.
            let sized = range_m.len() == crate::cylinder::WIDTH * crate::cylinder::HEIGHT;
            let guide = (self.inner.channels() == 2).then(|| {
                if sized {
                    crate::ip_basic::complete(range_m)
                } else {
                    range_m.to_vec()
                }
            });
            self.inner
                .complete(range_m, guide.as_deref())
                .map_err(|e| MapError::Network(e.to_string()))
        }
        #[cfg(not(feature = "onnx"))]
        {
            let _ = range_m;
            match self.none {}
        }
    }
}
