//! Radar configuration and the geometry it implies (the `[radar]` table of a scene bundle).
//!
//! Every conversion between FFT bins and physical units lives here, so the host and the module
//! convert identically. Sizes are bounded by [`MAX_TX`], [`MAX_RX`] and [`MAX_SLOTS`] so the
//! configuration fits in a fixed-size value (a cascade board has 12 TX and 16 RX).

use core::fmt;
use heapless::Vec;

/// Speed of light in m/s (as the bundle format defines it).
pub const SPEED_OF_LIGHT: f64 = 299_792_458.0;
/// Most transmitters a configuration can name.
pub const MAX_TX: usize = 16;
/// Most receivers a configuration can name.
pub const MAX_RX: usize = 16;
/// Most TDM chirp slots in one loop.
pub const MAX_SLOTS: usize = 16;

/// Reference antenna layouts (positions in half-wavelengths).
pub mod boards {
    /// TI MMWCAS cascade TX azimuth positions: nine at 0..32 step 4 and three elevated ones that
    /// overlap in azimuth; with [`CASCADE_RX`] they give 86 distinct virtual positions.
    pub const CASCADE_TX: [i16; 12] = [11, 10, 9, 32, 28, 24, 20, 16, 12, 8, 4, 0];
    /// TI MMWCAS cascade RX positions.
    pub const CASCADE_RX: [i16; 16] = [11, 12, 13, 14, 50, 51, 52, 53, 46, 47, 48, 49, 0, 1, 2, 3];
}

/// An FMCW TDM-MIMO radar configuration.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RadarConfig {
    /// Carrier at the start of the ramp, Hz.
    pub start_frequency_hz: f64,
    /// Chirp slope S, Hz/s.
    pub slope_hz_per_s: f64,
    /// Complex ADC sample rate fs, Hz.
    pub sample_rate_hz: f64,
    /// Samples per chirp N (even).
    pub adc_samples: u16,
    /// Start of one chirp to the start of the next, s.
    pub chirp_period_s: f64,
    /// Loops per frame (the Doppler length before padding).
    pub chirps_per_tx: u16,
    /// Frames in the capture.
    pub frames: u32,
    /// Start of one frame to the next, s.
    pub frame_period_s: f64,
    /// Azimuth position of each TX in half-wavelengths.
    pub tx_positions: Vec<i16, MAX_TX>,
    /// Azimuth position of each RX in half-wavelengths.
    pub rx_positions: Vec<i16, MAX_RX>,
    /// TDM order: chirp `c` of a loop is sent by TX `tx_order[c]`.
    pub tx_order: Vec<u8, MAX_SLOTS>,
}

/// A configuration value that the geometry cannot work with.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ConfigError {
    /// A frequency, rate or period is not a positive finite number (names the field).
    NotPositive(&'static str),
    /// `adc_samples` is zero, odd, or more than the largest FFT.
    AdcSamples(u16),
    /// `chirps_per_tx` is zero or more than the largest FFT.
    ChirpsPerTx(u16),
    /// A list that must not be empty is empty (names the field).
    Empty(&'static str),
    /// `tx_order` names a transmitter that `tx_positions` does not have.
    TxOrder {
        /// Slot in `tx_order`.
        slot: usize,
        /// The TX index found there.
        tx: u8,
    },
    /// Each field is fine alone, but a quantity derived from several is not physically
    /// plausible (an infinite maximum range from a slope of 1e-300, chirps that do not fit in
    /// the frame, …).
    Implausible {
        /// The quantity and the fields it comes from.
        quantity: Derived,
        /// Its value, in the quantity's unit.
        value: f64,
    },
}

/// A quantity [`RadarConfig::validate`] derives from several fields and bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Derived {
    /// The carrier `start_frequency_hz`, Hz: 1–300 GHz.
    Carrier,
    /// R_max = fs·c / (2·S), m: 0.5 m to 100 km.
    MaxRange,
    /// The swept bandwidth S·N / fs, Hz: 1 MHz to 20 GHz (range resolution 7.5 mm to 150 m).
    Bandwidth,
    /// The sampling window N / fs, s: at most `chirp_period_s`.
    SamplingWindow,
    /// The chirps of one frame, `chirps_per_tx · len(tx_order) · chirp_period_s`, s: at most
    /// `frame_period_s`.
    ChirpTime,
}

impl Derived {
    /// The accepted range, in the quantity's unit.
    pub fn bounds(self, config: &RadarConfig) -> (f64, f64) {
        match self {
            Self::Carrier => (1.0e9, 300.0e9),
            Self::MaxRange => (0.5, 100.0e3),
            Self::Bandwidth => (1.0e6, 20.0e9),
            Self::SamplingWindow => (0.0, config.chirp_period_s),
            Self::ChirpTime => (0.0, config.frame_period_s),
        }
    }

    /// The field most likely wrong (the one an error message names).
    pub fn field(self) -> &'static str {
        match self {
            Self::Carrier => "start_frequency_hz",
            Self::MaxRange | Self::Bandwidth => "slope_hz_per_s",
            Self::SamplingWindow => "chirp_period_s",
            Self::ChirpTime => "frame_period_s",
        }
    }

    /// The quantity, its unit and the fields to check.
    fn describe(self) -> (&'static str, &'static str, &'static str) {
        match self {
            Self::Carrier => ("carrier frequency", "Hz", "start_frequency_hz"),
            Self::MaxRange => (
                "maximum range fs·c/(2·S)",
                "m",
                "slope_hz_per_s and sample_rate_hz",
            ),
            Self::Bandwidth => (
                "swept bandwidth S·N/fs",
                "Hz",
                "slope_hz_per_s, adc_samples and sample_rate_hz",
            ),
            Self::SamplingWindow => (
                "sampling window N/fs",
                "s",
                "adc_samples, sample_rate_hz and chirp_period_s (samples must fit in a chirp)",
            ),
            Self::ChirpTime => (
                "chirp time of a frame",
                "s",
                "chirps_per_tx, tx_order, chirp_period_s and frame_period_s (a frame's chirps \
                 must fit in its period)",
            ),
        }
    }
}

impl core::error::Error for ConfigError {}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotPositive(field) => write!(f, "`{field}` must be a positive, finite number"),
            Self::AdcSamples(n) => write!(
                f,
                "`adc_samples` = {n}: use an even number of samples from 2 to {}",
                crate::fft::MAX_LEN
            ),
            Self::ChirpsPerTx(n) => {
                write!(
                    f,
                    "`chirps_per_tx` = {n}: use 1 to {} loops per frame",
                    crate::fft::MAX_LEN
                )
            }
            Self::Empty(field) => write!(f, "`{field}` must list at least one entry"),
            Self::TxOrder { slot, tx } => write!(
                f,
                "`tx_order[{slot}]` = {tx} names a transmitter that `tx_positions` does not have"
            ),
            Self::Implausible { quantity, value } => {
                let (what, unit, fields) = quantity.describe();
                write!(
                    f,
                    "the {what} is {value:e} {unit}, which no radar has; check {fields}"
                )
            }
        }
    }
}

impl RadarConfig {
    /// Checks every field the geometry depends on.
    ///
    /// # Errors
    /// The first [`ConfigError`] found.
    pub fn validate(&self) -> Result<(), ConfigError> {
        for (name, v) in [
            ("start_frequency_hz", self.start_frequency_hz),
            ("slope_hz_per_s", self.slope_hz_per_s),
            ("sample_rate_hz", self.sample_rate_hz),
            ("chirp_period_s", self.chirp_period_s),
            ("frame_period_s", self.frame_period_s),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(ConfigError::NotPositive(name));
            }
        }
        let n = self.adc_samples;
        if n == 0 || !n.is_multiple_of(2) || n as usize > crate::fft::MAX_LEN {
            return Err(ConfigError::AdcSamples(n));
        }
        if self.chirps_per_tx == 0 || self.chirps_per_tx as usize > crate::fft::MAX_LEN {
            return Err(ConfigError::ChirpsPerTx(self.chirps_per_tx));
        }
        if self.tx_positions.is_empty() {
            return Err(ConfigError::Empty("tx_positions"));
        }
        if self.rx_positions.is_empty() {
            return Err(ConfigError::Empty("rx_positions"));
        }
        if self.tx_order.is_empty() {
            return Err(ConfigError::Empty("tx_order"));
        }
        for (slot, &tx) in self.tx_order.iter().enumerate() {
            if tx as usize >= self.tx_positions.len() {
                return Err(ConfigError::TxOrder { slot, tx });
            }
        }
        self.check_derived()
    }

    /// Bounds every [`Derived`] quantity: each must be finite and inside its range.
    fn check_derived(&self) -> Result<(), ConfigError> {
        let n = self.adc_samples as f64;
        let window = n / self.sample_rate_hz;
        for (quantity, value) in [
            (Derived::Carrier, self.start_frequency_hz),
            (Derived::MaxRange, self.max_range_m()),
            (Derived::Bandwidth, self.slope_hz_per_s * window),
            (Derived::SamplingWindow, window),
            (
                Derived::ChirpTime,
                self.chirps_per_frame() as f64 * self.chirp_period_s,
            ),
        ] {
            let (lo, hi) = quantity.bounds(self);
            if !(value.is_finite() && (lo..=hi).contains(&value)) {
                return Err(ConfigError::Implausible { quantity, value });
            }
        }
        Ok(())
    }

    /// Largest unambiguous range R_max = fs·c / (2·S), m, in f64 (see [`Self::max_range`]).
    pub fn max_range_m(&self) -> f64 {
        self.sample_rate_hz * SPEED_OF_LIGHT / (2.0 * self.slope_hz_per_s)
    }

    /// Carrier wavelength λ = c / f₀, m.
    pub fn wavelength_m(&self) -> f64 {
        SPEED_OF_LIGHT / self.start_frequency_hz
    }

    /// TDM slots per loop (`len(tx_order)`).
    pub fn slots(&self) -> usize {
        self.tx_order.len()
    }

    /// Receivers.
    pub fn rx_count(&self) -> usize {
        self.rx_positions.len()
    }

    /// Virtual channels: one per (slot, RX), numbered `slot · rx_count + rx`.
    pub fn channels(&self) -> usize {
        self.slots() * self.rx_count()
    }

    /// Chirps in one frame (`chirps_per_tx · len(tx_order)`).
    pub fn chirps_per_frame(&self) -> usize {
        self.chirps_per_tx as usize * self.slots()
    }

    /// Complex samples in one frame.
    pub fn samples_per_frame(&self) -> usize {
        self.chirps_per_frame() * self.rx_count() * self.adc_samples as usize
    }

    /// Virtual position of `channel` in half-wavelengths, if the channel exists.
    pub fn channel_position(&self, channel: usize) -> Option<i32> {
        let rx_count = self.rx_count();
        let (slot, rx) = (
            channel.checked_div(rx_count)?,
            channel.checked_rem(rx_count)?,
        );
        let tx = *self.tx_order.get(slot)? as usize;
        Some(*self.tx_positions.get(tx)? as i32 + *self.rx_positions.get(rx)? as i32)
    }

    /// Range FFT length: `adc_samples` rounded up to a supported power of two.
    pub fn range_fft_len(&self) -> usize {
        crate::fft::padded_len(self.adc_samples as usize).unwrap_or(crate::fft::MAX_LEN)
    }

    /// Doppler FFT length: `chirps_per_tx` rounded up to a supported power of two.
    pub fn doppler_fft_len(&self) -> usize {
        crate::fft::padded_len(self.chirps_per_tx as usize).unwrap_or(crate::fft::MAX_LEN)
    }

    /// Largest unambiguous range R_max = fs·c / (2·S), m.
    pub fn max_range(&self) -> f32 {
        self.max_range_m() as f32
    }

    /// Metres per bin of a range FFT of `fft_len` points: c·fs / (2·S·fft_len).
    pub fn range_bin_size(&self, fft_len: usize) -> f32 {
        (SPEED_OF_LIGHT * self.sample_rate_hz / (2.0 * self.slope_hz_per_s * fft_len as f64)) as f32
    }

    /// Range (m) of a (fractional) bin of a range FFT of `fft_len` points.
    pub fn bin_to_range(&self, bin: f32, fft_len: usize) -> f32 {
        bin * self.range_bin_size(fft_len)
    }

    /// The (fractional) range bin of `range_m` in a range FFT of `fft_len` points.
    pub fn range_to_bin(&self, range_m: f32, fft_len: usize) -> f32 {
        range_m / self.range_bin_size(fft_len)
    }

    /// Time between two chirps of the same slot (one loop), s.
    pub fn loop_period_s(&self) -> f64 {
        self.chirp_period_s * self.slots() as f64
    }

    /// Radial velocity (m/s) of a signed, fractional Doppler bin of a `fft_len`-point Doppler
    /// FFT: v = bin · λ / (2 · T_loop · fft_len). Positive bins are targets moving away.
    pub fn doppler_to_velocity(&self, bin: f32, fft_len: usize) -> f32 {
        let res = self.wavelength_m() / (2.0 * self.loop_period_s() * fft_len as f64);
        (bin as f64 * res) as f32
    }

    /// Largest unambiguous speed λ / (4·T_loop), m/s.
    pub fn max_velocity(&self) -> f32 {
        (self.wavelength_m() / (4.0 * self.loop_period_s())) as f32
    }
}

/// Azimuth (rad) of a signed, fractional bin of an `fft_len`-point FFT over a half-wavelength
/// array: sin θ = 2·bin / fft_len. `None` outside the visible region (|sin θ| > 1).
pub fn azimuth_bin_to_angle(bin: f32, fft_len: usize) -> Option<f32> {
    let s = 2.0 * bin / fft_len as f32;
    (s.abs() <= 1.0).then(|| libm::asinf(s))
}

/// The (fractional) signed azimuth bin of angle `angle_rad`: bin = sin θ · fft_len / 2.
pub fn angle_to_azimuth_bin(angle_rad: f32, fft_len: usize) -> f32 {
    libm::sinf(angle_rad) * fft_len as f32 / 2.0
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The example configuration of the bundle format.
    pub(crate) fn example() -> RadarConfig {
        RadarConfig {
            start_frequency_hz: 77.0e9,
            slope_hz_per_s: 29.982e12,
            sample_rate_hz: 10.0e6,
            adc_samples: 256,
            chirp_period_s: 60.0e-6,
            chirps_per_tx: 16,
            frames: 4,
            frame_period_s: 0.1,
            tx_positions: Vec::from_slice(&[0, 4]).unwrap(),
            rx_positions: Vec::from_slice(&[0, 1, 2, 3]).unwrap(),
            tx_order: Vec::from_slice(&[0, 1]).unwrap(),
        }
    }

    #[test]
    fn geometry_matches_closed_forms() {
        let c = example();
        c.validate().unwrap();
        // R_max = fs c / 2S
        assert!((c.max_range() as f64 - 10e6 * SPEED_OF_LIGHT / (2.0 * 29.982e12)).abs() < 1e-4);
        assert!((c.range_bin_size(256) as f64 - c.max_range() as f64 / 256.0).abs() < 1e-6);
        assert_eq!(c.channels(), 8);
        assert_eq!(c.channel_position(5), Some(5));
        assert_eq!(c.channel_position(8), None);
        let v = c.doppler_to_velocity(1.0, 16) as f64;
        assert!((v - c.wavelength_m() / (2.0 * 120e-6 * 16.0)).abs() < 1e-6);
        let a = azimuth_bin_to_angle(16.0, 64).unwrap();
        assert!((a - core::f32::consts::FRAC_PI_6).abs() < 1e-6);
        assert!(azimuth_bin_to_angle(33.0, 64).is_none());
    }

    #[test]
    fn bad_fields_are_named() {
        let mut c = example();
        c.slope_hz_per_s = f64::NAN;
        assert_eq!(
            c.validate(),
            Err(ConfigError::NotPositive("slope_hz_per_s"))
        );
        let mut c = example();
        c.adc_samples = 255;
        assert_eq!(c.validate(), Err(ConfigError::AdcSamples(255)));
        let mut c = example();
        c.tx_order = Vec::from_slice(&[0, 2]).unwrap();
        assert_eq!(c.validate(), Err(ConfigError::TxOrder { slot: 1, tx: 2 }));
    }

    /// Issue #18, item 5: a slope of 1e-300 passed every per-field check and made R_max
    /// infinite; each derived quantity is now bounded, at both ends.
    #[test]
    fn implausible_derived_quantities_are_named() {
        let implausible = |edit: &dyn Fn(&mut RadarConfig)| {
            let mut c = example();
            edit(&mut c);
            match c.validate() {
                Err(ConfigError::Implausible { quantity, .. }) => Some(quantity),
                _ => None,
            }
        };
        assert_eq!(
            implausible(&|c| c.slope_hz_per_s = 1e-300),
            Some(Derived::MaxRange)
        );
        // Two samples at 1e12 Hz/s: R_max = 1.5 km is plausible, the sweep S·N/fs = 200 kHz
        // (a 750 m range resolution) is not.
        assert_eq!(
            implausible(&|c| {
                c.slope_hz_per_s = 1e12;
                c.adc_samples = 2;
            }),
            Some(Derived::Bandwidth)
        );
        assert_eq!(
            implausible(&|c| c.slope_hz_per_s = 1e16),
            Some(Derived::MaxRange)
        );
        assert_eq!(
            implausible(&|c| c.start_frequency_hz = 1e300),
            Some(Derived::Carrier)
        );
        // 256 samples at 10 MHz take 25.6 µs: not in a 20 µs chirp.
        assert_eq!(
            implausible(&|c| c.chirp_period_s = 20e-6),
            Some(Derived::SamplingWindow)
        );
        // 32 chirps of 60 µs = 1.92 ms: not in a 1 ms frame, but in a 1.92 ms one.
        assert_eq!(
            implausible(&|c| c.frame_period_s = 1e-3),
            Some(Derived::ChirpTime)
        );
        assert_eq!(implausible(&|c| c.frame_period_s = 1.92e-3), None);
        let err = ConfigError::Implausible {
            quantity: Derived::MaxRange,
            value: 1.5e306,
        };
        let text = std::string::ToString::to_string(&err);
        assert!(
            text.contains("maximum range") && text.contains("slope_hz_per_s"),
            "{text}"
        );
    }
}
