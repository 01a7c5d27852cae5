//! `metamoran eval`: runs `process` over every bundle of a folder and reports errors against the
//! ground truth like the Metamoran paper's Table I: median absolute depth error and its spread
//! per method, per class and per range bin, the detection rate, the fraction of errors over 1 m
//! (the long tail), and the median modified Hausdorff distance of the depth-image points.

pub mod metrics;

use crate::ProcessError;
use crate::{Mode, ProcessOptions, process};
use metamoran_bundle::Truth;
use metrics::{median, modified_hausdorff, quantile, std_dev};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Range bins of the report, m (the paper's three, then longer ones).
pub const RANGE_BINS: [(f64, f64); 5] = [
    (0.0, 20.0),
    (20.0, 40.0),
    (40.0, 60.0),
    (60.0, 90.0),
    (90.0, 300.0),
];

/// A detection further than this from the truth, m, counts as confidently wrong.
pub const CONFIDENTLY_WRONG_M: f64 = 3.0;

/// One object in one frame under one mode.
#[derive(Clone, Debug, Serialize)]
pub struct Sample {
    /// Bundle folder name.
    pub bundle: String,
    /// Method.
    pub mode: Mode,
    /// Class.
    pub class: String,
    /// True depth, m.
    pub truth_m: f64,
    /// Signed error (estimate − truth), m; `None` when not detected.
    pub error_m: Option<f64>,
    /// Modified Hausdorff distance to the truth points, m.
    pub mhd_m: Option<f64>,
    /// The method's confidence that its depth is within 1 m, where it gives one.
    pub confidence: Option<f64>,
    /// Signed error of the depth the confidence is about (the chosen candidate, detected or
    /// not), m.
    pub judged_error_m: Option<f64>,
    /// Error of the reported radial velocity (estimate − truth), m/s, where the method reported
    /// one.
    pub velocity_error_mps: Option<f64>,
    /// What the trust test saw (the calibration's input: `eval --samples`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub evidence: Option<crate::trust::Evidence>,
}

/// Statistics of a group of samples.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Stats {
    /// Objects.
    pub n: usize,
    /// Fraction reported detected.
    pub detection_rate: f64,
    /// Median absolute depth error of detected objects, m.
    pub mae_m: Option<f64>,
    /// Standard deviation of the absolute errors, m.
    pub std_m: Option<f64>,
    /// 90th percentile of the absolute errors, m.
    pub p90_m: Option<f64>,
    /// Fraction of detected objects off by more than 1 m.
    pub over_1m: Option<f64>,
    /// Fraction of all objects reported detected yet more than [`CONFIDENTLY_WRONG_M`] off:
    /// the answers a perimeter sensor must not give (an alert in the wrong zone).
    pub confidently_wrong: f64,
    /// Median modified Hausdorff distance, m.
    pub mhd_m: Option<f64>,
}

impl Stats {
    fn of<'a>(samples: impl Iterator<Item = &'a Sample>) -> Self {
        let s: Vec<&Sample> = samples.collect();
        if s.is_empty() {
            return Self::default();
        }
        let abs: Vec<f64> = s.iter().filter_map(|x| x.error_m.map(f64::abs)).collect();
        let mhd: Vec<f64> = s.iter().filter_map(|x| x.mhd_m).collect();
        Self {
            n: s.len(),
            detection_rate: abs.len() as f64 / s.len() as f64,
            mae_m: median(&abs),
            std_m: std_dev(&abs),
            p90_m: quantile(&abs, 0.9),
            over_1m: (!abs.is_empty())
                .then(|| abs.iter().filter(|&&e| e > 1.0).count() as f64 / abs.len() as f64),
            confidently_wrong: abs.iter().filter(|&&e| e > CONFIDENTLY_WRONG_M).count() as f64
                / s.len() as f64,
            mhd_m: median(&mhd),
        }
    }
}

/// Edges of the reliability table's confidence bins.
pub const RELIABILITY_EDGES: [f64; 6] = [0.0, 0.2, 0.5, 0.8, 0.95, 1.0];

/// One row of a reliability table: objects whose confidence fell in `[lo, hi)`, and how often
/// their depth was within 1 m.
#[derive(Clone, Debug, Serialize)]
pub struct Reliability {
    /// Lower edge of the confidence bin.
    pub lo: f64,
    /// Upper edge (the last bin includes 1).
    pub hi: f64,
    /// Objects in the bin.
    pub n: usize,
    /// Their mean confidence (predicted).
    pub predicted: Option<f64>,
    /// Fraction whose judged depth was within 1 m (observed).
    pub observed: Option<f64>,
}

/// The reliability table of `samples` that carry a confidence (empty when none does).
pub fn reliability<'a>(samples: impl Iterator<Item = &'a Sample> + Clone) -> Vec<Reliability> {
    let judged = samples.filter_map(|s| Some((s.confidence?, s.judged_error_m?)));
    if judged.clone().next().is_none() {
        return Vec::new();
    }
    RELIABILITY_EDGES
        .windows(2)
        .map(|w| {
            let (lo, hi) = (w[0], w[1]);
            let last = hi >= 1.0;
            let inside: Vec<(f64, f64)> = judged
                .clone()
                .filter(|&(c, _)| c >= lo && (c < hi || (last && c <= hi)))
                .collect();
            let n = inside.len();
            let mean = |v: Vec<f64>| (n > 0).then(|| v.iter().sum::<f64>() / n as f64);
            Reliability {
                lo,
                hi,
                n,
                predicted: mean(inside.iter().map(|x| x.0).collect()),
                observed: mean(
                    inside
                        .iter()
                        .map(|x| f64::from(u8::from(x.1.abs() <= 1.0)))
                        .collect(),
                ),
            }
        })
        .collect()
}

/// The report of one mode.
#[derive(Clone, Debug, Serialize)]
pub struct ModeReport {
    /// All objects.
    pub all: Stats,
    /// Confidence against outcome, for methods that give a confidence.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub reliability: Vec<Reliability>,
    /// Per class.
    pub by_class: BTreeMap<String, Stats>,
    /// Per range bin ("0-20", …).
    pub by_range: BTreeMap<String, Stats>,
}

/// The whole report.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Bundles evaluated.
    pub bundles: usize,
    /// Per mode.
    pub modes: BTreeMap<String, ModeReport>,
    /// Bundles that could not be processed, with the reason.
    pub failed: Vec<String>,
}

fn range_key(lo: f64, hi: f64) -> String {
    format!("{lo:.0}-{hi:.0}")
}

/// The bundle folders inside `dir` (those with a scene.toml), sorted.
///
/// # Errors
/// [`ProcessError`] if `dir` cannot be listed or holds no bundle.
pub fn bundles_in(dir: &Path) -> Result<Vec<PathBuf>, ProcessError> {
    let entries = std::fs::read_dir(dir).map_err(|source| ProcessError::List {
        dir: dir.to_owned(),
        source,
    })?;
    let mut v: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.join("scene.toml").is_file())
        .collect();
    v.sort();
    if v.is_empty() {
        return Err(ProcessError::NoBundles {
            dir: dir.to_owned(),
        });
    }
    Ok(v)
}

/// Evaluates one bundle under every mode.
fn evaluate(dir: &Path, modes: &[Mode]) -> Result<Vec<Sample>, ProcessError> {
    let truth_path = dir.join("truth.json");
    let bundle = dir
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let mut samples = Vec::new();
    for &mode in modes {
        let out = process(dir, &ProcessOptions::mode(mode))?;
        let truth = Truth::read(&truth_path, out.frames.len() as u32)?;
        for f in &out.frames {
            let Some(tf) = truth.frames.iter().find(|t| t.frame == f.frame) else {
                continue;
            };
            for t in &tf.objects {
                let est = f.objects.iter().find(|o| o.instance == t.instance);
                let error_m = est
                    .and_then(|o| o.detected.then_some(o.depth_m).flatten())
                    .map(|d| d - t.depth_m);
                let mhd_m = est.and_then(|o| modified_hausdorff(&o.points, &t.points));
                let judged = est.and_then(|o| o.evidence.as_deref());
                samples.push(Sample {
                    bundle: bundle.clone(),
                    mode,
                    class: t.class.clone(),
                    truth_m: t.depth_m,
                    error_m,
                    mhd_m,
                    confidence: est.and_then(|o| o.confidence),
                    judged_error_m: judged
                        .and_then(|(_, v)| v.as_ref())
                        .map(|v| v.depth_m - t.depth_m),
                    evidence: judged.map(|(e, _)| e.clone()),
                    velocity_error_mps: est
                        .and_then(|o| o.radial_velocity_mps)
                        .map(|v| v - t.radial_velocity_mps),
                });
            }
        }
    }
    Ok(samples)
}

/// Evaluates every bundle in `dir` (in parallel) under `modes`; `done` is called (from any
/// thread) as each bundle is finished, for a progress bar.
///
/// # Errors
/// [`ProcessError`] if `dir` holds no bundle. Bundles that fail are listed in the report.
pub fn run(
    dir: &Path,
    modes: &[Mode],
    done: &(dyn Fn() + Sync),
) -> Result<(Report, Vec<Sample>), ProcessError> {
    let dirs = bundles_in(dir)?;
    let results: Vec<Result<Vec<Sample>, ProcessError>> = dirs
        .par_iter()
        .map(|d| {
            let r = evaluate(d, modes);
            done();
            r
        })
        .collect();
    let mut samples = Vec::new();
    let mut failed = Vec::new();
    for r in results {
        match r {
            Ok(s) => samples.extend(s),
            Err(e) => failed.push(e.to_string()),
        }
    }
    let mut reports = BTreeMap::new();
    for &mode in modes {
        let of_mode = || samples.iter().filter(move |s| s.mode == mode);
        let classes: std::collections::BTreeSet<&str> =
            of_mode().map(|s| s.class.as_str()).collect();
        let by_class = classes
            .into_iter()
            .map(|c| (c.to_owned(), Stats::of(of_mode().filter(|s| s.class == c))))
            .collect();
        let by_range = RANGE_BINS
            .iter()
            .map(|&(lo, hi)| {
                (
                    range_key(lo, hi),
                    Stats::of(of_mode().filter(|s| s.truth_m >= lo && s.truth_m < hi)),
                )
            })
            .filter(|(_, s)| s.n > 0)
            .collect();
        reports.insert(
            mode.name().to_owned(),
            ModeReport {
                all: Stats::of(of_mode()),
                reliability: reliability(of_mode()),
                by_class,
                by_range,
            },
        );
    }
    Ok((
        Report {
            bundles: dirs.len() - failed.len(),
            modes: reports,
            failed,
        },
        samples,
    ))
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let cell = |s: Option<&Stats>| match s {
            Some(s) if s.n > 0 => match (s.mae_m, s.std_m) {
                (Some(m), Some(d)) => format!("{m:6.2} {d:6.2} {:>3}", s.n),
                _ => format!("{:>6} {:>6} {:>3}", "—", "—", s.n),
            },
            _ => format!("{:>6} {:>6} {:>3}", "", "", ""),
        };
        writeln!(
            f,
            "Depth estimation, {} bundles: median absolute error (MAE) and standard deviation (STD) in metres, n objects",
            self.bundles
        )?;
        let mut head = format!("{:<10} {:^17}", "method", "all");
        for c in ["car", "sign", "person"] {
            head += &format!(" {c:^17}");
        }
        for (lo, hi) in RANGE_BINS {
            head += &format!(" {:^17}", format!("{lo:.0}–{hi:.0} m"));
        }
        writeln!(f, "{head}")?;
        for (name, r) in &self.modes {
            let mut line = format!("{name:<10} {}", cell(Some(&r.all)));
            for c in ["car", "sign", "person"] {
                line += &format!(" {}", cell(r.by_class.get(c)));
            }
            for (lo, hi) in RANGE_BINS {
                line += &format!(" {}", cell(r.by_range.get(&range_key(lo, hi))));
            }
            writeln!(f, "{line}")?;
        }
        writeln!(
            f,
            "\n{:<10} {:>10} {:>10} {:>10} {:>12} {:>18}",
            "method", "detected", "p90 m", "> 1 m", "median MHD m", "detected, > 3 m"
        )?;
        for (name, r) in &self.modes {
            let a = &r.all;
            let opt = |v: Option<f64>, pct: bool| {
                v.map_or("—".into(), |x| {
                    if pct {
                        format!("{:.1}%", 100.0 * x)
                    } else {
                        format!("{x:.2}")
                    }
                })
            };
            writeln!(
                f,
                "{name:<10} {:>10} {:>10} {:>10} {:>12} {:>18}",
                opt(Some(a.detection_rate), true),
                opt(a.p90_m, false),
                opt(a.over_1m, true),
                opt(a.mhd_m, false),
                opt(Some(a.confidently_wrong), true)
            )?;
        }
        for (name, r) in self.modes.iter().filter(|(_, r)| !r.reliability.is_empty()) {
            writeln!(
                f,
                "\n{name}: reliability (confidence that the depth is within 1 m)\n{:<12} {:>5} {:>10} {:>10}",
                "confidence", "n", "predicted", "observed"
            )?;
            for b in &r.reliability {
                let pct = |v: Option<f64>| v.map_or("—".into(), |x| format!("{:.0}%", 100.0 * x));
                writeln!(
                    f,
                    "{:<12} {:>5} {:>10} {:>10}",
                    format!("{:.2}–{:.2}", b.lo, b.hi),
                    b.n,
                    pct(b.predicted),
                    pct(b.observed)
                )?;
            }
        }
        for e in &self.failed {
            writeln!(f, "FAILED: {e}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{Mode, Sample, Stats};

    fn sample(error_m: Option<f64>) -> Sample {
        Sample {
            bundle: "b".into(),
            mode: Mode::Metamoran,
            class: "car".into(),
            truth_m: 20.0,
            error_m,
            mhd_m: None,
            confidence: None,
            judged_error_m: None,
            evidence: None,
            velocity_error_mps: None,
        }
    }

    #[test]
    fn confidently_wrong_counts_detections_over_3_m_among_all_objects() {
        let samples = [
            sample(Some(0.1)),
            sample(Some(5.0)),
            sample(None),
            sample(Some(-4.0)),
            sample(Some(3.0)),
        ];
        let s = Stats::of(samples.iter());
        assert_eq!(s.n, 5);
        assert_eq!(s.detection_rate, 0.8);
        // 5.0 and −4.0 are over 3 m; exactly 3.0 is not; the miss is not counted as wrong.
        assert_eq!(s.confidently_wrong, 0.4);
        assert_eq!(s.over_1m, Some(0.75));
    }
}
