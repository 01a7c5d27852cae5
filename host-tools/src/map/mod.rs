//! Dense radar mapping from a moving platform (the second paper), built up step by step:
//! [`cloud`] turns each frame into a radar point cloud, [`odometry`] estimates the radar's and
//! the vehicle's velocity from its Doppler (RANSAC, `dsp::ego`) and checks it against the truth.

pub mod cloud;
pub mod odometry;
