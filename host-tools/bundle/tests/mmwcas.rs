//! MMWCAS-RF-EVM four-file captures (issue #19, part 3) against TI's own layout: device files
//! built from `readBinFile`'s indexing (`reshape(adc, numRX, numSamples, numChirpsPerLoop,
//! numLoops)`, column-major, I then Q), read back in our frame order.

use metamoran_bundle::RadarFile;
use metamoran_bundle::mmwcas::{DEVICES, index_bytes};
use metamoran_dsp::config::RadarConfig;
use std::path::Path;

const N: usize = 8;
const CHIRPS: usize = 12;
const LOOPS: usize = 2;
const FRAMES: usize = 3;

/// The MMWCAS-RF-EVM in TI's MIMO order (TX12 … TX1), its 16 RX master first.
fn config() -> RadarConfig {
    let b = metamoran_bundle::ti::Board::MmwcasRfEvm;
    let tx = (0..4).rev().flat_map(|d| (0..3).rev().map(move |c| (d, c)));
    RadarConfig {
        start_frequency_hz: 77e9,
        slope_hz_per_s: 30e12,
        sample_rate_hz: 10e6,
        adc_samples: N as u16,
        chirp_period_s: 60e-6,
        chirps_per_tx: LOOPS as u16,
        frames: 0,
        frame_period_s: 0.1,
        tx_positions: tx.map(|(d, c)| b.tx(d, c).unwrap().azimuth).collect(),
        rx_positions: (0..4)
            .flat_map(|d| (0..4).map(move |r| b.rx(d, r).unwrap().azimuth))
            .collect(),
        tx_order: (0..12).collect(),
    }
}

/// I and Q of (frame, device, loop, chirp, sample, rx): distinct everywhere.
fn value(f: usize, d: usize, l: usize, c: usize, s: usize, r: usize) -> (i16, i16) {
    let k = ((((f * 4 + d) * LOOPS + l) * CHIRPS + c) * N + s) * 4 + r;
    (
        (k as i16).wrapping_mul(3).wrapping_sub(7000),
        9000i16.wrapping_sub((k as i16).wrapping_mul(5)),
    )
}

/// Writes the four data and index files of `FRAMES` frames into `dir` as TI's reader lays them.
fn write_capture(dir: &Path) {
    let frame_bytes = (LOOPS * CHIRPS * N * 4 * 4) as u64;
    for (d, name) in DEVICES.iter().enumerate() {
        let mut words = Vec::new();
        for f in 0..FRAMES {
            // MATLAB column-major: rx fastest, then sample, then chirp, then loop.
            for l in 0..LOOPS {
                for c in 0..CHIRPS {
                    for s in 0..N {
                        for r in 0..4 {
                            let (i, q) = value(f, d, l, c, s, r);
                            words.extend_from_slice(&i.to_le_bytes());
                            words.extend_from_slice(&q.to_le_bytes());
                        }
                    }
                }
            }
        }
        std::fs::write(dir.join(format!("{name}_0000_data.bin")), words).unwrap();
        std::fs::write(
            dir.join(format!("{name}_0000_idx.bin")),
            index_bytes(FRAMES as u32, frame_bytes),
        )
        .unwrap();
    }
}

#[test]
fn a_cascade_capture_reads_in_our_frame_order() {
    let tmp = tempfile::tempdir().unwrap();
    write_capture(tmp.path());
    let mut file =
        RadarFile::open_mmwcas(&tmp.path().join("master_0000_data.bin"), config()).unwrap();
    assert_eq!(file.config().frames, FRAMES as u32);
    let mut frame = Vec::new();
    for f in 0..FRAMES {
        file.read_frame(f as u32, &mut frame).unwrap();
        assert_eq!(frame.len(), LOOPS * CHIRPS * 16 * N);
        for (l, c, d, r, s) in [
            (0, 0, 0, 0, 0),
            (1, 11, 3, 3, 7),
            (0, 5, 2, 1, 4),
            (1, 0, 1, 2, 3),
        ] {
            // Ours: [chirp][rx][sample], chirp = loop · 12 + chirp of the loop, rx = 4 · device + rx.
            let z = frame[((l * CHIRPS + c) * 16 + 4 * d + r) * N + s];
            assert_eq!(
                (z.re.0, z.im.0),
                value(f, d, l, c, s, r),
                "frame {f} ({l} {c} {d} {r} {s})"
            );
        }
    }
    // And back into one DCA1000-layout file: what the module under QEMU reads.
    let mut bin = Vec::new();
    file.write_dca1000(&mut bin).unwrap();
    let dca = tmp.path().join("radar.bin");
    std::fs::write(&dca, &bin).unwrap();
    let mut one = RadarFile::open(&dca, config(), metamoran_dsp::capture::IqOrder::Iiqq).unwrap();
    let mut again = Vec::new();
    for f in 0..FRAMES as u32 {
        file.read_frame(f, &mut frame).unwrap();
        one.read_frame(f, &mut again).unwrap();
        assert_eq!(frame, again, "frame {f}");
    }
    // The device's own round trip.
    let devices = metamoran_bundle::mmwcas::to_devices(file.config(), &frame);
    let mut back = Vec::new();
    metamoran_bundle::mmwcas::to_frame(file.config(), &devices, &mut back);
    assert_eq!(back, frame);
}

#[test]
fn a_broken_cascade_capture_names_its_file() {
    let open = |dir: &Path| {
        RadarFile::open_mmwcas(&dir.join("master_0000_data.bin"), config())
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    let tmp = tempfile::tempdir().unwrap();
    write_capture(tmp.path());
    // A slave's index disagrees.
    std::fs::write(tmp.path().join("slave2_0000_idx.bin"), index_bytes(2, 1)).unwrap();
    let e = open(tmp.path()).unwrap_err();
    assert!(
        e.contains("slave2_0000_idx.bin") && e.contains("numIdx"),
        "{e}"
    );
    // A data file short of its frames.
    write_capture(tmp.path());
    let p = tmp.path().join("slave3_0000_data.bin");
    let b = std::fs::read(&p).unwrap();
    std::fs::write(&p, &b[..b.len() - 4]).unwrap();
    let e = open(tmp.path()).unwrap_err();
    assert!(
        e.contains("slave3_0000_data.bin") && e.contains("indexed"),
        "{e}"
    );
    // A missing slave, a name that is no master's, a config without 16 receivers.
    write_capture(tmp.path());
    std::fs::remove_file(tmp.path().join("slave1_0000_data.bin")).unwrap();
    assert!(
        open(tmp.path())
            .unwrap_err()
            .contains("slave1_0000_data.bin")
    );
    let e = RadarFile::open_mmwcas(&tmp.path().join("radar.bin"), config()).unwrap_err();
    assert!(e.to_string().contains("master_NNNN_data.bin"), "{e}");
    let mut eight = config();
    eight.rx_positions.truncate(8);
    let e = RadarFile::open_mmwcas(&tmp.path().join("master_0000_data.bin"), eight).unwrap_err();
    assert!(e.to_string().contains("16"), "{e}");
}
