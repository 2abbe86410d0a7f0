//! Scalar functions of time `s(t)` of the loads `pattern * s(t)`: their values, the load
//! basis of a step, and the jumps inside a step that are integrated exactly.

use crate::error::CoreError;
use crate::speed::SpeedLaw;

use super::misalignment::Coupling;
use super::steps::Steps;
use super::table::{table_at, table_before, table_eval};

/// A direction in the plane of a rotor's cross-section (serialised as `"x"`, `"y"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    X,
    Y,
}

/// A scalar function of time. Serialised (a stored run's loads) as `{"step": {"t0": ...}}`,
/// `{"harmonic": {...}}`, `{"table": {"t": [...], "v": [...], "hold": ...}}`, ...
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TimeFunction {
    /// Heaviside step `H(t - t0)` (1 for `t >= t0`). Integrated exactly, also when `t0` falls
    /// inside a step.
    Step { t0: f64 },
    /// `sin(omega t + phase)`.
    Harmonic { omega: f64, phase: f64 },
    /// Piecewise-linear interpolation of `(t, v)` samples (`t` strictly increasing, at least
    /// two); outside `[t[0], t[last]]` the value is 0, or the last value after the end when
    /// `hold` is set. The jumps at the record's ends are integrated exactly also when they
    /// fall inside a step (a record whose times miss the step grid, if only by a rounding).
    Table {
        t: Vec<f64>,
        v: Vec<f64>,
        hold: bool,
    },
    /// One component of the force of a rotating eccentric mass, per unit `m e`, with
    /// `Theta = theta(t) + phase` (`theta` the angle of the speed law):
    /// x: `omega^2 cos Theta + omega' sin Theta`, y: `omega^2 sin Theta - omega' cos Theta`.
    ///
    /// The mass sits at `e (cos Theta, sin Theta)` from the shaft centre; its acceleration
    /// relative to the centre is `e (-Theta'' sin - Theta'^2 cos, Theta'' cos - Theta'^2 sin)`
    /// and the shaft carries the reaction, minus `m` times it. Where `omega'` jumps (the end
    /// of a run-up) the force jumps by `m e omega'`; inside a step that jump and the jumps of
    /// the first two derivatives are integrated exactly (see [`TimeFunction::jump_in`]).
    Unbalance {
        law: SpeedLaw,
        phase: f64,
        axis: Axis,
    },
    /// One component of a misaligned flexible coupling's reaction force (N) at the angle
    /// `theta(t)` of the speed law (see [`Coupling`]); continuous, a function of the angle.
    Misalignment {
        coupling: Coupling,
        law: SpeedLaw,
        axis: Axis,
    },
}

impl TimeFunction {
    /// Checks the parameters; `name` is the Python-side parameter for messages.
    pub fn validate(&self) -> Result<(), CoreError> {
        let bad = |name: &'static str, problem: &str| {
            Err(CoreError::InvalidInput {
                name,
                problem: problem.to_string(),
            })
        };
        match self {
            TimeFunction::Step { t0 } if !t0.is_finite() => bad("t0", "must be finite"),
            TimeFunction::Harmonic { omega, phase }
                if !(omega.is_finite() && phase.is_finite()) =>
            {
                bad("omega", "and `phase` must be finite")
            }
            TimeFunction::Unbalance { law, phase, .. } => {
                law.validate()?;
                if !phase.is_finite() {
                    return bad("phase", "must be finite");
                }
                Ok(())
            }
            TimeFunction::Misalignment { coupling, law, .. } => {
                law.validate()?;
                coupling.validate()
            }
            TimeFunction::Table { t, v, .. } => {
                if t.len() != v.len() {
                    return Err(CoreError::LengthMismatch {
                        name: "values",
                        got: v.len(),
                        expected: t.len(),
                    });
                }
                if t.len() < 2 {
                    return bad("t", "needs at least two samples");
                }
                if t.iter().chain(v.iter()).any(|x| !x.is_finite()) {
                    return bad("t", "and `values` must be finite");
                }
                if t.windows(2).any(|w| w[1] <= w[0]) {
                    return bad("t", "must be strictly increasing");
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// Value at `t`. For a step, the value just after `t` (right-continuous).
    pub fn eval(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Step { t0 } => {
                if t >= *t0 {
                    1.0
                } else {
                    0.0
                }
            }
            TimeFunction::Harmonic { omega, phase } => (omega * t + phase).sin(),
            TimeFunction::Table { t: ts, v, hold } => table_eval(ts, v, *hold, t),
            TimeFunction::Unbalance { law, phase, axis } => unbalance(law, *phase, *axis, t, false),
            TimeFunction::Misalignment { .. } => self.eval_before(t),
        }
    }

    /// Value just before `t` (left limit); differs from [`TimeFunction::eval`] only at a
    /// jump (a step's `t0`, a table's first or last sample).
    pub fn eval_before(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Step { t0 } => {
                if t > *t0 {
                    1.0
                } else {
                    0.0
                }
            }
            TimeFunction::Harmonic { .. } => self.eval(t),
            TimeFunction::Unbalance { law, phase, axis } => unbalance(law, *phase, *axis, t, true),
            TimeFunction::Misalignment {
                coupling,
                law,
                axis,
            } => coupling.force(law.theta(t))[(*axis == Axis::Y) as usize],
            TimeFunction::Table { t: ts, v, hold } => {
                // A validated table has at least two samples.
                let last = ts.len() - 1;
                if t.is_nan() {
                    f64::NAN
                } else if t <= ts[0] {
                    0.0
                } else if t == ts[last] && !hold {
                    v[last]
                } else {
                    table_eval(ts, v, *hold, t)
                }
            }
        }
    }

    /// The load basis `(p0, Dp, DDp)` over the step `[t, t + dt]` for the parabola through the
    /// value just after `t`, the value at the middle and the value just before `t + dt`, so a
    /// jump on a grid point is represented exactly. A step function is held at its value at
    /// `t`; its jump inside the step, if any, is added exactly by the caller (see
    /// [`TimeFunction::jump_in`]). For an unbalance load whose speed law breaks inside the
    /// step, the parabola represents the smooth part only (the jump's polynomial, which the
    /// caller adds exactly, is taken off the samples after the break).
    pub fn basis(&self, t: f64, dt: f64) -> [f64; 3] {
        match self {
            TimeFunction::Step { .. } => [self.eval(t), 0.0, 0.0],
            _ => self.parabola(t, dt, |x, before| {
                if before {
                    self.eval_before(x)
                } else {
                    self.eval(x)
                }
            }),
        }
    }

    /// [`TimeFunction::basis`] of a function that is not a step, its values (`before`: the
    /// left limit) given by `value`.
    #[inline(always)]
    fn parabola(&self, t: f64, dt: f64, mut value: impl FnMut(f64, bool) -> f64) -> [f64; 3] {
        let p0 = value(t, false);
        let mut pm = value(t + 0.5 * dt, false);
        let mut p1 = value(t + dt, true);
        if let Some((tj, j)) = self.break_in(t, dt) {
            let poly = |s: f64| {
                let d = s - tj;
                if d >= 0.0 {
                    j[0] + d * (j[1] + d * j[2])
                } else {
                    0.0
                }
            };
            pm -= poly(t + 0.5 * dt);
            p1 -= poly(t + dt);
        }
        [p0, p1 - p0, pm - 0.5 * (p0 + p1)]
    }

    /// The bases of the steps `steps`, appended to `out` with stride `stride` starting at
    /// `out[offset]`. A harmonic (or a constant-speed unbalance) is evaluated twice per
    /// step, not three times: the end of one step is the start of the next.
    pub fn bases(
        &self,
        steps: &Steps<impl Fn(usize) -> f64>,
        out: &mut [[f64; 3]],
        offset: usize,
        stride: usize,
    ) {
        let Steps { time, dt, len } = steps;
        let (dt, len) = (*dt, *len);
        // Smooth functions: the end of one step is the start of the next, evaluated once.
        let smooth = matches!(
            self,
            TimeFunction::Harmonic { .. }
                | TimeFunction::Unbalance {
                    law: SpeedLaw::Constant(_),
                    ..
                }
        );
        match self {
            _ if smooth => {
                let mut p0 = self.eval(time(0));
                for n in 0..len {
                    let t = time(n);
                    let pm = self.eval(t + 0.5 * dt);
                    let p1 = self.eval(time(n + 1));
                    out[offset + n * stride] = [p0, p1 - p0, pm - 0.5 * (p0 + p1)];
                    p0 = p1;
                }
            }
            TimeFunction::Table { t: ts, v, hold } => {
                // The steps advance through the record: each sample is found from the last
                // one found (a short walk), not by a search of the whole record; the
                // segment, hence the value, is the search's.
                let mut at = ts.partition_point(|&x| x <= time(0));
                for n in 0..len {
                    let value = |x: f64, before: bool| {
                        if before {
                            table_before(ts, v, *hold, x, &mut at)
                        } else {
                            table_at(ts, v, *hold, x, &mut at)
                        }
                    };
                    out[offset + n * stride] = self.parabola(time(n), dt, value);
                }
            }
            _ => {
                for n in 0..len {
                    out[offset + n * stride] = self.basis(time(n), dt);
                }
            }
        }
    }

    /// [`TimeFunction::bases`] of two functions at once when they are the x and y parts of
    /// one constant-speed unbalance (same speed and phase): one sine and cosine per sample
    /// serve both, with values identical to evaluating each. Returns false (writing nothing)
    /// for any other pair. `self` is written at `out[offset.0 + n * stride]`, `other` at
    /// `out[offset.1 + n * stride]`.
    pub fn pair_bases(
        &self,
        other: &TimeFunction,
        steps: &Steps<impl Fn(usize) -> f64>,
        out: &mut [[f64; 3]],
        offset: (usize, usize),
        stride: usize,
    ) -> bool {
        let Steps { time, dt, len } = steps;
        let (dt, len) = (*dt, *len);
        let (
            TimeFunction::Unbalance {
                law: law @ SpeedLaw::Constant(w),
                phase,
                axis: a,
            },
            TimeFunction::Unbalance {
                law: SpeedLaw::Constant(w2),
                phase: phase2,
                axis: b,
            },
        ) = (self, other)
        else {
            return false;
        };
        if w != w2 || phase != phase2 || a == b {
            return false;
        }
        let w2 = w * w;
        // (x, y) = w^2 (cos, sin) of the angle, exactly as `unbalance` with `omega' = 0`.
        let eval = |t: f64| {
            let (s, c) = (law.theta(t) + phase).sin_cos();
            match a {
                Axis::X => (w2 * c, w2 * s),
                Axis::Y => (w2 * s, w2 * c),
            }
        };
        let mut p0 = eval(time(0));
        for n in 0..len {
            let pm = eval(time(n) + 0.5 * dt);
            let p1 = eval(time(n + 1));
            out[offset.0 + n * stride] = [p0.0, p1.0 - p0.0, pm.0 - 0.5 * (p0.0 + p1.0)];
            out[offset.1 + n * stride] = [p0.1, p1.1 - p0.1, pm.1 - 0.5 * (p0.1 + p1.1)];
            p0 = p1;
        }
        true
    }

    /// For a function that breaks strictly inside `(t, t + dt)`, at `tj`: the time from the
    /// break to the end of the step, `t + dt - tj`, and the coefficients `j` of the part
    /// `(j0 + j1 (s - tj) + j2 (s - tj)^2) H(s - tj)` that the caller integrates exactly (the
    /// rest is smooth enough for the parabola: twice continuously differentiable). A step:
    /// `j = (1, 0, 0)`; an unbalance at the end of a run-up: the jumps of the force and of its
    /// first two derivatives (the second halved); a misalignment at a kink of its angular
    /// force: the jumps of the first two derivatives.
    pub fn jump_in(&self, t: f64, dt: f64) -> Option<(f64, [f64; 3])> {
        self.break_in(t, dt).map(|(tj, j)| (t + dt - tj, j))
    }

    /// The time of a break inside `(t, t + dt)` and its jump coefficients (see
    /// [`TimeFunction::jump_in`]).
    fn break_in(&self, t: f64, dt: f64) -> Option<(f64, [f64; 3])> {
        match self {
            TimeFunction::Step { t0 } if *t0 > t && *t0 < t + dt => Some((*t0, [1.0, 0.0, 0.0])),
            TimeFunction::Table { t: ts, v, hold } => {
                // The record's ends: from 0 to its first segment, and from its last segment to
                // 0 (or, held, to its last value). Interior kinks are left to the parabola. A
                // record shorter than a step breaks at its start only.
                let inside = |x: f64| x > t && x < t + dt;
                let slope = |i: usize| (v[i + 1] - v[i]) / (ts[i + 1] - ts[i]);
                let last = ts.len() - 1;
                if inside(ts[0]) {
                    Some((ts[0], [v[0], slope(0), 0.0]))
                } else if inside(ts[last]) {
                    let drop = if *hold { 0.0 } else { -v[last] };
                    Some((ts[last], [drop, -slope(last - 1), 0.0]))
                } else {
                    None
                }
            }
            TimeFunction::Unbalance { law, phase, axis } => {
                let tj = law.breakpoint_in(t, dt)?;
                // f_x + i f_y = (w^2 - i w') z, z = exp(i Theta), with w'' = 0 on each side:
                // f' = (3 w w' + i w^3) z, f'' = (3 w'^2 - w^4 + 6 i w^2 w') z. At the break
                // w' drops from `a` to 0 (w, Theta continuous).
                let a = law.domega_side(tj, true) - law.domega_side(tj, false);
                let w = law.omega(tj);
                let (s, c) = (law.theta(tj) + phase).sin_cos();
                // jumps as complex multiples of z: i a, -3 w a, (-1.5 a^2 - 3 i w^2 a)
                let parts = [
                    (0.0, a),
                    (-3.0 * w * a, 0.0),
                    (-1.5 * a * a, -3.0 * w * w * a),
                ];
                let j = parts.map(|(re, im)| match axis {
                    Axis::X => re * c - im * s,
                    Axis::Y => re * s + im * c,
                });
                Some((tj, j))
            }
            TimeFunction::Misalignment {
                coupling,
                law,
                axis,
            } => {
                // A kink of the angular force at the angle `theta_k`: `f = h(theta(t))` keeps
                // its value and gains `h' omega` in slope and `h'' omega^2 + h' omega'` in
                // curvature (one kink per step at most: else the parabola takes them).
                let theta_k = coupling.kink_in(law.theta(t), law.theta(t + dt))?;
                let tj = law.time_at_angle(theta_k, t, t + dt)?;
                let [d1, d2] = coupling.kink_jumps(theta_k)[(*axis == Axis::Y) as usize];
                let (w, a) = (law.omega(tj), law.domega(tj));
                Some((tj, [0.0, d1 * w, 0.5 * (d2 * w * w + d1 * a)]))
            }
            _ => None,
        }
    }
}

/// The unbalance force per unit `m e` (see [`TimeFunction::Unbalance`]); `left` takes the
/// angular acceleration from the left where it jumps.
fn unbalance(law: &SpeedLaw, phase: f64, axis: Axis, t: f64, left: bool) -> f64 {
    let w = law.omega(t);
    let dw = law.domega_side(t, left);
    let (s, c) = (law.theta(t) + phase).sin_cos();
    match axis {
        Axis::X => w * w * c + dw * s,
        Axis::Y => w * w * s - dw * c,
    }
}

#[cfg(test)]
mod tests;
