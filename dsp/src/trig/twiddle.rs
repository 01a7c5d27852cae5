//! Twiddle tables `exp(−j·2π·k/2048)`, built by the compiler.
//!
//! One full-circle table of the largest size serves every smaller FFT by striding
//! (`W_N^k = W_2048^(k·2048/N)`); it also backs [`crate::trig::expj_neg`].
//! Flash cost: 8 KiB (Q15) + 16 KiB (Q31).

use super::cos_sin_turn;
use crate::fixed::{CQ15, CQ31, Complex, Q15, Q31};

/// Entries in each table: the largest supported FFT length.
pub const TABLE_LEN: usize = 2048;

/// `exp(−j·2π·k/2048)` in Q15 (1.0 saturates to 32767).
pub static TWIDDLE_Q15: [CQ15; TABLE_LEN] = {
    let mut t = [Complex::new(Q15::ZERO, Q15::ZERO); TABLE_LEN];
    let mut k = 0;
    while k < TABLE_LEN {
        let (c, s) = cos_sin_turn(k as i64, TABLE_LEN as i64);
        t[k] = Complex::new(Q15::from_f64(c), Q15::from_f64(-s));
        k += 1;
    }
    t
};

/// `exp(−j·2π·k/2048)` in Q31 (1.0 saturates to 2³¹ − 1).
pub static TWIDDLE_Q31: [CQ31; TABLE_LEN] = {
    let mut t = [Complex::new(Q31::ZERO, Q31::ZERO); TABLE_LEN];
    let mut k = 0;
    while k < TABLE_LEN {
        let (c, s) = cos_sin_turn(k as i64, TABLE_LEN as i64);
        t[k] = Complex::new(Q31::from_f64(c), Q31::from_f64(-s));
        k += 1;
    }
    t
};
