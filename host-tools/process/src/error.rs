//! The processing crate's errors.

use metamoran_bundle::error::InputError;
use metamoran_edge::EdgeError;
use std::path::PathBuf;

/// Why a bundle or frame could not be processed. Input problems name the file and field; the
/// radar configuration's say which limit of the DSP it breaks.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ProcessError {
    /// A bad or unreadable input file.
    #[error(transparent)]
    Input(#[from] InputError),
    /// The module under QEMU failed.
    #[error(transparent)]
    Edge(#[from] EdgeError),
    /// The radar configuration is not one the DSP handles.
    #[error("radar configuration: {0}")]
    Config(#[from] metamoran_dsp::config::ConfigError),
    /// The virtual array cannot be built from the configuration.
    #[error("radar configuration: {0}")]
    Array(#[from] metamoran_dsp::array::ArrayError),
    /// The range stage refused its input.
    #[error("range processing: {0}")]
    Range(#[from] metamoran_dsp::range::RangeError),
    /// The Doppler stage refused its input.
    #[error("Doppler processing: {0}")]
    Doppler(#[from] metamoran_dsp::doppler::DopplerError),
    /// The azimuth FFT refused its input.
    #[error("azimuth processing: {0}")]
    Fft(#[from] metamoran_dsp::fft::FftError),
    /// The point cloud could not be formed.
    #[error("point cloud: {0}")]
    Points(#[from] metamoran_dsp::points::PointsError),
    /// The module's pipeline failed.
    #[error("module pipeline: {0}")]
    Pipeline(#[from] metamoran_dsp::pipeline::PipelineError),
    /// The depth search failed.
    #[error("depth search: {0}")]
    Search(#[from] metamoran_dsp::search::depth::SearchError),
    /// A frame's sample count does not match the configuration.
    #[error("frame has {got} samples; the config needs {expected}")]
    FrameLength {
        /// Samples in the frame.
        got: usize,
        /// Samples the configuration implies.
        expected: usize,
    },
    /// A Doppler index past the Doppler FFT.
    #[error("Doppler index {0} out of range")]
    DopplerIndex(usize),
    /// A channel the virtual array does not hold.
    #[error("channel outside the array")]
    Channel,
    /// `--edge qemu` with a capture in QQII order.
    #[error(
        "--edge qemu: the module reads radar.bin in the bundle's IIQQ order; convert the capture or use --edge in-process"
    )]
    IqOrder,
    /// The channel calibration does not fit the frame.
    #[error("channel calibration: {0}")]
    ChannelCalibration(#[from] metamoran_dsp::range::calibration::CalibrationError),
    /// No calibration from this capture.
    #[error(transparent)]
    Calibration(#[from] crate::calibrate::CalibrateError),
    /// A frame number past the bundle's end.
    #[error("frame {frame}: the bundle has {frames} frames (use --frame 0..{})", frames.saturating_sub(1))]
    NoFrame {
        /// The frame asked for.
        frame: u32,
        /// Frames in the bundle.
        frames: u32,
    },
    /// A folder that could not be listed.
    #[error("{}: cannot list it ({source})", dir.display())]
    List {
        /// The folder.
        dir: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A folder without bundles.
    #[error("{}: no bundle folders (with scene.toml) inside; make some with `metamoran simulate`", dir.display())]
    NoBundles {
        /// The folder.
        dir: PathBuf,
    },
    /// The consumer of the frames (a view, a publisher) stopped the run.
    #[error("{0}")]
    Consumer(Box<dyn std::error::Error + Send + Sync>),
}
