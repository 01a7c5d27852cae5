//! The DCA1000 2-lane layout of xWR16xx/xWR18xx devices.
//!
//! Little-endian int16; every group of four holds two complex samples of one receiver's chirp:
//! `I[2k], I[2k+1], Q[2k], Q[2k+1]` (IIQQ). Devices configured with `sampleSwap = 1` store
//! `Q[2k], Q[2k+1], I[2k], I[2k+1]` (QQII) instead.

use crate::fixed::CQ15;
use core::fmt;

/// Order of the I and Q pairs inside each group of four int16.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum IqOrder {
    /// `I[2k], I[2k+1], Q[2k], Q[2k+1]` (the bundle format's order).
    #[default]
    Iiqq,
    /// `Q[2k], Q[2k+1], I[2k], I[2k+1]` (`adcbufCfg` sample swap set).
    Qqii,
}

/// Why raw bytes could not be turned into samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum CaptureError {
    /// The output holds an odd number of samples; groups carry two samples each.
    OddSampleCount(usize),
    /// The byte count is not four per output sample.
    Length {
        /// Bytes needed for the output.
        expected: usize,
        /// Bytes given.
        got: usize,
    },
}

impl core::error::Error for CaptureError {}

impl fmt::Display for CaptureError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::OddSampleCount(n) => {
                write!(
                    f,
                    "{n} samples requested: DCA1000 groups carry two samples, ask for an even count"
                )
            }
            Self::Length { expected, got } => write!(
                f,
                "{got} bytes given for {expected} bytes of samples: the capture is truncated or the \
                 radar configuration does not match it"
            ),
        }
    }
}

/// Decodes `4 · out.len()` little-endian bytes of DCA1000 groups into `out`. O(N).
///
/// # Errors
/// [`CaptureError`] if `out.len()` is odd or `bytes.len() != 4 · out.len()`.
pub fn deinterleave_bytes(
    bytes: &[u8],
    order: IqOrder,
    out: &mut [CQ15],
) -> Result<(), CaptureError> {
    if !out.len().is_multiple_of(2) {
        return Err(CaptureError::OddSampleCount(out.len()));
    }
    if bytes.len() != out.len() * 4 {
        return Err(CaptureError::Length {
            expected: out.len() * 4,
            got: bytes.len(),
        });
    }
    for (group, pair) in bytes.chunks_exact(8).zip(out.chunks_exact_mut(2)) {
        let w = |i: usize| i16::from_le_bytes([group[2 * i], group[2 * i + 1]]);
        let (first, second) = ([w(0), w(1)], [w(2), w(3)]);
        let (i, q) = match order {
            IqOrder::Iiqq => (first, second),
            IqOrder::Qqii => (second, first),
        };
        pair[0] = CQ15::from_raw(i[0], q[0]);
        pair[1] = CQ15::from_raw(i[1], q[1]);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_orders() {
        let words: [i16; 8] = [1, 2, 3, 4, -5, -6, -7, -8];
        let bytes: std::vec::Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        let mut out = [CQ15::default(); 4];
        deinterleave_bytes(&bytes, IqOrder::Iiqq, &mut out).unwrap();
        assert_eq!(
            out,
            [
                CQ15::from_raw(1, 3),
                CQ15::from_raw(2, 4),
                CQ15::from_raw(-5, -7),
                CQ15::from_raw(-6, -8)
            ]
        );
        deinterleave_bytes(&bytes, IqOrder::Qqii, &mut out).unwrap();
        assert_eq!(out[0], CQ15::from_raw(3, 1));
        assert_eq!(
            deinterleave_bytes(&bytes[..12], IqOrder::Iiqq, &mut out),
            Err(CaptureError::Length {
                expected: 16,
                got: 12
            })
        );
        assert_eq!(
            deinterleave_bytes(&bytes[..12], IqOrder::Iiqq, &mut out[..3]),
            Err(CaptureError::OddSampleCount(3))
        );
    }
}
