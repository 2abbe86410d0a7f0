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
//! adds their magnitudes (the parabola term of [`super::mode_bounds`]) is 2x to 600x the true
//! error on the family of docs/accuracy.md, this is within 3x of it in most runs (not a bound:
//! measured down to a third). Force jumps keep their first-order term ([`super::jumps`]),
//! added in magnitude.

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};

use super::ModalRun;
use crate::kernel::oscillator::Transfer;

/// Saved rows per block of the combination (the errors of a block, then one product).
const ROWS: usize = 256;

/// A 2 x 2 matrix acting on `(q, v)`.
type M2 = [[f64; 2]; 2];

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
struct Interval {
    carry: M2,
    local: [f64; 2],
}

fn interval(w: f64, c: f64, run: &ModalRun<'_>, m: usize) -> Interval {
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
    Interval { carry, local }
}

/// Per row `r` of the `(g, n)` row-major matrix `signed` (the mode shapes, with their signs,
/// at a saved dof or along an element's deformation), the largest magnitude over the run of
/// `sum_m signed[r, m] e_m(t)`, `e_m` mode `m`'s propagated displacement error, plus
/// `sum_m |signed[r, m]| jumps[m]` (the force jumps' errors, `jumps` per mode). `w` per mode
/// is the propagation's frequency (not finite: a coordinate without inertia, no error).
/// Zeros for fewer than three saved instants.
pub(super) fn row_errors(
    run: &ModalRun<'_>,
    w: &[f64],
    jumps: &[f64],
    signed: &[f64],
    g: usize,
) -> Vec<f64> {
    let n = run.omega.len();
    let rows = run.rows;
    let mut out = vec![0.0; g];
    if rows < 3 || n == 0 || g == 0 {
        return out;
    }
    let p = run.pseudo;
    let steps: Vec<Option<Interval>> = (0..n)
        .map(|m| {
            let c = run.c[m];
            let c = if c.is_finite() && c > 0.0 { c } else { 0.0 };
            (run.omega[m].is_finite() && w[m].is_finite()).then(|| interval(w[m], c, run, m))
        })
        .collect();
    // the second difference at saved row r (1 ..= rows - 2), the ends taking their neighbour's
    let second = |r: usize, m: usize| {
        let r = r.clamp(1, rows - 2);
        (p[(r + 1) * n + m] + p[(r - 1) * n + m]) - 2.0 * p[r * n + m]
    };
    let mut state = vec![[0.0_f64; 2]; n];
    let mut block = vec![0.0; ROWS * n];
    let mut combined = vec![0.0; ROWS * g];
    let weights = MatRef::from_row_major_slice(signed, g, n);
    let mut row = 1; // row 0 is the initial state: no error
    while row < rows {
        let count = (rows - row).min(ROWS);
        for i in 0..count {
            let r = row + i; // the error at saved row r, after interval r - 1 -> r
            for (m, step) in steps.iter().enumerate() {
                let Some(step) = step else {
                    block[i * n + m] = 0.0;
                    continue;
                };
                let d2 = 0.5 * (second(r - 1, m) + second(r, m));
                let e = state[m];
                let a = &step.carry;
                let next = [
                    a[0][0] * e[0] + a[0][1] * e[1] + step.local[0] * d2,
                    a[1][0] * e[0] + a[1][1] * e[1] + step.local[1] * d2,
                ];
                state[m] = next;
                block[i * n + m] = next[0];
            }
        }
        let lhs = MatRef::from_row_major_slice(&block[..count * n], count, n);
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
                if v.is_nan() {
                    *o = f64::NAN;
                } else if !o.is_nan() {
                    *o = o.max(v.abs());
                }
            }
        }
        row += count;
    }
    for (r, o) in out.iter_mut().enumerate() {
        let shapes = &signed[r * n..(r + 1) * n];
        *o += shapes
            .iter()
            .zip(jumps)
            .map(|(s, j)| s.abs() * j)
            .sum::<f64>();
    }
    out
}
