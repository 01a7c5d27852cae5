//! Benchmarks reported by `metamoran bench`: figures measured in one run against named baselines.

pub mod budget;
pub mod cmsis;
pub mod dca1000;
pub mod fft;
pub mod m7;
pub mod network;
pub mod search;
pub mod site;
