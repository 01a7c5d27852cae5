//! Stand-ins for the module's hardware on a host (feature `host-mock`; always in unit tests):
//! a serial line whose two directions are byte queues, and a deterministic nonce source. The
//! module's tests, the soak benchmark and the fuzz target drive the module through them.

extern crate std;
use std::collections::VecDeque;
use std::vec::Vec;

/// Both directions of a serial line: what the host wrote for the module (`rx`), what the
/// module wrote (`tx`). Writes fail while `refuse` is set.
#[derive(Debug, Default)]
pub struct Line {
    /// Bytes for the module to read.
    pub rx: VecDeque<u8>,
    /// Bytes the module wrote.
    pub tx: Vec<u8>,
    /// Refuse every write (a link that is down).
    pub refuse: bool,
}

impl embedded_io::ErrorType for Line {
    type Error = embedded_io::ErrorKind;
}

impl embedded_io::ReadReady for Line {
    fn read_ready(&mut self) -> Result<bool, Self::Error> {
        Ok(!self.rx.is_empty())
    }
}

impl embedded_io::Read for Line {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        match (self.rx.pop_front(), buf.first_mut()) {
            (Some(b), Some(out)) => {
                *out = b;
                Ok(1)
            }
            _ => Ok(0),
        }
    }
}

impl embedded_io::Write for Line {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        if self.refuse {
            return Err(embedded_io::ErrorKind::Other);
        }
        self.tx.extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// A deterministic nonce source: SplitMix64 from a seed (another seed per simulated boot, as a
/// TRNG would give another nonce). Not a secret: for tests only.
#[derive(Clone, Debug)]
pub struct SeededNonces(pub u64);

impl rand_core::TryRngCore for SeededNonces {
    type Error = core::convert::Infallible;

    fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
        self.try_next_u64().map(|v| v as u32)
    }

    fn try_next_u64(&mut self) -> Result<u64, Self::Error> {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        Ok(z ^ (z >> 31))
    }

    fn try_fill_bytes(&mut self, dest: &mut [u8]) -> Result<(), Self::Error> {
        for chunk in dest.chunks_mut(8) {
            let v = self.try_next_u64()?.to_le_bytes();
            chunk.copy_from_slice(&v[..chunk.len()]);
        }
        Ok(())
    }
}

impl rand_core::TryCryptoRng for SeededNonces {}
