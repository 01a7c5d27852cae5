//! Physical units and bin indices, so that a range is never mistaken for a bin.

/// A distance in metres.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct Meters(pub f32);

/// A radial velocity in metres per second, positive away from the radar.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct MetersPerSecond(pub f32);

/// An angle in radians; azimuth is positive to the right (+x).
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct Radians(pub f32);

impl Radians {
    /// The angle in degrees.
    pub fn to_degrees(self) -> f32 {
        self.0.to_degrees()
    }
}

/// A range FFT bin, possibly fractional after peak interpolation.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct RangeBin(pub f32);

/// A signed Doppler bin (after `fftshift`: `-N/2..N/2`), possibly fractional.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct DopplerBin(pub f32);

/// A signed azimuth FFT bin (after `fftshift`: `-N/2..N/2`), possibly fractional.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct AzimuthBin(pub f32);

/// Maps FFT index `k` of an `n`-point FFT to its signed bin in `-n/2..n/2`.
pub const fn signed_bin(k: usize, n: usize) -> i32 {
    if k < n / 2 {
        k as i32
    } else {
        k as i32 - n as i32
    }
}
