//! Automatic step subdivision: a step whose equation does not converge is retried as two
//! half steps, each of them again in halves if it fails, down to `dt / 2^depth`.
//!
//! Every level has its own exact transition matrices and quadrature weights (the modal
//! oscillators stay exact at any step) and its own step solver; the loads of a substep are
//! the step's own load basis restricted to the substep (exact for the quadratic in time that
//! the step represents them by). A step with a step load starting inside it (an exact jump)
//! is not subdivided. Hysteretic elements commit at the end of every accepted substep.

use std::cell::OnceCell;
use std::sync::Arc;

use super::force::PseudoForce;
use super::newton::StepSolver;
use super::problem::{NonlinearProblem, Options};
use super::rows::{linear_step, step_rows, StepRows};
use super::scheme::{Rule, StepInput};
use super::stiff_rule::{too_stiff, Watch};
use crate::error::CoreError;
use crate::kernel::oscillator::Transfer;
use crate::kernel::transfer_memo;

/// The transfer matrices and quadrature rule of each level, `dt / 2`, `dt / 4`, ..., each
/// made when a substep of that level is first taken (most runs never subdivide: a run's
/// fixed cost then holds none of them).
pub(super) struct LevelRules<'p> {
    problem: &'p NonlinearProblem<'p>,
    made: Vec<OnceCell<(Arc<[Transfer]>, Rule)>>,
}

impl<'p> LevelRules<'p> {
    /// The rules of `problem`'s levels down to `dt / 2^depth`, none made yet.
    pub(super) fn new(problem: &'p NonlinearProblem<'p>, depth: usize) -> Self {
        LevelRules {
            problem,
            made: (0..depth).map(|_| OnceCell::new()).collect(),
        }
    }

    /// The levels below the run's step.
    fn depth(&self) -> usize {
        self.made.len()
    }

    /// The transfers and rule of level `d + 1` (steps of `dt / 2^(d + 1)`).
    fn get(&self, d: usize) -> &(Arc<[Transfer]>, Rule) {
        self.made[d].get_or_init(|| {
            let (base, o) = (&self.problem.base, self.problem.options);
            let h = base.dt * 0.5f64.powi(d as i32 + 1);
            let transfers = transfer_memo::transfers(base.k, base.c, h);
            let rule = Rule::new(o.scheme, o.quadrature, h, &transfers);
            (transfers, rule)
        })
    }
}

/// One level: steps of `dt / 2^depth`.
struct Level<'r> {
    rows: StepRows,
    solver: StepSolver<'r>,
    /// Its substep's buffers, kept from substep to substep.
    buf: Buffers,
}

/// A substep's end state, linear prediction and restricted load basis.
#[derive(Default)]
struct Buffers {
    q1: Vec<f64>,
    v1: Vec<f64>,
    ql: Vec<f64>,
    vl: Vec<f64>,
    pb: [Vec<f64>; 3],
}

impl Buffers {
    fn new(n: usize) -> Self {
        let zeros = || vec![0.0; n];
        Buffers {
            q1: zeros(),
            v1: zeros(),
            ql: zeros(),
            vl: zeros(),
            pb: std::array::from_fn(|_| zeros()),
        }
    }
}

/// The levels of subdivision below the run's step, and what they did.
pub(super) struct Subdivider<'r> {
    /// The levels made so far (each when a substep of it is first taken), from `dt / 2`.
    levels: Vec<Level<'r>>,
    rules: &'r LevelRules<'r>,
    options: Options,
    /// Whether the mass is estimated (the step solvers' unknowns).
    estimate: bool,
    n: usize,
    /// Whether hysteretic elements commit at the end of every accepted substep.
    stateful: bool,
    /// Whether the elements' tangent stiffness is watched (then at the end of every substep,
    /// with the run's [`Watch`]).
    watch: bool,
    dt: f64,
    /// Steps that needed subdividing, and the deepest level reached.
    pub steps: usize,
    pub deepest: usize,
}

/// Whether a failed step may be retried in halves.
pub(super) fn retriable(error: &CoreError) -> bool {
    match error {
        // a residual that is no longer finite is an overflowing state, not a convergence
        // problem (as `CoreError::located` reports it): halving the step only hides it
        CoreError::NoConvergence { residual, .. } => residual.is_finite(),
        CoreError::OutOfDomain { .. } => true,
        _ => false,
    }
}

impl<'r> Subdivider<'r> {
    pub fn new(
        problem: &'r NonlinearProblem,
        rules: &'r LevelRules<'r>,
        pf: &PseudoForce,
        options: Options,
        estimate: bool,
    ) -> Self {
        Subdivider {
            levels: Vec::new(),
            rules,
            options,
            estimate,
            n: problem.base.n_modes(),
            stateful: pf.stateful(),
            watch: pf.space().watched(),
            dt: problem.base.dt,
            steps: 0,
            deepest: 0,
        }
    }

    /// The number of levels below the run's step.
    pub fn depth(&self) -> usize {
        self.rules.depth()
    }

    /// Makes the levels down to `depth` that are not made yet (the same solvers as made at
    /// the run's start: they read the elements' definitions, not their state).
    fn reach(&mut self, depth: usize, pf: &PseudoForce) -> Result<(), CoreError> {
        while self.levels.len() < depth {
            let d = self.levels.len();
            let (transfers, rule) = self.rules.get(d);
            let h = self.dt * 0.5f64.powi(d as i32 + 1);
            let solver = StepSolver::new(rule, h, &self.options, pf, self.estimate)?;
            self.levels.push(Level {
                rows: step_rows(transfers),
                solver,
                buf: Buffers::new(self.n),
            });
        }
        Ok(())
    }

    /// Advances `(q, v)` over the step `[t, t + dt]` whose modal load basis is `pb` in
    /// halves (the step itself failed, or was too stiff: then in at least `2^min_depth`
    /// substeps); returns the Newton iterations.
    pub fn step(
        &mut self,
        pf: &mut PseudoForce,
        (t, dt): (f64, f64),
        pb: [&[f64]; 3],
        (q, v): (&mut [f64], &mut [f64]),
        (min_depth, watch): (usize, Option<&mut Watch>),
    ) -> Result<usize, CoreError> {
        self.steps += 1;
        let mut watch = watch.filter(|_| self.watch);
        let span = Span {
            t,
            dt,
            pb,
            min_depth,
        };
        let first = self.advance(1, pf, &span, 0.0, (q, v), &mut watch)?;
        let second = self.advance(1, pf, &span, 0.5, (q, v), &mut watch)?;
        Ok(first + second)
    }

    /// Advances over `[a, a + 2^-depth]` of the step (fractions of it) at level `depth`,
    /// in halves below when that fails.
    fn advance(
        &mut self,
        depth: usize,
        pf: &mut PseudoForce,
        span: &Span,
        a: f64,
        (q, v): (&mut [f64], &mut [f64]),
        watch: &mut Option<&mut Watch>,
    ) -> Result<usize, CoreError> {
        let h = 0.5f64.powi(depth as i32);
        let deeper = depth < self.depth();
        if depth < span.min_depth && deeper {
            let first = self.advance(depth + 1, pf, span, a, (q, v), watch)?;
            let second = self.advance(depth + 1, pf, span, a + 0.5 * h, (q, v), watch)?;
            return Ok(first + second);
        }
        self.reach(depth, pf)?;
        // the level's buffers, put back before a deeper level runs or this one returns
        let mut buf = std::mem::take(&mut self.levels[depth - 1].buf);
        let here = Substep { depth, a, h };
        let result = self.attempt(here, pf, span, (q, v), watch, &mut buf);
        self.levels[depth - 1].buf = buf;
        match result? {
            Some(iterations) => Ok(iterations),
            None => {
                let first = self.advance(depth + 1, pf, span, a, (q, v), watch)?;
                let mid = a + 0.5 * h;
                let second = self.advance(depth + 1, pf, span, mid, (q, v), watch)?;
                Ok(first + second)
            }
        }
    }

    /// One substep (`here`) in `buf`: the Newton iterations when it is accepted (`(q, v)`
    /// then advanced), None when it must be taken in halves.
    fn attempt(
        &mut self,
        here: Substep,
        pf: &mut PseudoForce,
        span: &Span,
        (q, v): (&mut [f64], &mut [f64]),
        watch: &mut Option<&mut Watch>,
        buf: &mut Buffers,
    ) -> Result<Option<usize>, CoreError> {
        let Substep { depth, a, h } = here;
        let n = self.n;
        let t = span.t + a * span.dt;
        span.restricted(a, h, n, &mut buf.pb);
        let deeper = depth < self.depth();
        let Buffers { q1, v1, ql, vl, pb } = buf;
        let attempt = {
            let level = &mut self.levels[depth - 1];
            let basis = [&pb[0][..], &pb[1][..], &pb[2][..]];
            linear_step(&level.rows, (q, v), basis, (ql, vl));
            let input = StepInput {
                t,
                q0: q,
                v0: v,
                q_lin: ql,
                v_lin: vl,
                pb: basis,
            };
            level.solver.solve(pf, &input, q1, v1)
        };
        let end = t + h * span.dt;
        let attempt = match attempt {
            Ok(iterations) if watch.is_some() => {
                // the run's rule, with the tangent at this substep's end
                let stiffness = pf.tangent_stiffness(q1, v1, end)?;
                let levels = self.depth();
                let fraction = h;
                let end_state = (stiffness.0, pf.space().background());
                match watch
                    .as_mut()
                    .map(|w| w.depth(end_state, self.dt, fraction, levels))
                {
                    Some(Ok(need)) if depth >= need => {
                        if let Some(w) = watch.as_mut() {
                            w.accept(end_state);
                        }
                        Ok(iterations)
                    }
                    _ if deeper => Err(None),
                    _ => return Err(too_stiff(pf, stiffness, h * self.dt, depth)),
                }
            }
            Ok(iterations) => Ok(iterations),
            Err(error) if retriable(&error) && deeper => Err(None),
            Err(error) => Err(Some(error)),
        };
        match attempt {
            Ok(iterations) => {
                self.deepest = self.deepest.max(depth);
                if self.stateful {
                    pf.commit(q1, v1, end, false)?;
                }
                q.copy_from_slice(q1);
                v.copy_from_slice(v1);
                Ok(Some(iterations))
            }
            Err(None) => Ok(None),
            Err(Some(error)) => Err(error),
        }
    }
}

/// Where a substep lies: its level (`dt / 2^depth`) and its span `[a, a + h]` as fractions
/// of the step.
#[derive(Clone, Copy)]
struct Substep {
    depth: usize,
    a: f64,
    h: f64,
}

/// The step being subdivided: its start, length and modal load basis.
struct Span<'s> {
    t: f64,
    dt: f64,
    pb: [&'s [f64]; 3],
    /// The level above which no substep is attempted (the step is known to be too stiff).
    min_depth: usize,
}

impl Span<'_> {
    /// The load basis of the substep `[a, a + h]` (fractions of the step): the step's load
    /// `p(s) = p0 + Dp s + 4 DDp s (1 - s)` sampled at its start, middle and end.
    fn restricted(&self, a: f64, h: f64, n: usize, out: &mut [Vec<f64>; 3]) {
        let [p0, dp, ddp] = self.pb;
        let at = |s: f64, m: usize| p0[m] + dp[m] * s + 4.0 * ddp[m] * s * (1.0 - s);
        for o in out.iter_mut() {
            o.clear();
        }
        for m in 0..n {
            let (f0, fm, f1) = (at(a, m), at(a + 0.5 * h, m), at(a + h, m));
            out[0].push(f0);
            out[1].push(f1 - f0);
            out[2].push(fm - 0.5 * (f0 + f1));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Span;

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn restricted_load_is_the_step_load() {
        let (p0, dp, ddp) = ([1.5, -2.0], [0.25, 3.0], [-0.7, 0.1]);
        let span = Span {
            t: 0.0,
            dt: 0.1,
            pb: [&p0, &dp, &ddp],
            min_depth: 0,
        };
        let step = |s: f64, m: usize| p0[m] + dp[m] * s + 4.0 * ddp[m] * s * (1.0 - s);
        for (a, h) in [(0.0, 0.5), (0.5, 0.5), (0.25, 0.25), (0.8125, 0.0625)] {
            let mut sub: [Vec<f64>; 3] = Default::default();
            span.restricted(a, h, 2, &mut sub);
            for m in 0..2 {
                for sigma in [0.0, 0.3, 0.5, 0.9, 1.0] {
                    let local =
                        sub[0][m] + sub[1][m] * sigma + 4.0 * sub[2][m] * sigma * (1.0 - sigma);
                    let want = step(a + sigma * h, m);
                    assert!(
                        (local - want).abs() < 1e-14,
                        "{a} {h} {sigma}: {local} {want}"
                    );
                }
            }
        }
    }
}
