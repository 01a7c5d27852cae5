//! An object's contour as the camera sees it: azimuths and relative ranges.

use heapless::Vec;

/// Most contour points (the telemetry carries at most this many per object).
pub const MAX_CONTOUR: usize = 32;

/// One point of a contour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContourPoint {
    /// sin(azimuth).
    pub sin_az: f32,
    /// Range relative to the contour's closest point, m (≥ 0).
    pub rel_range_m: f32,
}

/// A contour of at most [`MAX_CONTOUR`] points, normalized so the closest point has range 0.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Contour {
    points: Vec<ContourPoint, MAX_CONTOUR>,
}

impl Contour {
    /// Builds a contour from `(sin azimuth, range)` pairs, keeping at most [`MAX_CONTOUR`]
    /// (evenly spaced) and dropping non-finite ones; ranges become relative to the smallest.
    pub fn new(points: impl IntoIterator<Item = (f32, f32)>) -> Self {
        let mut all: Vec<(f32, f32), 256> = Vec::new();
        for p in points
            .into_iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite() && p.0.abs() <= 1.0)
        {
            if all.push(p).is_err() {
                break;
            }
        }
        let min = all.iter().map(|p| p.1).fold(f32::INFINITY, f32::min);
        let step = all.len().div_ceil(MAX_CONTOUR).max(1);
        let mut c = Self::default();
        for &(s, r) in all.iter().step_by(step) {
            let _ = c.points.push(ContourPoint {
                sin_az: s,
                rel_range_m: r - min,
            });
        }
        c
    }

    /// The points.
    pub fn points(&self) -> &[ContourPoint] {
        &self.points
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The contour with each sin(azimuth) rounded to a multiple of `step` (the search then
    /// beamforms once per distinct direction).
    pub fn snapped(&self, step: f32) -> Self {
        let mut c = self.clone();
        if step > 0.0 {
            for p in &mut c.points {
                p.sin_az = (libm::roundf(p.sin_az / step) * step).clamp(-1.0, 1.0);
            }
        }
        c
    }

    /// Largest relative range, m.
    pub fn depth_extent(&self) -> f32 {
        self.points
            .iter()
            .map(|p| p.rel_range_m)
            .fold(0.0, f32::max)
    }
}
