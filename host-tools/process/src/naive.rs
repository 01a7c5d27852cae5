//! The naive radar–camera baseline (Metamoran, Sec. V): the mask's azimuth span bounds standard
//! FMCW range–azimuth processing, and the strongest reflector inside the span is the object.

use super::ObjectEstimate;
use super::camera_points::CameraObject;
use crate::ProcessError;
use crate::frame::FrameProcessor;
use metamoran_dsp::config::azimuth_bin_to_angle;
use metamoran_dsp::detect::quadratic_offset;
use metamoran_dsp::units::signed_bin;

/// The range–azimuth map of the static scene: `|azimuth spectrum|` per range bin.
pub struct RangeAzimuth {
    /// Row-major `[range bin][azimuth index]`, natural FFT order along azimuth.
    pub map: Vec<f32>,
    /// Range bins.
    pub bins: usize,
    /// Azimuth FFT length.
    pub az_len: usize,
}

impl RangeAzimuth {
    /// Computes the map of the last frame processed by `proc` (Doppler index 0, no clutter removal).
    ///
    /// # Errors
    /// [`ProcessError`] if processing fails.
    pub fn new(proc: &mut FrameProcessor, bins: usize) -> Result<Self, ProcessError> {
        let az_len = proc.azimuth_len();
        let mut map = Vec::with_capacity(bins * az_len);
        for b in 0..bins {
            map.extend(proc.azimuth_profile(b, 0, false)?);
        }
        Ok(Self { map, bins, az_len })
    }

    /// Azimuth indices whose direction lies in `[lo, hi]` (radians); the nearest one if none.
    pub fn indices_in(&self, lo: f64, hi: f64) -> Vec<usize> {
        let angle = |k: usize| {
            azimuth_bin_to_angle(signed_bin(k, self.az_len) as f32, self.az_len).map(|a| a as f64)
        };
        let inside: Vec<usize> = (0..self.az_len)
            .filter(|&k| angle(k).is_some_and(|a| a >= lo && a <= hi))
            .collect();
        if !inside.is_empty() {
            return inside;
        }
        let mid = (lo + hi) / 2.0;
        (0..self.az_len)
            .filter(|&k| angle(k).is_some())
            .min_by(|&a, &b| {
                (angle(a).unwrap_or(9.0) - mid)
                    .abs()
                    .total_cmp(&(angle(b).unwrap_or(9.0) - mid).abs())
            })
            .into_iter()
            .collect()
    }
}

/// The naive estimate for one object.
pub fn estimate(ra: &RangeAzimuth, proc: &FrameProcessor, obj: &CameraObject) -> ObjectEstimate {
    let Some((lo, hi)) = obj.span else {
        return ObjectEstimate::missed(obj);
    };
    let cols = ra.indices_in(lo, hi);
    let mut best = (0.0f32, 0usize, 0usize);
    for b in 1..ra.bins {
        for &k in &cols {
            let v = ra.map[b * ra.az_len + k];
            if v > best.0 {
                best = (v, b, k);
            }
        }
    }
    let (_, b, k) = best;
    if b == 0 {
        return ObjectEstimate::missed(obj);
    }
    let at = |bb: usize| 20.0 * ra.map[bb * ra.az_len + k].max(1e-30).log10();
    let off = if b + 1 < ra.bins {
        quadratic_offset(at(b - 1), at(b), at(b + 1))
    } else {
        0.0
    };
    let c = proc.config();
    let depth = c.bin_to_range(b as f32 + off, ra.bins) as f64;
    let azimuth =
        azimuth_bin_to_angle(signed_bin(k, ra.az_len) as f32, ra.az_len).map(|a| a as f64);
    ObjectEstimate::found(obj, depth, azimuth, obj.anchored(depth))
}
