//! The exact linear step of every mode, stored as a structure of arrays.
//!
//! The step forms the state's increment and adds it last (`A - 1` on the diagonal): a
//! product `A00 x` rounds at the scale of `x` on every step, and over many short steps those
//! roundings drift (the transition's determinant is off by an ulp: energy grows or decays
//! steadily — 7e-11 of the Duffing oscillator's energy over 256,000 steps); the increment
//! rounds at its own, much smaller, scale.

use crate::kernel::oscillator::Transfer;

/// The exact step's coefficients of every mode, one array per coefficient (structure of
/// arrays: the loop over the modes vectorises): `A - 1` (row-major) then `B` (row-major).
pub(super) type StepRows = [Vec<f64>; 10];

/// The rows of the transfer matrices of every mode.
pub(super) fn step_rows(transfers: &[Transfer]) -> StepRows {
    let mut rows: StepRows = std::array::from_fn(|_| Vec::with_capacity(transfers.len()));
    for tr in transfers {
        let ([_, a12], [a21, _]) = (tr.a[0], tr.a[1]);
        let [a11, a22] = tr.a_less_one;
        let [[b11, b12, b13], [b21, b22, b23]] = tr.b();
        let row = [a11, a12, a21, a22, b11, b12, b13, b21, b22, b23];
        for (column, value) in rows.iter_mut().zip(row) {
            column.push(value);
        }
    }
    rows
}

/// The linear step of every mode (background and the load basis `pb` = `(p0, Dp, DDp)`
/// over the step) into `(ql, vl)`.
#[inline(always)]
pub(super) fn linear_step(
    rows: &StepRows,
    (q, v): (&[f64], &[f64]),
    pb: [&[f64]; 3],
    (ql, vl): (&mut [f64], &mut [f64]),
) {
    let n = rows[0].len();
    let (q, v, ql, vl) = (&q[..n], &v[..n], &mut ql[..n], &mut vl[..n]);
    let (p0, p1, p2) = (&pb[0][..n], &pb[1][..n], &pb[2][..n]);
    let [a11, a12, a21, a22, b11, b12, b13, b21, b22, b23] = rows.each_ref().map(|r| &r[..n]);
    for m in 0..n {
        let dq = a11[m] * q[m] + a12[m] * v[m] + b11[m] * p0[m] + b12[m] * p1[m] + b13[m] * p2[m];
        let dv = a21[m] * q[m] + a22[m] * v[m] + b21[m] * p0[m] + b22[m] * p1[m] + b23[m] * p2[m];
        ql[m] = q[m] + dq;
        vl[m] = v[m] + dv;
    }
}
