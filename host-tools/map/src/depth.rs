//! The depth images of a frame (dense radar mapping, Sec. 3.3 and Tables 1–3): the frame's own
//! static points, its submap (every frame so far moved into it by the odometry), the submap
//! completed by IP-Basic and, given one, by the network, and the lidar-like truth's image
//! where the bundle has it.

use super::cylinder::{DepthImage, Visibility};
use super::odometry::Odometry;
use super::submap::{Keep, accumulate_keeping};
use crate::MapError;
use metamoran_dsp::points::{CloudOptions, Peaks, Screen};
use std::path::Path;

/// A network that completes a submap's depth image: row-major ranges (m, 0 = empty) in, the
/// dense image out, or a message naming the model. See `metamoran_vision::RadarHr`.
pub type Completion<'a> = &'a dyn Fn(&[f32]) -> Result<Vec<f32>, MapError>;

/// How a frame's submap and images are made. The default keeps every point and cuts nothing
/// (the paper's submap).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SubmapOptions {
    /// Which earlier frames' points the submap keeps.
    pub keep: Keep,
    /// Whether the frame's and the submap's images are cut to what is visible, and how.
    pub visibility: Option<Visibility>,
    /// Which detections become the frames' points, for odometry and submaps alike (odometry
    /// runs with [`Self::cloud`]).
    pub peaks: Peaks,
    /// A looser test of the cells the detector misses, for odometry and submaps alike.
    pub screen: Option<Screen>,
}

impl SubmapOptions {
    /// The mapping detector for these options' `peaks` ([`crate::cloud::options`]) with their
    /// `screen`: what odometry runs with for these submaps.
    pub fn cloud(&self) -> CloudOptions {
        CloudOptions {
            screen: self.screen,
            ..crate::cloud::options(self.peaks)
        }
    }
}

/// One frame's depth images.
#[derive(Clone, Debug)]
pub struct DepthImages {
    /// The frame's own static points.
    pub frame: DepthImage,
    /// Its submap's.
    pub submap: DepthImage,
    /// The submap completed by IP-Basic.
    pub ip_basic: DepthImage,
    /// The submap completed by the network, if one was given.
    pub network: Option<DepthImage>,
    /// The lidar-like truth's, if the bundle has `lidar/`.
    pub lidar: Option<DepthImage>,
    /// The submap's points (radar frame of this frame, m).
    pub submap_points: Vec<[f64; 3]>,
}

/// The frame's and the submap's images of frame `k` of `odometry` (submap over frames `0..=k`).
///
/// # Panics
/// If `k` is not a frame of `odometry`.
pub fn submap(odometry: &Odometry, k: usize) -> (DepthImage, DepthImage, Vec<[f64; 3]>) {
    submap_with(odometry, k, &SubmapOptions::default())
}

/// [`submap`] made as `options` say.
///
/// # Panics
/// If `k` is not a frame of `odometry`.
pub fn submap_with(
    odometry: &Odometry,
    k: usize,
    options: &SubmapOptions,
) -> (DepthImage, DepthImage, Vec<[f64; 3]>) {
    let points = accumulate_keeping(&odometry.tracked, 0, k, options.keep);
    let vis = |img: DepthImage| match &options.visibility {
        Some(v) => img.visible(v),
        None => img,
    };
    (
        vis(DepthImage::project(odometry.tracked[k].1.iter().copied())),
        vis(DepthImage::project(points.iter().copied())),
        points,
    )
}

/// The lidar truth's depth image of frame `k` of the bundle in `dir`, if it has one.
///
/// # Errors
/// [`MapError`] naming a lidar file that cannot be read.
pub fn lidar(dir: &Path, k: u32) -> Result<Option<DepthImage>, MapError> {
    let file = metamoran_bundle::lidar::path(dir, k);
    if !file.exists() {
        return Ok(None);
    }
    let points = metamoran_bundle::lidar::read(&file)?;
    Ok(Some(DepthImage::project(points)))
}

/// All depth images of the last frame of `odometry` (`None` for a bundle without frames).
///
/// # Errors
/// A lidar file that cannot be read, or the network's message.
pub fn last(
    dir: &Path,
    odometry: &Odometry,
    network: Option<Completion>,
) -> Result<Option<DepthImages>, MapError> {
    last_with(dir, odometry, network, &SubmapOptions::default())
}

/// [`last`] with the submap and the images made as `options` say, before completion.
///
/// # Errors
/// A lidar file that cannot be read, or the network's message.
pub fn last_with(
    dir: &Path,
    odometry: &Odometry,
    network: Option<Completion>,
    options: &SubmapOptions,
) -> Result<Option<DepthImages>, MapError> {
    let Some(k) = odometry.tracked.len().checked_sub(1) else {
        return Ok(None);
    };
    let (frame, submap, submap_points) = submap_with(odometry, k, options);
    let ip_basic = DepthImage {
        range_m: super::ip_basic::complete(&submap.range_m),
    };
    let network = network
        .map(|n| n(&submap.range_m).map(|range_m| DepthImage { range_m }))
        .transpose()?;
    Ok(Some(DepthImages {
        lidar: lidar(dir, k as u32)?,
        frame,
        submap,
        ip_basic,
        network,
        submap_points,
    }))
}

/// Training pairs for the network: for every frame with lidar truth, `(frame, submap image,
/// lidar image)`, the submap made as `options` say.
///
/// # Errors
/// A lidar file that cannot be read.
pub fn training_pairs(
    dir: &Path,
    odometry: &Odometry,
    options: &SubmapOptions,
) -> Result<Vec<(u32, DepthImage, DepthImage)>, MapError> {
    let mut pairs = Vec::new();
    for k in 0..odometry.tracked.len() {
        if let Some(truth) = lidar(dir, k as u32)? {
            pairs.push((k as u32, submap_with(odometry, k, options).1, truth));
        }
    }
    Ok(pairs)
}
