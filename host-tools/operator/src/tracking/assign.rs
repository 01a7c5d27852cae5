//! Optimal one-to-one assignment (the Hungarian method, shortest augmenting paths with
//! potentials): which detection each track takes so that the summed cost is least. The tracker
//! and its CLEAR-MOT score both call it. O(n² · m) for n rows ≤ m columns, exact for finite
//! costs.

/// The least-cost assignment of rows to columns of `cost` (row-major, `rows × cols`): for each
/// row, its column, or `None` where the row takes none. Pairs whose cost is at least `forbid`
/// are never made (the row and column stay unassigned instead), so `forbid` is the price of
/// leaving one unmatched.
///
/// ```
/// use metamoran_operator::tracking::assign::assign;
/// // Greedy would give row 0 its cheapest column (0, cost 1) and leave row 1 column 1 at 9;
/// // the optimum crosses over: 2 + 2 < 1 + 9.
/// let cost = [1.0, 2.0, 2.0, 9.0];
/// assert_eq!(assign(&cost, 2, 2, 100.0), vec![Some(1), Some(0)]);
/// // Only pairs under 1.5 may be made: row 1 stays unmatched.
/// assert_eq!(assign(&cost, 2, 2, 1.5), vec![Some(0), None]);
/// ```
pub fn assign(cost: &[f64], rows: usize, cols: usize, forbid: f64) -> Vec<Option<usize>> {
    if rows == 0 || cost.len() < rows * cols {
        return vec![None; rows];
    }
    // Square problem of rows + cols: each row may take a real column or its own "unmatched"
    // column, at `forbid`; each real column may be left to a dummy row at no cost.
    let n = rows + cols;
    let big = forbid.max(0.0);
    let at = |r: usize, c: usize| -> f64 {
        match (r < rows, c < cols) {
            (true, true) => {
                let v = cost[r * cols + c];
                if v.is_finite() && v < big {
                    v
                } else {
                    big * 2.0 + 1.0
                }
            }
            (true, false) => {
                if c - cols == r {
                    big
                } else {
                    big * 2.0 + 1.0
                }
            }
            // A dummy row takes a real column left unmatched, or the unmatched column of a row
            // that found a real one: free either way.
            (false, _) => 0.0,
        }
    };
    let matched = hungarian(n, at);
    (0..rows)
        .map(|r| {
            let c = matched[r];
            (c < cols && at(r, c) < big).then_some(c)
        })
        .collect()
}

/// The classic potentials method on an `n × n` cost given by `at`: the column of each row.
fn hungarian(n: usize, at: impl Fn(usize, usize) -> f64) -> Vec<usize> {
    // 1-based arrays, column 0 a sentinel (as in the textbook formulation).
    let (mut u, mut v) = (vec![0.0f64; n + 1], vec![0.0f64; n + 1]);
    let (mut row_of, mut way) = (vec![0usize; n + 1], vec![0usize; n + 1]);
    for i in 1..=n {
        row_of[0] = i;
        let mut j0 = 0;
        let mut min_to = vec![f64::INFINITY; n + 1];
        let mut used = vec![false; n + 1];
        loop {
            used[j0] = true;
            let (i0, mut delta, mut j1) = (row_of[j0], f64::INFINITY, 0);
            for j in 1..=n {
                if !used[j] {
                    let cur = at(i0 - 1, j - 1) - u[i0] - v[j];
                    if cur < min_to[j] {
                        min_to[j] = cur;
                        way[j] = j0;
                    }
                    if min_to[j] < delta {
                        delta = min_to[j];
                        j1 = j;
                    }
                }
            }
            for j in 0..=n {
                if used[j] {
                    u[row_of[j]] += delta;
                    v[j] -= delta;
                } else {
                    min_to[j] -= delta;
                }
            }
            j0 = j1;
            if row_of[j0] == 0 {
                break;
            }
        }
        loop {
            let j1 = way[j0];
            row_of[j0] = row_of[j1];
            j0 = j1;
            if j0 == 0 {
                break;
            }
        }
    }
    let mut col_of = vec![0usize; n];
    for j in 1..=n {
        if row_of[j] > 0 {
            col_of[row_of[j] - 1] = j - 1;
        }
    }
    col_of
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every assignment of a small problem, tried: the least total (unmatched rows at
    /// `forbid`, pairs at or above it not allowed).
    fn brute(cost: &[f64], rows: usize, cols: usize, forbid: f64) -> f64 {
        fn go(r: usize, used: &mut Vec<bool>, c: &[f64], rows: usize, cols: usize, f: f64) -> f64 {
            if r == rows {
                return 0.0;
            }
            let mut best = f + go(r + 1, used, c, rows, cols, f);
            for j in 0..cols {
                if !used[j] && c[r * cols + j] < f {
                    used[j] = true;
                    best = best.min(c[r * cols + j] + go(r + 1, used, c, rows, cols, f));
                    used[j] = false;
                }
            }
            best
        }
        go(0, &mut vec![false; cols], cost, rows, cols, forbid)
    }

    #[test]
    fn assignments_are_optimal_against_exhaustive_search() {
        let mut x = 12345u64;
        let mut next = || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 33) as f64 / (1u64 << 31) as f64 * 10.0
        };
        for rows in 0..=5 {
            for cols in 0..=5 {
                for _ in 0..20 {
                    let cost: Vec<f64> = (0..rows * cols).map(|_| next()).collect();
                    let forbid = 6.0;
                    let got = assign(&cost, rows, cols, forbid);
                    let mut seen = vec![false; cols];
                    let mut total = 0.0;
                    for (r, c) in got.iter().enumerate() {
                        match c {
                            Some(c) => {
                                assert!(!seen[*c], "column {c} twice");
                                seen[*c] = true;
                                assert!(cost[r * cols + c] < forbid);
                                total += cost[r * cols + c];
                            }
                            None => total += forbid,
                        }
                    }
                    let best = brute(&cost, rows, cols, forbid);
                    assert!(
                        (total - best).abs() < 1e-9,
                        "{rows}×{cols}: {total} vs {best}"
                    );
                }
            }
        }
    }

    #[test]
    fn non_finite_costs_are_never_assigned() {
        let cost = [f64::NAN, 1.0, f64::INFINITY, 2.0];
        assert_eq!(assign(&cost, 2, 2, 5.0), vec![Some(1), None]);
    }
}
