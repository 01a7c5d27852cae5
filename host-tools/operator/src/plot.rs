//! PNG plots (plotters, bitmap backend) of an [`ObjectView`]: the range–azimuth maps before and
//! after SIC side by side and the correlation score `P(d)`; and of a frame's fused depth image
//! with one object picked out.
//!
//! Labels need a TrueType font; plotters' `ab_glyph` backend takes one from memory, so the first
//! plot reads DejaVu Sans from the usual system places (or `METAMORAN_FONT`) and registers it.

use crate::OperatorError;
use crate::depth_image::rasterize;
use metamoran_bundle::geometry::CameraModel;
use metamoran_process::FrameResult;
use metamoran_process::inspect::{AZIMUTH_STEP_DEG, MAX_AZIMUTH_DEG, Map, ObjectView};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// Dynamic range of the maps' colour scale, dB below the strongest cell before SIC.
pub const DYNAMIC_RANGE_DB: f32 = 40.0;

/// Where the font is looked for, after `METAMORAN_FONT`.
const FONT_PATHS: [&str; 4] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/Library/Fonts/Arial Unicode.ttf",
];

/// Registers the label font once.
fn font() -> Result<(), OperatorError> {
    static FONT: OnceLock<Result<(), String>> = OnceLock::new();
    FONT.get_or_init(|| {
        let wanted = std::env::var("METAMORAN_FONT").ok();
        let path = wanted
            .iter()
            .map(String::as_str)
            .chain(FONT_PATHS)
            .find(|p| Path::new(p).is_file())
            .ok_or_else(|| {
                "no TrueType font for the plot labels: install DejaVu (apt-get install -y \
                 fonts-dejavu-core) or set METAMORAN_FONT=/path/to/font.ttf"
                    .to_owned()
            })?;
        let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
        plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            Box::leak(bytes.into_boxed_slice()),
        )
        .map_err(|_| format!("{path}: not a TrueType/OpenType font (METAMORAN_FONT)"))
    })
    .clone()
    .map_err(OperatorError::Font)
}

/// `lo..hi` if both ends are finite and `lo < hi`: the plotting library loops forever over an
/// infinite axis (issue #18, item 5), so no plot is drawn on one.
fn finite_axis(lo: f64, hi: f64) -> Result<std::ops::Range<f64>, String> {
    if lo.is_finite() && hi.is_finite() && lo < hi {
        Ok(lo..hi)
    } else {
        Err(format!(
            "cannot draw an axis from {lo} to {hi}; the radar configuration gives no finite range"
        ))
    }
}

fn err(path: &Path) -> impl Fn(String) -> OperatorError + '_ {
    move |e| OperatorError::output(path, "draw the plot", e)
}

/// The maps before and after SIC side by side (1400 × 700): colour is power within
/// [`DYNAMIC_RANGE_DB`] of the strongest cell before SIC; white lines bound the object's span,
/// the magenta bar is the chosen depth across the span, red crosses the cancelled reflectors.
///
/// # Errors
/// [`OperatorError`] naming the file, or the missing font.
pub fn range_azimuth(path: &Path, frame: u32, view: &ObjectView) -> Result<(), OperatorError> {
    font()?;
    let root = BitMapBackend::new(path, (1400, 700)).into_drawing_area();
    let e = err(path);
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let hi = view.before.max_db();
    let lo = hi - DYNAMIC_RANGE_DB;
    let (left, right) = root.split_horizontally(700);
    let title = |what: &str| format!("frame {frame}, {} #{}: {what}", view.class, view.instance);
    map_panel(&left, &title("before SIC"), &view.before, view, (lo, hi)).map_err(&e)?;
    map_panel(
        &right,
        &title(&format!("after SIC ({} cancelled)", view.cancelled.len())),
        &view.after,
        view,
        (lo, hi),
    )
    .map_err(&e)?;
    root.present().map_err(|x| e(x.to_string()))
}

fn map_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    map: &Map,
    view: &ObjectView,
    (lo, hi): (f32, f32),
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let ranges = finite_axis(0.0, map.bins as f64 * map.bin_m)?;
    let max_range = ranges.end;
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(-MAX_AZIMUTH_DEG..MAX_AZIMUTH_DEG, 0.0..max_range)
        .map_err(|x| x.to_string())?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(format!(
            "azimuth (deg); colour: power, 0 to -{DYNAMIC_RANGE_DB} dB re the strongest cell"
        ))
        .y_desc("range (m)")
        .draw()
        .map_err(|x| x.to_string())?;
    let half = AZIMUTH_STEP_DEG / 2.0;
    chart
        .draw_series(map.azimuth_deg.iter().enumerate().flat_map(|(row, &a)| {
            (0..map.bins).map(move |k| {
                let db = map.db.get(row * map.bins + k).copied().unwrap_or(lo);
                let colour = ViridisRGB::get_color_normalized(db.clamp(lo, hi), lo, hi);
                Rectangle::new(
                    [
                        (a - half, k as f64 * map.bin_m),
                        (a + half, (k + 1) as f64 * map.bin_m),
                    ],
                    colour.filled(),
                )
            })
        }))
        .map_err(|x| x.to_string())?;
    let (s0, s1) = view.span_deg;
    for s in [s0, s1] {
        chart
            .draw_series(LineSeries::new(
                [(s, 0.0), (s, max_range)],
                WHITE.stroke_width(1),
            ))
            .map_err(|x| x.to_string())?;
    }
    chart
        .draw_series(LineSeries::new(
            [(s0, view.depth_m), (s1, view.depth_m)],
            MAGENTA.stroke_width(4),
        ))
        .map_err(|x| x.to_string())?
        .label(format!("chosen depth {:.2} m", view.depth_m))
        .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], MAGENTA.stroke_width(4)));
    chart
        .draw_series(
            view.cancelled
                .iter()
                .map(|&(r, a)| Cross::new((a, r), 7, RED.stroke_width(2))),
        )
        .map_err(|x| x.to_string())?
        .label("cancelled by SIC")
        .legend(|(x, y)| Cross::new((x + 8, y), 5, RED.stroke_width(2)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .draw()
        .map_err(|x| x.to_string())
}

/// The coarse score `P(d)` over the searched depths (900 × 450), the chosen depth and the
/// median floor marked.
///
/// # Errors
/// [`OperatorError`] naming the file, or the missing font.
pub fn score(path: &Path, frame: u32, view: &ObjectView) -> Result<(), OperatorError> {
    font()?;
    let e = err(path);
    let root = BitMapBackend::new(path, (900, 450)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let (d0, d1) = view
        .scores
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(d, _)| {
            (a.min(d), b.max(d))
        });
    let (d0, d1) = if d0 < d1 { (d0, d1) } else { (0.0, 1.0) };
    let top = view.scores.iter().map(|s| s.1).fold(view.floor, f32::max) as f64 * 1.1;
    let verdict = if view.detected {
        format!("{:.1} dB over the floor", view.confidence_db)
    } else {
        "not detected".to_owned()
    };
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "frame {frame}, {} #{}: P(d), chosen {:.2} m ({verdict})",
                view.class, view.instance, view.depth_m
            ),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(
            finite_axis(d0, d1).map_err(&e)?,
            finite_axis(0.0, top.max(1e-12)).map_err(&e)?,
        )
        .map_err(|x| e(x.to_string()))?;
    chart
        .configure_mesh()
        .x_desc("depth of the closest point (m)")
        .y_desc("correlation score P(d)")
        .y_label_formatter(&|v| format!("{v:.2e}"))
        .draw()
        .map_err(|x| e(x.to_string()))?;
    chart
        .draw_series(LineSeries::new(
            view.scores.iter().map(|&(d, s)| (d, s as f64)),
            BLUE.stroke_width(2),
        ))
        .map_err(|x| e(x.to_string()))?
        .label("P(d)")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLUE.stroke_width(2)));
    chart
        .draw_series(LineSeries::new(
            [(d0, view.floor as f64), (d1, view.floor as f64)],
            BLACK.mix(0.5).stroke_width(1),
        ))
        .map_err(|x| e(x.to_string()))?
        .label("median (floor)")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLACK.mix(0.5)));
    chart
        .draw_series(LineSeries::new(
            [(view.depth_m, 0.0), (view.depth_m, top)],
            MAGENTA.stroke_width(2),
        ))
        .map_err(|x| e(x.to_string()))?
        .label("chosen depth")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], MAGENTA.stroke_width(2)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .draw()
        .map_err(|x| e(x.to_string()))?;
    root.present().map_err(|x| e(x.to_string()))
}

/// Margin around the depth picture and its colour bar, px.
const DEPTH_MARGIN: u32 = 16;
/// Height of the depth picture's title and colour-bar areas, px.
const DEPTH_TITLE_PX: u32 = 36;
const DEPTH_BAR_PX: u32 = 64;

/// The frame's fused depth image (`depth_F.png`'s pixels, [`rasterize`]d through `camera`) as a
/// picture: object `instance`'s pixels coloured by camera depth (viridis from 0 m to the
/// frame's farthest point, scale below), the other objects' in grey, a white box and label
/// around the selected one. Each depth pixel is drawn 3 × 3 so sparse points show. The picture
/// is the camera's size plus margins, a title and the scale. O(pixels).
///
/// # Errors
/// [`OperatorError`] naming the file, or the missing font.
pub fn depth_image(
    path: &Path,
    camera: &CameraModel,
    frame: &FrameResult,
    instance: u16,
    title: &str,
) -> Result<(), OperatorError> {
    font()?;
    let e = err(path);
    let (w, h) = (camera.width, camera.height);
    let size = (w + 2 * DEPTH_MARGIN, h + DEPTH_TITLE_PX + DEPTH_BAR_PX);
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let (top, rest) = root.split_vertically(DEPTH_TITLE_PX);
    let (picture, bar) = rest.split_vertically(h);
    top.titled(title, ("sans-serif", 18))
        .map_err(|x| e(x.to_string()))?;
    let picture = picture.margin(0, 0, DEPTH_MARGIN, DEPTH_MARGIN);
    picture
        .fill(&RGBColor(24, 24, 24))
        .map_err(|x| e(x.to_string()))?;
    let pixels = rasterize(camera, frame);
    let farthest = pixels.iter().flatten().map(|p| p.0).fold(0.0, f64::max);
    // A round scale: the next 5 m above the farthest point.
    let scale_m = ((farthest / 5.0).ceil() * 5.0).max(5.0);
    let mut boxed: Option<(i32, i32, i32, i32)> = None;
    for (i, px) in pixels.iter().enumerate() {
        let Some((z, id)) = *px else { continue };
        let (u, v) = ((i % w as usize) as i32, (i / w as usize) as i32);
        let colour = if id == instance {
            boxed = Some(boxed.map_or((u, v, u, v), |(a, b, c, d)| {
                (a.min(u), b.min(v), c.max(u), d.max(v))
            }));
            ViridisRGB::get_color_normalized(z, 0.0, scale_m)
        } else {
            let g = (200.0 - 140.0 * (z / scale_m).clamp(0.0, 1.0)) as u8;
            RGBColor(g, g, g)
        };
        picture
            .draw(&Rectangle::new(
                [(u - 1, v - 1), (u + 2, v + 2)],
                colour.filled(),
            ))
            .map_err(|x| e(x.to_string()))?;
    }
    if let Some((u0, v0, u1, v1)) = boxed {
        picture
            .draw(&Rectangle::new(
                [(u0 - 4, v0 - 4), (u1 + 5, v1 + 5)],
                WHITE.stroke_width(2),
            ))
            .map_err(|x| e(x.to_string()))?;
        let label = frame
            .objects
            .iter()
            .find(|o| o.instance == instance)
            .map_or(String::new(), |o| match o.depth_m {
                Some(d) => format!("{} #{instance}: {d:.1} m", o.class),
                None => format!("{} #{instance}", o.class),
            });
        picture
            .draw(&Text::new(
                label,
                (u0 - 4, (v0 - 24).max(2)),
                ("sans-serif", 16).into_font().color(&WHITE),
            ))
            .map_err(|x| e(x.to_string()))?;
    }
    let mut chart = ChartBuilder::on(&bar)
        .margin_left(DEPTH_MARGIN)
        .margin_right(DEPTH_MARGIN)
        .margin_top(6)
        .x_label_area_size(34)
        .build_cartesian_2d(0.0..scale_m, 0.0..1.0)
        .map_err(|x| e(x.to_string()))?;
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_y_axis()
        .x_desc("camera depth (m); grey: other objects")
        .draw()
        .map_err(|x| e(x.to_string()))?;
    let step = scale_m / 200.0;
    chart
        .draw_series((0..200).map(|k| {
            let d = k as f64 * step;
            Rectangle::new(
                [(d, 0.0), (d + step, 1.0)],
                ViridisRGB::get_color_normalized(d + step / 2.0, 0.0, scale_m).filled(),
            )
        }))
        .map_err(|x| e(x.to_string()))?;
    root.present().map_err(|x| e(x.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use metamoran_bundle::CameraConfig;
    use metamoran_process::ObjectEstimate;

    const FX: f64 = 500.0;
    const CX: f64 = 320.0;
    const CY: f64 = 180.0;

    /// An object filling pixels `us × vs` at camera depth `z`: points by the pinhole's inverse
    /// (camera at the radar's origin, no rotation), not through `CameraModel`.
    fn object(
        instance: u16,
        us: std::ops::Range<u32>,
        vs: std::ops::Range<u32>,
        z: f64,
    ) -> ObjectEstimate {
        let points = us
            .flat_map(|u| vs.clone().map(move |v| (u, v)))
            .map(|(u, v)| {
                let x = (f64::from(u) + 0.5 - CX) * z / FX;
                let y = (f64::from(v) + 0.5 - CY) * z / FX;
                [x, y, z]
            })
            .collect();
        ObjectEstimate {
            depth_m: Some(z),
            points,
            ..ObjectEstimate::unprocessed(instance, "car")
        }
    }

    fn rgb(png: &[u8], width: usize, (u, v): (u32, u32)) -> [u8; 3] {
        let (x, y) = ((u + DEPTH_MARGIN) as usize, (v + DEPTH_TITLE_PX) as usize);
        let i = (y * width + x) * 3;
        [png[i], png[i + 1], png[i + 2]]
    }

    fn render(frame: &FrameResult, instance: u16) -> (Vec<u8>, usize) {
        let camera = CameraModel::new(&CameraConfig {
            width: 640,
            height: 360,
            fx: FX,
            fy: FX,
            cx: CX,
            cy: CY,
            translation_m: [0.0; 3],
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            roll_deg: 0.0,
        });
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("depth.png");
        depth_image(&path, &camera, frame, instance, "test").unwrap();
        let decoder =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        assert_eq!(
            (info.width, info.height),
            (640 + 2 * DEPTH_MARGIN, 360 + DEPTH_TITLE_PX + DEPTH_BAR_PX)
        );
        (buf, info.width as usize)
    }

    fn grey(c: [u8; 3]) -> bool {
        c[0] == c[1] && c[1] == c[2]
    }

    #[test]
    fn the_selected_object_is_coloured_by_depth_and_the_others_grey() {
        let near = object(1, 100..120, 150..160, 10.0);
        let far = object(2, 400..410, 100..140, 30.0);
        let frame = FrameResult::new(0, vec![near, far]);
        let (a, w) = render(&frame, 1);
        let (b, _) = render(&frame, 2);
        let (in_near, in_far, empty) = ((110, 155), (405, 120), (600, 300));
        assert!(!grey(rgb(&a, w, in_near)) && grey(rgb(&a, w, in_far)));
        assert!(grey(rgb(&b, w, in_near)) && !grey(rgb(&b, w, in_far)));
        assert_eq!(rgb(&a, w, empty), [24, 24, 24]);
        // Viridis' green rises with the value: the far object is greener than the near one.
        assert!(rgb(&a, w, in_near)[1] + 60 < rgb(&b, w, in_far)[1]);
        // The grey of the other objects darkens with depth.
        assert!(rgb(&b, w, in_near)[0] > rgb(&a, w, in_far)[0]);
    }
}
