//! FMCW beat-signal synthesis, exactly the model of bundle.md:
//!
//! `a · exp(j·4πR/λ) · exp(j·2π·(2SR/c)·n/fs) · exp(jπ·p·sin θ)` per scatterer, virtual element
//! and sample, times `exp(j·4π·v·t/λ)` at chirp start time `t` for moving scatterers, with
//! `a = GAIN · √RCS · g_az(θ) · g_el(φ) · H_IF(R) / R²` (radar equation in amplitude, element
//! pattern in azimuth, a narrow elevation beam, and the IF low-pass that keeps anything beyond
//! R_max from aliasing in), thermal noise, and int16 quantization.

use super::object::SceneObject;
use metamoran_dsp::config::{RadarConfig, SPEED_OF_LIGHT};
use rand::Rng;
use rand_distr::StandardNormal;
use std::f64::consts::PI;

/// ADC amplitude (LSB) of a 1 m² scatterer at 1 m on boresight. Leaves headroom: strong clutter
/// at 10–20 m stays well inside int16, and clipping only happens for very close strong reflectors.
pub const GAIN: f64 = 3.0e4;
/// Thermal noise, standard deviation per I and Q component, LSB.
pub const NOISE_LSB: f64 = 2.0;
/// Elevation beam (1σ) of the parking-lot boards, degrees: the narrow beam that lets ground
/// clutter in only far away.
pub const ELEVATION_BEAM_DEG: f64 = 4.0;

/// One scatterer as the radar sees it.
#[derive(Clone, Copy, Debug)]
pub struct Echo {
    /// Range in the x–z plane, m.
    pub range: f64,
    /// sin(azimuth).
    pub sin_az: f64,
    /// sin(elevation), positive up.
    pub sin_el: f64,
    /// Radial velocity, m/s (positive away).
    pub velocity: f64,
    /// Amplitude, LSB.
    pub amplitude: f64,
    /// Phase of the scattering, rad.
    pub phase: f64,
}

/// IF low-pass response at range `r` for a radar with unambiguous range `r_max`: flat to
/// 0.9·R_max, raised-cosine to zero at R_max.
pub fn if_response(r: f64, r_max: f64) -> f64 {
    let edge = 0.9 * r_max;
    if r <= edge {
        1.0
    } else if r >= r_max {
        0.0
    } else {
        0.5 * (1.0 + (PI * (r - edge) / (r_max - edge)).cos())
    }
}

/// The echoes of every visible scatterer of `objects`, for an antenna whose elevation beam has
/// a 1σ width of `elevation_beam_deg` degrees.
pub fn echoes(
    objects: &[SceneObject],
    extra: &[super::object::Scatterer],
    config: &RadarConfig,
    elevation_beam_deg: f64,
) -> Vec<Echo> {
    let r_max = config.max_range() as f64;
    let sigma_el = elevation_beam_deg.to_radians();
    let origin = nalgebra::Vector3::zeros();
    let mut out = Vec::new();
    let owners = objects
        .iter()
        .flat_map(|o| o.scatterers.iter().map(move |s| (Some(o), s)))
        .chain(extra.iter().map(|s| (None, s)));
    for (owner, s) in owners {
        let p = s.position;
        let range = p.x.hypot(p.z);
        let h = if_response(range, r_max);
        if h == 0.0 || range < 0.5 {
            continue;
        }
        let az = p.x.atan2(p.z);
        if az.abs() >= PI / 2.0 {
            continue;
        }
        // Hidden behind another object?
        let dist = p.norm();
        let dir = p / dist;
        let hidden = objects.iter().any(|o| {
            owner.is_none_or(|w| w.id != o.id)
                && o.shape
                    .intersect(&origin, &dir)
                    .is_some_and(|t| t < dist - 0.05)
        });
        if hidden {
            continue;
        }
        let el = (-p.y).atan2(range);
        let g_az = az.cos().powf(1.5);
        let g_el = (-0.5 * (el / sigma_el).powi(2)).exp();
        out.push(Echo {
            range,
            sin_az: az.sin(),
            sin_el: el.sin(),
            velocity: owner.map_or(0.0, |o| o.radial_velocity(&p)),
            amplitude: GAIN * s.rcs.sqrt() * g_az * g_el * h / (range * range),
            phase: s.phase,
        });
    }
    out
}

/// A board's channel errors (issue #19): each (TX, RX) pair's received signal is multiplied by
/// a complex gain and delayed by a few centimetres of extra path, as the traces and mixers of a
/// real cascade do. What `metamoran calibrate` measures and undoes.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelErrors {
    /// Receivers per TX (the row length of `errors`).
    pub rx: usize,
    /// Per (TX, RX), TX-major: (complex gain (re, im), extra range in m). A range offset `ΔR`
    /// shifts the beat frequency by `2·S·ΔR/c`, so its size in range bins depends on the
    /// chirp; in metres it is the board's, whatever chirp a scene uses.
    pub errors: Vec<((f64, f64), f64)>,
}

impl ChannelErrors {
    /// Board `seed`'s errors for `tx × rx` channels: phase uniform in ±180°, gain uniform in
    /// ±3 dB, range offset uniform in ±0.5 of `bin_m` (the figures, for a chirp whose
    /// range bin is `bin_m`).
    pub fn draw(seed: u64, tx: usize, rx: usize, bin_m: f64) -> Self {
        use rand::SeedableRng;
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed ^ 0xB0A2_D5EE_D000_0019);
        let errors = (0..tx * rx)
            .map(|_| {
                let phase = rng.random_range(-PI..PI);
                let gain = 10f64.powf(rng.random_range(-3.0..3.0) / 20.0);
                let delay = rng.random_range(-0.5..0.5) * bin_m;
                ((gain * phase.cos(), gain * phase.sin()), delay)
            })
            .collect();
        Self { rx, errors }
    }

    /// Channel `(tx, rx)`'s error, if drawn.
    pub fn get(&self, tx: usize, rx: usize) -> Option<((f64, f64), f64)> {
        (rx < self.rx)
            .then(|| self.errors.get(tx * self.rx + rx).copied())
            .flatten()
    }
}

/// Synthesizes one frame of `config` as DCA1000 xWR18xx bytes (IIQQ, `[chirp][rx][sample]`).
/// `elevation` gives each virtual channel's elevation in half-wavelengths (empty: all 0), which
/// adds `exp(jπ·e·sin φ)` for an echo at elevation φ; `errors` the board's channel errors
/// (applied before the noise, which is the receiver's own).
pub fn synthesize(
    config: &RadarConfig,
    echoes: &[Echo],
    elevation: &[i16],
    errors: Option<&ChannelErrors>,
    rng: &mut impl Rng,
) -> Vec<u8> {
    let (n, rx, slots, loops) = (
        config.adc_samples as usize,
        config.rx_count(),
        config.slots(),
        config.chirps_per_tx as usize,
    );
    let lambda = config.wavelength_m();
    let channels = rx * slots;
    let positions: Vec<f64> = (0..channels)
        .map(|ch| config.channel_position(ch).unwrap_or(0) as f64)
        .collect();
    // Sample phasor of each echo: exp(j·2π·(2SR/c)·n/fs).
    let ramp = |e: &Echo| -> Vec<(f32, f32)> {
        let w = 2.0 * PI * (2.0 * config.slope_hz_per_s * e.range / SPEED_OF_LIGHT)
            / config.sample_rate_hz;
        (0..n)
            .map(|k| {
                let (s, c) = (w * k as f64).sin_cos();
                (c as f32, s as f32)
            })
            .collect()
    };
    // Adds echo `e` with extra phase `extra` to the `n` samples of channel `ch` in `row`.
    let add = |row: &mut [(f32, f32)], e: &Echo, r: &[(f32, f32)], ch: usize, extra: f64| {
        let el = elevation.get(ch).map_or(0.0, |&v| f64::from(v));
        let phi = 4.0 * PI * e.range / lambda
            + e.phase
            + PI * (positions[ch] * e.sin_az + el * e.sin_el)
            + extra;
        let (s, c) = phi.sin_cos();
        let (ar, ai) = ((e.amplitude * c) as f32, (e.amplitude * s) as f32);
        for (o, &(rr, ri)) in row.iter_mut().zip(r) {
            o.0 += ar * rr - ai * ri;
            o.1 += ar * ri + ai * rr;
        }
    };
    let (moving, fixed): (Vec<&Echo>, Vec<&Echo>) = echoes.iter().partition(|e| e.velocity != 0.0);
    // The static scene is the same in every loop.
    let mut base = vec![(0f32, 0f32); channels * n];
    for e in &fixed {
        let r = ramp(e);
        for (ch, row) in base.chunks_exact_mut(n).enumerate() {
            add(row, e, &r, ch, 0.0);
        }
    }
    let ramps: Vec<Vec<(f32, f32)>> = moving.iter().map(|e| ramp(e)).collect();
    // Each channel's error as a per-sample factor.
    let distort: Vec<Option<Vec<(f32, f32)>>> = (0..channels)
        .map(|ch| {
            let tx = usize::from(config.tx_order[ch / rx]);
            let ((gr, gi), offset_m) = errors?.get(tx, ch % rx)?;
            let w = 2.0 * PI * (2.0 * config.slope_hz_per_s * offset_m / SPEED_OF_LIGHT)
                / config.sample_rate_hz;
            Some(
                (0..n)
                    .map(|k| {
                        let (s, c) = (w * k as f64).sin_cos();
                        ((gr * c - gi * s) as f32, (gr * s + gi * c) as f32)
                    })
                    .collect(),
            )
        })
        .collect();
    let mut bytes = Vec::with_capacity(loops * channels * n * 4);
    let mut row = vec![(0f32, 0f32); n];
    for lp in 0..loops {
        for slot in 0..slots {
            let t = (lp * slots + slot) as f64 * config.chirp_period_s;
            for r_i in 0..rx {
                let ch = slot * rx + r_i;
                row.copy_from_slice(&base[ch * n..(ch + 1) * n]);
                for (e, r) in moving.iter().zip(&ramps) {
                    add(&mut row, e, r, ch, 4.0 * PI * e.velocity * t / lambda);
                }
                if let Some(d) = &distort[ch] {
                    for (o, &(dr, di)) in row.iter_mut().zip(d) {
                        *o = (o.0 * dr - o.1 * di, o.0 * di + o.1 * dr);
                    }
                }
                let mut q = |v: f32| {
                    let noise: f64 = rng.sample(StandardNormal);
                    (v as f64 + NOISE_LSB * noise)
                        .round()
                        .clamp(i16::MIN as f64, i16::MAX as f64) as i16
                };
                for pair in row.chunks_exact(2) {
                    let (i0, q0, i1, q1) = (q(pair[0].0), q(pair[0].1), q(pair[1].0), q(pair[1].1));
                    for w in [i0, i1, q0, q1] {
                        bytes.extend_from_slice(&w.to_le_bytes());
                    }
                }
            }
        }
    }
    bytes
}
