//! The end-to-end tests, one module per concern (each module's `//!` says what it checks).
//! They share one binary so the host stack is linked once; run one module with
//! `cargo test -p metamoran-e2e --test e2e MODULE::`.

mod baselines;
mod camera_models;
mod demo;
mod edge;
mod fft_vs_cmsis;
mod inspect;
mod ip_basic;
mod metamoran;
mod mqtt;
mod nats;
mod qemu;
mod radarhr;
mod real_captures;
mod site;
mod ti_calibration;
mod tracking;
mod web;
