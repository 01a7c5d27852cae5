//! `metamoran bench search`: the depth search on a cascade-86, 512-sample frame — production
//! coarse-to-fine against the brute-force matched filter, in multiply-accumulates (counted by the
//! searches themselves) and host time, plus the clutter cancellation that precedes them.

use metamoran_bundle::CameraFrame;
use metamoran_bundle::geometry::CameraModel;
use metamoran_dsp::capture::{IqOrder, deinterleave_bytes};
use metamoran_dsp::fixed::CQ15;
use metamoran_process::camera_points::objects_of_interest;
use metamoran_process::metamoran::{StaticScene, both_searches, fast_search, prepare};
use metamoran_sim::{layout::Preset, radar::RadarKind, simulate_scene};
use serde::Serialize;
use std::time::Instant;

/// The report.
#[derive(Clone, Debug, Serialize)]
pub struct SearchReport {
    /// The frame searched.
    pub frame: String,
    /// Contour points.
    pub contour_points: usize,
    /// Complex MACs of the production search.
    pub coarse_to_fine_macs: u64,
    /// Complex MACs of the brute-force reference.
    pub brute_force_macs: u64,
    /// `brute_force_macs / coarse_to_fine_macs`.
    pub mac_ratio: f64,
    /// Host time of the production search, ms.
    pub coarse_to_fine_ms: f64,
    /// Host time of the reference, ms.
    pub brute_force_ms: f64,
    /// Host time of static sums + SIC for the object, ms.
    pub prepare_ms: f64,
    /// Depths found (production, reference), m.
    pub depths_m: (f32, f32),
}

/// Runs on a simulated long-range cascade scene (seed 7, first object of interest).
///
/// # Errors
/// A message if the scene has no object to search.
pub fn run() -> Result<SearchReport, crate::Error> {
    let scene = simulate_scene(Preset::LongRange, RadarKind::Cascade, 7, 0);
    let mut frame = vec![CQ15::default(); scene.radar.samples_per_frame()];
    deinterleave_bytes(&scene.adc, IqOrder::Iiqq, &mut frame).map_err(|e| e.to_string())?;
    let cam = CameraFrame {
        width: scene.camera.width,
        height: scene.camera.height,
        mask: scene.shots[0].products.mask.clone(),
        depth: scene.shots[0].products.depth_png.clone(),
        instances: scene.shots[0].instances.clone(),
    };
    let obj = objects_of_interest(&CameraModel::new(&scene.camera), &cam)
        .into_iter()
        .next()
        .ok_or("no object of interest in the benchmark scene")?;
    let t = Instant::now();
    let mut statics = StaticScene::new(&scene.radar, &frame)?;
    let prepared = prepare(&mut statics, &obj).ok_or("the object has no azimuth span")?;
    let prepare_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    let (fast, reference) = both_searches(&mut statics, &prepared)?;
    let both_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    fast_search(&mut statics, &prepared)?;
    let fast_ms = t.elapsed().as_secs_f64() * 1e3;
    Ok(SearchReport {
        frame: format!(
            "cascade-86 ({} channels), {} samples, {}-bin range FFT",
            scene.radar.channels(),
            scene.radar.adc_samples,
            scene.radar.range_fft_len()
        ),
        contour_points: prepared.hint.contour.points().len(),
        coarse_to_fine_macs: fast.macs,
        brute_force_macs: reference.macs,
        mac_ratio: reference.macs as f64 / fast.macs as f64,
        coarse_to_fine_ms: fast_ms,
        brute_force_ms: both_ms - fast_ms,
        prepare_ms,
        depths_m: (fast.depth_m, reference.depth_m),
    })
}

impl std::fmt::Display for SearchReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "Depth search on a {}; {} contour points",
            self.frame, self.contour_points
        )?;
        writeln!(
            f,
            "  brute force     {:>14} MACs {:>9.1} ms  depth {:.3} m",
            self.brute_force_macs, self.brute_force_ms, self.depths_m.1
        )?;
        writeln!(
            f,
            "  coarse-to-fine  {:>14} MACs {:>9.1} ms  depth {:.3} m",
            self.coarse_to_fine_macs, self.coarse_to_fine_ms, self.depths_m.0
        )?;
        writeln!(f, "  ratio           {:>14.0}×", self.mac_ratio)?;
        writeln!(
            f,
            "  static sums + SIC for the object: {:.1} ms",
            self.prepare_ms
        )
    }
}
