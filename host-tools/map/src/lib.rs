//! Dense radar mapping from a moving platform (the second paper), built up step by step:
//! [`cloud`] turns each frame into a radar point cloud, [`odometry`] estimates the radar's and
//! the vehicle's velocity from its Doppler (RANSAC, `metamoran_dsp::ego`) and integrates the poses
//! (`metamoran_bundle::pose`), [`submap`] accumulates the static points of past frames into the current one,
//! [`cylinder`] projects points into the paper's cylindrical depth images and [`ip_basic`]
//! completes them by morphology; [`depth`] builds a frame's images (the network's too, given
//! one), `metamoran_bundle::lidar` is the dense truth they are measured against and [`report`] the figures.

pub mod cloud;
pub mod cylinder;
pub mod depth;
mod error;
pub mod ip_basic;
pub mod network;
pub mod odometry;
pub mod report;
pub mod submap;

pub use error::MapError;
