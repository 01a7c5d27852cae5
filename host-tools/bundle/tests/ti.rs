//! TI configurations (issue #19): the mmWave SDK `.cfg` and mmWave Studio `.mmwave.json`
//! readers against hand-worked configurations, and every refusal naming its line or key.

use metamoran_bundle::ti::{Board, cfg, studio};
use metamoran_dsp::capture::IqOrder;
use std::path::Path;

/// The xWR18xx profile of the mmwave-capture-std capture, without its processing commands.
const CFG: &str = "\
% Platform:xWR18xx
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 5 0
adcCfg 2 1
adcbufCfg -1 0 1 1 1
profileCfg 0 77 429 7 57.14 0 0 70 1 256 5209 0 0 30
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 4
frameCfg 0 1 16 0 100 1 0
lowPower 0 0
guiMonitor -1 1 1 0 0 0 1
sensorStart
";

fn parse(text: &str) -> Result<metamoran_bundle::ti::CaptureConfig, String> {
    cfg::parse(Path::new("p.cfg"), text, Board::Xwr18xxBoost).map_err(|e| e.to_string())
}

#[test]
fn a_cfg_becomes_the_radar_config_it_describes() {
    let c = parse(CFG).unwrap();
    let r = &c.radar;
    assert_eq!(r.start_frequency_hz, 77e9);
    assert!((r.slope_hz_per_s - 70e12).abs() < 1.0);
    assert!((r.sample_rate_hz - 5.209e6).abs() < 1e-3);
    assert!((r.chirp_period_s - 486.14e-6).abs() < 1e-15);
    assert_eq!((r.adc_samples, r.chirps_per_tx, r.frames), (256, 16, 0));
    assert!((r.frame_period_s - 0.1).abs() < 1e-12);
    // channelCfg 15 5: RX0–3, TX0 and TX2; chirp 0 from TX0, chirp 1 from TX2.
    assert_eq!(r.tx_positions.as_slice(), &[0, 4]);
    assert_eq!(r.rx_positions.as_slice(), &[0, 1, 2, 3]);
    assert_eq!(r.tx_order.as_slice(), &[0, 1]);
    assert_eq!(c.iq_order, IqOrder::Qqii);
    assert_eq!(cfg::platform(CFG), Some(Board::Xwr18xxBoost));
    assert_eq!(cfg::platform("% Platform:xWR68xx\n"), None);
    // Three TX in TDM: TX1 is half a wavelength up on the BOOST board; no swap reads IIQQ.
    let three = CFG
        .replace("channelCfg 15 5 0", "channelCfg 15 7 0")
        .replace(
            "chirpCfg 1 1 0 0 0 0 0 4",
            "chirpCfg 1 1 0 0 0 0 0 2\nchirpCfg 2 2 0 0 0 0 0 4",
        )
        .replace("frameCfg 0 1 16", "frameCfg 0 2 16")
        .replace("adcbufCfg -1 0 1 1 1", "adcbufCfg -1 0 0 1 1");
    let c = parse(&three).unwrap();
    assert_eq!(c.radar.tx_positions.as_slice(), &[0, 2, 4]);
    assert_eq!(c.tx_elevation, [0, 1, 0]);
    assert_eq!(c.iq_order, IqOrder::Iiqq);
}

#[test]
fn what_the_cfg_reader_refuses_it_names() {
    let cases: &[(&str, &str, &str)] = &[
        (
            "guiMonitor -1 1 1 0 0 0 1",
            "advFrameCfg 1 0 0 1 0",
            "line 13: advFrameCfg",
        ),
        (
            "guiMonitor -1 1 1 0 0 0 1",
            "bpmCfg -1 1 0 1",
            "bpmCfg enabled",
        ),
        (
            "guiMonitor -1 1 1 0 0 0 1",
            "frobnicate 3",
            "line 13: frobnicate",
        ),
        (
            "chirpCfg 1 1 0 0 0 0 0 4",
            "chirpCfg 1 1 0 0 0 0 0 5",
            "line 10: chirpCfg txEnable",
        ),
        (
            "chirpCfg 1 1 0 0 0 0 0 4",
            "chirpCfg 1 1 0 0 0 0 0 2",
            "line 10: chirpCfg txEnable",
        ),
        (
            "chirpCfg 1 1 0 0 0 0 0 4",
            "chirpCfg 1 1 0 0 5 0 0 4",
            "freqSlopeVar",
        ),
        (
            "chirpCfg 1 1 0 0 0 0 0 4",
            "chirpCfg 1 1 1 0 0 0 0 4",
            "profileId",
        ),
        ("adcCfg 2 1", "adcCfg 2 0", "adcCfg adcOutputFmt"),
        ("adcCfg 2 1", "adcCfg 1 1", "adcCfg numADCBits"),
        (
            "adcbufCfg -1 0 1 1 1",
            "adcbufCfg -1 0 1 0 1",
            "ChanInterleave",
        ),
        ("dfeDataOutputMode 1", "dfeDataOutputMode 3", "modeType"),
        ("channelCfg 15 5 0", "channelCfg 15 5 2", "cascading"),
        (
            "frameCfg 0 1 16 0 100 1 0",
            "frameCfg 0 2 16 0 100 1 0",
            "chirp 2 of the frame",
        ),
        ("frameCfg 0 1 16 0 100 1 0", "", "frameCfg"),
        (
            "profileCfg 0 77 429 7 57.14 0 0 70 1 256 5209 0 0 30",
            "profileCfg 0 77 429 7 40 0 0 70 1 256 5209 0 0 30",
            "rampEndTime",
        ),
        (
            "profileCfg 0 77 429 7 57.14 0 0 70 1 256 5209 0 0 30",
            "profileCfg 0 77 429 7 57.14 0 0 seventy 1 256 5209 0 0 30",
            "freqSlopeConst",
        ),
    ];
    for (from, to, named) in cases {
        assert!(CFG.contains(from), "test bug: {from}");
        let err = parse(&CFG.replacen(from, to, 1)).unwrap_err();
        assert!(
            err.contains("p.cfg") && err.contains(named),
            "{to:?}: {err}"
        );
    }
    // A cascade is not one .cfg.
    let err = cfg::parse(Path::new("p.cfg"), CFG, Board::MmwcasRfEvm).unwrap_err();
    assert!(err.to_string().contains(".mmwave.json"), "{err}");
}

/// One device of a Studio export: RX mask, TX mask, and per chirp (start, end, txEnable).
fn device(
    id: u32,
    rx: &str,
    tx: &str,
    chirps: &[(u32, u32, &str)],
    frame_end: u32,
) -> serde_json::Value {
    serde_json::json!({
        "mmWaveDeviceId": id,
        "rfConfig": {
            "rlChanCfg_t": {"rxChannelEn": rx, "txChannelEn": tx, "cascading": 0},
            "rlAdcOutCfg_t": {"fmt": {"b2AdcBits": 2, "b8FullScaleReducFctr": 0, "b2AdcOutFmt": 1}},
            "rlProfiles": [{"rlProfileCfg_t": {
                "profileId": 0, "startFreqConst_GHz": 77.0, "idleTimeConst_usec": 5.0,
                "adcStartTimeConst_usec": 6.0, "rampEndTime_usec": 40.0,
                "freqSlopeConst_MHz_usec": 79.0, "numAdcSamples": 256, "digOutSampleRate": 8000.0,
                "txStartTime_usec": 0.0, "rxGain_dB": "0x30"}}],
            "rlChirps": chirps.iter().map(|&(s, e, t)| serde_json::json!({"rlChirpCfg_t": {
                "chirpStartIdx": s, "chirpEndIdx": e, "profileId": 0, "startFreqVar_MHz": 0.0,
                "freqSlopeVar_KHz_usec": 0.0, "idleTimeVar_usec": 0.0,
                "adcStartTimeVar_usec": 0.0, "txEnable": t}})).collect::<Vec<_>>(),
            "rlFrameCfg_t": {"chirpStartIdx": 0, "chirpEndIdx": frame_end, "numLoops": 64,
                             "numFrames": 8, "framePeriodicity_msec": 100.0}
        },
        "rawDataCaptureConfig": {"rlDevDataFmtCfg_t": {"iqSwapSel": 0, "chInterleave": 1}}
    })
}

fn studio(
    devices: Vec<serde_json::Value>,
    board: Option<Board>,
) -> Result<metamoran_bundle::ti::CaptureConfig, String> {
    let file = serde_json::json!({"configGenerator": {"createdBy": "mmWaveStudio"}, "mmWaveDevices": devices});
    studio::parse(
        Path::new("s.mmwave.json"),
        file.to_string().as_bytes(),
        board,
    )
    .map_err(|e| e.to_string())
}

#[test]
fn a_studio_export_of_one_device() {
    let one = || vec![device(0, "0xF", "0x5", &[(0, 0, "0x1"), (1, 1, "0x4")], 1)];
    let c = studio(one(), Some(Board::Xwr18xxBoost)).unwrap();
    assert_eq!(c.radar.tx_positions.as_slice(), &[0, 4]);
    assert_eq!(
        (c.radar.adc_samples, c.radar.chirps_per_tx, c.radar.frames),
        (256, 64, 8)
    );
    assert!((c.radar.chirp_period_s - 45e-6).abs() < 1e-15);
    assert_eq!(c.iq_order, IqOrder::Iiqq);
    let err = studio(one(), None).unwrap_err();
    assert!(err.contains("--board"), "{err}");
    let err = studio(
        vec![device(0, "0xF", "0x5", &[(0, 0, "0x3"), (1, 1, "0x4")], 1)],
        Some(Board::Xwr18xxBoost),
    )
    .unwrap_err();
    assert!(err.contains("rlChirps[0].rlChirpCfg_t.txEnable"), "{err}");
    let err = studio(
        vec![device(0, "zz", "0x5", &[(0, 0, "0x1"), (1, 1, "0x4")], 1)],
        Some(Board::Xwr18xxBoost),
    )
    .unwrap_err();
    assert!(err.contains("rxChannelEn") && err.contains("hex"), "{err}");
}

/// TI's MIMO script (`Cascade_Configuration_MIMO.lua`): chirps 0–2 from slave 3's TX2, TX1,
/// TX0, then slave 2, slave 1 and the master's likewise.
fn cascade(frame_end: u32) -> Vec<serde_json::Value> {
    (0..4u32)
        .map(|d| {
            let base = 3 * (3 - d);
            let chirps: Vec<(u32, u32, &str)> = (0..12u32)
                .map(|c| {
                    let tx = match c.checked_sub(base) {
                        Some(0) => "0x4",
                        Some(1) => "0x2",
                        Some(2) => "0x1",
                        _ => "0x0",
                    };
                    (c, c, tx)
                })
                .collect();
            device(d, "0xF", "0x7", &chirps, frame_end)
        })
        .collect()
}

#[test]
fn a_studio_export_of_the_cascade() {
    let c = studio(cascade(11), None).unwrap();
    assert_eq!(c.board, Board::MmwcasRfEvm);
    // TxToEnable = [12 11 … 1] of TI's reference: TX12 first, at azimuth 0.
    assert_eq!(
        c.radar.tx_positions.as_slice(),
        &[0, 4, 8, 12, 16, 20, 24, 28, 32, 9, 10, 11]
    );
    assert_eq!(c.tx_elevation, [0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 4, 6]);
    assert_eq!(
        c.radar.rx_positions.as_slice(),
        &[50, 51, 52, 53, 0, 1, 2, 3, 46, 47, 48, 49, 11, 12, 13, 14]
    );
    assert_eq!(c.radar.channels(), 192);
    // A chirp no device sends, and a board with another device count.
    let err = studio(cascade(12), None).unwrap_err();
    assert!(err.contains("chirp 12"), "{err}");
    let err = studio(cascade(11), Some(Board::Iwr6843Isk)).unwrap_err();
    assert!(err.contains("4 devices"), "{err}");
}
