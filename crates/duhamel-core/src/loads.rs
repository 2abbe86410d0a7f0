//! Loads `f(t) = sum_l pattern_l * s_l(t)`: a fixed spatial (here: modal) pattern times a
//! scalar time function evaluated in Rust.

use crate::error::CoreError;

/// A scalar function of time.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeFunction {
    /// Heaviside step `H(t - t0)` (1 for `t >= t0`). Integrated exactly, also when `t0` falls
    /// inside a step.
    Step { t0: f64 },
    /// `sin(omega t + phase)`.
    Harmonic { omega: f64, phase: f64 },
    /// Piecewise-linear interpolation of `(t, v)` samples (`t` strictly increasing); outside
    /// `[t[0], t[last]]` the value is 0, or the last value after the end when `hold` is set.
    Table {
        t: Vec<f64>,
        v: Vec<f64>,
        hold: bool,
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
            TimeFunction::Table { t: ts, v, hold } => {
                let last = ts.len() - 1;
                if t <= ts[0] {
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
    /// [`TimeFunction::jump_in`]).
    pub fn basis(&self, t: f64, dt: f64) -> [f64; 3] {
        match self {
            TimeFunction::Step { .. } => [self.eval(t), 0.0, 0.0],
            _ => {
                let p0 = self.eval(t);
                let pm = self.eval(t + 0.5 * dt);
                let p1 = self.eval_before(t + dt);
                [p0, p1 - p0, pm - 0.5 * (p0 + p1)]
            }
        }
    }

    /// The bases of `len` consecutive steps `[t0 + n dt, t0 + (n + 1) dt]` (with the grid
    /// times `t0 + n dt` computed as `time(n)`), appended to `out` with stride `stride`
    /// starting at `out[offset]`. A harmonic is evaluated twice per step, not three times:
    /// the end of one step is the start of the next.
    pub fn bases(
        &self,
        time: impl Fn(usize) -> f64,
        dt: f64,
        len: usize,
        out: &mut [[f64; 3]],
        offset: usize,
        stride: usize,
    ) {
        match self {
            TimeFunction::Harmonic { .. } => {
                let mut p0 = self.eval(time(0));
                for n in 0..len {
                    let t = time(n);
                    let pm = self.eval(t + 0.5 * dt);
                    let p1 = self.eval(time(n + 1));
                    out[offset + n * stride] = [p0, p1 - p0, pm - 0.5 * (p0 + p1)];
                    p0 = p1;
                }
            }
            _ => {
                for n in 0..len {
                    out[offset + n * stride] = self.basis(time(n), dt);
                }
            }
        }
    }

    /// For a step whose jump lies strictly inside `(t, t + dt)`, the time from the jump to
    /// the end of the step.
    pub fn jump_in(&self, t: f64, dt: f64) -> Option<f64> {
        match self {
            TimeFunction::Step { t0 } if *t0 > t && *t0 < t + dt => Some(t + dt - t0),
            _ => None,
        }
    }
}

/// Right-continuous table value: 0 before the first sample, and after the last one unless
/// `hold` (the value at the last sample itself is the value just after it: 0 unless `hold`).
fn table_eval(ts: &[f64], v: &[f64], hold: bool, t: f64) -> f64 {
    let last = ts.len() - 1;
    if t < ts[0] {
        return 0.0;
    }
    if t >= ts[last] {
        return if hold { v[last] } else { 0.0 };
    }
    // first index with ts[i] > t
    let i = ts.partition_point(|&x| x <= t);
    let (t0, t1) = (ts[i - 1], ts[i]);
    let w = (t - t0) / (t1 - t0);
    v[i - 1] + w * (v[i] - v[i - 1])
}

/// A load in modal coordinates: `pattern[mode] * s(t)`.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalLoad {
    /// Modal load per unit of the time function, one entry per retained mode.
    pub pattern: Vec<f64>,
    /// The time function.
    pub time: TimeFunction,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_interpolates_and_ends() {
        let f = TimeFunction::Table {
            t: vec![0.0, 1.0, 3.0],
            v: vec![0.0, 2.0, -2.0],
            hold: false,
        };
        assert_eq!(f.eval(0.5), 1.0);
        assert_eq!(f.eval(2.0), 0.0);
        // the record ends at t = 3: -2 just before, 0 from then on
        assert_eq!(f.eval_before(3.0), -2.0);
        assert_eq!(f.eval(3.0), 0.0);
        assert_eq!(f.eval(3.5), 0.0);
        assert_eq!(f.eval(-1.0), 0.0);
        // a step [2, 3] sees the line from 0 to -2, a step [3, 4] sees zero
        assert_eq!(f.basis(2.0, 1.0), [0.0, -2.0, 0.0]);
        assert_eq!(f.basis(3.0, 1.0), [0.0, 0.0, 0.0]);
    }

    #[test]
    fn step_jump_inside() {
        let f = TimeFunction::Step { t0: 0.25 };
        assert_eq!(f.jump_in(0.0, 1.0), Some(0.75));
        assert_eq!(f.jump_in(0.25, 1.0), None);
        assert_eq!(f.basis(0.25, 1.0), [1.0, 0.0, 0.0]);
        assert_eq!(f.basis(0.0, 1.0), [0.0, 0.0, 0.0]);
    }

    #[test]
    fn harmonic_basis_is_parabola() {
        let f = TimeFunction::Harmonic {
            omega: 2.0,
            phase: 0.3,
        };
        let b = f.basis(0.1, 0.2);
        assert!((b[0] - (0.5f64).sin()).abs() < 1e-15);
        assert!((b[0] + b[1] - (0.9f64).sin()).abs() < 1e-15);
    }
}
