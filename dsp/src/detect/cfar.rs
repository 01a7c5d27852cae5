//! CA-CFAR and OS-CFAR.
//!
//! For each cell under test, the noise level is estimated from `train` cells on each side
//! beyond `guard` cells that keep the target's own main lobe out: the mean (cell averaging) or
//! the k-th smallest (ordered statistic, robust to a second target in the window). A cell is a
//! detection when it exceeds `scale ×` that level. Inputs are power or magnitude, as the caller
//! chooses `scale` for.

use core::fmt;

/// Most training cells an OS-CFAR window may hold (its sort scratch lives on the stack).
pub const MAX_OS_CELLS: usize = 512;

/// How the noise level is estimated from the training cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CfarKind {
    /// The mean of the training cells.
    CellAveraging,
    /// The value at fraction `rank` (0..=1) of the sorted training cells (0.75 is typical).
    OrderedStatistic {
        /// Fraction of the sorted cells, 0 = smallest, 1 = largest.
        rank: f32,
    },
}

/// What happens where the window runs past the ends of an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    /// Use only the cells that exist (range axis).
    Truncate,
    /// Wrap around (Doppler and azimuth axes, which are circular).
    Wrap,
}

/// A 1D CFAR detector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cfar {
    /// Guard cells on each side.
    pub guard: usize,
    /// Training cells on each side.
    pub train: usize,
    /// Threshold factor over the noise estimate.
    pub scale: f32,
    /// Noise estimator.
    pub kind: CfarKind,
    /// Behaviour at the ends.
    pub boundary: Boundary,
}

/// One cell that crossed the threshold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detection {
    /// Index of the cell (row-major `row · cols + col` in 2D).
    pub index: usize,
    /// The cell's value.
    pub value: f32,
    /// The threshold it crossed.
    pub threshold: f32,
}

/// Why a CFAR could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum CfarError {
    /// The window holds more training cells than OS-CFAR can sort.
    TooManyTrainingCells(usize),
    /// The map size does not match `rows × cols`.
    Shape {
        /// `rows × cols`.
        expected: usize,
        /// Cells given.
        got: usize,
    },
}

impl core::error::Error for CfarError {}

impl fmt::Display for CfarError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooManyTrainingCells(n) => {
                write!(
                    f,
                    "{n} training cells: OS-CFAR sorts at most {MAX_OS_CELLS}; use fewer training cells"
                )
            }
            Self::Shape { expected, got } => write!(f, "map of {got} cells given for {expected}"),
        }
    }
}

/// Maps `i + offset` onto `0..len`, or `None` past a truncated edge.
fn neighbour(i: usize, offset: isize, len: usize, boundary: Boundary) -> Option<usize> {
    let j = i as isize + offset;
    match boundary {
        Boundary::Truncate => (0..len as isize).contains(&j).then_some(j as usize),
        Boundary::Wrap => Some(j.rem_euclid(len as isize) as usize),
    }
}

/// [`neighbour`] without a division where `i + offset` lies within one period of the axis
/// (every window no wider than the axis): the same index, for the 2D detector's inner loop.
#[inline(always)]
fn neighbour_fast(i: usize, offset: isize, len: usize, boundary: Boundary) -> Option<usize> {
    let (j, n) = (i as isize + offset, len as isize);
    if (0..n).contains(&j) {
        Some(j as usize)
    } else if boundary == Boundary::Truncate {
        None
    } else if (-n..0).contains(&j) {
        Some((j + n) as usize)
    } else if (n..2 * n).contains(&j) {
        Some((j - n) as usize)
    } else {
        neighbour(i, offset, len, boundary)
    }
}

/// The noise estimate of a set of training cells (NaN cells are ignored).
struct Estimator {
    kind: CfarKind,
    sum: f64,
    count: usize,
    cells: [f32; MAX_OS_CELLS],
}

impl Estimator {
    fn new(kind: CfarKind) -> Self {
        Self {
            kind,
            sum: 0.0,
            count: 0,
            cells: [0.0; MAX_OS_CELLS],
        }
    }

    fn reset(&mut self) {
        self.sum = 0.0;
        self.count = 0;
    }

    fn push(&mut self, v: f32) -> Result<(), CfarError> {
        if v.is_nan() {
            return Ok(());
        }
        match self.kind {
            CfarKind::CellAveraging => self.sum += v as f64,
            CfarKind::OrderedStatistic { .. } => {
                *self
                    .cells
                    .get_mut(self.count)
                    .ok_or(CfarError::TooManyTrainingCells(self.count + 1))? = v;
            }
        }
        self.count += 1;
        Ok(())
    }

    fn level(&mut self) -> Option<f32> {
        if self.count == 0 {
            return None;
        }
        Some(match self.kind {
            CfarKind::CellAveraging => (self.sum / self.count as f64) as f32,
            CfarKind::OrderedStatistic { rank } => {
                let cells = &mut self.cells[..self.count];
                let k = libm::roundf(rank.clamp(0.0, 1.0) * (self.count - 1) as f32) as usize;
                *cells.select_nth_unstable_by(k, f32::total_cmp).1
            }
        })
    }
}

impl Cfar {
    /// Runs over `x`, calling `emit` for each detection in index order; returns how many.
    /// O(N · train) for CA, O(N · train) expected for OS (quickselect).
    ///
    /// # Errors
    /// [`CfarError::TooManyTrainingCells`] if OS-CFAR's window exceeds `MAX_OS_CELLS`.
    pub fn detect(&self, x: &[f32], mut emit: impl FnMut(Detection)) -> Result<usize, CfarError> {
        let mut est = Estimator::new(self.kind);
        let mut found = 0;
        for (i, &v) in x.iter().enumerate() {
            est.reset();
            for d in (self.guard + 1)..=(self.guard + self.train) {
                for off in [-(d as isize), d as isize] {
                    if let Some(j) = neighbour(i, off, x.len(), self.boundary) {
                        est.push(x[j])?;
                    }
                }
            }
            if let Some(level) = est.level() {
                let threshold = self.scale * level;
                if v > threshold {
                    emit(Detection {
                        index: i,
                        value: v,
                        threshold,
                    });
                    found += 1;
                }
            }
        }
        Ok(found)
    }
}

/// A 2D CFAR over a row-major map (rows = range bins, cols = Doppler bins): the training region
/// is the rectangle `(guard + train)` cells around the cell minus the guard rectangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cfar2d {
    /// Guard and training cells along rows (range), with its boundary behaviour.
    pub rows: Cfar,
    /// Guard and training cells along columns (Doppler), with its boundary behaviour.
    pub cols: Cfar,
}

impl Cfar2d {
    /// Runs over `map` (`rows × cols`), using the threshold scale and estimator of `self.rows`.
    /// O(cells · window).
    ///
    /// # Errors
    /// [`CfarError`] if the shape is wrong or the OS window is too large.
    pub fn detect(
        &self,
        map: &[f32],
        rows: usize,
        cols: usize,
        emit: impl FnMut(Detection),
    ) -> Result<usize, CfarError> {
        self.detect_rows(map, rows, cols, 0..rows, emit)
    }

    /// [`Self::detect`] for the cells under test in rows `under_test` only (their training
    /// windows still reach the rows around them): the same detections of those rows, so parts
    /// of a map can be tested apart (on the host, one per thread). O(cells tested · window).
    ///
    /// # Errors
    /// [`CfarError`] if the shape is wrong or the OS window is too large.
    pub fn detect_rows(
        &self,
        map: &[f32],
        rows: usize,
        cols: usize,
        under_test: core::ops::Range<usize>,
        mut emit: impl FnMut(Detection),
    ) -> Result<usize, CfarError> {
        if map.len() != rows * cols {
            return Err(CfarError::Shape {
                expected: rows * cols,
                got: map.len(),
            });
        }
        let mut est = Estimator::new(self.rows.kind);
        let mut found = 0;
        for r in under_test.start.min(rows)..under_test.end.min(rows) {
            for c in 0..cols {
                let level = if self.rows.kind == CfarKind::CellAveraging {
                    // The estimator's sum by value (a register, not the estimator's memory):
                    // the same additions in the same order.
                    let (sum, count) = self.fold_training(
                        map,
                        (rows, cols),
                        (r, c),
                        (0.0f64, 0usize),
                        |(sum, count), v| {
                            Ok(if v.is_nan() {
                                (sum, count)
                            } else {
                                (sum + f64::from(v), count + 1)
                            })
                        },
                    )?;
                    (count > 0).then(|| (sum / count as f64) as f32)
                } else {
                    est.reset();
                    self.fold_training(map, (rows, cols), (r, c), (), |(), v| est.push(v))?;
                    est.level()
                };
                let v = map[r * cols + c];
                if let Some(level) = level {
                    let threshold = self.rows.scale * level;
                    if v > threshold {
                        emit(Detection {
                            index: r * cols + c,
                            value: v,
                            threshold,
                        });
                        found += 1;
                    }
                }
            }
        }
        Ok(found)
    }

    /// Folds `step` over each training cell of `(r, c)` in a `rows × cols` map, rows outer and
    /// columns inner, each once (the guard rectangle skipped, the boundaries applied). The
    /// accumulator goes by value, so a sum stays in registers.
    #[inline(always)]
    fn fold_training<A>(
        &self,
        map: &[f32],
        (rows, cols): (usize, usize),
        (r, c): (usize, usize),
        init: A,
        mut step: impl FnMut(A, f32) -> Result<A, CfarError>,
    ) -> Result<A, CfarError> {
        let (rg, rt) = (
            self.rows.guard as isize,
            (self.rows.guard + self.rows.train) as isize,
        );
        let (cg, ct) = (
            self.cols.guard as isize,
            (self.cols.guard + self.cols.train) as isize,
        );
        let mut acc = init;
        for dr in -rt..=rt {
            let Some(rr) = neighbour_fast(r, dr, rows, self.rows.boundary) else {
                continue;
            };
            for dc in -ct..=ct {
                if dr.abs() <= rg && dc.abs() <= cg {
                    continue;
                }
                if let Some(cc) = neighbour_fast(c, dc, cols, self.cols.boundary) {
                    acc = step(acc, map[rr * cols + cc])?;
                }
            }
        }
        Ok(acc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    fn noise_with_targets() -> Vec<f32> {
        let mut x: Vec<f32> = (0..128)
            .map(|i| 1.0 + 0.2 * ((i * 37 % 11) as f32 / 11.0))
            .collect();
        x[40] = 30.0;
        x[44] = 25.0; // a second target inside the first one's training window
        x[100] = 3.0; // too weak
        x
    }

    #[test]
    fn ca_and_os_find_targets_and_os_resists_masking() {
        let x = noise_with_targets();
        let base = Cfar {
            guard: 1,
            train: 6,
            scale: 5.0,
            kind: CfarKind::CellAveraging,
            boundary: Boundary::Truncate,
        };
        let mut ca = Vec::new();
        base.detect(&x, |d| ca.push(d.index)).unwrap();
        let os = Cfar {
            kind: CfarKind::OrderedStatistic { rank: 0.75 },
            ..base
        };
        let mut os_hits = Vec::new();
        os.detect(&x, |d| os_hits.push(d.index)).unwrap();
        assert_eq!(os_hits, [40, 44]);
        assert!(ca.contains(&40) && !ca.contains(&100));
        // CA's threshold at 44 is raised by the target at 40: 4 cells of 30 in 12 → masked at scale 5.
        let mut ca_strict = Vec::new();
        Cfar { scale: 8.0, ..base }
            .detect(&x, |d| ca_strict.push(d.index))
            .unwrap();
        assert!(!ca_strict.contains(&44));
    }

    #[test]
    fn closed_form_ca_threshold() {
        let x = [1.0, 2.0, 3.0, 100.0, 5.0, 6.0, 7.0];
        let cfar = Cfar {
            guard: 0,
            train: 3,
            scale: 2.0,
            kind: CfarKind::CellAveraging,
            boundary: Boundary::Wrap,
        };
        let mut d = Vec::new();
        cfar.detect(&x, |v| d.push(v)).unwrap();
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].index, 3);
        assert!((d[0].threshold - 2.0 * 24.0 / 6.0).abs() < 1e-6);
    }

    #[test]
    fn the_fast_neighbour_is_the_neighbour() {
        for len in [1usize, 2, 5, 16] {
            for boundary in [Boundary::Truncate, Boundary::Wrap] {
                for i in 0..len {
                    for offset in -40isize..=40 {
                        assert_eq!(
                            neighbour_fast(i, offset, len, boundary),
                            neighbour(i, offset, len, boundary),
                            "{len} {boundary:?} {i} {offset}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn two_d_in_parts_is_the_whole() {
        // A map with structure in both axes and targets near the edges, so windows wrap and
        // truncate; CA and OS, the parts split at every row.
        let (rows, cols) = (24, 16);
        let m: Vec<f32> = (0..rows * cols)
            .map(|i| match i {
                5 | 100 | 377 => 40.0,
                _ => 1.0 + ((i * 7919) % 13) as f32 / 5.0,
            })
            .collect();
        for kind in [
            CfarKind::CellAveraging,
            CfarKind::OrderedStatistic { rank: 0.75 },
        ] {
            let axis = |boundary| Cfar {
                guard: 1,
                train: 4,
                scale: 3.0,
                kind,
                boundary,
            };
            let cfar = Cfar2d {
                rows: axis(Boundary::Truncate),
                cols: axis(Boundary::Wrap),
            };
            let mut whole = Vec::new();
            cfar.detect(&m, rows, cols, |d| whole.push(d)).unwrap();
            assert!(whole.iter().any(|d| d.index == 5) && whole.iter().any(|d| d.index == 377));
            for split in 0..=rows {
                let mut parts = Vec::new();
                cfar.detect_rows(&m, rows, cols, 0..split, |d| parts.push(d))
                    .unwrap();
                cfar.detect_rows(&m, rows, cols, split..usize::MAX, |d| parts.push(d))
                    .unwrap();
                assert_eq!(parts, whole, "{kind:?} split at {split}");
            }
        }
    }

    /// The 2D CA threshold of every detection, bit for bit, from a brute-force window: every
    /// cell whose wrapped row and column offsets lie in the training rectangle and outside the
    /// guard, summed in f64 rows outer, columns inner (the order the detector promises), NaN
    /// cells skipped.
    #[test]
    fn two_d_ca_thresholds_are_the_brute_force_window_mean() {
        let (rows, cols) = (20, 16);
        let mut m: Vec<f32> = (0..rows * cols)
            .map(|i| 1.0 + ((i * 7919) % 17) as f32 / 3.0)
            .collect();
        m[37] = f32::NAN;
        let axis = |guard, train| Cfar {
            guard,
            train,
            scale: 1.5,
            kind: CfarKind::CellAveraging,
            boundary: Boundary::Wrap,
        };
        let cfar = Cfar2d {
            rows: axis(1, 3),
            cols: axis(2, 4),
        };
        let mut found = Vec::new();
        cfar.detect(&m, rows, cols, |d| found.push(d)).unwrap();
        assert!(found.len() > 20, "{} detections", found.len());
        for d in &found {
            let (r, c) = ((d.index / cols) as isize, (d.index % cols) as isize);
            let (mut sum, mut n) = (0.0f64, 0u32);
            for dr in -4isize..=4 {
                for dc in -6isize..=6 {
                    if dr.abs() <= 1 && dc.abs() <= 2 {
                        continue;
                    }
                    let rr = (r + dr).rem_euclid(rows as isize) as usize;
                    let cc = (c + dc).rem_euclid(cols as isize) as usize;
                    let v = m[rr * cols + cc];
                    if !v.is_nan() {
                        sum += f64::from(v);
                        n += 1;
                    }
                }
            }
            let expected = 1.5 * (sum / f64::from(n)) as f32;
            assert_eq!(
                d.threshold.to_bits(),
                expected.to_bits(),
                "cell {}",
                d.index
            );
        }
    }

    #[test]
    fn two_d_finds_a_cell_and_checks_shape() {
        let (rows, cols) = (32, 16);
        let mut m = std::vec![1.0f32; rows * cols];
        m[10 * cols + 3] = 50.0;
        let axis = Cfar {
            guard: 1,
            train: 3,
            scale: 6.0,
            kind: CfarKind::OrderedStatistic { rank: 0.75 },
            boundary: Boundary::Truncate,
        };
        let cfar = Cfar2d {
            rows: axis,
            cols: Cfar {
                boundary: Boundary::Wrap,
                ..axis
            },
        };
        let mut hits = Vec::new();
        cfar.detect(&m, rows, cols, |d| hits.push(d.index)).unwrap();
        assert_eq!(hits, [10 * cols + 3]);
        assert!(cfar.detect(&m[1..], rows, cols, |_| ()).is_err());
        let big = Cfar { train: 20, ..axis };
        assert_eq!(
            Cfar2d {
                rows: big,
                cols: Cfar {
                    boundary: Boundary::Wrap,
                    ..big
                }
            }
            .detect(&m, rows, cols, |_| ()),
            Err(CfarError::TooManyTrainingCells(MAX_OS_CELLS + 1))
        );
    }
}
