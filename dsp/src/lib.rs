//! Fixed-point radar signal processing for the Metamoran edge module.
//!
//! `#![no_std]`, no allocation, deterministic: the same bits on x86 and on the Cortex-M7.
//! The modules follow the pipeline:
//!
//! * [`capture`]: DCA1000 sample layouts → complex Q15 samples;
//! * [`range`]: windowed range FFT per (chirp, RX), streaming as chirps arrive;
//! * [`array`](mod@array): the TDM-MIMO virtual array;
//! * [`clutter`]: static clutter removal, the frame's strong reflectors, SIC;
//! * [`doppler`]: Doppler FFT and the range–Doppler map;
//! * [`azimuth`]: azimuth FFT over the virtual array and steering-vector beamforming;
//! * [`detect`]: CA/OS-CFAR and peak interpolation;
//! * [`points`]: range–Doppler–azimuth–elevation point clouds;
//! * [`response`]: the point-reflector response model (array geometry, range kernel, steering)
//!   that SIC and the search share;
//! * [`search`]: contour templates and the depth search;
//! * [`ego`]: the radar's and the vehicle's velocity from Doppler (dense radar mapping);
//! * [`pipeline`]: the module's per-frame job (sums → spectra → SIC → search per object);
//! * [`wire`]: the authenticated telemetry link between the module and the host;
//!
//! on top of [`fixed`] (Q15/Q31 and complex values), [`fft`], [`window`], [`trig`] and the
//! radar geometry in [`config`] and [`units`].
#![no_std]
#![deny(missing_docs)]

#[cfg(test)]
extern crate std;

pub mod array;
pub mod azimuth;
pub mod capture;
pub mod clutter;
pub mod config;
pub mod detect;
pub mod doppler;
pub mod ego;
pub mod fft;
pub mod fixed;
pub mod pipeline;
pub mod points;
pub mod range;
pub mod response;
pub mod search;
pub mod trig;
pub mod units;
pub mod window;
pub mod wire;
