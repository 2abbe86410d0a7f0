//! The error of force jumps inside a step (issue 41): a first-order error that the
//! parabola term of [`super::mode_bounds`] does not measure.
//!
//! An element whose force jumps inside a step (a `MinMax` material failing, a strength
//! drop) makes the pseudo-force a step `J H(s - theta)` at an unknown fraction `theta` of
//! the internal step `h`, where the step integrates the straight line `J s`. The error
//! `J (H(s - theta) - s)` enters each mode through the exact step's load transfer: `J (b0 -
//! b1)` for a jump at the step's start, `-J b1` at its end (`b0`, `b1` the end states from
//! rest under a unit constant load and under `s`, [`Transfer::b`]'s first two columns),
//! anything between for a jump inside. Its velocity part turns into a displacement error
//! through the mode's dynamics after the jump: the largest displacement of the impulse
//! response of `x'' + c x' + w^2 x = 0` over the rest of the run, `w^2` the background
//! stiffened (or softened: a failed element takes its stiffness away) by the part of the
//! pseudo-force in phase with the mode after the jump (a secant over the rest of the run).
//!
//! A jump is read from the saved pseudo-force: an interval whose change stands out from the
//! changes of both neighbouring intervals by more than either of them (`excess`, the part
//! outside their range); a smooth force, a kink (a yield point, a gap closing) or a switch
//! spread over several saved intervals leave no such excess (their error is the parabola
//! term's). Only softening jumps count, whose excess has the sign of the mode's motion
//! after them (a force released in the direction of the motion: a failure, a fracture, a
//! strength drop); a stiffening switch (a friction force reversing against the new motion,
//! through its stick branch) is placed by the element's own stiffness within the step and
//! makes no first-order error (measured: a friction pendulum converges at second order). The estimate of a jump is its expected error for a jump placed uniformly in
//! the step (the mean of the two ends' magnitudes over two), an estimate rather than a
//! bound: a jump placed at a step's end errs up to twice it, one at mid-step not at all.
//! Jumps add without decay (a failed element's drift does not decay). The work per step
//! without a jump is one comparison of three differences per mode.

use super::ModalRun;
use crate::kernel::oscillator::Transfer;

/// A jump must also exceed this fraction of the mode's largest pseudo-force magnitude
/// (round-off in a history that is constant or zero is no jump).
const NOISE: f64 = 1e-9;

/// The signed excess of the change `here` over an interval outside the range of the
/// changes `before` and `after` of its neighbours, where it is larger than both of them (a
/// candidate jump), else 0.
#[inline(always)]
pub(super) fn excess(before: f64, here: f64, after: f64) -> f64 {
    // min and max rather than `clamp` (which panics on NaN bounds), branch-free: a history
    // that is not finite has no jump (its estimate is NaN from the other passes)
    let (lo, hi) = (before.min(after), before.max(after));
    let signed = here - here.max(lo).min(hi);
    if signed.abs() > before.abs().max(after.abs()) {
        signed
    } else {
        0.0
    }
}

/// Per mode, the summed displacement errors of the jumps among the `candidates` (`(interval,
/// mode, signed excess)` by interval then mode, from [`super::passes::first_sums`]) of the
/// row-major `(rows, n)` histories `pseudo` and `q` of `run` (zeros without a jump).
pub(super) fn jump_bounds(
    candidates: &[(usize, usize, f64)],
    pseudo: &[f64],
    q: &[f64],
    rows: usize,
    run: &ModalRun<'_>,
) -> Vec<f64> {
    let n = run.omega.len();
    let mut out = vec![0.0; n];
    let found = softening(candidates, pseudo, q, n, rows);
    if found.is_empty() {
        return out;
    }
    // per mode, the secant of the pseudo-force against the mode over the rows after each
    // jump: the sums of p q and q q from the end, walked once backwards
    let (mut pq, mut qq) = (vec![0.0; n], vec![0.0; n]);
    let mut next = rows; // rows >= next are summed
    let saved = run.k as f64 * run.h;
    // the load transfer of each mode's internal step, made once per mode (the same for
    // every jump of that mode)
    let mut transfers: Vec<Option<[[f64; 3]; 2]>> = vec![None; n];
    for &(row, m, size) in found.iter().rev() {
        while next > row + 1 {
            next -= 1;
            let (pr, qr) = (&pseudo[next * n..][..n], &q[next * n..][..n]);
            for j in 0..n {
                pq[j] += pr[j] * qr[j];
                qq[j] += qr[j] * qr[j];
            }
        }
        let (o, cm) = (run.omega[m], run.c[m]);
        if !(o.is_finite() && cm.is_finite()) {
            continue; // a massless dof's quasi-static coordinate: no quadrature in time
        }
        let softening = if qq[m] > 0.0 { pq[m] / qq[m] } else { 0.0 };
        let w2 = (o * o - softening).max(0.0);
        let rest = (run.span - (row + 1) as f64 * saved).max(run.h);
        let g = impulse_peak(0.5 * cm.max(0.0), w2, rest);
        let b = *transfers[m].get_or_insert_with(|| Transfer::new(o * o, cm, run.h).b());
        let start = (b[0][0] - b[0][1]).abs() + g * (b[1][0] - b[1][1]).abs();
        let end = b[0][1].abs() + g * b[1][1].abs();
        out[m] += size * 0.25 * (start + end);
    }
    out
}

/// The jumps among the `candidates` (see the module's docs): above round-off
/// ([`NOISE`] of the mode's largest pseudo-force) and softening (the excess has the sign of
/// the mode's motion after it: a force released in the direction of the motion; a
/// stiffening switch, a friction force reversing against the new motion, is held by the
/// element's own stiffness). `(interval, mode, size)`, by interval then mode.
fn softening(
    candidates: &[(usize, usize, f64)],
    p: &[f64],
    q: &[f64],
    n: usize,
    rows: usize,
) -> Vec<(usize, usize, f64)> {
    // every mode's largest |p|, made at the first softening candidate: one pass over the
    // rows (the same maxima as column by column: `f64::max` from 0 is the largest number,
    // in any order)
    let mut largest: Option<Vec<f64>> = None;
    let mut found = Vec::new();
    for &(r, m, signed) in candidates {
        let moving = q[(r + 2) * n + m] - q[(r + 1) * n + m];
        if signed * moving <= 0.0 {
            continue;
        }
        let top = largest.get_or_insert_with(|| {
            let mut top = vec![0.0_f64; n];
            for row in p[..rows * n].chunks_exact(n) {
                for (t, v) in top.iter_mut().zip(row) {
                    *t = t.max(v.abs());
                }
            }
            top
        })[m];
        if signed.abs() > NOISE * top {
            found.push((r, m, signed.abs()));
        }
    }
    found
}

/// The largest `|x(t)|`, `0 <= t <= rest`, of `x'' + 2 a x' + w2 x = 0` from `x(0) = 0`,
/// `x'(0) = 1` (`a >= 0`, `w2 >= 0`): the displacement a unit velocity error becomes.
fn impulse_peak(a: f64, w2: f64, rest: f64) -> f64 {
    let d = a * a - w2;
    if d < 0.0 {
        // underdamped: the first peak, at tan(wd t) = wd / a, is the largest
        let wd = (-d).sqrt();
        let first = wd.atan2(a) / wd;
        let t = first.min(rest);
        return (-a * t).exp() * (wd * t).sin() / wd;
    }
    // critically or over-damped: rises to its peak at atanh(beta / a) / beta (never, with
    // w2 = 0: a free mass's drift, towards 1 / (2 a))
    let beta = d.sqrt();
    let peak_at = if w2 <= 0.0 || beta >= a {
        f64::INFINITY
    } else if beta <= 1e-8 * a {
        1.0 / a
    } else {
        (beta / a).atanh() / beta
    };
    let t = peak_at.min(rest);
    let sinh_over = if beta * t <= 1e-8 {
        t
    } else {
        (beta * t).sinh() / beta
    };
    (-a * t).exp() * sinh_over
}

#[cfg(test)]
mod tests {
    use super::super::passes::first_sums;
    use super::*;

    /// The impulse response sampled finely: its largest magnitude over `[0, rest]`.
    fn sampled(a: f64, w2: f64, rest: f64) -> f64 {
        let (mut x, mut v, mut top) = (0.0_f64, 1.0_f64, 0.0_f64);
        let steps = 200_000;
        let dt = rest / steps as f64;
        for _ in 0..steps {
            // velocity Verlet with the damping implicit in the half steps (second order)
            let acc = -2.0 * a * v - w2 * x;
            let vh = v + 0.5 * dt * acc;
            x += dt * vh;
            v = (vh - 0.5 * dt * w2 * x) / (1.0 + a * dt);
            top = top.max(x.abs());
        }
        top
    }

    #[test]
    fn impulse_peaks_are_those_of_the_sampled_response() {
        for &(a, w2, rest) in &[
            (0.3, 40.0, 10.0),
            (0.3, 40.0, 0.05),
            (0.0, 4.0, 10.0),
            (0.3, 0.0, 10.0),
            (0.3, 0.0, 0.5),
            (2.0, 1.0, 20.0),
            (1.0, 1.0, 20.0),
            (0.0, 0.0, 3.0),
        ] {
            let (got, want) = (impulse_peak(a, w2, rest), sampled(a, w2, rest));
            assert!(
                (got - want).abs() <= 1e-4 * want,
                "a {a} w2 {w2} rest {rest}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn no_number_is_no_jump() {
        let nan = f64::NAN;
        assert_eq!(excess(nan, 1.0, nan), 0.0);
        assert_eq!(excess(0.0, nan, 0.1), 0.0);
        assert_eq!(excess(0.0, 1.0, 0.1), 0.9);
        assert_eq!(excess(0.1, -1.0, 0.0), -1.0);
    }

    #[test]
    fn a_jump_is_found_and_a_kink_or_a_curve_is_not() {
        // one mode: a parabola, a kink at row 20, a jump of 3 in the interval 40 -> 41
        let rows = 60;
        let p: Vec<f64> = (0..rows)
            .map(|r| {
                let t = r as f64 * 0.1;
                let kink = if r > 20 { 0.2 * (t - 2.0) } else { 0.0 };
                0.01 * t * t + kink + if r > 40 { 3.0 } else { 0.0 }
            })
            .collect();
        let q: Vec<f64> = (0..rows).map(|r| r as f64).collect(); // moving up: softening
        let candidates = first_sums(&p, &q, 1, rows).jumps;
        let found = softening(&candidates, &p, &q, 1, rows);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].0, 40);
        assert!((found[0].2 - 3.0).abs() < 0.05, "{found:?}");
        let down: Vec<f64> = q.iter().map(|v| -v).collect(); // moving down: stiffening
        assert!(softening(&candidates, &p, &down, 1, rows).is_empty());
    }

    #[test]
    fn a_rigid_mode_jump_is_the_mean_velocity_error_over_the_drift() {
        // a free mass (omega 0, c 0) and a jump of 2 at the saved interval 9 -> 10 of 21
        // rows, one internal step each: velocity error J h |1/2 - theta|, mean J h / 4,
        // drift over the rest of the run; the displacement error J h^2 (1/3 + 1/6) / 4
        let (rows, h) = (21, 0.01);
        let p: Vec<f64> = (0..rows).map(|r| if r >= 10 { 2.0 } else { 0.0 }).collect();
        let q: Vec<f64> = (0..rows).map(|r| r as f64).collect();
        let run = ModalRun {
            pseudo: &p,
            q: &q,
            rows,
            omega: &[0.0],
            c: &[0.0],
            moments: &[0.0, 0.0],
            h,
            k: 1,
            span: 20.0 * h,
        };
        let candidates = first_sums(&p, &q, 1, rows).jumps;
        let got = jump_bounds(&candidates, &p, &q, rows, &run)[0];
        let rest = 20.0 * h - 10.0 * h;
        let want = 2.0 * (h * h / 2.0 + rest * h) / 4.0;
        assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    }
}
