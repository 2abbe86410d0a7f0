//! The error estimate of a semi-analytic run (issue 41): the per-mode bound of what the
//! pseudo-force quadrature left out, accumulated over the run from its saved modal history.
//!
//! The default step integrates the modal pseudo-force `Q(t)` as the straight line between
//! its values at the start and the end of the step; its local error is, to leading order,
//! the parabola `4 DDQ s (1 - s)` the line leaves out, `|DDQ| = |Q''| h^2 / 8`, read from the
//! second differences of the saved pseudo-force and entering each mode through that
//! parabola's moments (`(q, v)` at the end of a step from rest, computed by the caller). The
//! local errors are accumulated as amplitudes decaying with the mode's damping between
//! steps. The Python package (`duhamel._engine.accuracy`, docs/accuracy.md) says what the
//! bound means; this module is its arithmetic, one pass over the history after the loop
//! (a few microseconds where the same in numpy cost a fifth of a millisecond per call).

use crate::kernel::oscillator::Transfer;

mod jumps;
mod passes;
mod signed;
mod tangent;

use passes::{decaying_max_of_seconds, first_sums, floor_div, peak_of};

/// The run's history and step for [`mode_bounds`]: row-major `(rows, n)` arrays.
#[derive(Debug, Clone, Copy)]
pub struct ModalRun<'a> {
    /// The modal pseudo-force at the saved instants (`rows * n`, row-major).
    pub pseudo: &'a [f64],
    /// The modal displacements at the saved instants (`rows * n`, row-major).
    pub q: &'a [f64],
    /// Saved instants.
    pub rows: usize,
    /// Circular frequency per mode (`inf` for the coordinates of massless dofs).
    pub omega: &'a [f64],
    /// Modal damping per unit modal mass, per mode.
    pub c: &'a [f64],
    /// Per mode, the end state `(q, v)` of the parabola `4 s (1 - s)` over one internal step
    /// from rest (`n * 2`, row-major, [`parabola_moments`]).
    pub moments: &'a [f64],
    /// The internal step.
    pub h: f64,
    /// Internal steps between saved instants.
    pub k: usize,
    /// The run's duration.
    pub span: f64,
}

/// Per mode, the end state `(q, v)` of `q'' + c q' + omega^2 q = 4 s (1 - s)`, `s = t / h`,
/// from rest over one step `h` (`n * 2`, row-major): the `DDp` column of the exact step's
/// load transfer ([`Transfer::b`]). Zero for the quasi-static coordinates of massless dofs
/// (`omega` or `c` not finite).
pub fn parabola_moments(omega: &[f64], c: &[f64], h: f64) -> Vec<f64> {
    let mut out = vec![0.0; 2 * omega.len()];
    for ((o, c), end) in omega.iter().zip(c).zip(out.chunks_exact_mut(2)) {
        if o.is_finite() && c.is_finite() {
            let b = Transfer::new(o * o, *c, h).b();
            end.copy_from_slice(&[b[0][2], b[1][2]]);
        }
    }
    out
}

/// Per mode, the largest accumulated bound of the modal displacement error over the run
/// (zeros for fewer than three saved instants), plus the estimated errors of the force
/// jumps found in the history (`jumps`). Lengths must agree (`omega.len() = n`,
/// `pseudo.len() = q.len() = rows * n`, `moments.len() = 2 n`): the caller checks them.
pub fn mode_bounds(run: &ModalRun<'_>) -> Vec<f64> {
    let n = run.omega.len();
    if run.rows < 3 || n == 0 {
        return vec![0.0; n];
    }
    let first = first_sums(run.pseudo, run.q, n, run.rows);
    let jumps = jumps::jump_bounds(&first.jumps, run.pseudo, run.q, run.rows, run);
    bounds_from(run, &first, &jumps)
}

/// [`mode_bounds`] from the history's first pass and the jumps' errors per mode.
fn bounds_from(run: &ModalRun<'_>, first: &passes::FirstSums, jumps: &[f64]) -> Vec<f64> {
    let n = run.omega.len();
    let rows = run.rows;
    let p = run.pseudo;
    // |Q''| h^2 per internal step from the second differences (saved spacing k h), summed
    // per mode; the frequency at which a velocity error becomes a displacement error: the
    // background stiffened by the part of the pseudo-force in phase with the mode (a secant
    // over the run, never below omega); at least the drift over half the run for slow,
    // rigid modes. One pass over the history, row by row (no copy of it).
    let len = rows - 2;
    let passes::FirstSums { sums, qq, pq, .. } = first;
    let k = run.k as f64;
    let w = secant(run, qq, pq);
    let mut scale = vec![0.0; n];
    let mut decay = vec![0.0; n];
    let mut out = vec![0.0; n];
    for m in 0..n {
        let w = w[m];
        let (m0, m1) = (run.moments[2 * m], run.moments[2 * m + 1]);
        // |DDQ| = |Q''| h^2 / 8 per internal step, k of them per saved interval
        scale[m] = m0.hypot(m1 / w) / (8.0 * k);
        let c = run.c[m];
        let c = if c.is_finite() && c > 0.0 { c } else { 0.0 };
        decay[m] = (-0.5 * c * k * run.h).exp();
        out[m] = scale[m] * sums[m];
    }
    // the undamped sums bound the recurrence; the modes that make up 95 % of their total are
    // run through it, the others keep their sum (a bound within 5 % of the total)
    let total: f64 = out.iter().sum();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| out[a].total_cmp(&out[b]));
    let mut big = vec![true; n];
    let mut running = 0.0;
    for &m in &order {
        running += out[m];
        if running <= 0.05 * total {
            big[m] = false;
        }
    }
    let chosen: Vec<usize> = (0..n).filter(|&m| big[m]).collect();
    let top = decaying_max_of_seconds(p, n, len, &chosen, &decay);
    for (&m, t) in chosen.iter().zip(top) {
        out[m] = scale[m] * t;
    }
    // the first-order errors of force jumps inside steps, which the parabola does not see
    for (o, j) in out.iter_mut().zip(jumps) {
        *o += j;
    }
    out
}

/// Per mode, the frequency at which a velocity error becomes a displacement error: the
/// background stiffened by the part of the pseudo-force in phase with the mode (a secant
/// over the run, `-sum(p q) / sum(q q)`, never below omega); at least the drift over half
/// the run for slow, rigid modes (`qq`, `pq` the sums of `q q` and `p q` per mode).
fn secant(run: &ModalRun<'_>, qq: &[f64], pq: &[f64]) -> Vec<f64> {
    let floor = 2.0 / run.span.max(run.h);
    (0..run.omega.len())
        .map(|m| {
            let omega = if run.omega[m].is_finite() {
                run.omega[m]
            } else {
                0.0
            };
            let stiffening = -pq[m] / if qq[m] > 0.0 { qq[m] } else { 1.0 };
            (omega * omega + stiffening.max(0.0)).sqrt().max(floor)
        })
        .collect()
}

/// The run's error at each of the components of its quantities, the default estimate, and
/// its bound: per row of the `(g, n)` row-major `signed` (the mode shapes with their signs
/// at a saved dof, or along an element's deformation), the largest magnitude over the run of
/// the modes' propagated errors combined with those shapes, plus the force jumps' errors
/// (see [`signed`]); and the modes' [`mode_bounds`] combined in magnitude
/// ([`bound_rows`]). One first pass over the history for both. Zeros for fewer than three
/// saved instants. Lengths as for [`mode_bounds`], `signed.len()` a multiple of `n`.
pub fn row_errors(run: &ModalRun<'_>, signed: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = run.omega.len();
    if run.rows < 3 || n == 0 {
        let g = signed.len().checked_div(n).unwrap_or(0);
        return (vec![0.0; g], vec![0.0; g]);
    }
    let first = first_sums(run.pseudo, run.q, n, run.rows);
    let jumps = jumps::jump_bounds(&first.jumps, run.pseudo, run.q, run.rows, run);
    let w = secant(run, &first.qq, &first.pq);
    let bounds_per_mode = bounds_from(run, &first, &jumps);
    let mut errors = signed::row_errors(run, &w, &jumps, &bounds_per_mode, signed);
    let bounds = bound_rows(&bounds_per_mode, signed);
    tangent::raise(run, &jumps, &bounds_per_mode, signed, &bounds, &mut errors);
    (errors, bounds)
}

/// The largest of `errors` (per component row, [`row_errors`]) over `quantity`'s rows, over
/// the peak magnitude of its response (`history`: rows of `width` values): 0 where the
/// error is 0, infinite where the response's peak is 0 (or not a number) and the error is
/// not, NaN for a NaN error.
pub fn relative_rows(errors: &[f64], quantity: &Quantity, history: &[f64], width: usize) -> f64 {
    relative_both(errors, &[], quantity, history, width).0
}

/// [`relative_rows`] of `errors` and of `bounds` (empty: not asked, 0), the response's peak
/// read once for both.
pub fn relative_both(
    errors: &[f64],
    bounds: &[f64],
    quantity: &Quantity,
    history: &[f64],
    width: usize,
) -> (f64, f64) {
    let mut peak = None;
    let mut relative = |values: &[f64]| {
        if values.is_empty() {
            return 0.0;
        }
        let worst = worst_row(values, quantity);
        if quantity.rows.is_empty() || worst == 0.0 {
            return 0.0;
        }
        let peak = *peak.get_or_insert_with(|| peak_of(&quantity.columns, history, width));
        if peak > 0.0 {
            worst / peak
        } else {
            f64::INFINITY
        }
    };
    let errors = relative(errors);
    (errors, relative(bounds))
}

/// The largest of `values` over `quantity`'s rows (NaN if one of them is; `-inf` for none).
fn worst_row(values: &[f64], quantity: &Quantity) -> f64 {
    let mut worst = f64::NEG_INFINITY;
    for r in quantity.rows.clone() {
        let e = values[r];
        worst = if worst.is_nan() || e.is_nan() {
            f64::NAN
        } else {
            worst.max(e)
        };
    }
    worst
}

/// One quantity of a run whose error is estimated relative to its peak: its components'
/// error bounds are `weights` (row `i` of a row-major `(_, n)` matrix: the magnitudes of the
/// mode shapes there) times the modes' bounds; its response is read from `columns` of a
/// row-major history (`(a, None)`: column `a`; `(a, Some(b))`: column `a` minus column `b`,
/// a two-node deformation).
#[derive(Debug, Clone)]
pub struct Quantity {
    /// The rows of the weights matrix this quantity's components use.
    pub rows: std::ops::Range<usize>,
    /// The history's columns of its response (one per component).
    pub columns: Vec<(usize, Option<usize>)>,
}

/// Per row of the `(g, n)` row-major `shapes` (the mode shapes at a quantity's component,
/// their signs ignored), the modes' `bounds` combined in magnitude, `sum_m |shapes[r, m]|
/// bounds[m]` (NaN where a bound is NaN): the bound of that component's error.
pub fn bound_rows(bounds: &[f64], shapes: &[f64]) -> Vec<f64> {
    let n = bounds.len();
    if n == 0 {
        return vec![0.0; 0];
    }
    shapes
        .chunks_exact(n)
        .map(|row| row.iter().zip(bounds).map(|(w, b)| w.abs() * b).sum())
        .collect()
}

/// Per row `m` of `x` (`decay.len()` rows of `len` values, row-major), the largest `acc_i`
/// of `acc_{i+1} = decay[m] acc_i + x[m, i]` from `acc_0 = 0` (and 0 at least). Rows
/// decaying faster than `e^-0.5` a step take the bound `max(x) / (1 - decay)`; when the
/// slowest-decaying of the others allows it, they are lumped in groups of `g` values at
/// the groups' ends (`g rate <= 0.1`, the largest rate of those rows), a bound within
/// `e^0.2` of the recurrence, `g` times fewer values.
pub fn decaying_max(x: &[f64], len: usize, decay: &[f64]) -> Vec<f64> {
    let n = decay.len();
    let rate: Vec<f64> = decay.iter().map(|d| -d.clamp(1e-300, 1.0).ln()).collect();
    let mut best = vec![0.0; n];
    let row = |m: usize| &x[m * len..(m + 1) * len];
    // maxima that keep a NaN (a history that is not finite is not estimated)
    let most = |a: f64, b: f64| {
        if a.is_nan() || b.is_nan() {
            f64::NAN
        } else {
            a.max(b)
        }
    };
    let mut slow = Vec::with_capacity(n);
    for m in 0..n {
        if rate[m] > 0.5 {
            best[m] = row(m).iter().fold(0.0_f64, |a, &b| most(a, b)) / (1.0 - decay[m]);
        } else {
            slow.push(m);
        }
    }
    if slow.is_empty() || len == 0 {
        return best;
    }
    let fastest = slow.iter().map(|&m| rate[m]).fold(0.0_f64, f64::max);
    let g = if fastest > 0.0 {
        (len as f64).min(floor_div(0.1, fastest)) as usize
    } else {
        1 // undamped: running sums
    };
    for m in slow {
        let values = row(m);
        let (mut acc, mut top) = (0.0_f64, 0.0_f64);
        if g >= 2 {
            // groups of `g` values summed, the recurrence at the groups' ends; a last group
            // of the values left over (after whole groups: a zero input)
            let step = (-rate[m] * g as f64).exp();
            let whole = len / g * g;
            for group in values[..whole].chunks_exact(g) {
                acc = step * acc + group.iter().sum::<f64>();
                top = most(top, acc);
            }
            acc = step * acc + values[whole..].iter().sum::<f64>();
            top = most(top, acc);
            best[m] = top * (rate[m] * g as f64).exp();
        } else {
            let step = (-rate[m]).exp();
            for &v in values {
                acc = step * acc + v;
                top = most(top, acc);
            }
            best[m] = top;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The recurrence, value by value.
    fn recurrence(x: &[f64], d: f64) -> f64 {
        let (mut acc, mut top) = (0.0_f64, 0.0_f64);
        for &v in x {
            acc = d * acc + v;
            top = top.max(acc);
        }
        top
    }

    fn values(len: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        (0..len)
            .map(|i| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let u = (s >> 11) as f64 / (1u64 << 53) as f64;
                u * (0.01 * i as f64).sin().powi(2)
            })
            .collect()
    }

    #[test]
    fn decaying_max_is_the_recurrence_or_bounds_it_closely() {
        let len = 5001;
        for &d in &[1.0, 0.99999, 0.9999, 0.999, 0.9, 0.7] {
            let x = values(len, 7);
            let want = recurrence(&x, d);
            let got = decaying_max(&x, len, &[d])[0];
            assert!(got >= want * (1.0 - 1e-12), "{d}: {got} < {want}");
            assert!(
                got <= want * 0.2_f64.exp() * (1.0 + 1e-12),
                "{d}: {got} > {want}"
            );
        }
        // fast decay: the geometric bound, at most 1 / decay above the recurrence
        let x = values(100, 3);
        let d = 0.5;
        let (want, got) = (recurrence(&x, d), decaying_max(&x, 100, &[d])[0]);
        assert!(got >= want && got <= want / d);
    }

    #[test]
    fn parabola_moments_of_a_rigid_mode_are_the_polynomial_integrals() {
        // q'' = 4 s (1 - s), s = t / h, from rest: v(h) = 2 h / 3, q(h) = h^2 / 3
        let h = 0.3;
        let got = parabola_moments(&[0.0, f64::INFINITY], &[0.0, 1.0], h);
        assert!((got[0] - h * h / 3.0).abs() <= 1e-15 && (got[1] - 2.0 * h / 3.0).abs() <= 1e-15);
        assert_eq!(&got[2..], &[0.0, 0.0]);
    }

    #[test]
    fn floor_division_is_pythons() {
        assert_eq!(floor_div(0.1, 0.05), 2.0);
        assert_eq!(floor_div(0.1, 0.1), 1.0);
        assert_eq!(floor_div(0.1, 0.3), 0.0);
        assert_eq!(floor_div(0.1, 0.001), 100.0);
    }

    #[test]
    fn a_parabolic_pseudo_force_gives_its_second_difference_times_the_moment() {
        // one undamped rigid mode (omega 0) under Q = t^2 sampled at unit spacing: second
        // differences 2 everywhere, accumulated undamped over the run
        let rows = 11;
        let pseudo: Vec<f64> = (0..rows).map(|r| (r * r) as f64).collect();
        let q = vec![0.0; rows];
        let run = ModalRun {
            pseudo: &pseudo,
            q: &q,
            rows,
            omega: &[0.0],
            c: &[0.0],
            moments: &[3.0, 4.0],
            h: 1.0,
            k: 1,
            span: 10.0,
        };
        // w = 2 / span = 0.2: scale = hypot(3, 4 / 0.2) / 8
        let want = 3.0_f64.hypot(20.0) / 8.0 * 2.0 * (rows - 2) as f64;
        let got = mode_bounds(&run)[0];
        assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    }
}
