//! Deterministic inputs: the same values on every platform.

use metamoran_dsp::fixed::{CQ15, CQ31, Complex, Q15, Q31};

/// A 32-bit linear congruential generator (Numerical Recipes constants).
#[derive(Clone, Debug)]
pub struct Lcg(pub u32);

impl Lcg {
    /// The next value, uniform over `u32`.
    pub fn next_u32(&mut self) -> u32 {
        self.0 = self.0.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        self.0
    }

    /// The next value, uniform in `[-amplitude, amplitude)` of Q15 full scale.
    pub fn next_q15(&mut self, amplitude: Q15) -> Q15 {
        let u = (self.next_u32() >> 16) as i16 as i32; // uniform over i16
        Q15(((u * amplitude.0 as i32) >> 15) as i16)
    }
}

/// Fills `buf` with complex uniform noise of the given amplitude.
pub fn noise_q15(seed: u32, amplitude: Q15, buf: &mut [CQ15]) {
    let mut g = Lcg(seed);
    for z in buf {
        *z = Complex::new(g.next_q15(amplitude), g.next_q15(amplitude));
    }
}

/// Fills `buf` with complex uniform noise of the given amplitude, at Q31 resolution.
pub fn noise_q31(seed: u32, amplitude: Q15, buf: &mut [CQ31]) {
    let mut g = Lcg(seed);
    for z in buf {
        let mut part = || {
            let u = g.next_u32() as i32 as i64;
            Q31(((u * amplitude.0 as i64) >> 15) as i32)
        };
        *z = Complex::new(part(), part());
    }
}

/// FNV-1a over little-endian bytes: a compact fingerprint of a workload's output.
#[derive(Clone, Copy, Debug)]
pub struct Fnv(pub u32);

impl Default for Fnv {
    fn default() -> Self {
        Self(0x811c_9dc5)
    }
}

impl Fnv {
    /// Adds bytes.
    pub fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 = (self.0 ^ x as u32).wrapping_mul(0x0100_0193);
        }
    }

    /// Adds a `u32`.
    pub fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
}
