//! The budget scene of the instruction-count benchmark: a cascade-86 board (12 TX × 16 RX,
//! 512 samples, 2 loops, 59 m unambiguous range), four car-like objects between 14 and 40 m and
//! three strong clutter reflectors. Chirps are synthesized on demand from the bundle signal model
//! with exact binary-angle phases, so host and module make the same frame.

use crate::workload::Lcg;
use metamoran_dsp::config::RadarConfig;
use metamoran_dsp::config::boards::{CASCADE_RX, CASCADE_TX};
use metamoran_dsp::fixed::CQ15;
use metamoran_dsp::pipeline::ObjectHint;
use metamoran_dsp::response::kernel::half_turns;
use metamoran_dsp::search::Contour;
use metamoran_dsp::trig::{Phase, expj_neg};

/// Samples per chirp.
pub const N: usize = 512;
/// The pipeline's arena for this board: 86 elements × 2·512 words.
pub const ARENA_WORDS: usize = 86 * 2 * N;
/// Unambiguous range, m.
const MAX_RANGE: f64 = 59.4;
/// Objects: closest range m, centre sin(azimuth).
const OBJECTS: [(f32, f32); 4] = [(14.0, -0.3), (22.0, -0.05), (31.0, 0.2), (40.0, 0.45)];
/// Clutter: range m, sin(azimuth), amplitude LSB.
const CLUTTER: [(f32, f32, i32); 3] = [(8.0, 0.7, 4000), (18.0, -0.6, 3000), (27.0, 0.35, 2500)];
/// Half width of an object in sin(azimuth).
const HALF_WIDTH: f32 = 0.04;
/// Depth of an object's contour from its centre to its edges, m.
const DEPTH: f32 = 1.5;

/// The board configuration.
pub fn config() -> RadarConfig {
    RadarConfig {
        start_frequency_hz: 77.0e9,
        slope_hz_per_s: 10.0e6 * metamoran_dsp::config::SPEED_OF_LIGHT / (2.0 * MAX_RANGE),
        sample_rate_hz: 10.0e6,
        adc_samples: N as u16,
        chirp_period_s: 59.2e-6,
        chirps_per_tx: 2,
        frames: 1,
        frame_period_s: 0.1,
        tx_positions: heapless::Vec::from_slice(&CASCADE_TX).unwrap_or_default(),
        rx_positions: heapless::Vec::from_slice(&CASCADE_RX).unwrap_or_default(),
        tx_order: (0..CASCADE_TX.len() as u8).collect(),
    }
}

/// The contour point at `u ∈ [−1, 1]` across an object: (sin az offset, relative range m).
fn shape(u: f32) -> (f32, f32) {
    (HALF_WIDTH * u, DEPTH * u * u)
}

/// Chirp `chirp` of receiver `rx` into `out`: five scatterers per object (60 LSB each), the
/// clutter, and ±2 LSB of noise.
pub fn chirp(config: &RadarConfig, chirp: usize, rx: usize, out: &mut [CQ15]) {
    synthesize(config, chirp, rx, false, out);
}

/// [`chirp`] as an imperfect board records it: each (TX, RX) channel with its own gain, phase
/// and delay ([`board_error`]), which [`calibration`] undoes.
pub fn chirp_on_board(config: &RadarConfig, chirp: usize, rx: usize, out: &mut [CQ15]) {
    synthesize(config, chirp, rx, true, out);
}

/// Channel `k` (= TX · RX count + RX)'s error on the imperfect board: gain 0.6…1, phase in
/// half-turns (±0.9), delay in range bins (±0.3).
pub fn board_error(k: usize) -> (f32, f32, f32) {
    use metamoran_dsp::trig::cos_sin_pi;
    let k = k as f32;
    (
        0.8 + 0.2 * cos_sin_pi(0.37 * k).0,
        0.9 * cos_sin_pi(0.22 * k).1,
        0.3 * cos_sin_pi(0.1 * k).0,
    )
}

fn synthesize(config: &RadarConfig, chirp: usize, rx: usize, board: bool, out: &mut [CQ15]) {
    let slot = chirp % config.slots();
    let channel = slot * config.rx_count() + rx;
    let p = config.channel_position(channel).unwrap_or(0) as u32;
    let bin_m = config.range_bin_size(N) as f64;
    let tx = config.tx_order.get(slot).map_or(0, |&t| usize::from(t));
    let (gain, half_turns_off, bins) = if board {
        board_error(tx * config.rx_count() + rx)
    } else {
        (1.0, 0.0, 0.0)
    };
    let (offset, drift) = (
        Phase::from_turns(f64::from(half_turns_off) / 2.0).0,
        Phase::from_turns(f64::from(bins) / N as f64).0,
    );
    let mut acc = [(0i32, 0i32); N];
    let mut add = |range: f32, sin_az: f32, amplitude: i32, seed: u32| {
        let amplitude = (amplitude as f32 * gain) as i32;
        let inc = Phase::from_turns(range as f64 / bin_m / N as f64)
            .0
            .wrapping_add(drift);
        let mut ph = half_turns(sin_az)
            .wrapping_mul(p)
            .wrapping_add(seed.wrapping_mul(0x9E37_79B9))
            .wrapping_add(offset);
        for a in &mut acc {
            // exp(+jθ) = conj(exp(−jθ)).
            let z = expj_neg(Phase(ph));
            a.0 += (z.re.0 as i32 * amplitude) >> 15;
            a.1 -= (z.im.0 as i32 * amplitude) >> 15;
            ph = ph.wrapping_add(inc);
        }
    };
    for (i, &(r, s)) in OBJECTS.iter().enumerate() {
        for j in 0..5 {
            let (ds, dr) = shape(-0.8 + 0.4 * j as f32);
            add(r + dr, s + ds, 60, (i * 5 + j) as u32);
        }
    }
    for (i, &(r, s, a)) in CLUTTER.iter().enumerate() {
        add(r, s, a, 100 + i as u32);
    }
    let mut noise = Lcg(chirp as u32 * 131 + rx as u32 + 1);
    for (o, &(re, im)) in out.iter_mut().zip(&acc) {
        let n = |l: &mut Lcg| (l.next_u32() >> 30) as i32 - 2;
        let (re, im) = (re + n(&mut noise), im + n(&mut noise));
        *o = CQ15::from_raw(
            re.clamp(-32768, 32767) as i16,
            im.clamp(-32768, 32767) as i16,
        );
    }
}

/// True closest range of object `i`, m.
pub fn truth_m(i: usize) -> f32 {
    OBJECTS.get(i).map_or(0.0, |o| o.0)
}

/// The camera's hints: 24-point contours, monocular ranges 2 m long.
pub fn hints() -> [ObjectHint; 4] {
    core::array::from_fn(|i| {
        let (r, s) = OBJECTS[i];
        ObjectHint {
            id: i as u16 + 1,
            class: 1,
            span: (s - HALF_WIDTH, s + HALF_WIDTH),
            prior_m: r + 2.0,
            window_m: (0.0, 0.0),
            contour: Contour::new((0..24).map(|k| {
                let (ds, dr) = shape(-1.0 + 2.0 * k as f32 / 23.0);
                (s + ds, r + 2.0 + dr)
            })),
        }
    })
}

/// The calibration that undoes [`board_error`] on every (TX, RX) of [`config`]: gain
/// `e^{−jφ} / g`, frequency −delay. What the budget frame's calibrated count and the module's
/// calibration tests apply to [`chirp_on_board`].
pub fn calibration() -> Option<metamoran_dsp::range::calibration::AppliedCalibration> {
    use metamoran_dsp::range::calibration::{Calibration, Correction};
    use metamoran_dsp::trig::cos_sin_pi;
    let config = config();
    let (tx, rx) = (config.tx_positions.len(), config.rx_count());
    let mut cal = Calibration::identity(tx, rx).ok()?;
    for t in 0..tx {
        for r in 0..rx {
            let (g, phase, bins) = board_error(t * rx + r);
            let (c, s) = cos_sin_pi(phase);
            let gain = (f64::from(c / g), f64::from(-s / g));
            cal.set(t, r, Correction::from_f64(gain, -f64::from(bins), N as u16))
                .ok()?;
        }
    }
    Some(cal.normalized())
}
