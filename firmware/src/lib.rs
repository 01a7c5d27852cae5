//! The Metamoran edge module's firmware logic, portable so that it also runs in host tests.
//!
//! * [`selftest`]: deterministic DSP workloads whose output hashes the host recomputes, proving
//!   the module computes the same bits as x86;
//! * [`bench_scene`]: the cascade-86, 4-object frame of the instruction budget;
//! * [`workload`]: the inputs of those workloads and of the instruction-count benchmarks;
//! * [`module`]: the module's loop (link → hints, capture → pipeline → results), generic over
//!   the hardware traits of [`capture`], [`clock`] and `embedded-io`;
//! * [`provisioned`]: the device key built into the image;
//! * `host_mock` (feature `host-mock`): a byte-queue serial line and a seeded nonce source
//!   for driving the module on a host;
//! * [`uart`]: the CMSDK UART driver of the QEMU board's link;
//! * [`log`]: the event log (`defmt` on the target);
//! * `board` (embedded targets only): the QEMU mps2-an500 timer, semihosting exit, fault and
//!   panic handlers, and the semihosting capture file.
#![no_std]
#![deny(missing_docs)]

pub mod bench_scene;
#[cfg(target_os = "none")]
pub mod board;
pub mod capture;
pub mod clock;
#[cfg(any(test, feature = "host-mock"))]
pub mod host_mock;
pub mod log;
pub mod module;
pub mod provisioned;
pub mod selftest;
pub mod uart;
pub mod workload;

#[cfg(target_os = "none")]
mod defmt_logger;
