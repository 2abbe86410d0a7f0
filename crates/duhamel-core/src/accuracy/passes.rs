//! The passes of the error estimate ([`super::mode_bounds`], [`super::relative`]) over a
//! run's row-major history: by blocks of columns (one cache line of each row), each
//! column's arithmetic in row order, so that a history of few modes and many rows costs a
//! few nanoseconds per value rather than a loop over the columns of every row.

/// The magnitude of a second difference (the estimate's `|Q''| h^2` at the saved spacing).
fn second(a: f64, b: f64, c: f64) -> f64 {
    ((c + a) - 2.0 * b).abs()
}

/// Modes per block of the passes over a history: the history is read by blocks of
/// columns (one cache line of each row), each column's arithmetic in row order (the values
/// of a column-by-column pass, bit for bit), without a loop over the columns of every row.
const BLOCK: usize = 8;

/// Columns `b0..b0 + W` of row `r` of a row-major history of `n` columns.
#[inline(always)]
fn lanes<const W: usize>(x: &[f64], n: usize, r: usize, b0: usize) -> [f64; W] {
    let mut out = [0.0; W];
    out.copy_from_slice(&x[r * n + b0..r * n + b0 + W]);
    out
}

/// The sums of [`first_sums`] per mode, and its candidate jumps.
pub(super) struct FirstSums {
    pub sums: Vec<f64>,
    pub qq: Vec<f64>,
    pub pq: Vec<f64>,
    /// `(interval, mode, signed excess)`, by interval then mode ([`super::jumps::excess`]).
    pub jumps: Vec<(usize, usize, f64)>,
}

/// [`mode_bounds`](super::mode_bounds)'s first pass over a `(rows, n)` history (`rows` at
/// least 3): per mode, the sum of the second differences of the pseudo-force `p` and the
/// sums of `q q` and `p q` over the rows; the intervals whose change stands out from their
/// neighbours' (candidate jumps, a few operations per value of the same pass).
pub(super) fn first_sums(p: &[f64], q: &[f64], n: usize, rows: usize) -> FirstSums {
    if n == 1 {
        return first_sums_one(&p[..rows], &q[..rows]);
    }
    let (mut sums, mut qq, mut pq) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut jumps = Vec::new();
    // row by row, every column's arithmetic in row order (the compiler vectorises across
    // the columns of a row)
    let len = rows.saturating_sub(2);
    let mut before = vec![0.0; n]; // the change over the interval r - 1 -> r
    let mut excess = vec![0.0; n];
    for r in 0..rows {
        let (pr, qr) = (&p[r * n..(r + 1) * n], &q[r * n..(r + 1) * n]);
        for (((a, b), &x), &f) in qq.iter_mut().zip(pq.iter_mut()).zip(qr).zip(pr) {
            *a += x * x;
            *b += f * x;
        }
        if r < len {
            let (b, c) = (&p[(r + 1) * n..(r + 2) * n], &p[(r + 2) * n..(r + 3) * n]);
            // every slice of length n: no bounds check in the loop (which the compiler then
            // vectorises across the columns, the same arithmetic per column)
            let (sums, excess, before) = (&mut sums[..n], &mut excess[..n], &mut before[..n]);
            let mut any = false;
            for j in 0..n {
                sums[j] += second(pr[j], b[j], c[j]);
                // the interval r -> r + 1 between its neighbours: a jump's excess
                let (here, after) = (b[j] - pr[j], c[j] - b[j]);
                excess[j] = super::jumps::excess(before[j], here, after);
                any |= excess[j] != 0.0;
                before[j] = here;
            }
            if r > 0 && any {
                for (j, &e) in excess.iter().enumerate() {
                    if e != 0.0 {
                        jumps.push((r, j, e));
                    }
                }
            }
        }
    }
    FirstSums {
        sums,
        qq,
        pq,
        jumps,
    }
}

/// [`first_sums`] of a history of one mode (an SDOF's): the same arithmetic in the same
/// order on scalars, without the per-row slices and loops over one column (a third of the
/// pass's time on an SDOF's long run).
fn first_sums_one(p: &[f64], q: &[f64]) -> FirstSums {
    let rows = p.len();
    let (mut sums, mut qq, mut pq) = (0.0, 0.0, 0.0);
    let mut jumps = Vec::new();
    let len = rows.saturating_sub(2);
    let mut before = 0.0; // the change over the interval r - 1 -> r
    for r in 0..rows {
        let (f, x) = (p[r], q[r]);
        qq += x * x;
        pq += f * x;
        if r < len {
            let (b, c) = (p[r + 1], p[r + 2]);
            sums += second(f, b, c);
            let (here, after) = (b - f, c - b);
            let excess = super::jumps::excess(before, here, after);
            before = here;
            if r > 0 && excess != 0.0 {
                jumps.push((r, 0, excess));
            }
        }
    }
    FirstSums {
        sums: vec![sums],
        qq: vec![qq],
        pq: vec![pq],
        jumps,
    }
}

/// What [`decaying_block`] keeps per mode: the largest second difference, the largest
/// grouped recurrence, and whether a difference or the recurrence was not a number.
#[derive(Clone, Copy, Default)]
struct Decayed {
    peak: f64,
    top: f64,
    nan_difference: bool,
    nan_recurrence: bool,
}

/// The grouping of [`decaying_max_of_seconds`]: `g` values per group, the recurrence's
/// factor per group and mode, and whether a last partial group is pushed.
struct Grouping<'a> {
    g: usize,
    step: &'a [f64],
    leftover: bool,
}

/// [`decaying_max_of_seconds`]'s pass over columns `b0..b0 + W` (every column of the block
/// is computed; the caller keeps the chosen modes').
fn decaying_block<const W: usize>(
    p: &[f64],
    n: usize,
    len: usize,
    b0: usize,
    grouping: &Grouping<'_>,
    out: &mut [Decayed],
) {
    let mut step = [0.0; W];
    step.copy_from_slice(&grouping.step[b0..b0 + W]);
    let (mut peak, mut acc, mut top, mut sum) = ([0.0_f64; W], [0.0; W], [0.0_f64; W], [0.0; W]);
    let (mut nan_d, mut nan_r) = ([false; W], [false; W]);
    let mut push = |sum: &mut [f64; W]| {
        for j in 0..W {
            acc[j] = step[j] * acc[j] + sum[j];
            nan_r[j] |= acc[j].is_nan();
            top[j] = top[j].max(acc[j]);
            sum[j] = 0.0;
        }
    };
    let mut filled = 0;
    for r in 0..len {
        let (a, b, c) = (
            lanes::<W>(p, n, r, b0),
            lanes::<W>(p, n, r + 1, b0),
            lanes::<W>(p, n, r + 2, b0),
        );
        for j in 0..W {
            let d = second(a[j], b[j], c[j]);
            nan_d[j] |= d.is_nan();
            peak[j] = peak[j].max(d);
            sum[j] += d;
        }
        filled += 1;
        if filled == grouping.g {
            push(&mut sum);
            filled = 0;
        }
    }
    if grouping.leftover {
        push(&mut sum); // the values left over after whole groups (none: a zero input)
    }
    for j in 0..W {
        out[b0 + j] = Decayed {
            peak: peak[j],
            top: top[j],
            nan_difference: nan_d[j],
            nan_recurrence: nan_r[j],
        };
    }
}

/// [`decaying_max`] of the `modes`' second differences of the row-major history `p` (`n`
/// columns, `len + 2` rows), computed as they are read, one pass over the history by blocks
/// of columns (the same values, in the same order, as on the stored differences). A mode
/// whose differences (or, decaying slowly, whose recurrence) are not all numbers gets NaN.
pub(super) fn decaying_max_of_seconds(
    p: &[f64],
    n: usize,
    len: usize,
    modes: &[usize],
    decay: &[f64],
) -> Vec<f64> {
    let rate: Vec<f64> = decay.iter().map(|d| -d.clamp(1e-300, 1.0).ln()).collect();
    // a chosen mode decays fast (its largest difference bounds it) or slowly (its grouped
    // recurrence)
    let mut slow = vec![false; n];
    for &m in modes {
        slow[m] = rate[m] <= 0.5;
    }
    let fastest = (0..n)
        .filter(|&m| slow[m])
        .map(|m| rate[m])
        .fold(0.0_f64, f64::max);
    let g = if fastest > 0.0 {
        ((len as f64).min(floor_div(0.1, fastest)) as usize).max(1)
    } else {
        1 // undamped: running sums
    };
    let step: Vec<f64> = (0..n)
        .map(|m| {
            if slow[m] {
                (-rate[m] * g as f64).exp()
            } else {
                0.0
            }
        })
        .collect();
    let grouping = Grouping {
        g,
        step: &step,
        leftover: g >= 2 && slow.contains(&true) && len > 0,
    };
    let mut out = vec![Decayed::default(); n];
    let full = n / BLOCK * BLOCK;
    for b0 in (0..full).step_by(BLOCK) {
        decaying_block::<BLOCK>(p, n, len, b0, &grouping, &mut out);
    }
    for m in full..n {
        decaying_block::<1>(p, n, len, m, &grouping, &mut out);
    }
    modes
        .iter()
        .map(|&m| {
            let d = out[m];
            if d.nan_difference {
                f64::NAN
            } else if !slow[m] {
                d.peak / (1.0 - decay[m])
            } else if d.nan_recurrence {
                f64::NAN
            } else if len == 0 {
                0.0
            } else if g >= 2 {
                d.top * (rate[m] * g as f64).exp()
            } else {
                d.top
            }
        })
        .collect()
}

/// The largest magnitude of the response read from `columns` of `history` (rows of `width`
/// values; see [`Quantity::columns`]), NaN when one of them is not a number. Columns that
/// are the whole row in order (the saved dofs) are read as one run of values.
pub(super) fn peak_of(columns: &[(usize, Option<usize>)], history: &[f64], width: usize) -> f64 {
    if width == 0 {
        return 0.0;
    }
    let whole = columns.len() == width
        && columns
            .iter()
            .enumerate()
            .all(|(i, &(a, b))| a == i && b.is_none());
    let (mut peak, mut nan) = ([0.0_f64; BLOCK], false);
    if whole {
        let values = &history[..history.len() / width * width];
        let mut blocks = values.chunks_exact(BLOCK);
        for block in &mut blocks {
            for (p, v) in peak.iter_mut().zip(block) {
                nan |= v.is_nan();
                *p = p.max(v.abs());
            }
        }
        for v in blocks.remainder() {
            nan |= v.is_nan();
            peak[0] = peak[0].max(v.abs());
        }
    } else {
        for row in history.chunks_exact(width) {
            for &(a, b) in columns {
                let value = match b {
                    Some(b) => row[a] - row[b],
                    None => row[a],
                };
                nan |= value.is_nan();
                peak[0] = peak[0].max(value.abs());
            }
        }
    }
    if nan {
        f64::NAN
    } else {
        peak.iter().fold(0.0_f64, |a, &b| a.max(b))
    }
}

/// Python's `a // b` for positive floats (`float.__floordiv__`: from `fmod`, not the
/// rounded quotient), so that the grouping below is the one the estimate was defined with.
pub(super) fn floor_div(a: f64, b: f64) -> f64 {
    let rem = a % b;
    let div = (a - rem) / b;
    let floor = div.floor();
    if div - floor > 0.5 {
        floor + 1.0
    } else {
        floor
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accuracy::decaying_max;

    /// A `(rows, n)` history of pseudo-random values (a NaN at `nan`, if given).
    fn history(rows: usize, n: usize, seed: u64, nan: Option<usize>) -> Vec<f64> {
        let mut s = seed;
        let mut out: Vec<f64> = (0..rows * n)
            .map(|i| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * (1.0 + (i % 7) as f64)
            })
            .collect();
        if let Some(at) = nan {
            out[at] = f64::NAN;
        }
        out
    }

    #[test]
    fn blocked_passes_equal_column_by_column_ones_bit_for_bit() {
        for &n in &[1_usize, 3, 8, 9, 20] {
            let rows = 257;
            let (p, q) = (history(rows, n, 11, None), history(rows, n, 5, None));
            let FirstSums { sums, qq, pq, .. } = first_sums(&p, &q, n, rows);
            for m in 0..n {
                let col = |x: &[f64], r: usize| x[r * n + m];
                let (mut s, mut a, mut b) = (0.0, 0.0, 0.0);
                for r in 0..rows {
                    a += col(&q, r) * col(&q, r);
                    b += col(&p, r) * col(&q, r);
                    if r < rows - 2 {
                        s += second(col(&p, r), col(&p, r + 1), col(&p, r + 2));
                    }
                }
                assert_eq!((sums[m], qq[m], pq[m]), (s, a, b), "n = {n}, mode {m}");
            }
            // the decaying maxima of the chosen modes (fast and slow decays, every other
            // mode) equal decaying_max on their stored second differences
            let len = rows - 2;
            let decay: Vec<f64> = (0..n).map(|m| [1.0, 0.9999, 0.99, 0.3][m % 4]).collect();
            let modes: Vec<usize> = (0..n).step_by(2).collect();
            let mut stored = Vec::new();
            for &m in &modes {
                stored.extend(
                    (0..len).map(|r| second(p[r * n + m], p[(r + 1) * n + m], p[(r + 2) * n + m])),
                );
            }
            let chosen: Vec<f64> = modes.iter().map(|&m| decay[m]).collect();
            let want = decaying_max(&stored, len, &chosen);
            let got = decaying_max_of_seconds(&p, n, len, &modes, &decay);
            assert_eq!(got, want, "n = {n}");
        }
    }

    #[test]
    fn one_mode_pass_equals_the_columns_pass_with_its_jumps() {
        // three modes, each a smooth series with force jumps; every column alone through
        // the one-mode pass gives that column's sums and jump candidates, bit for bit
        let (rows, n) = (300, 3);
        let mut p = history(rows, n, 17, None);
        let q = history(rows, n, 23, None);
        for (r, value) in p.iter_mut().enumerate() {
            let (row, m) = (r / n, r % n);
            *value = 1e-3 * *value + (row as f64 * 0.01 * (m + 1) as f64).sin();
            if row % (40 + 7 * m) == 0 {
                *value += 5.0; // a jump the neighbours' changes do not explain
            }
        }
        let all = first_sums(&p, &q, n, rows);
        assert!(all.jumps.len() > 10, "{}", all.jumps.len());
        for m in 0..n {
            let column = |x: &[f64]| (0..rows).map(|r| x[r * n + m]).collect::<Vec<f64>>();
            let one = first_sums(&column(&p), &column(&q), 1, rows);
            assert_eq!(
                (one.sums[0], one.qq[0], one.pq[0]),
                (all.sums[m], all.qq[m], all.pq[m])
            );
            let want: Vec<(usize, usize, f64)> = all
                .jumps
                .iter()
                .filter(|j| j.1 == m)
                .map(|&(r, _, e)| (r, 0, e))
                .collect();
            assert_eq!(one.jumps, want, "mode {m}");
        }
    }

    #[test]
    fn a_difference_that_is_not_a_number_makes_its_mode_nan_only() {
        let (rows, n) = (40, 9);
        let p = history(rows, n, 3, Some(10 * n + 8)); // mode 8, row 10
        let decay = vec![0.99; n];
        let modes: Vec<usize> = (0..n).collect();
        let got = decaying_max_of_seconds(&p, n, rows - 2, &modes, &decay);
        assert!(got[8].is_nan());
        assert!(got[..8].iter().all(|v| v.is_finite()));
        let columns: Vec<(usize, Option<usize>)> = (0..n).map(|a| (a, None)).collect();
        assert!(peak_of(&columns, &p, n).is_nan());
        assert!(peak_of(&[(0, Some(1))], &p, n).is_finite());
    }
}
