//! Units: every physical quantity in the public API is a plain float whose name ends in its unit
//! (`depth_m`, `bin_m`, `radial_velocity_mps`, `yaw_rad`, `slope_hz_per_s`, `chirp_period_s`;
//! `_bins` for FFT bins), as the wire messages and the JSON documents name them; fixed-point
//! formats are types (`Q15`, `Q31`, `CQ15`). One style, so a reader never has to ask whether a
//! number is wrapped.
//!
//! This module keeps the one index map every stage shares.

/// Maps FFT index `k` of an `n`-point FFT to its signed bin in `-n/2..n/2`.
pub const fn signed_bin(k: usize, n: usize) -> i32 {
    if k < n / 2 {
        k as i32
    } else {
        k as i32 - n as i32
    }
}
