//! The capture summary: what a radar engineer looks at first (range-profile peaks, and moving
//! targets found by CFAR on the range–Doppler map with their range, velocity and azimuth).

use crate::frame::{FrameOptions, FrameProcessor};
use metamoran_bundle::RadarFile;
use metamoran_bundle::error::InputError;
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::detect::{Boundary, Cfar, Cfar2d, CfarKind, is_local_max, quadratic_offset};
use metamoran_dsp::units::signed_bin;
use metamoran_dsp::window::WindowKind;
use serde::Serialize;

/// Geometry of the capture.
#[derive(Clone, Debug, Serialize)]
pub struct ConfigSummary {
    /// Frames in the capture.
    pub frames: u32,
    /// Range FFT length.
    pub range_fft_len: usize,
    /// Doppler FFT length.
    pub doppler_fft_len: usize,
    /// Metres per range bin.
    pub range_resolution_m: f32,
    /// Largest unambiguous range, m.
    pub max_range_m: f32,
    /// m/s per Doppler bin.
    pub velocity_resolution_mps: f32,
    /// Largest unambiguous speed, m/s.
    pub max_velocity_mps: f32,
    /// Virtual channels.
    pub virtual_channels: usize,
    /// Distinct virtual element positions.
    pub virtual_elements: usize,
}

/// A peak of the mean range profile.
#[derive(Clone, Debug, Serialize)]
pub struct RangePeak {
    /// Range bin.
    pub bin: usize,
    /// Interpolated range, m.
    pub range_m: f32,
    /// Mean magnitude, dB relative to a full-scale tone (which reads 0 dBFS without a window).
    pub level_dbfs: f32,
    /// Azimuth of the static scene at this range, degrees (None: outside the visible region).
    pub azimuth_deg: Option<f32>,
}

/// A CFAR detection on the clutter-removed range–Doppler map.
#[derive(Clone, Debug, Serialize)]
pub struct MovingTarget {
    /// Range bin.
    pub range_bin: usize,
    /// Signed Doppler bin.
    pub doppler_bin: i32,
    /// Interpolated range, m.
    pub range_m: f32,
    /// Interpolated radial velocity, m/s (positive away).
    pub velocity_mps: f32,
    /// Azimuth, degrees.
    pub azimuth_deg: Option<f32>,
    /// Level over the CFAR noise estimate, dB.
    pub snr_db: f32,
}

/// Summary of one frame.
#[derive(Clone, Debug, Serialize)]
pub struct FrameReport {
    /// Frame number.
    pub frame: u32,
    /// Strongest range-profile peaks, strongest first.
    pub range_peaks: Vec<RangePeak>,
    /// Moving targets, strongest first.
    pub moving_targets: Vec<MovingTarget>,
}

/// Summary of a capture.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// The file summarized.
    pub source: String,
    /// Geometry.
    pub config: ConfigSummary,
    /// Per frame.
    pub frames: Vec<FrameReport>,
}

/// How many peaks and targets to report per frame.
const TOP: usize = 5;

fn config_summary(c: &RadarConfig, elements: usize) -> ConfigSummary {
    let (nr, nd) = (c.range_fft_len(), c.doppler_fft_len());
    ConfigSummary {
        frames: c.frames,
        range_fft_len: nr,
        doppler_fft_len: nd,
        range_resolution_m: c.range_bin_size(nr),
        max_range_m: c.max_range(),
        velocity_resolution_mps: c.doppler_to_velocity(1.0, nd),
        max_velocity_mps: c.max_velocity(),
        virtual_channels: c.channels(),
        virtual_elements: elements,
    }
}

fn db(x: f32) -> f32 {
    20.0 * x.max(1e-12).log10()
}

/// Summarizes every frame of `file` (Hann windows on both axes).
///
/// # Errors
/// [`InputError`] if a frame cannot be read or processed.
pub fn summarize(file: &mut RadarFile) -> Result<Summary, InputError> {
    let config = file.config().clone();
    let options = FrameOptions {
        range_window: WindowKind::Hann,
        doppler_window: WindowKind::Hann,
        remove_static: true,
    };
    let path = file.path().to_owned();
    let to_err = |e: crate::ProcessError| InputError::file(&path, e.to_string());
    let mut proc = FrameProcessor::new(&config, options).map_err(to_err)?;
    let mut samples = Vec::new();
    let mut frames = Vec::new();
    for f in 0..config.frames {
        file.read_frame(f, &mut samples)?;
        let spectra = proc.process(&samples).map_err(to_err)?;
        let (nr, nd) = (spectra.range_bins, spectra.doppler_len);
        let profile = &spectra.range_profile;
        let mut peaks: Vec<usize> = (0..nr).filter(|&k| is_local_max(profile, k)).collect();
        peaks.sort_by(|&a, &b| profile[b].total_cmp(&profile[a]));
        let mut range_peaks = Vec::new();
        for &k in peaks.iter().take(TOP) {
            let off = if k > 0 && k + 1 < nr {
                quadratic_offset(db(profile[k - 1]), db(profile[k]), db(profile[k + 1]))
            } else {
                0.0
            };
            let az = proc.azimuth_at(k, 0, false).map_err(to_err)?;
            range_peaks.push(RangePeak {
                bin: k,
                range_m: config.bin_to_range(k as f32 + off, nr),
                level_dbfs: db(profile[k] / config.adc_samples as f32),
                azimuth_deg: az.map(f32::to_degrees),
            });
        }
        let map = &spectra.range_doppler;
        let axis = Cfar {
            guard: 2,
            train: 8,
            scale: 4.0,
            kind: CfarKind::OrderedStatistic { rank: 0.75 },
            boundary: Boundary::Truncate,
        };
        let cfar = Cfar2d {
            rows: axis,
            cols: Cfar {
                guard: 1,
                train: 4,
                boundary: Boundary::Wrap,
                ..axis
            },
        };
        let mut hits = Vec::new();
        if nd > 1 {
            cfar.detect(map, nr, nd, |d| hits.push(d))
                .map_err(|e| InputError::file(file.path(), e.to_string()))?;
        }
        let is_peak = |i: usize| {
            let (r, d) = (i / nd, i % nd);
            let v = map[i];
            (r.saturating_sub(1)..=(r + 1).min(nr - 1))
                .all(|rr| (0..3).all(|k| map[rr * nd + (d + nd + k - 1) % nd] <= v))
        };
        hits.retain(|h| is_peak(h.index));
        hits.sort_by(|a, b| (b.value / b.threshold).total_cmp(&(a.value / a.threshold)));
        let mut moving_targets = Vec::new();
        for h in hits.iter().take(TOP) {
            let (r, d) = (h.index / nd, h.index % nd);
            let at = |rr: usize, dd: usize| db(map[rr * nd + dd % nd]);
            let r_off = if r > 0 && r + 1 < nr {
                quadratic_offset(at(r - 1, d), at(r, d), at(r + 1, d))
            } else {
                0.0
            };
            let d_off = quadratic_offset(at(r, d + nd - 1), at(r, d), at(r, d + 1));
            let doppler_bin = signed_bin(d, nd);
            let az = proc.azimuth_at(r, d, true).map_err(to_err)?;
            moving_targets.push(MovingTarget {
                range_bin: r,
                doppler_bin,
                range_m: config.bin_to_range(r as f32 + r_off, nr),
                velocity_mps: config.doppler_to_velocity(doppler_bin as f32 + d_off, nd),
                azimuth_deg: az.map(f32::to_degrees),
                snr_db: db(h.value / h.threshold) + db(axis.scale),
            });
        }
        frames.push(FrameReport {
            frame: f,
            range_peaks,
            moving_targets,
        });
    }
    Ok(Summary {
        source: file.path().display().to_string(),
        config: config_summary(&config, proc.array().elements()),
        frames,
    })
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let c = &self.config;
        writeln!(f, "{}", self.source)?;
        writeln!(
            f,
            "  {} frame(s); range {:.3} m/bin to {:.1} m ({}-pt FFT); velocity {:.3} m/s/bin to ±{:.2} m/s ({}-pt); {} virtual channels at {} positions",
            c.frames,
            c.range_resolution_m,
            c.max_range_m,
            c.range_fft_len,
            c.velocity_resolution_mps,
            c.max_velocity_mps,
            c.doppler_fft_len,
            c.virtual_channels,
            c.virtual_elements
        )?;
        let deg = |a: Option<f32>| a.map_or("    —".to_owned(), |a| format!("{a:+6.1}°"));
        for fr in &self.frames {
            writeln!(f, "frame {}", fr.frame)?;
            writeln!(
                f,
                "  range-profile peaks (Hann; bins 0–1 are near-DC leakage):"
            )?;
            writeln!(
                f,
                "    {:>5} {:>9} {:>9} {:>8}",
                "bin", "range m", "dBFS", "azimuth"
            )?;
            for p in &fr.range_peaks {
                writeln!(
                    f,
                    "    {:>5} {:>9.3} {:>9.1} {:>8}",
                    p.bin,
                    p.range_m,
                    p.level_dbfs,
                    deg(p.azimuth_deg)
                )?;
            }
            writeln!(
                f,
                "  moving targets (static clutter removed, OS-CFAR on range–Doppler):"
            )?;
            if fr.moving_targets.is_empty() {
                writeln!(f, "    none")?;
            } else {
                writeln!(
                    f,
                    "    {:>5} {:>7} {:>9} {:>9} {:>8} {:>7}",
                    "bin", "doppler", "range m", "v m/s", "azimuth", "SNR dB"
                )?;
            }
            for t in &fr.moving_targets {
                writeln!(
                    f,
                    "    {:>5} {:>+7} {:>9.3} {:>+9.3} {:>8} {:>7.1}",
                    t.range_bin,
                    t.doppler_bin,
                    t.range_m,
                    t.velocity_mps,
                    deg(t.azimuth_deg),
                    t.snr_db
                )?;
            }
        }
        Ok(())
    }
}
