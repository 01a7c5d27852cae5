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

/// Samples per chirp of the two-reflector frame.
pub const TWO_REFLECTOR_N: usize = 64;

/// The radar of the two-reflector frame: 2 TX × 4 RX (8 elements), 64 samples, 2 loops.
pub fn two_reflector_config() -> metamoran_dsp::config::RadarConfig {
    metamoran_dsp::config::RadarConfig {
        start_frequency_hz: 77.0e9,
        slope_hz_per_s: 2.342e14,
        sample_rate_hz: 10.0e6,
        adc_samples: TWO_REFLECTOR_N as u16,
        chirp_period_s: 10.0e-6,
        chirps_per_tx: 2,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: heapless::Vec::from_slice(&[0, 4]).unwrap_or_default(),
        rx_positions: heapless::Vec::from_slice(&[0, 1, 2, 3]).unwrap_or_default(),
        tx_order: heapless::Vec::from_slice(&[0, 1]).unwrap_or_default(),
    }
}

/// Row (`chirp`, `rx`) of the two-reflector frame plus `noise` (same length as `out`): a weak
/// contour object at range bin 20.3 straight ahead and a strong reflector at bin 9.6, 35° away
/// (a phase step of 0.3 turn per element).
pub fn two_reflector_row(chirp: usize, rx: usize, noise: &[CQ15], out: &mut [CQ15]) {
    let config = two_reflector_config();
    let p = config.channel_position((chirp % 2) * 4 + rx).unwrap_or(0);
    let n_total = out.len() as f64;
    for (n, (z, e)) in out.iter_mut().zip(noise).enumerate() {
        let turns = |bin: f64, extra: f64| {
            metamoran_dsp::trig::Phase::from_turns(-(bin * n as f64) / n_total - extra)
        };
        let a = metamoran_dsp::trig::expj_neg(turns(20.3, 0.0));
        let b = metamoran_dsp::trig::expj_neg(turns(9.6, p as f64 * 0.3));
        *z = CQ15::from_raw(
            a.re.0 / 64 + b.re.0 / 4 + e.re.0,
            a.im.0 / 64 + b.im.0 / 4 + e.im.0,
        );
    }
}
