//! TI configs: the mmWave SDK `.cfg` reader (first byte even) and the mmWave Studio
//! `.mmwave.json` reader (odd) on any bytes, for every board. Either an `InputError` or a
//! configuration that validates.
#![no_main]
use libfuzzer_sys::fuzz_target;
use metamoran_bundle::ti::{Board, cfg, studio};
use std::path::Path;

fuzz_target!(|bytes: &[u8]| {
    let Some((&kind, rest)) = bytes.split_first() else {
        return;
    };
    let board = Board::ALL[usize::from(kind >> 1) % Board::ALL.len()];
    let parsed = if kind & 1 == 0 {
        let Ok(text) = std::str::from_utf8(rest) else {
            return;
        };
        cfg::parse(Path::new("x.cfg"), text, board)
    } else {
        studio::parse(Path::new("x.mmwave.json"), rest, Some(board))
    };
    if let Ok(c) = parsed {
        assert!(c.radar.validate().is_ok());
        assert_eq!(c.tx_elevation.len(), c.radar.tx_positions.len());
        assert_eq!(c.rx_elevation.len(), c.radar.rx_positions.len());
    }
});
