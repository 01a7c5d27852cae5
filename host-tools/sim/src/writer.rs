//! Writing a scene bundle exactly as bundle.md lays it out.

use crate::SimError;
use metamoran_bundle::{AdcLayout, CameraConfig, FORMAT, Truth};
use metamoran_dsp::config::RadarConfig;
use std::path::Path;

fn io(path: &Path, e: impl Into<Box<dyn std::error::Error + Send + Sync>>) -> SimError {
    SimError::Write {
        path: path.to_owned(),
        source: e.into(),
    }
}

/// The `adc_file` each layout's bundles name.
pub fn adc_file(layout: AdcLayout) -> &'static str {
    match layout {
        AdcLayout::Dca1000 => "radar.bin",
        AdcLayout::Mmwcas => "master_0000_data.bin",
    }
}

/// `scene.toml` text for a radar and camera configuration, its samples stored as `layout`.
pub fn scene_toml(
    name: &str,
    radar: &RadarConfig,
    camera: &CameraConfig,
    layout: AdcLayout,
) -> String {
    let list = |v: &[i64]| {
        format!(
            "[{}]",
            v.iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    let tx: Vec<i64> = radar.tx_positions.iter().map(|&p| p as i64).collect();
    let rx: Vec<i64> = radar.rx_positions.iter().map(|&p| p as i64).collect();
    let order: Vec<i64> = radar.tx_order.iter().map(|&t| t as i64).collect();
    let t = camera.translation_m;
    format!(
        "format = \"{FORMAT}\"\nname = \"{name}\"\n\n[radar]\nstart_frequency_hz = {:?}\nslope_hz_per_s = {:?}\nsample_rate_hz = {:?}\n\
         adc_samples = {}\nchirp_period_s = {:?}\nchirps_per_tx = {}\nframes = {}\nframe_period_s = {:?}\ntx_positions = {}\n\
         rx_positions = {}\ntx_order = {}\nadc_file = \"{}\"\nadc_layout = \"{}\"\n\n[camera]\nwidth = {}\nheight = {}\n\
         fx = {:?}\nfy = {:?}\ncx = {:?}\ncy = {:?}\ntranslation_m = [{:?}, {:?}, {:?}]\nyaw_deg = {:?}\npitch_deg = {:?}\nroll_deg = {:?}\n",
        radar.start_frequency_hz,
        radar.slope_hz_per_s,
        radar.sample_rate_hz,
        radar.adc_samples,
        radar.chirp_period_s,
        radar.chirps_per_tx,
        radar.frames,
        radar.frame_period_s,
        list(&tx),
        list(&rx),
        list(&order),
        adc_file(layout),
        layout.name(),
        camera.width,
        camera.height,
        camera.fx,
        camera.fy,
        camera.cx,
        camera.cy,
        t[0],
        t[1],
        t[2],
        camera.yaw_deg,
        camera.pitch_deg,
        camera.roll_deg
    )
}

/// Writes a 16-bit grayscale PNG.
///
/// # Errors
/// [`SimError`] naming the file.
pub fn png16(path: &Path, width: u32, height: u32, values: &[u16]) -> Result<(), SimError> {
    let file = std::fs::File::create(path).map_err(|e| io(path, e))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Sixteen);
    enc.set_compression(png::Compression::Fast);
    let mut w = enc.write_header().map_err(|e| io(path, e))?;
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
    w.write_image_data(&bytes).map_err(|e| io(path, e))
}

/// Everything a simulated bundle holds.
pub struct BundleContents<'a> {
    /// Bundle name.
    pub name: &'a str,
    /// Radar configuration (one frame).
    pub radar: &'a RadarConfig,
    /// Camera configuration.
    pub camera: &'a CameraConfig,
    /// `radar.bin` bytes, every frame.
    pub adc: &'a [u8],
    /// Elevation of each TX, half-wavelengths (written only when one is not 0).
    pub tx_elevation: &'a [i16],
    /// How the samples are stored: `radar.bin`, or the MMWCAS board's four device files.
    pub layout: AdcLayout,
    /// The camera products of every frame.
    pub shots: &'a [super::Shot],
    /// The lidar-like truth of every frame (written as `lidar/F.ply` when there is one).
    pub lidar: &'a [Vec<[f64; 3]>],
    /// Ground truth.
    pub truth: &'a Truth,
}

/// Writes a bundle into folder `dir` (created).
///
/// # Errors
/// [`SimError`] naming the file that could not be written.
pub fn write(dir: &Path, b: &BundleContents<'_>) -> Result<(), SimError> {
    let cam = dir.join("camera");
    std::fs::create_dir_all(&cam).map_err(|e| io(&cam, e))?;
    let p = dir.join("scene.toml");
    let mut toml = scene_toml(b.name, b.radar, b.camera, b.layout);
    if b.tx_elevation.iter().any(|&e| e != 0) {
        // The README's extension of bundle.md: after the [radar] keys, before [camera].
        let list: Vec<String> = b.tx_elevation.iter().map(i16::to_string).collect();
        toml = toml.replacen(
            "\n\n[camera]",
            &format!("\ntx_elevation = [{}]\n\n[camera]", list.join(", ")),
            1,
        );
    }
    std::fs::write(&p, toml).map_err(|e| io(&p, e))?;
    match b.layout {
        AdcLayout::Dca1000 => {
            let p = dir.join("radar.bin");
            std::fs::write(&p, b.adc).map_err(|e| io(&p, e))?;
        }
        AdcLayout::Mmwcas => write_mmwcas(dir, b.radar, b.adc)?,
    }
    for (f, shot) in b.shots.iter().enumerate() {
        let paths = metamoran_bundle::CameraPaths::new(dir, f as u32);
        let (w, h) = (b.camera.width, b.camera.height);
        png16(&paths.mask, w, h, &shot.products.mask)?;
        png16(&paths.depth, w, h, &shot.products.depth_png)?;
        let p = &paths.instances;
        let json = serde_json::json!({ "instances": shot.instances });
        std::fs::write(p, serde_json::to_vec(&json).map_err(|e| io(p, e))?)
            .map_err(|e| io(p, e))?;
    }
    for (f, points) in b.lidar.iter().enumerate() {
        metamoran_bundle::lidar::write(&metamoran_bundle::lidar::path(dir, f as u32), points)?;
    }
    let p = dir.join("truth.json");
    std::fs::write(&p, serde_json::to_vec(b.truth).map_err(|e| io(&p, e))?).map_err(|e| io(&p, e))
}

/// The MMWCAS board's four data files and their index files of `adc` (`radar.bin`'s layout,
/// every frame) into `dir`.
fn write_mmwcas(dir: &Path, radar: &RadarConfig, adc: &[u8]) -> Result<(), SimError> {
    use metamoran_bundle::mmwcas;
    let frame_bytes = radar.samples_per_frame() * 4;
    let mut devices: [Vec<u8>; 4] = Default::default();
    let mut frame = vec![metamoran_dsp::fixed::CQ15::default(); radar.samples_per_frame()];
    for bytes in adc.chunks_exact(frame_bytes.max(1)) {
        metamoran_dsp::capture::deinterleave_bytes(
            bytes,
            metamoran_dsp::capture::IqOrder::Iiqq,
            &mut frame,
        )
        .map_err(|e| io(&dir.join("radar.bin"), e.to_string()))?;
        for (all, one) in devices.iter_mut().zip(mmwcas::to_devices(radar, &frame)) {
            all.extend_from_slice(&one);
        }
    }
    let frames = (adc.len() / frame_bytes.max(1)) as u32;
    for (name, data) in mmwcas::DEVICES.iter().zip(&devices) {
        let p = dir.join(format!("{name}_0000_data.bin"));
        std::fs::write(&p, data).map_err(|e| io(&p, e))?;
        let p = mmwcas::index_file(&p);
        std::fs::write(
            &p,
            mmwcas::index_bytes(frames, mmwcas::device_frame_bytes(radar)),
        )
        .map_err(|e| io(&p, e))?;
    }
    Ok(())
}
