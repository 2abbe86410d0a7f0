//! Automatic step subdivision: a step whose equation does not converge is retried as two
//! half steps, each of them again in halves if it fails, down to `dt / 2^depth`.
//!
//! Every level has its own exact transition matrices and quadrature weights (the modal
//! oscillators stay exact at any step) and its own step solver; the loads of a substep are
//! the step's own load basis restricted to the substep (exact for the quadratic in time that
//! the step represents them by). A step with a step load starting inside it (an exact jump)
//! is not subdivided. Hysteretic elements commit at the end of every accepted substep.

use super::force::PseudoForce;
use super::local::DOMINANT;
use super::newton::StepSolver;
use super::problem::{NonlinearProblem, Options};
use super::rows::{linear_step, step_rows, StepRows};
use super::scheme::{Rule, StepInput};
use crate::error::CoreError;
use crate::kernel::oscillator::Transfer;

/// The largest `omega_c dt` a (sub)step may take, `omega_c^2` the closed state's frequency
/// bound of [`super::local::ElementSpace::tangent_stiffness`] (elements that dominate the
/// modes they load). The pseudo-force step (scheme b, trapezoid) of an element much stiffer
/// than its background is the linear-acceleration method, stable up to
/// `omega_c dt = 2 sqrt(3) = 3.46`; with the background the limit is 3.30 - 3.32 for an
/// element as stiff as it and 3.21 - 3.30 for 0.3 of it (zeta 0 - 0.05; docs/nonlinear.md).
/// Steps are held below 2 and subdivided when the elements stiffen beyond: a hardening element
/// stiffens inside the step, and at 3 a stiff `Cubic` still grew (peak 2.5 times the
/// converged one at omega_c dt = 10 subdivided to <= 3; at <= 2 it is within 2 %).
pub(super) const STIFF_LIMIT: f64 = 2.0;

/// The `omega_c dt` of a substep the accuracy rule aims at (see [`depth_for`]).
pub(super) const ACCURATE_LIMIT: f64 = 1.0;

/// The largest change of the closed state's `ln omega_c^2` over a substep the accuracy rule
/// allows (see [`depth_for`]).
pub(super) const CHANGE_LIMIT: f64 = 2.0;

/// The largest `omega_c dt` the coupled (first-order) route, which does not subdivide,
/// steps at: measured on a stiff stop with non-classical damping (`Gap(k=1e8)` on two dofs
/// of 1e4, issue 23) its error was 0.011 of the peak at 0.45 (Newmark's 0.098) and 0.084 at
/// 0.89 (Newmark's 0.027). Beyond it the run stops, naming the element.
pub(crate) const COUPLED_LIMIT: f64 = 0.5;

/// The halvings that bring `x` within `limit`.
fn halvings_to(x: f64, limit: f64) -> usize {
    if x <= limit {
        0
    } else {
        (x / limit).log2().ceil().min(64.0) as usize
    }
}

/// The one substep rule, for a step of the run's `dt` at `omega_c dt = h` (`omega_c` of the
/// elements that dominate the modes they load, the larger at its ends; 0 when none does),
/// `peak` the largest `omega_c dt` of the run so far (see [`Watch`]) and `change` the change
/// of `ln omega_c^2` over the step, with `max_depth` levels of subdivision: `Ok(d)`, the step
/// is taken in `2^d` substeps, or `Err(d)` when stability needs `d > max_depth` halvings.
///
/// Stability: substeps of `omega_c dt <= STIFF_LIMIT`, or the run stops. Accuracy (as far as
/// `max_depth` allows; it never stops a run): substeps of `omega_c dt <= ACCURATE_LIMIT` at
/// the run's `peak` (beyond, the stiff state's phase error over many of its periods grew
/// larger than Newmark's at the same step: a `Cubic` 1e4 times its mode at `omega_c dt = 1`,
/// 0.61 of the peak against 0.24; docs/nonlinear.md, "Stiff elements"), and substeps over
/// which the closed state's stiffness changes by at most `e^CHANGE_LIMIT` (a gap closing, a
/// smoothed contact's ramp, a yield: a kink inside the step, where the trapezoid of the
/// pseudo-force erred 1.3 - 1.5 times more than Newmark at `omega_c dt = 0.1`, and a ramp
/// faster than the stiff state vibrates). Both limits are the largest that keep the whole
/// family within Newmark's error while the paper's Duffing oscillator (12 times its
/// background at the amplitude, `omega_c dt` 0.23 and 0.45 at 100 and 50 steps per period,
/// its stiffness changing by at most `e^0.64` per step) keeps its plain steps.
pub(super) fn depth_for(h: f64, peak: f64, change: f64, max_depth: usize) -> Result<usize, usize> {
    if !(h > 0.0) {
        return Ok(0);
    }
    let stable = halvings_to(h, STIFF_LIMIT);
    if stable > max_depth {
        return Err(stable);
    }
    let accurate = halvings_to(peak.max(h), ACCURATE_LIMIT).max(halvings_to(change, CHANGE_LIMIT));
    Ok(stable.max(accurate.min(max_depth)))
}

/// The number of halvings that bring `omega_c dt` (`h`) within [`STIFF_LIMIT`].
pub(super) fn halvings(h: f64) -> usize {
    halvings_to(h, STIFF_LIMIT)
}

/// The stiffness watch of a run: the closed state's `omega_c^2`
/// ([`super::local::ElementSpace::tangent_stiffness`]) at the start of the (sub)step, the
/// largest met so far and the largest accuracy depth needed so far, and the substep rule
/// ([`depth_for`]) on them. A dominated step is taken at least as finely as any before it:
/// a tangent that varies inside a contact (a smoothed `Contact`, a `Cubic`, the ramp into a
/// stop) would otherwise change the substep from step to step while the stiff state
/// vibrates, and each change costs the linear-acceleration step its energy balance
/// (measured: a stiff `Contact` at `omega_c dt = 1` in 2 and 3 levels: 9.5e-4 and 4.0e-3 of
/// the peak with the depth following the tangent, 1.2e-4 and 3.0e-5 in uniform substeps;
/// with the ramp taken finely and the rest coarser, 9.8e-3 against Newmark's 4.4e-3).
#[derive(Clone, Debug)]
pub(super) struct Watch {
    /// `omega_c^2` at the start of the (sub)step (0: no element dominates) and the
    /// background's modal stiffness it counted.
    start: (f64, f64),
    /// The largest `omega_c^2` met so far.
    peak: f64,
    /// The largest accuracy depth a dominated (sub)step has needed so far.
    held: std::cell::Cell<usize>,
}

impl Watch {
    /// The watch of a run whose initial state has `omega_c^2 = start.0` over a background
    /// of `start.1`.
    pub fn new(start: (f64, f64)) -> Self {
        Watch {
            start,
            peak: if start.0 > 0.0 { start.0 } else { 0.0 },
            held: std::cell::Cell::new(0),
        }
    }

    /// `omega_c^2` at the start of the step.
    pub fn start(&self) -> f64 {
        self.start.0
    }

    /// The depth ([`depth_for`]) of a (sub)step from the last accepted state to one whose
    /// elements' `omega_c^2` is `end.0` over a background `end.1`, the (sub)step `fraction`
    /// of the run's `dt`, with `max_depth` levels. An element that starts or stops
    /// dominating changes the stiffness from its threshold, `DOMINANT + 1` times the
    /// background.
    pub fn depth(
        &self,
        end: (f64, f64),
        dt: f64,
        fraction: f64,
        max_depth: usize,
    ) -> Result<usize, usize> {
        let lambda = end.0.max(self.start.0);
        if !(lambda > 0.0) {
            return Ok(0);
        }
        let threshold = |(l, b): (f64, f64)| if l > 0.0 { l } else { (DOMINANT + 1.0) * b };
        let (a, b) = if end.0 > 0.0 && self.start.0 > 0.0 {
            (end.0, self.start.0)
        } else if end.0 > 0.0 {
            (end.0, threshold((0.0, end.1)))
        } else {
            (self.start.0, threshold((0.0, self.start.1)))
        };
        let change = if b > 0.0 {
            (a / b).ln().abs() / fraction
        } else {
            f64::INFINITY
        };
        let peak = self.peak.max(lambda);
        let need = depth_for(dt * lambda.sqrt(), dt * peak.sqrt(), change, max_depth)?;
        self.held.set(self.held.get().max(need));
        Ok(need.max(self.held.get().min(max_depth)))
    }

    /// An accepted (sub)step ends at `omega_c^2 = end.0` over a background `end.1`.
    pub fn accept(&mut self, end: (f64, f64)) {
        self.start = end;
        if end.0 > self.peak {
            self.peak = end.0;
        }
    }
}

/// The failure of a step whose elements are too stiff for it even at the deepest level
/// (`depth` halvings; `lambda` their modal stiffness, `worst` the element adding most).
pub(super) fn too_stiff(
    pf: &PseudoForce,
    (lambda, worst): (f64, usize),
    dt: f64,
    depth: usize,
) -> CoreError {
    let h = dt * lambda.sqrt();
    let dofs = pf.space().element_dofs(worst);
    let step = dt * 2f64.powi(depth as i32);
    CoreError::TooStiff {
        message: format!(
            "element {worst} (on dofs {dofs:?}) is too stiff for the step: with its tangent \
             the modes it loads (dominating them) vibrate at omega_c^2 = {lambda:.4e} \
             (rad/s)^2, omega_c dt = {h:.4} in steps of {dt:e} after {depth} halvings of \
             dt = {step:e} (`subdivisions`), and the pseudo-force step is held below \
             omega_c dt = {STIFF_LIMIT} (unstable beyond 2 sqrt(3) = 3.46); reduce `dt` below \
             {:.4e} or raise `subdivisions` to {}",
            STIFF_LIMIT * 2f64.powi(depth as i32) / lambda.sqrt(),
            depth + halvings(h)
        ),
        time: 0.0,
        step: 0,
        last_good_time: None,
    }
}

/// The transfer matrices and quadrature rule of each level, `dt / 2`, `dt / 4`, ...
pub(super) fn level_rules(problem: &NonlinearProblem, depth: usize) -> Vec<(Vec<Transfer>, Rule)> {
    let base = &problem.base;
    let o = problem.options;
    (1..=depth)
        .map(|d| {
            let h = base.dt * 0.5f64.powi(d as i32);
            let transfers: Vec<Transfer> = base
                .k
                .iter()
                .zip(base.c)
                .map(|(&k, &c)| Transfer::new(k, c, h))
                .collect();
            let rule = Rule::new(o.scheme, o.quadrature, h, &transfers);
            (transfers, rule)
        })
        .collect()
}

/// One level: steps of `dt / 2^depth`.
struct Level<'r> {
    rows: StepRows,
    solver: StepSolver<'r>,
}

/// The levels of subdivision below the run's step, and what they did.
pub(super) struct Subdivider<'r> {
    levels: Vec<Level<'r>>,
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
    matches!(
        error,
        CoreError::NoConvergence { .. } | CoreError::OutOfDomain { .. }
    )
}

impl<'r> Subdivider<'r> {
    pub fn new(
        problem: &'r NonlinearProblem,
        rules: &'r [(Vec<Transfer>, Rule)],
        pf: &PseudoForce,
        options: Options,
        estimate: bool,
    ) -> Result<Self, CoreError> {
        let n = problem.base.n_modes();
        let mut levels = Vec::with_capacity(rules.len());
        for (d, (transfers, rule)) in rules.iter().enumerate() {
            let h = problem.base.dt * 0.5f64.powi(d as i32 + 1);
            let solver = StepSolver::new(rule, h, &options, pf, estimate)?;
            levels.push(Level {
                rows: step_rows(transfers),
                solver,
            });
        }
        Ok(Subdivider {
            levels,
            n,
            stateful: pf.stateful(),
            watch: pf.space().watched(),
            dt: problem.base.dt,
            steps: 0,
            deepest: 0,
        })
    }

    /// The number of levels below the run's step.
    pub fn depth(&self) -> usize {
        self.levels.len()
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
        let n = self.n;
        let h = 0.5f64.powi(depth as i32);
        let t = span.t + a * span.dt;
        let pb = span.restricted(a, h, n);
        let (mut q1, mut v1) = (vec![0.0; n], vec![0.0; n]);
        let deeper = depth < self.levels.len();
        if depth < span.min_depth && deeper {
            let first = self.advance(depth + 1, pf, span, a, (q, v), watch)?;
            let second = self.advance(depth + 1, pf, span, a + 0.5 * h, (q, v), watch)?;
            return Ok(first + second);
        }
        let attempt = {
            let level = &mut self.levels[depth - 1];
            let (mut ql, mut vl) = (vec![0.0; n], vec![0.0; n]);
            let basis = [&pb[0][..], &pb[1][..], &pb[2][..]];
            linear_step(&level.rows, (q, v), basis, (&mut ql, &mut vl));
            let input = StepInput {
                t,
                q0: q,
                v0: v,
                q_lin: &ql,
                v_lin: &vl,
                pb: basis,
            };
            level.solver.solve(pf, &input, &mut q1, &mut v1)
        };
        let end = t + h * span.dt;
        let attempt = match attempt {
            Ok(iterations) if watch.is_some() => {
                // the run's rule, with the tangent at this substep's end
                let stiffness = pf.tangent_stiffness(&q1, &v1, end)?;
                let levels = self.levels.len();
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
                    pf.commit(&q1, &v1, end, false)?;
                }
                q.copy_from_slice(&q1);
                v.copy_from_slice(&v1);
                Ok(iterations)
            }
            Err(None) => {
                let first = self.advance(depth + 1, pf, span, a, (q, v), watch)?;
                let mid = a + 0.5 * h;
                let second = self.advance(depth + 1, pf, span, mid, (q, v), watch)?;
                Ok(first + second)
            }
            Err(Some(error)) => Err(error),
        }
    }
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
    fn restricted(&self, a: f64, h: f64, n: usize) -> [Vec<f64>; 3] {
        let [p0, dp, ddp] = self.pb;
        let at = |s: f64, m: usize| p0[m] + dp[m] * s + 4.0 * ddp[m] * s * (1.0 - s);
        let mut out: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(n));
        for m in 0..n {
            let (f0, fm, f1) = (at(a, m), at(a + 0.5 * h, m), at(a + h, m));
            out[0].push(f0);
            out[1].push(f1 - f0);
            out[2].push(fm - 0.5 * (f0 + f1));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::{depth_for, Span, Watch, ACCURATE_LIMIT, CHANGE_LIMIT, STIFF_LIMIT};

    /// The rule: stability first (an error when the levels cannot reach it), then accuracy
    /// as far as the levels allow; nothing for a step no element dominates.
    #[test]
    fn one_rule_for_stability_and_accuracy() {
        assert_eq!((ACCURATE_LIMIT, CHANGE_LIMIT), (1.0, 2.0));
        assert_eq!(depth_for(0.0, 10.0, f64::INFINITY, 4), Ok(0));
        assert_eq!(depth_for(f64::NAN, 0.0, 0.0, 4), Ok(0));
        // within both limits: the plain step
        assert_eq!(
            depth_for(ACCURATE_LIMIT, ACCURATE_LIMIT, CHANGE_LIMIT, 4),
            Ok(0)
        );
        // accuracy: omega_c dt 2 -> 1 in one halving, capped by the levels, never an error
        assert_eq!(depth_for(2.0, 2.0, 0.0, 4), Ok(1));
        assert_eq!(depth_for(2.0, 2.0, 0.0, 0), Ok(0));
        // the run's peak, not the current stiffness, sets the accuracy depth
        assert_eq!(depth_for(0.1, 4.0, 0.0, 4), Ok(2));
        // a fast change of the stiffness: e^8 over the step -> 2 halvings to e^2
        assert_eq!(depth_for(0.1, 0.1, 8.0, 4), Ok(2));
        assert_eq!(depth_for(0.1, 0.1, f64::INFINITY, 4), Ok(4));
        // stability: 2^3 substeps bring 10 to 1.25; with 2 levels the run stops
        assert_eq!(depth_for(10.0, 10.0, 0.0, 2), Err(3));
        assert_eq!(depth_for(2.0 * STIFF_LIMIT, 0.0, 0.0, 1), Ok(1));
        assert_eq!(depth_for(10.0, 10.0, 0.0, 6), Ok(4));
    }

    /// The watch: an element that starts dominating changes the stiffness from its
    /// threshold (3 times the background); the peak and the depth it needed are kept.
    #[test]
    fn watch_counts_onset_from_the_threshold_and_keeps_the_depth() {
        let dt = 0.01;
        let mut w = Watch::new((0.0, 1.0));
        // just dominating (3.1 x a background of 1): no change worth a substep
        assert_eq!(w.depth((3.1, 1.0), dt, 1.0, 4), Ok(0));
        // a gap closing at 1e4 x its background: ln(1e4 / 3) = 8.1 -> 3 halvings to e^2
        assert_eq!(w.depth((1e4, 1.0), dt, 1.0, 4), Ok(3));
        w.accept((1e4, 1.0));
        // closed and steady at omega_c dt = 1: no substep needed, the depth is held
        assert_eq!(w.depth((1e4, 1.0), dt, 1.0, 4), Ok(3));
        // fewer levels available: as many as there are
        assert_eq!(w.depth((1e4, 1.0), dt, 1.0, 2), Ok(2));
        w.accept((0.0, 0.0));
        // open: the plain step
        assert_eq!(w.depth((0.0, 0.0), dt, 1.0, 4), Ok(0));
        // a fresh watch: steady at omega_c dt = 2, one halving, also for a half substep
        let mut fresh = Watch::new((4e4, 1.0));
        assert_eq!(fresh.depth((4e4, 1.0), dt, 1.0, 4), Ok(1));
        fresh.accept((4e4, 1.0));
        assert_eq!(fresh.depth((4e4, 1.0), dt, 0.5, 4), Ok(1));
    }

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
            let sub = span.restricted(a, h, 2);
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
