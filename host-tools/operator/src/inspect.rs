//! `metamoran inspect`'s products: the plots of [`metamoran_process::inspect`]'s views (drawn by
//! [`crate::plot`]) and the report of what was found and written.

use crate::OperatorError;
use crate::plot;
use metamoran_bundle::{Bundle, OpenOptions};
use metamoran_process::inspect::{ObjectView, inspect_frame};
use serde::Serialize;

/// Cancelled reflectors listed per object in the text summary.
const SHOWN_REFLECTORS: usize = 5;

/// Writes each view's plots into `out` as `frame<F>_obj<I>_range_azimuth.png` and
/// `frame<F>_obj<I>_score.png`; returns the file names.
///
/// # Errors
/// [`OperatorError`] naming the file that could not be written, or the missing font.
pub fn write_plots(
    out: &std::path::Path,
    frame: u32,
    views: &[ObjectView],
) -> Result<Vec<String>, OperatorError> {
    let mut files = Vec::new();
    for v in views {
        let map = format!("frame{frame}_obj{}_range_azimuth.png", v.instance);
        plot::range_azimuth(&out.join(&map), frame, v)?;
        let score = format!("frame{frame}_obj{}_score.png", v.instance);
        plot::score(&out.join(&score), frame, v)?;
        files.extend([map, score]);
    }
    Ok(files)
}

/// What `metamoran inspect` found and wrote.
#[derive(Clone, Debug, Serialize)]
pub struct InspectReport {
    /// The bundle folder.
    pub bundle: String,
    /// The frame inspected.
    pub frame: u32,
    /// The output folder.
    pub out: String,
    /// Files written into it.
    pub files: Vec<String>,
    /// Per object of interest.
    pub objects: Vec<ObjectView>,
}

impl std::fmt::Display for InspectReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "{} frame {}:", self.bundle, self.frame)?;
        for o in &self.objects {
            let verdict = match &o.verdict {
                Some(v) => format!(
                    "{:.1} dB; trust test: {:.2} m at confidence {:.2}{}",
                    o.confidence_db,
                    v.depth_m,
                    v.confidence,
                    if v.detected() { "" } else { ", not detected" }
                ),
                None => "no candidate".to_owned(),
            };
            writeln!(
                f,
                "  {} #{}: span {:+.1}..{:+.1}°, monocular {:.2} m, radar {:.2} m ({verdict})",
                o.class, o.instance, o.span_deg.0, o.span_deg.1, o.prior_m, o.depth_m
            )?;
            let shown: Vec<String> = o
                .cancelled
                .iter()
                .take(SHOWN_REFLECTORS)
                .map(|(r, a)| format!("{r:.1} m {a:+.1}°"))
                .collect();
            let more = o.cancelled.len().saturating_sub(SHOWN_REFLECTORS);
            writeln!(
                f,
                "    SIC cancelled {}: {}{}",
                o.cancelled.len(),
                shown.join(", "),
                if more > 0 {
                    format!(" and {more} more (--json lists all)")
                } else {
                    String::new()
                }
            )?;
            let candidates: Vec<String> = o
                .evidence
                .candidates
                .iter()
                .map(|c| {
                    let lobe = if c.survives { "" } else { " (side lobe)" };
                    format!("{:.2} m {:.1} dB{lobe}", c.depth_m, c.over_floor_db)
                })
                .collect();
            let window = match o.evidence.height {
                Some(h) => format!("{:.1}–{:.1} m", h.near_m, h.far_m),
                None => "none".to_owned(),
            };
            writeln!(
                f,
                "    candidates: {}; the mask's height allows {window}",
                candidates.join(", ")
            )?;
        }
        writeln!(f, "wrote {} plots to {}", self.files.len(), self.out)
    }
}

/// Opens the bundle in `dir`, inspects frame `frame` and writes its plots into `out` (created).
///
/// # Errors
/// [`OperatorError`] naming the bad file or field, the frame out of range, or what could not be written.
pub fn run(
    dir: &std::path::Path,
    frame: u32,
    out: &std::path::Path,
    options: OpenOptions,
) -> Result<InspectReport, OperatorError> {
    let mut bundle = Bundle::open(dir, options)?;
    let objects = inspect_frame(&mut bundle, frame)?;
    std::fs::create_dir_all(out)
        .map_err(|e| OperatorError::output(out, "create the output folder", e))?;
    let files = write_plots(out, frame, &objects)?;
    Ok(InspectReport {
        bundle: dir.display().to_string(),
        frame,
        out: out.display().to_string(),
        files,
        objects,
    })
}
