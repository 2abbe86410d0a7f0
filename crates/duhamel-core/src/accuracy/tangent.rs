//! The propagated error carried at the run's tangent (issue 41): each saved interval's
//! local error carried at the frequency of that interval's tangent, `w^2 = omega^2 - dQ dq /
//! dq^2` (the pseudo-force's change over the mode's: the finite-difference tangent of what
//! the elements add), instead of the run's secant; and a kink of the pseudo-force inside an
//! interval (a yield point, a gap closing) given the error of a kink rather than of a
//! parabola.
//!
//! Where the stiffness changes along the run (yielding, contact) the secant carries an error
//! made while an element is soft as if it were stiff, and the errors of successive cycles
//! cancel where they add; and a contact's error, made at its kinks, is amplified through the
//! impacts that follow. On the SDOFs of docs/accuracy.md the secant's estimate is 0.16-0.64
//! of the true error on yielding and contact; carried at the tangent with the kinks'
//! errors, 0.3-2.4 (the gap 0.46-1.4: with the true local errors in place of the estimated
//! ones, the tangent's carriage gives 0.8 of the gap's error, the secant's 0.31). A kink is
//! found where two neighbouring second differences of one sign stand out from theirs
//! ([`kinks`]); its place in the interval and its change of slope follow from them, and its
//! error is the exact step's response to what the straight line leaves out ([`kink_error`]).
//!
//! The tangent is not always the better model: on smooth hardening springs at coarse steps
//! it is low (Duffing 0.15 at 50 steps a period, where the secant gives 1.6); where the
//! tangent switches between very different stiffnesses (sticking and sliding friction) the
//! carried error grows without bound (a parametric pumping the run itself does not have).
//! So the tangent's estimate only ever raises the secant's, and only where it stays within
//! the bound of [`super::mode_bounds`] (the local errors' magnitudes summed, never below the
//! error on that family but for a failing `MinMax`): above it, the tangent's carriage is not
//! the run's and is not used.
//!
//! The tangent's `w^2` is taken on a grid of 32 bins an octave (its transition computed once
//! per bin, at the bin's middle); when the tangent takes more than [`MAX_VALUES`] bins, or
//! more than [`MAX_MODES`] mode makes up the bound, the run is not carried at its tangent
//! (it keeps the secant's estimate).

use faer::MatRef;

use super::signed::{combine, interval, kept_modes, Interval, Kept, M2, ROWS};
use super::ModalRun;
use crate::kernel::oscillator::Transfer;

/// The bits of a `w^2` below its grid bin (52 of the mantissa less 5: 32 bins an octave).
const BIN_SHIFT: u32 = 47;

/// The most modes carried at their tangent. A mode's tangent is read from its own
/// pseudo-force and displacement; in a run of several modes a mode's pseudo-force also
/// changes with the others' motion, and the ratio is not its tangent (on the 5-dof frame of
/// docs/accuracy.md the carriage rose to 6.3 times the error at an element, from the
/// secant's 2.1, within the bound): a run whose bound is made up by more modes keeps the
/// secant's estimate.
const MAX_MODES: usize = 1;

/// The most distinct grid bins of one mode's tangent over a run (each one transition).
const MAX_VALUES: usize = 288;

/// The span of bins a mode's tangent may take, centred on its first (128 octaves).
const SPAN: usize = 1 << 12;

/// Raises `errors` (per row of the `(g, n)` row-major `signed`: the secant's estimate,
/// [`super::signed::row_errors`]) to the tangent's where that is larger and at most
/// `bound_rows` (the row's bound); `jumps` and the modes left out as the secant's pass
/// leaves them out, `bounds` per mode.
pub(super) fn raise(
    run: &ModalRun<'_>,
    jumps: &[f64],
    bounds: &[f64],
    signed: &[f64],
    bound_rows: &[f64],
    errors: &mut [f64],
) {
    let n = run.omega.len();
    let g = signed.len().checked_div(n).unwrap_or(0);
    if run.rows < 3 || n == 0 || g == 0 {
        return;
    }
    let stepped: Vec<usize> = (0..n).filter(|&m| run.omega[m].is_finite()).collect();
    let Kept { modes, dropped, .. } = kept_modes(n, &stepped, bounds, signed);
    if modes.len() > MAX_MODES {
        return;
    }
    let Some(tangent) = carried(run, &modes, signed, g) else {
        return;
    };
    for r in 0..g {
        let row = &signed[r * n..(r + 1) * n];
        let jump: f64 = row.iter().zip(jumps).map(|(s, j)| s.abs() * j).sum();
        let t = tangent[r] + dropped[r] + jump;
        if t <= bound_rows[r] && t > errors[r] {
            errors[r] = t;
        }
    }
}

/// The grid bin of `w^2`: its exponent and the first five bits of its mantissa (32 bins an
/// octave, `w^2` known to 3 %), None where it is not a positive finite number.
fn key(w2: f64) -> Option<i64> {
    (w2.is_finite() && w2 > 0.0).then(|| (w2.to_bits() >> BIN_SHIFT) as i64)
}

/// The `w` of a grid bin: the square root of the bin's middle.
fn middle(key: i64) -> f64 {
    f64::from_bits(((key as u64) << BIN_SHIFT) | (1_u64 << (BIN_SHIFT - 1))).sqrt()
}

/// Per mode, its transitions by grid bin, made when first met: an index per bin within
/// [`SPAN`] / 2 bins of the first one met.
struct Table {
    origin: i64,
    index: Vec<u16>,
    made: Vec<Interval>,
}

impl Table {
    fn new() -> Self {
        Table {
            origin: i64::MIN,
            index: vec![u16::MAX; SPAN],
            made: Vec::new(),
        }
    }

    /// The transition of bin `key` of mode `m`; None past [`MAX_VALUES`] bins or beyond the
    /// span.
    fn get(&mut self, key: i64, run: &ModalRun<'_>, m: usize) -> Option<&Interval> {
        if self.origin == i64::MIN {
            self.origin = key - (SPAN / 2) as i64;
        }
        let at = usize::try_from(key - self.origin)
            .ok()
            .filter(|&a| a < SPAN)?;
        if self.index[at] == u16::MAX {
            if self.made.len() >= MAX_VALUES {
                return None;
            }
            let c = run.c[m];
            let c = if c.is_finite() && c > 0.0 { c } else { 0.0 };
            self.index[at] = self.made.len() as u16;
            self.made.push(interval(middle(key), c, run, m));
        }
        Some(&self.made[usize::from(self.index[at])])
    }
}

/// A kink of a mode's pseudo-force inside a saved interval: where (`theta`, the fraction of
/// the interval) and the change of its slope over the saved spacing (`change`, the sum of
/// the two second differences at the interval's ends).
#[derive(Clone, Copy)]
struct Kink {
    theta: f64,
    change: f64,
}

/// The zero-ended second differences `D` of mode `m`'s saved pseudo-force (`D_r` at rows
/// `1..rows - 1`, 0 at the history's ends).
fn seconds(run: &ModalRun<'_>, m: usize) -> Vec<f64> {
    let (n, rows, p) = (run.omega.len(), run.rows, run.pseudo);
    let mut d = vec![0.0; rows];
    for (r, o) in d.iter_mut().enumerate().take(rows - 1).skip(1) {
        *o = (p[(r + 1) * n + m] + p[(r - 1) * n + m]) - 2.0 * p[r * n + m];
    }
    d
}

/// Per saved interval `i -> i + 1`, whether it holds a kink, and the kinks in order: a
/// straight piece on either side meeting inside the interval, read from the second
/// differences `d` ([`seconds`]): `D_i` and `D_{i+1}` of one sign, their neighbours
/// `D_{i-1}` and `D_{i+2}` together below half of them; where the two pieces meet,
/// `theta = D_{i+1} / (D_i + D_{i+1})`.
fn kinks(d: &[f64]) -> (Vec<bool>, Vec<Kink>) {
    let rows = d.len();
    let at = |r: usize| d.get(r).copied().unwrap_or(0.0);
    let mut flags = vec![false; rows];
    let mut found = Vec::new();
    for (i, flag) in flags
        .iter_mut()
        .enumerate()
        .take(rows.saturating_sub(2))
        .skip(1)
    {
        let (a, b) = (d[i], d[i + 1]);
        if a * b > 0.0 && d[i - 1].abs() + at(i + 2).abs() < 0.5 * (a.abs() + b.abs()) {
            *flag = true;
            found.push(Kink {
                theta: b / (a + b),
                change: a + b,
            });
        }
    }
    (flags, found)
}

/// The error a kink leaves at its interval's end (the exact step's response to what the
/// straight line between the ends leaves out, `change (tau - theta)_+ - change (1 - theta)
/// tau` over the internal step holding the kink, carried to the interval's end by `step`).
/// `ramp` is the background's response to the ramp `tau` over a whole internal step.
fn kink_error(
    kink: Kink,
    run: &ModalRun<'_>,
    m: usize,
    c: f64,
    ramp: [f64; 2],
    step: &M2,
) -> [f64; 2] {
    let k = run.k;
    let at = kink.theta * k as f64;
    let j = (at.floor() as usize).min(k - 1);
    let theta = at - j as f64;
    let change = kink.change / k as f64;
    if theta >= 1.0 {
        return [0.0; 2]; // at the step's end: the line meets the kink there
    }
    let omega = run.omega[m];
    let late = Transfer::new(omega * omega, c, (1.0 - theta) * run.h).m;
    let mut e = [
        change * (1.0 - theta) * (late[0][1] - ramp[0]),
        change * (1.0 - theta) * (late[1][1] - ramp[1]),
    ];
    for _ in j + 1..k {
        e = [
            step[0][0] * e[0] + step[0][1] * e[1],
            step[1][0] * e[0] + step[1][1] * e[1],
        ];
    }
    e
}

/// Per row of `signed`, the largest magnitude over the run of the `modes`' errors carried
/// at their tangent, combined with the signed shapes; None when a mode's tangent takes more
/// than [`MAX_VALUES`] bins or strays [`SPAN`] / 2 bins from its first, or is not finite.
fn carried(run: &ModalRun<'_>, modes: &[usize], signed: &[f64], g: usize) -> Option<Vec<f64>> {
    let (n, rows, p, q) = (run.omega.len(), run.rows, run.pseudo, run.q);
    let width = modes.len();
    let mut out = vec![0.0_f64; g];
    if width == 0 {
        return Some(out);
    }
    let floor = (2.0 / run.span.max(run.h)).powi(2);
    let mut tables: Vec<Table> = (0..width).map(|_| Table::new()).collect();
    let shapes: Vec<f64> = (0..g)
        .flat_map(|r| modes.iter().map(move |&m| signed[r * n + m]))
        .collect();
    let weights = MatRef::from_row_major_slice(&shapes, g, width);
    // per mode, the second differences of its pseudo-force (0 beyond the ends) and its kinks
    let d: Vec<Vec<f64>> = modes.iter().map(|&m| seconds(run, m)).collect();
    let found: Vec<(Vec<bool>, Vec<Kink>)> = d.iter().map(|d| kinks(d)).collect();
    let mut next = vec![0_usize; width]; // the next kink of each mode
    let damping = |m: usize| {
        let c = run.c[m];
        if c.is_finite() && c > 0.0 {
            c
        } else {
            0.0
        }
    };
    let ramps: Vec<[f64; 2]> = modes
        .iter()
        .map(|&m| {
            let omega = run.omega[m];
            let t = Transfer::new(omega * omega, damping(m), run.h).m;
            [t[0][1], t[1][1]]
        })
        .collect();
    let omega2: Vec<f64> = modes.iter().map(|&m| run.omega[m] * run.omega[m]).collect();
    let mut e = vec![[0.0_f64; 2]; width];
    // a short run's rows, not a whole block's
    let mut block = vec![0.0; ROWS.min(rows) * width];
    let mut combined = vec![0.0; ROWS.min(rows) * g];
    let mut row = 1;
    while row < rows {
        let count = (rows - row).min(ROWS);
        for (i, at) in block[..count * width].chunks_exact_mut(width).enumerate() {
            let r = row + i; // the interval r - 1 -> r
            for (j, (&m, o)) in modes.iter().zip(at.iter_mut()).enumerate() {
                let (dp, dq) = (
                    p[r * n + m] - p[(r - 1) * n + m],
                    q[r * n + m] - q[(r - 1) * n + m],
                );
                let stiffening = if dq != 0.0 { -dp * dq / (dq * dq) } else { 0.0 };
                let step = tables[j].get(key((omega2[j] + stiffening).max(floor))?, run, m)?;
                // the mean of the second differences at the interval's ends (the history's
                // ends take their neighbour's); a kink's interval takes its kink's error,
                // its neighbours their outer second difference (theirs at the kink's side is
                // the kink's)
                let (i, d, (flags, kinked)) = (r - 1, &d[j], &found[j]);
                let (d2, extra) = if flags[i] {
                    let kink = kinked[next[j]];
                    next[j] += 1;
                    (
                        0.0,
                        kink_error(kink, run, m, damping(m), ramps[j], &step.step),
                    )
                } else if i >= 1 && flags[i - 1] {
                    (d[i + 1], [0.0; 2])
                } else if flags.get(i + 1) == Some(&true) {
                    (d[i], [0.0; 2])
                } else {
                    let clamped = |r: usize| d[r.clamp(1, rows - 2)];
                    (0.5 * (clamped(i) + clamped(r)), [0.0; 2])
                };
                let [x, v] = e[j];
                let (a, l) = (&step.carry, &step.local);
                e[j] = [
                    a[0][0] * x + a[0][1] * v + l[0] * d2 + extra[0],
                    a[1][0] * x + a[1][1] * v + l[1] * d2 + extra[1],
                ];
                *o = e[j][0];
            }
        }
        combine(
            &mut out,
            &block[..count * width],
            count,
            weights,
            &mut combined,
        );
        row += count;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run<'a>(omega: &'a [f64], c: &'a [f64], h: f64, k: usize) -> ModalRun<'a> {
        ModalRun {
            pseudo: &[],
            q: &[],
            rows: 0,
            omega,
            c,
            moments: &[],
            h,
            k,
            span: 1.0,
        }
    }

    /// A rigid mode's kink error against the integrals of what the line leaves out,
    /// `change ((s - theta)_+ - (1 - theta) s)`: `v = change h (1 - theta)(-theta) / 2`,
    /// `x = change h^2 ((1 - theta)^3 - (1 - theta)) / 6`; carried over the interval's other
    /// internal steps by `step`, and none at a step's end.
    #[test]
    fn a_rigid_modes_kink_error_is_the_integral_of_what_the_line_leaves_out() {
        let (omega, c, h) = ([0.0], [0.0], 0.01);
        let ramp = Transfer::new(0.0, 0.0, h).m;
        let ramp = [ramp[0][1], ramp[1][1]];
        let free: M2 = [[1.0, h], [0.0, 1.0]];
        for (k, theta) in [(1, 0.25), (1, 0.9), (4, 0.3)] {
            let kink = Kink { theta, change: 2.0 };
            let got = kink_error(kink, &run(&omega, &c, h, k), 0, 0.0, ramp, &free);
            // the internal step holding the kink, its place there, and the steps after it
            let at = theta * k as f64;
            let (j, t) = (at.floor(), at - at.floor());
            let change = 2.0 / k as f64;
            let v = change * h * (1.0 - t) * (-t) / 2.0;
            let x = change * h * h * ((1.0 - t).powi(3) - (1.0 - t)) / 6.0;
            let after = (k as f64 - 1.0 - j) * h; // a free mass drifts with its velocity
            let want = [x + v * after, v];
            for (g, w) in got.iter().zip(want) {
                assert!(
                    (g - w).abs() <= 1e-12 * w.abs().max(1e-300),
                    "{got:?} {want:?}"
                );
            }
        }
        let end = Kink {
            theta: 1.0,
            change: 2.0,
        };
        assert_eq!(
            kink_error(end, &run(&omega, &c, h, 1), 0, 0.0, ramp, &free),
            [0.0; 2]
        );
    }

    /// A kink is found where two second differences of one sign stand out, at the place
    /// where the straight pieces on either side meet.
    #[test]
    fn a_kink_between_two_straight_pieces_is_found_where_they_meet() {
        // slope 1 until t = 3.3, then slope 4 (samples at integers)
        let f = |t: f64| if t <= 3.3 { t } else { 3.3 + 4.0 * (t - 3.3) };
        let p: Vec<f64> = (0..8).map(|r| f(r as f64)).collect();
        let mut d = vec![0.0; p.len()];
        for r in 1..p.len() - 1 {
            d[r] = p[r + 1] + p[r - 1] - 2.0 * p[r];
        }
        let (flags, found) = kinks(&d);
        assert_eq!(flags.iter().filter(|f| **f).count(), 1);
        assert!(flags[3]);
        assert!((found[0].theta - 0.3).abs() < 1e-12);
        assert!((found[0].change - 3.0).abs() < 1e-12);
    }
}
