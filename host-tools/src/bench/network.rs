//! `metamoran bench network`: 3D-RadarHR's time per depth image on this host against IP-Basic's
//! (the paper's conventional completion) on the same drive submaps, measured in one run, and the
//! whole map path per frame (point cloud, odometry, submap, network) for the frame-rate goal, on
//! either board's drive scenes; and the first scene's map path again after the inferences, which
//! shows whether running the network slows what its thread does next.

use metamoran_dsp::points::Peaks;
use metamoran_map::cylinder::DepthImage;
use metamoran_map::network::{Board, CompletionNetwork};
use metamoran_map::submap::Keep;
use metamoran_map::{depth, odometry};
use metamoran_sim::{drive::MOUNT, layout::Preset, radar::RadarKind, simulate};
use serde::Serialize;
use std::time::Instant;

/// Drive scenes the figures are taken over (seed 77).
pub const SCENES: u64 = 3;
/// Timed repetitions per submap (after one untimed).
pub const REPEATS: u32 = 10;

/// The report.
#[derive(Clone, Debug, Serialize)]
pub struct NetworkReport {
    /// The board the scenes were seen by (`small` or `imaging`).
    pub board: &'static str,
    /// Submaps timed.
    pub submaps: usize,
    /// Which earlier points the submaps kept: `all` or `seen again`.
    pub keep: &'static str,
    /// Which detections became points: `map` (the range–Doppler map's local maxima) or
    /// `direction` (each direction's own peak).
    pub peaks: &'static str,
    /// Whether the detector's screen applied (`map --screen`).
    pub screen: bool,
    /// Network, ms per 320 × 80 image (with a guided model, the IP-Basic completion it takes
    /// as its second image included).
    pub network_ms: f64,
    /// IP-Basic (the baseline), ms per image.
    pub ip_basic_ms: f64,
    /// `network_ms / ip_basic_ms`.
    pub ratio: f64,
    /// Network inferences per second.
    pub network_fps: f64,
    /// The map path per radar frame without the network (point cloud, RANSAC, submap
    /// projection), ms: odometry and submaps over the scenes' frames divided by their count.
    pub map_path_ms: f64,
    /// Frames per second of the whole path with the network, `1000 / (map_path_ms + network_ms)`.
    pub path_fps: f64,
    /// The first scene's map path per frame, ms, timed again after every inference had run on
    /// this thread: the same work as its share of `map_path_ms`, which ran before any.
    pub after_network_ms: f64,
    /// `after_network_ms` over the first scene's map path per frame before any inference: 1
    /// when running the network leaves nothing behind that slows what the thread does next
    /// (tract's kernels left the vector registers dirty, which made it about 2).
    pub after_ratio: f64,
}

/// The map path of `bundle` (odometry, then every frame's submap): the submaps and the time
/// per frame, ms.
fn map_path(
    bundle: &std::path::Path,
    options: &depth::SubmapOptions,
) -> Result<(Vec<DepthImage>, f64), crate::Error> {
    let t = Instant::now();
    let o = odometry::run_with(bundle, &MOUNT, options.cloud())?;
    let n = o.tracked.len();
    let submaps: Vec<_> = (0..n)
        .map(|k| depth::submap_with(&o, k, options).1)
        .collect();
    Ok((submaps, t.elapsed().as_secs_f64() * 1e3 / n.max(1) as f64))
}

fn per_run<E: Into<crate::Error>>(
    mut f: impl FnMut() -> Result<(), E>,
) -> Result<f64, crate::Error> {
    f().map_err(Into::into)?;
    let t = Instant::now();
    for _ in 0..REPEATS {
        f().map_err(Into::into)?;
    }
    Ok(t.elapsed().as_secs_f64() * 1e3 / f64::from(REPEATS))
}

/// Runs on [`SCENES`] simulated drive scenes of `board` with the network shipped for it, the
/// points and submaps made as `options` say (`map` uses [`Board::submap_options`]).
///
/// # Errors
/// The network cannot be loaded (e.g. a build without the `onnx` feature), or a scene fails.
pub fn run(board: Board, options: depth::SubmapOptions) -> Result<NetworkReport, crate::Error> {
    let network = CompletionNetwork::load(None, board)?;
    let (kind, name) = match board {
        Board::Small => (RadarKind::Xwr18xx, "small"),
        Board::Imaging => (RadarKind::Imaging, "imaging"),
    };
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let bundles = simulate(Preset::Drive, kind, 77, SCENES, dir.path(), &|| ())?;
    let (mut network_ms, mut ip_basic_ms, mut path_ms, mut frames) = (0.0, 0.0, 0.0, 0usize);
    let mut first_ms = None;
    for b in &bundles {
        let (submaps, ms) = map_path(b, &options)?;
        let n = submaps.len();
        path_ms += ms * n as f64;
        frames += n;
        first_ms.get_or_insert(ms);
        let Some(last) = submaps.last().map(|s| &s.range_m) else {
            continue;
        };
        network_ms += per_run(|| network.complete(last).map(drop))?;
        ip_basic_ms += per_run(|| {
            metamoran_map::ip_basic::complete(last);
            Ok::<_, crate::Error>(())
        })?;
    }
    let after_network_ms = match bundles.first() {
        Some(b) => map_path(b, &options)?.1,
        None => f64::NAN,
    };
    let before_ms = first_ms.unwrap_or(f64::NAN);
    let s = bundles.len() as f64;
    let (network_ms, ip_basic_ms) = (network_ms / s, ip_basic_ms / s);
    let map_path_ms = path_ms / frames as f64;
    Ok(NetworkReport {
        board: name,
        submaps: bundles.len(),
        keep: match options.keep {
            Keep::All => "all",
            Keep::SeenAgain { .. } => "seen again",
        },
        peaks: match options.peaks {
            Peaks::RangeDoppler => "map",
            Peaks::Direction => "direction",
        },
        screen: options.screen.is_some(),
        network_ms,
        ip_basic_ms,
        ratio: network_ms / ip_basic_ms,
        network_fps: 1e3 / network_ms,
        map_path_ms,
        path_fps: 1e3 / (map_path_ms + network_ms),
        after_network_ms,
        after_ratio: after_network_ms / before_ms,
    })
}

impl std::fmt::Display for NetworkReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "Depth completion of a 320 × 80 drive submap, {} board ({} submaps, {} runs each; \
             earlier points kept: {}; peaks: {}; screen: {})",
            self.board,
            self.submaps,
            REPEATS,
            self.keep,
            self.peaks,
            if self.screen { "on" } else { "off" }
        )?;
        writeln!(f, "  IP-Basic (baseline)  {:>7.2} ms", self.ip_basic_ms)?;
        writeln!(
            f,
            "  3D-RadarHR (tract)   {:>7.2} ms  {:.2}× IP-Basic, {:.0} Hz",
            self.network_ms, self.ratio, self.network_fps
        )?;
        writeln!(
            f,
            "  map path per frame without the network {:.1} ms; with it {:.0} Hz",
            self.map_path_ms, self.path_fps
        )?;
        writeln!(
            f,
            "  first scene's map path again after the inferences {:.1} ms per frame, \
             {:.2}× its time before them",
            self.after_network_ms, self.after_ratio
        )
    }
}
