//! The mapping report (the paper's Tables 1–3 for one bundle): ego-velocity error, density
//! growth, MAE and RMSE of each depth image against the lidar truth, each image's point
//! accuracy (median distance to the nearest lidar point), and the network's frame rate. Its
//! JSON is what `metamoran map --json` prints.
//!
//! Errors are taken over three pixel sets ([`Pixels`]): where the image and the lidar both have
//! a depth (`mae_m`, `rmse_m`), every lidar pixel (KITTI's depth-completion convention: an empty
//! image pixel counts as 0 m), and every pixel of the image's own (a return where the lidar has
//! none is scored against the lidar's range limit).

use super::depth::{self, Completion, DepthImages};
use super::odometry::{self, Odometry};
use super::submap::density_growth;
use crate::MapError;
use metamoran_dsp::ego::Mount;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// Timed inferences behind [`MapReport::network_fps`] (after one untimed).
pub const FPS_RUNS: u32 = 5;

/// One figure per depth image of the last frame, m; `null` where its pixel set is empty (or,
/// for `network`, without a network).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ImageErrors {
    /// The radar frame's depth image.
    pub frame: Option<f64>,
    /// The submap's.
    pub submap: Option<f64>,
    /// The submap completed by IP-Basic.
    pub ip_basic: Option<f64>,
    /// The submap completed by the network.
    pub network: Option<f64>,
}

/// A bundle's mapping figures.
#[derive(Clone, Debug, Serialize)]
pub struct MapReport {
    /// Mean ego-velocity error norm over the frames, m/s (needs truth).
    pub ego_velocity_error_mps: Option<f64>,
    /// Filled pixels of the last frame's submap over those of the frame alone.
    pub density_growth_factor: Option<f64>,
    /// Filled pixels of the network's image over those of the frame alone (the paper's "more
    /// than 50×" claim), or `null` without a network.
    pub network_density_growth_factor: Option<f64>,
    /// Mean absolute depth error against the lidar truth over the pixels both fill
    /// ([`Pixels::Both`]), m (needs `lidar/`).
    pub mae_m: Option<ImageErrors>,
    /// Root-mean-square depth error against the lidar truth over the same pixels, m.
    pub rmse_m: Option<ImageErrors>,
    /// Point accuracy (the paper's): the median distance from each image's points (its
    /// pixels' centre rays at their ranges) to the nearest lidar point, m; distances over
    /// [`ACCURACY_CAP_M`] count as that.
    pub point_accuracy_m: Option<ImageErrors>,
    /// MAE and RMSE over every pixel the lidar image fills, an empty image pixel counting as
    /// a depth of 0 m ([`Pixels::Lidar`]).
    pub lidar_pixels: Option<PixelErrors>,
    /// MAE and RMSE over every pixel the image fills, a pixel the lidar leaves empty scored
    /// against its range limit ([`Pixels::Own`]).
    pub own_pixels: Option<PixelErrors>,
    /// Network inferences per second on this machine (mean of [`FPS_RUNS`] on the last
    /// submap), or `null` without a network.
    pub network_fps: Option<f64>,
}

/// Largest nearest-lidar distance [`point_accuracy`] resolves, m: the median is exact while
/// more than half the points are nearer.
pub const ACCURACY_CAP_M: f64 = 3.0;

/// The median distance from each of `points` to the nearest of `lidar` (m, capped at
/// [`ACCURACY_CAP_M`]); `None` without points or lidar points. Lidar points are hashed in
/// 1 m cells: O((points + lidar) · 7³).
pub fn point_accuracy(points: &[[f64; 3]], lidar: &[[f64; 3]]) -> Option<f64> {
    if points.is_empty() || lidar.is_empty() {
        return None;
    }
    let cell = |p: &[f64; 3]| p.map(|v| v.floor() as i64);
    let mut grid: std::collections::HashMap<[i64; 3], Vec<[f64; 3]>> =
        std::collections::HashMap::new();
    for q in lidar {
        grid.entry(cell(q)).or_default().push(*q);
    }
    let reach = ACCURACY_CAP_M.ceil() as i64;
    let mut d: Vec<f64> = points
        .iter()
        .map(|p| {
            let c = cell(p);
            let mut best = ACCURACY_CAP_M;
            for dx in -reach..=reach {
                for dy in -reach..=reach {
                    for dz in -reach..=reach {
                        for q in grid
                            .get(&[c[0] + dx, c[1] + dy, c[2] + dz])
                            .into_iter()
                            .flatten()
                        {
                            let e = ((p[0] - q[0]).powi(2)
                                + (p[1] - q[1]).powi(2)
                                + (p[2] - q[2]).powi(2))
                            .sqrt();
                            best = best.min(e);
                        }
                    }
                }
            }
            best
        })
        .collect();
    d.sort_by(f64::total_cmp);
    let n = d.len();
    Some(if n % 2 == 1 {
        d[n / 2]
    } else {
        (d[n / 2 - 1] + d[n / 2]) / 2.0
    })
}

/// Each image's [`point_accuracy`] against the lidar image's points, if there is one.
pub fn accuracy(images: &DepthImages) -> Option<ImageErrors> {
    let lidar = images.lidar.as_ref()?.points();
    let a = |img: Option<&super::cylinder::DepthImage>| {
        img.and_then(|i| point_accuracy(&i.points(), &lidar))
    };
    Some(ImageErrors {
        frame: a(Some(&images.frame)),
        submap: a(Some(&images.submap)),
        ip_basic: a(Some(&images.ip_basic)),
        network: a(images.network.as_ref()),
    })
}

/// The pixels a depth image's error is taken over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pixels {
    /// Where the image and the lidar image both have a depth: how right the image is where it
    /// says something.
    Both,
    /// Every pixel the lidar fills; an empty image pixel counts as 0 m, so its error is the
    /// lidar's depth (KITTI's depth-completion convention): coverage and accuracy in one.
    Lidar,
    /// Every pixel the image fills; where the lidar has no return within its range limit
    /// ([`metamoran_bundle::lidar::RANGE_M`]) the image is scored against that limit, so a
    /// return where there is nothing near is an error.
    Own,
}

/// MAE and RMSE of each depth image over one [`Pixels`] set.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct PixelErrors {
    /// Mean absolute error, m.
    pub mae_m: ImageErrors,
    /// Root-mean-square error, m.
    pub rmse_m: ImageErrors,
}

/// (MAE, RMSE) of `image` against `truth` (row-major ranges, m, 0 = empty) over `pixels`;
/// `None` where the set is empty. O(pixels).
///
/// ```
/// use metamoran_map::report::{Pixels, image_errors};
/// let image = [10.0, 0.0, 30.0, 0.0];
/// let lidar = [11.0, 20.0, 0.0, 0.0];
/// assert_eq!(image_errors(&image, &lidar, Pixels::Both), Some((1.0, 1.0)));
/// // The empty second pixel counts as 0 m: errors 1 and 20.
/// assert_eq!(image_errors(&image, &lidar, Pixels::Lidar).unwrap().0, 10.5);
/// // The third pixel has no lidar return within 80 m: errors 1 and 50.
/// assert_eq!(image_errors(&image, &lidar, Pixels::Own).unwrap().0, 25.5);
/// ```
pub fn image_errors(image: &[f32], truth: &[f32], pixels: Pixels) -> Option<(f64, f64)> {
    let limit = metamoran_bundle::lidar::RANGE_M;
    let d: Vec<f64> = image
        .iter()
        .zip(truth)
        .filter_map(|(&a, &b)| {
            let (a, b) = (f64::from(a), f64::from(b));
            match pixels {
                Pixels::Both => (a > 0.0 && b > 0.0).then_some(a - b),
                Pixels::Lidar => (b > 0.0).then_some(a.max(0.0) - b),
                Pixels::Own => (a > 0.0).then_some(a - if b > 0.0 { b } else { limit }),
            }
        })
        .collect();
    (!d.is_empty()).then(|| {
        let n = d.len() as f64;
        (
            d.iter().map(|e| e.abs()).sum::<f64>() / n,
            (d.iter().map(|e| e * e).sum::<f64>() / n).sqrt(),
        )
    })
}

/// (MAE, RMSE) of each image against the lidar image over `pixels`, if there is a lidar image.
pub fn errors(images: &DepthImages, pixels: Pixels) -> Option<PixelErrors> {
    let truth = &images.lidar.as_ref()?.range_m;
    let e = |img: Option<&super::cylinder::DepthImage>| {
        img.and_then(|i| image_errors(&i.range_m, truth, pixels))
    };
    let all = [
        e(Some(&images.frame)),
        e(Some(&images.submap)),
        e(Some(&images.ip_basic)),
        e(images.network.as_ref()),
    ];
    let pick = |k: fn((f64, f64)) -> f64| ImageErrors {
        frame: all[0].map(k),
        submap: all[1].map(k),
        ip_basic: all[2].map(k),
        network: all[3].map(k),
    };
    Some(PixelErrors {
        mae_m: pick(|e| e.0),
        rmse_m: pick(|e| e.1),
    })
}

/// Maps the bundle in `dir` (radar on `mount`): odometry, the last frame's depth images (the
/// network's too, if given) and the report.
///
/// # Errors
/// [`MapError`] naming the file and field of a bad bundle, or the network's.
pub fn run(
    dir: &Path,
    mount: &Mount,
    network: Option<Completion>,
) -> Result<(MapReport, Odometry, Option<DepthImages>), MapError> {
    run_with(dir, mount, network, &depth::SubmapOptions::default())
}

/// [`run`] with the submap and the depth images made as `options` say ([`depth::last_with`]).
///
/// # Errors
/// As [`run`].
pub fn run_with(
    dir: &Path,
    mount: &Mount,
    network: Option<Completion>,
    options: &depth::SubmapOptions,
) -> Result<(MapReport, Odometry, Option<DepthImages>), MapError> {
    let odometry = odometry::run_with(dir, mount, options.cloud())?;
    let images = depth::last_with(dir, &odometry, network, options)?;
    let network_fps = match (network, &images) {
        (Some(n), Some(im)) => {
            let start = Instant::now();
            for _ in 0..FPS_RUNS {
                n(&im.submap.range_m)?;
            }
            Some(f64::from(FPS_RUNS) / start.elapsed().as_secs_f64())
        }
        _ => None,
    };
    let errors = |pixels| images.as_ref().and_then(|im| errors(im, pixels));
    let both = errors(Pixels::Both);
    let report = MapReport {
        ego_velocity_error_mps: odometry.ego_velocity_error_mps,
        density_growth_factor: images
            .as_ref()
            .and_then(|im| density_growth(&im.frame, &im.submap)),
        network_density_growth_factor: images
            .as_ref()
            .and_then(|im| density_growth(&im.frame, im.network.as_ref()?)),
        mae_m: both.map(|e| e.mae_m),
        rmse_m: both.map(|e| e.rmse_m),
        point_accuracy_m: images.as_ref().and_then(accuracy),
        lidar_pixels: errors(Pixels::Lidar),
        own_pixels: errors(Pixels::Own),
        network_fps,
    };
    Ok((report, odometry, images))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_accuracy_is_the_median_nearest_lidar_distance() {
        let lidar = [[0.0, 0.0, 10.0], [5.0, 0.0, 10.0], [0.0, 0.0, 30.0]];
        // 0.1 m, 0.2 m and 0.4 m from their nearest lidar points, and one beyond the cap.
        let points = [
            [0.1, 0.0, 10.0],
            [5.0, 0.2, 10.0],
            [0.0, 0.0, 29.6],
            [20.0, 0.0, 50.0],
        ];
        let m = point_accuracy(&points, &lidar).unwrap();
        assert!((m - 0.3).abs() < 1e-9, "{m}");
        let m = point_accuracy(&points[..3], &lidar).unwrap();
        assert!((m - 0.2).abs() < 1e-9, "{m}");
        assert_eq!(point_accuracy(&[], &lidar), None);
    }
}
