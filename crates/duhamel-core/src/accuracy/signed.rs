//! The propagated (signed) error of the pseudo-force quadrature (issue 41): the local errors
//! of [`super::mode_bounds`]'s parabola term, carried with their signs by each mode's
//! linearised dynamics and combined with the signs of the mode shapes at every saved dof and
//! element.
//!
//! The local error of a step is the response to the parabola `4 DDQ s (1 - s)` the straight
//! line leaves out (`DDQ = -Q'' h^2 / 8`, `Q''` from the second differences of the saved
//! pseudo-force, the mean of the two ends of the saved interval), through the exact step's
//! moments. The global error obeys, to first order, the run's equation linearised about its
//! response: in a mode, `e'' + c e' + w^2 e = local errors`, with `w^2` the background's
//! `omega^2` stiffened by the part of the pseudo-force in phase with the mode (the secant over
//! the run of [`super::mode_bounds`]: the frequency at which the response, and with it its
//! phase error, turns). Carried at that frequency, the local errors of an oscillation's
//! cycles add where the response's phase drifts and cancel where they do not; a bound that
//! adds their magnitudes (the parabola term of [`super::mode_bounds`]) is 1.3x to 650x the
//! true error on the family of docs/accuracy.md, this was within 3x of it in 61 of its 68
//! runs (not a bound: measured 0.16x to 4x; low on yielding and contact, which
//! [`super::tangent`] raises in runs of one mode). Force jumps keep their first-order term
//! ([`super::jumps`]), added in magnitude.

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};

use super::ModalRun;
use crate::kernel::oscillator::Transfer;

/// Saved rows per block of the combination (the errors of a block, then one product).
pub(super) const ROWS: usize = 256;

/// A 2 x 2 matrix acting on `(q, v)`.
pub(super) type M2 = [[f64; 2]; 2];

fn mul(a: &M2, b: &M2) -> M2 {
    let mut out = [[0.0; 2]; 2];
    for (r, row) in out.iter_mut().enumerate() {
        for (c, x) in row.iter_mut().enumerate() {
            *x = a[r][0] * b[0][c] + a[r][1] * b[1][c];
        }
    }
    out
}

/// Per mode, what one saved interval does to the propagated error: `carry` its transition
/// over the `k` internal steps, `local` the error it adds per unit second difference of the
/// pseudo-force at the saved spacing (the `k` internal steps' parabola responses, each carried
/// to the interval's end).
#[derive(Clone, Copy)]
pub(super) struct Interval {
    pub carry: M2,
    pub local: [f64; 2],
    /// The transition over one internal step.
    pub step: M2,
}

pub(super) fn interval(w: f64, c: f64, run: &ModalRun<'_>, m: usize) -> Interval {
    let k = run.k;
    let a = Transfer::new(w * w, c, run.h).a;
    // DDQ per internal step = -D2 / (8 k^2), D2 the second difference at the saved spacing
    let unit = -1.0 / (8.0 * (k * k) as f64);
    let (m0, m1) = (run.moments[2 * m] * unit, run.moments[2 * m + 1] * unit);
    let mut carry = [[1.0, 0.0], [0.0, 1.0]];
    let mut local = [0.0; 2];
    for _ in 0..k {
        local = [
            a[0][0] * local[0] + a[0][1] * local[1] + m0,
            a[1][0] * local[0] + a[1][1] * local[1] + m1,
        ];
        carry = mul(&a, &carry);
    }
    Interval {
        carry,
        local,
        step: a,
    }
}

/// Per mode, the [`Interval`]s' entries as arrays (zeros for a mode without a step: its
/// error stays 0), for a recurrence over the modes that the compiler vectorises.
struct Coefficients {
    carry: [Vec<f64>; 4],
    local: [Vec<f64>; 2],
}

impl Coefficients {
    fn new(steps: &[Option<Interval>]) -> Self {
        let pick = |f: &dyn Fn(&Interval) -> f64| -> Vec<f64> {
            steps.iter().map(|s| s.as_ref().map_or(0.0, f)).collect()
        };
        Coefficients {
            carry: [
                pick(&|s| s.carry[0][0]),
                pick(&|s| s.carry[0][1]),
                pick(&|s| s.carry[1][0]),
                pick(&|s| s.carry[1][1]),
            ],
            local: [pick(&|s| s.local[0]), pick(&|s| s.local[1])],
        }
    }
}

/// The modes' propagated displacement errors at the saved rows `1..rows`, by blocks of up
/// to [`ROWS`] rows: `visit(block, count)` gets each block, row-major `(count, width)`: every
/// mode (`modes` None, `width = n`) or the `modes` given, in that order.
fn propagate(
    run: &ModalRun<'_>,
    coef: &Coefficients,
    modes: Option<&[usize]>,
    mut visit: impl FnMut(&[f64], usize),
) {
    let (n, rows, p) = (run.omega.len(), run.rows, run.pseudo);
    let width = modes.map_or(n, <[usize]>::len);
    // the second differences at saved row r (1 ..= rows - 2), the ends taking their
    // neighbour's
    let second = |r: usize, out: &mut [f64]| {
        let r = r.clamp(1, rows - 2);
        let (a, b, c) = (
            &p[(r - 1) * n..r * n],
            &p[r * n..(r + 1) * n],
            &p[(r + 1) * n..(r + 2) * n],
        );
        for (((o, a), b), c) in out.iter_mut().zip(a).zip(b).zip(c) {
            *o = (c + a) - 2.0 * b;
        }
    };
    let [a00, a01, a10, a11] = &coef.carry;
    let [l0, l1] = &coef.local;
    let (mut e0, mut e1) = (vec![0.0; n], vec![0.0; n]);
    let (mut before, mut here) = (vec![0.0; n], vec![0.0; n]);
    second(0, &mut before);
    // a short run's rows, not a whole block's (no buffer larger than the run's errors)
    let mut block = vec![0.0; ROWS.min(rows) * width];
    let mut row = 1; // row 0 is the initial state: no error
    while row < rows {
        let count = (rows - row).min(ROWS);
        for (i, out) in block[..count * width].chunks_exact_mut(width).enumerate() {
            // the error at saved row r, after the interval r - 1 -> r
            second(row + i, &mut here);
            {
                // every slice of length n: no bounds check in the loop (vectorised across
                // the modes, the same arithmetic per mode)
                let (e0, e1) = (&mut e0[..n], &mut e1[..n]);
                let (before, here) = (&before[..n], &here[..n]);
                let (a00, a01, a10, a11) = (&a00[..n], &a01[..n], &a10[..n], &a11[..n]);
                let (l0, l1) = (&l0[..n], &l1[..n]);
                for m in 0..n {
                    let d2 = 0.5 * (before[m] + here[m]);
                    let (x, v) = (e0[m], e1[m]);
                    e0[m] = a00[m] * x + a01[m] * v + l0[m] * d2;
                    e1[m] = a10[m] * x + a11[m] * v + l1[m] * d2;
                }
            }
            std::mem::swap(&mut before, &mut here);
            match modes {
                None => out.copy_from_slice(&e0),
                Some(modes) => {
                    for (o, &m) in out.iter_mut().zip(modes) {
                        *o = e0[m];
                    }
                }
            }
        }
        visit(&block[..count * width], count);
        row += count;
    }
}

/// The share of every row's bound (`sum_m |signed[r, m]| bound_m`, the modes' bounds of
/// [`super::mode_bounds`]) that the modes left out of the combination may make up: their
/// bound is added instead (an upper bound of their part), the modes' combination made with
/// the others only.
const LEFT_OUT: f64 = 1e-3;

/// Per row `r` of the `(g, n)` row-major matrix `signed` (the mode shapes, with their signs,
/// at a saved dof or along an element's deformation), the largest magnitude over the run of
/// `sum_m signed[r, m] e_m(t)`, `e_m` mode `m`'s propagated displacement error, plus
/// `sum_m |signed[r, m]| jumps[m]` (the force jumps' errors, `jumps` per mode); `w` per mode
/// is the propagation's frequency (not finite: a coordinate without inertia, no error).
///
/// One pass over the history, one matrix product per block of rows, with the modes that
/// make up all but [`LEFT_OUT`] of every row's bound `sum_m |signed[r, m]| bounds[m]`
/// (`bounds` per mode, each at least its mode's `max_t |e_m(t)|`: the local errors' sum in
/// magnitude), the others' bound added. Zeros for fewer than three saved instants.
pub(super) fn row_errors(
    run: &ModalRun<'_>,
    w: &[f64],
    jumps: &[f64],
    bounds: &[f64],
    signed: &[f64],
) -> Vec<f64> {
    let n = run.omega.len();
    let g = signed.len().checked_div(n).unwrap_or(0);
    let mut out = vec![0.0_f64; g];
    if run.rows < 3 || n == 0 || g == 0 {
        return out;
    }
    let steps: Vec<Option<Interval>> = (0..n)
        .map(|m| {
            let c = run.c[m];
            let c = if c.is_finite() && c > 0.0 { c } else { 0.0 };
            (run.omega[m].is_finite() && w[m].is_finite()).then(|| interval(w[m], c, run, m))
        })
        .collect();
    let row = |r: usize| &signed[r * n..(r + 1) * n];
    let stepped: Vec<usize> = (0..n).filter(|&m| steps[m].is_some()).collect();
    let Kept {
        modes,
        dropped,
        kept,
    } = kept_modes(n, &stepped, bounds, signed);
    let k = modes.len();
    if k > 0 {
        // few modes left out: the block of every mode, the others' weights zero
        let gather = 2 * k < n;
        let width = if gather { k } else { n };
        let columns: Vec<Option<usize>> = if gather {
            modes.iter().map(|&m| Some(m)).collect()
        } else {
            (0..n).map(|m| kept[m].then_some(m)).collect()
        };
        let shapes: Vec<f64> = (0..g)
            .flat_map(|r| {
                columns
                    .iter()
                    .map(move |c| c.map_or(0.0, |m| signed[r * n + m]))
            })
            .collect();
        let weights = MatRef::from_row_major_slice(&shapes, g, width);
        let mut combined = vec![0.0; ROWS.min(run.rows) * g];
        let coef = Coefficients::new(&steps);
        let subset = gather.then_some(modes.as_slice());
        propagate(run, &coef, subset, |block, count| {
            combine(&mut out, block, count, weights, &mut combined);
        });
    }
    for (r, o) in out.iter_mut().enumerate() {
        let jump: f64 = row(r).iter().zip(jumps).map(|(s, j)| s.abs() * j).sum();
        *o += dropped[r] + jump;
    }
    out
}

/// The modes of a combination ([`row_errors`]) and what the others leave: `modes` the ones
/// combined, in order; `dropped` per row the bound of the others; `kept` per mode.
pub(super) struct Kept {
    pub modes: Vec<usize>,
    pub dropped: Vec<f64>,
    pub kept: Vec<bool>,
}

/// Of the `stepped` modes, those that make up all but [`LEFT_OUT`] of every row's bound
/// `sum_m |signed[r, m]| bounds[m]` (the smallest contributions are left out first).
pub(super) fn kept_modes(n: usize, stepped: &[usize], bounds: &[f64], signed: &[f64]) -> Kept {
    let g = signed.len().checked_div(n).unwrap_or(0);
    let share = |r: usize, m: usize| signed[r * n + m].abs() * bounds[m];
    let weight: Vec<f64> = (0..n)
        .map(|m| (0..g).map(|r| share(r, m)).fold(0.0_f64, f64::max))
        .collect();
    let mut order = stepped.to_vec();
    order.sort_by(|&a, &b| weight[a].total_cmp(&weight[b]));
    let totals: Vec<f64> = (0..g)
        .map(|r| stepped.iter().map(|&m| share(r, m)).sum())
        .collect();
    let mut dropped = vec![0.0_f64; g];
    let mut kept = vec![true; n];
    for &m in &order {
        if !(0..g).all(|r| dropped[r] + share(r, m) <= LEFT_OUT * totals[r]) {
            break;
        }
        kept[m] = false;
        for (r, d) in dropped.iter_mut().enumerate() {
            *d += share(r, m);
        }
    }
    let modes = stepped.iter().copied().filter(|&m| kept[m]).collect();
    Kept {
        modes,
        dropped,
        kept,
    }
}

/// The most entries of a combination's weights formed row by row rather than by a matrix
/// product ([`combine`]).
const SMALL: usize = 16;

/// `out[r] = max(out[r], max_i |(block weights^T)[i, r]|)` over the `count` rows of the
/// row-major `block` (`count` x `weights.ncols()`), `combined` the product's scratch (NaN
/// kept once seen: `f64::max` would drop it).
pub(super) fn combine(
    out: &mut [f64],
    block: &[f64],
    count: usize,
    weights: MatRef<'_, f64>,
    combined: &mut [f64],
) {
    let (g, width) = (weights.nrows(), weights.ncols());
    if g * width <= SMALL {
        // a product too small for a matrix kernel's dispatch: row by row
        let mut w = [0.0; SMALL];
        for r in 0..g {
            for m in 0..width {
                w[r * width + m] = weights[(r, m)];
            }
        }
        for values in block[..count * width].chunks_exact(width) {
            for (o, row) in out.iter_mut().zip(w.chunks_exact(width)) {
                let v: f64 = values.iter().zip(row).map(|(x, s)| x * s).sum();
                *o = if o.is_nan() || v.is_nan() {
                    f64::NAN
                } else {
                    o.max(v.abs())
                };
            }
        }
        return;
    }
    let lhs = MatRef::from_row_major_slice(block, count, width);
    let mut dst = MatMut::from_row_major_slice_mut(&mut combined[..count * g], count, g);
    matmul(
        &mut dst,
        Accum::Replace,
        lhs,
        weights.transpose(),
        1.0,
        Par::Seq,
    );
    for values in combined[..count * g].chunks_exact(g) {
        for (o, v) in out.iter_mut().zip(values) {
            *o = if o.is_nan() || v.is_nan() {
                f64::NAN
            } else {
                o.max(v.abs())
            };
        }
    }
}
