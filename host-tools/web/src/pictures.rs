//! The selected track's pictures, drawn on request from the sensors' bundles (`DIR/<sensor>/`,
//! as `simulate --preset site` writes them or a pole records them) at the latest frame one of
//! its sensors detected it: the range–azimuth map before and after SIC (`metamoran inspect`'s
//! plot) and that frame's fused depth image with the track's object picked out.
//!
//! A sensor's bundle is processed once, on the first depth picture asked of it (about 0.2 s
//! for 40 frames of the site preset), and kept. Frame numbers that go on across a replay's
//! laps are taken modulo the bundle's frames.

use crate::{App, lock, session_user, unauthorized};
use axum::extract::State;
use axum::http::{HeaderMap, StatusCode, header};
use axum::response::{IntoResponse, Response};
use metamoran_bundle::Bundle;
use metamoran_bundle::geometry::CameraModel;
use metamoran_process::{FrameResult, Mode, ProcessOptions};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Which picture.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Picture {
    /// The range–azimuth map before and after SIC.
    RangeAzimuth,
    /// The frame's fused depth image.
    Depth,
}

/// The sensors' bundles and what has been processed of them.
pub(crate) struct Bundles {
    dir: PathBuf,
    processed: Mutex<HashMap<String, Arc<Vec<FrameResult>>>>,
}

impl Bundles {
    /// The bundles in `dir`, one folder per sensor id.
    pub(crate) fn new(dir: PathBuf) -> Self {
        Self {
            dir,
            processed: Mutex::new(HashMap::new()),
        }
    }

    /// Sensor `sensor`'s bundle, and its frame for the sensor's frame number `frame`.
    fn open(&self, sensor: &str, frame: u32) -> Result<(PathBuf, Bundle, u32), String> {
        // The sensor id is one of the site file's (a checked subject token): a folder name.
        let dir = self.dir.join(sensor);
        let bundle = Bundle::open(&dir, Default::default()).map_err(|e| e.to_string())?;
        let frames = bundle.frames();
        if frames == 0 {
            return Err(format!("{}: the bundle has no frames", dir.display()));
        }
        Ok((dir, bundle, frame % frames))
    }

    /// The sensor's processed frames (processed now if this is the first time).
    fn frames(&self, sensor: &str, dir: &Path) -> Result<Arc<Vec<FrameResult>>, String> {
        // Held while processing: a second request for the same sensor waits for the first.
        let mut processed = lock(&self.processed);
        if let Some(f) = processed.get(sensor) {
            return Ok(f.clone());
        }
        let out = metamoran_process::process(dir, &ProcessOptions::mode(Mode::Metamoran))
            .map_err(|e| e.to_string())?;
        let frames = Arc::new(out.frames);
        processed.insert(sensor.to_owned(), frames.clone());
        Ok(frames)
    }

    /// The PNG of `picture` for object `instance` at the sensor's frame `frame`.
    fn draw(
        &self,
        picture: Picture,
        track: u32,
        (sensor, frame, instance): (String, u32, u16),
    ) -> Result<Vec<u8>, String> {
        let (dir, bundle, frame) = self.open(&sensor, frame)?;
        let out = tempfile::tempdir().map_err(|e| e.to_string())?;
        let path = match picture {
            Picture::RangeAzimuth => {
                metamoran_operator::inspect::run(&dir, frame, out.path(), Default::default())
                    .map_err(|e| e.to_string())?;
                out.path()
                    .join(format!("frame{frame}_obj{instance}_range_azimuth.png"))
            }
            Picture::Depth => {
                let frames = self.frames(&sensor, &dir)?;
                let result = frames
                    .iter()
                    .find(|f| f.frame == frame)
                    .ok_or_else(|| format!("{}: no frame {frame}", dir.display()))?;
                let camera = CameraModel::new(&bundle.scene.camera);
                let path = out.path().join("depth.png");
                let title = format!("track {track}: {sensor} frame {frame}, fused depth image");
                metamoran_operator::plot::depth_image(&path, &camera, result, instance, &title)
                    .map_err(|e| e.to_string())?;
                path
            }
        };
        std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))
    }
}

/// `GET /api/track/{id}/{picture}`: `depth.png` or `range-azimuth.png` of track `id`, for a
/// logged-in operator.
pub(crate) async fn track_picture(
    State(app): State<Arc<App>>,
    headers: HeaderMap,
    axum::extract::Path((id, file)): axum::extract::Path<(u32, String)>,
) -> Response {
    if session_user(&app, &headers).is_none() {
        return unauthorized();
    }
    let picture = match file.as_str() {
        "depth.png" => Picture::Depth,
        "range-azimuth.png" => Picture::RangeAzimuth,
        _ => {
            return (
                StatusCode::NOT_FOUND,
                "pictures: depth.png, range-azimuth.png",
            )
                .into_response();
        }
    };
    if app.bundles.is_none() {
        return (
            StatusCode::NOT_FOUND,
            "pictures need the sensors' bundles: serve --bundles DIR (or --replay DIR)",
        )
            .into_response();
    }
    let sources = lock(&app.live).site().sources(id);
    let Some(source) = sources.into_iter().next() else {
        return (StatusCode::NOT_FOUND, "no detection of that track to draw").into_response();
    };
    let png = tokio::task::spawn_blocking(move || {
        app.bundles
            .as_ref()
            .map_or(Err(String::new()), |b| b.draw(picture, id, source))
    })
    .await;
    match png {
        Ok(Ok(png)) => ([(header::CONTENT_TYPE, "image/png")], png).into_response(),
        Ok(Err(e)) => (StatusCode::INTERNAL_SERVER_ERROR, e).into_response(),
        Err(_) => StatusCode::INTERNAL_SERVER_ERROR.into_response(),
    }
}
