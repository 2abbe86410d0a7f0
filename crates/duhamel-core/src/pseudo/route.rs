//! The pseudo-force route: the uncoupled background stepped exactly, mode by mode, and the
//! implicit step equation of the pseudo-force (elements, couplings, mass law) solved every
//! step ([`super::newton`]).

use super::energy_hook::{energy_step, energy_tap};
use super::force::{Parts, PseudoForce};
use super::growth::{growth_guard, GrowthGuard};
use super::newton::StepSolver;
use super::problem::{validate, NonlinearProblem};
use super::rows::{linear_step, step_rows, StepRows};
use super::scheme::{Rule, StepInput};
use super::stiff_rule::Watch;
use super::subdivide::{retriable, LevelRules, Subdivider};
use crate::driver::{drive_modal, finish, Control, ModalRoute, StepFailure};
use crate::energy::EnergyTap;
use crate::error::CoreError;
use crate::history::{size, zeroed, Coordinates, ElementRows, Failure, History, Stats};
use crate::kernel::transfer_memo;
use crate::loads::block::BlockLoads;
use crate::loads::ModalForcing;
use crate::mass::MassTreatment;
use crate::problem::ModalProblem;

/// The state of a step: start and end state, the linear prediction and the load basis.
#[derive(Default)]
struct StepBuffers {
    q: Vec<f64>,
    v: Vec<f64>,
    q1: Vec<f64>,
    v1: Vec<f64>,
    ql: Vec<f64>,
    vl: Vec<f64>,
    /// The modal external load basis `(p0, Dp, DDp)` of the current step.
    pb: [Vec<f64>; 3],
}

impl StepBuffers {
    fn new(q0: &[f64], v0: &[f64]) -> Self {
        let n = q0.len();
        StepBuffers {
            q: q0.to_vec(),
            v: v0.to_vec(),
            q1: vec![0.0; n],
            v1: vec![0.0; n],
            ql: vec![0.0; n],
            vl: vec![0.0; n],
            pb: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
        }
    }
}

/// The modal external load basis of local step `s` (row `s = len`: the end value).
#[inline(always)]
fn load_basis(pb: &mut [Vec<f64>; 3], problem: &ModalProblem, loads: &BlockLoads, s: usize) {
    // Without loads nothing ever writes the basis: it stays zero.
    if !problem.loads.is_empty() || !loads.forcing.is_empty() {
        fill_basis(pb, problem, loads, s);
    }
}

/// [`load_basis`] with loads.
#[inline(never)]
fn fill_basis(pb: &mut [Vec<f64>; 3], problem: &ModalProblem, loads: &BlockLoads, s: usize) {
    let n_loads = problem.loads.len();
    let mut written = false;
    for (load, basis) in problem.loads.iter().zip(&loads.basis[s * n_loads..]) {
        // the first load written, `0 + pattern b` as the sum from a zeroed basis forms it (a
        // `memset` per row and a second pass over it cost more than the sum for one mode)
        let first = !written && load.pattern.len() >= pb[0].len();
        if !written && !first {
            pb.iter_mut().for_each(|pj| pj.fill(0.0));
        }
        written = true;
        for (pj, &bj) in pb.iter_mut().zip(basis) {
            for (p, &pattern) in pj.iter_mut().zip(&load.pattern) {
                *p = if first { 0.0 } else { *p } + pattern * bj;
            }
        }
    }
    if !written {
        pb.iter_mut().for_each(|pj| pj.fill(0.0));
    }
    if !loads.forcing.is_empty() {
        let n = problem.n_modes();
        let row = |h: usize| &loads.forcing[(2 * s + h).min(2 * loads.len) * n..][..n];
        let (f0, fm, f1) = (row(0), row(1), row(2));
        for m in 0..n {
            pb[0][m] += f0[m];
            pb[1][m] += f1[m] - f0[m];
            pb[2][m] += fm[m] - 0.5 * (f0[m] + f1[m]);
        }
    }
}

/// The linear step of every mode (background and external loads only) into `(ql, vl)`,
/// with the jumps of step loads that start inside local step `s`.
#[inline(always)]
fn predict(
    rows: &StepRows,
    (q, v): (&[f64], &[f64]),
    pb: &[Vec<f64>; 3],
    (ql, vl): (&mut [f64], &mut [f64]),
    loads: &BlockLoads,
    s: usize,
) {
    linear_step(rows, (q, v), [&pb[0], &pb[1], &pb[2]], (ql, vl));
    for (_, dx, dv) in loads.jumps.iter().filter(|j| j.0 == s) {
        for (x, d) in ql.iter_mut().zip(dx) {
            *x += d;
        }
        for (x, d) in vl.iter_mut().zip(dv) {
            *x += d;
        }
    }
}

/// The pseudo-force route: the background's matrices, the corrector and the history.
struct PseudoRoute<'r, 'a> {
    /// The exact step of each mode.
    rows: StepRows,
    pf: PseudoForce<'a>,
    solver: StepSolver<'r>,
    /// The estimated-mass treatment (the saved pseudo-force is then evaluated anew).
    estimate: bool,
    /// Whether hysteretic elements commit their variables after each step.
    stateful: bool,
    /// The levels of automatic subdivision, when the step equation is nonlinear or the
    /// elements' stiffness is watched.
    sub: Option<Subdivider<'r>>,
    /// The elements' modal tangent stiffness, when watched, and the substep rule on it (see
    /// [`super::subdivide::Watch`]).
    stiffness: Option<Watch>,
    /// The growth guard.
    guard: Option<GrowthGuard>,
    state: StepBuffers,
    hq: Vec<f64>,
    hv: Vec<f64>,
    hp: Vec<f64>,
    /// The elements' saved rows.
    he: ElementRows,
    stats: Stats,
    /// The energy integrals, when asked for ([`crate::energy`], hooks in `energy_hook.rs`).
    energy: Option<EnergyTap>,
}

impl PseudoRoute<'_, '_> {
    /// Saves the state `(q, v)` and its pseudo-force (evaluated, with the modal load `p`,
    /// unless `known`) in `slot`.
    fn save(
        &mut self,
        (q, v, p): (&[f64], &[f64], &[f64]),
        slot: usize,
        t: f64,
        known: bool,
    ) -> Result<(), CoreError> {
        if let Some(tap) = self.energy.as_mut() {
            tap.acc.save(slot);
        }
        let n = q.len();
        let r = slot * n..(slot + 1) * n;
        self.hq[r.clone()].copy_from_slice(q);
        self.hv[r.clone()].copy_from_slice(v);
        if self.he.width > 0 {
            let w = self.he.width;
            let e = slot * w..(slot + 1) * w;
            let he = &mut self.he;
            let rows = (&mut he.x[e.clone()], &mut he.v[e.clone()], &mut he.r[e]);
            self.pf.record((q, v), t, rows)?;
        }
        match self.solver.start_pseudo().filter(|_| known) {
            Some(k) => {
                self.hp[r].copy_from_slice(k);
                Ok(())
            }
            None => {
                let out = &mut self.hp[r];
                if known && self.solver.local_start(&self.pf, (q, v, p), t, out) {
                    return Ok(());
                }
                self.pf.at_state(q, v, t, p, out)
            }
        }
    }

    /// The steps of a block. The state is taken out of the route while they run, into
    /// locals: the hot loop then swaps and indexes registers, not the route's fields
    /// (measured: 10 % more instructions per Duffing step otherwise).
    fn steps(&mut self, problem: &ModalProblem, loads: &BlockLoads) -> Result<(), StepFailure> {
        let mut st = std::mem::take(&mut self.state);
        let StepBuffers {
            q,
            v,
            q1,
            v1,
            ql,
            vl,
            pb,
        } = &mut st;
        let mut result = Ok(());
        for s in 0..loads.len {
            let step = loads.n0 + s;
            let t = problem.time(step);
            load_basis(pb, problem, loads, s);
            predict(&self.rows, (q, v), pb, (ql, vl), loads, s);
            let input = StepInput {
                t,
                q0: q,
                v0: v,
                q_lin: ql,
                v_lin: vl,
                pb: [&pb[0], &pb[1], &pb[2]],
            };
            // the error boxed: the result is held across the save below, and a large
            // `Result` spilled there and reloaded whole stalled the loop (perf: 2 % of a
            // one-dof device's step on one load)
            let solved = self
                .solver
                .solve(&mut self.pf, &input, q1, v1)
                .map_err(Box::new);
            // The start state is saved after its step: the step has usually evaluated the
            // start state's pseudo-force already.
            if let Some(slot) = loads.slot[s] {
                if let Err(e) = self.save((q, v, &pb[0]), slot, t, !self.estimate) {
                    result = Err(StepFailure { error: e, step });
                    break;
                }
            }
            // The elements' tangent at the end state (and the start's): a step they make
            // too stiff for the pseudo-force step is taken in enough halves, or stops.
            let mut min_depth = 0;
            let solved = match (solved, self.stiffness.as_mut()) {
                (Ok(iters), Some(watch)) => {
                    // a step holding a load jump is not subdivided: only stability
                    let jump = loads.jumps.iter().any(|j| j.0 == s);
                    let depth = self.sub.as_ref().filter(|_| !jump).map_or(0, |s| s.depth());
                    let ends = ((&**q, &**v, t), (&**q1, &**v1, problem.time(step + 1)));
                    match watch.decide(&mut self.pf, ends, problem.dt, depth) {
                        Ok(0) => Ok(iters),
                        Ok(need) => {
                            min_depth = need;
                            Err(Box::new(CoreError::NoConvergence {
                                time: 0.0,
                                step: 0,
                                residual: 0.0,
                                iterations: 0,
                                last_good_time: None,
                            }))
                        }
                        Err(error) => Err(Box::new(error)),
                    }
                }
                (solved, _) => solved,
            };
            let mut subdivided = false;
            let iters = match (solved, &mut self.sub) {
                (Ok(iters), _) => iters,
                (Err(error), Some(sub))
                    if retriable(&error) && !loads.jumps.iter().any(|j| j.0 == s) =>
                {
                    subdivided = true;
                    q1.copy_from_slice(q);
                    v1.copy_from_slice(v);
                    let basis = [&pb[0][..], &pb[1][..], &pb[2][..]];
                    let span = (t, problem.dt);
                    let watch = (min_depth, self.stiffness.as_mut());
                    match sub.step(&mut self.pf, span, basis, (q1, v1), watch) {
                        Ok(iters) => {
                            if let Some(watch) = self.stiffness.as_mut() {
                                let end = problem.time(step + 1);
                                match self.pf.tangent_stiffness(q1, v1, end) {
                                    Ok((lambda, _)) => watch.accept((lambda, self.pf.bg())),
                                    Err(error) => {
                                        result = Err(StepFailure {
                                            error,
                                            step: step + 1,
                                        });
                                        break;
                                    }
                                }
                            }
                            iters
                        }
                        Err(error) => {
                            result = Err(StepFailure {
                                error,
                                step: step + 1,
                            });
                            break;
                        }
                    }
                }
                (Err(error), _) => {
                    result = Err(StepFailure {
                        error: *error,
                        step: step + 1,
                    });
                    break;
                }
            };
            self.stats.newton_iterations += iters;
            if iters == 0 && self.solver.analytic() {
                self.stats.closed_form_steps += 1;
            }
            // x * 0 is NaN exactly for a non-finite x: a branch-free (vectorised) test
            let poison = q1.iter().chain(v1.iter()).fold(0.0, |acc, x| acc + x * 0.0);
            if poison != 0.0 || poison.is_nan() {
                let error = CoreError::NonFinite {
                    time: 0.0,
                    step: step + 1,
                    last_good_time: None,
                };
                result = Err(StepFailure {
                    error,
                    step: step + 1,
                });
                break;
            }
            if self.stateful && !subdivided {
                let end = problem.time(step + 1);
                if let Err(error) = self.pf.commit(q1, v1, end, false) {
                    result = Err(StepFailure {
                        error,
                        step: step + 1,
                    });
                    break;
                }
            }
            if let Some(guard) = self.guard.as_mut() {
                let load = [&pb[0][..], &pb[1][..], &pb[2][..]];
                if let Err(error) = guard.step_basis(problem.dt, (q1, v1), load) {
                    result = Err(StepFailure {
                        error,
                        step: step + 1,
                    });
                    break;
                }
            }
            if let Err(f) = energy_step(
                &mut self.energy,
                &mut self.pf,
                (problem, loads, s),
                [&**q, v, q1, v1],
                pb,
            ) {
                result = Err(f);
                break;
            }
            std::mem::swap(q, q1);
            std::mem::swap(v, v1);
        }
        self.state = st;
        result
    }
}

impl ModalRoute for PseudoRoute<'_, '_> {
    fn block(&mut self, problem: &ModalProblem, loads: &BlockLoads) -> Result<(), StepFailure> {
        self.steps(problem, loads)
    }

    fn save_current(
        &mut self,
        problem: &ModalProblem,
        loads: &BlockLoads,
        slot: usize,
    ) -> Result<(), CoreError> {
        let mut st = std::mem::take(&mut self.state);
        load_basis(&mut st.pb, problem, loads, loads.len);
        let t = problem.time(loads.n0 + loads.len);
        let result = self.save((&st.q, &st.v, &st.pb[0]), slot, t, false);
        self.state = st;
        result
    }
}

/// Integrates the problem; `forcing` adds modal loads computed outside the engine,
/// `control` may stop or watch the run.
pub fn integrate(
    problem: &NonlinearProblem,
    forcing: Option<&mut dyn ModalForcing>,
    control: &mut dyn Control,
) -> Result<(History, Stats), Box<Failure>> {
    let fail = |e: CoreError| Box::new(Failure::from(e));
    validate(problem).map_err(fail)?;
    let base = &problem.base;
    let (n, dt) = (base.n_modes(), base.dt);
    // made once per model and step (a prepared model's runs share them)
    let transfers = transfer_memo::transfers(base.k, base.c, dt);
    let o = problem.options;
    let rule = Rule::new(o.scheme, o.quadrature, dt, &transfers);
    let pf = PseudoForce::new(Parts {
        phi: problem.phi,
        n_dof: problem.n_dof,
        elements: problem.elements,
        coupling_k: problem.coupling_k,
        coupling_c: problem.coupling_c,
        scaled: problem.scaled,
        mass: problem.mass,
        k: base.k,
        c: base.c,
    })
    .map_err(fail)?;
    let estimate = problem
        .mass
        .is_some_and(|m| m.treatment == MassTreatment::Estimate);
    let solver = StepSolver::new(&rule, dt, &o, &pf, estimate).map_err(fail)?;
    let mut pf = pf;
    let watch = pf.space().watched();
    let depth = if pf.linear && !watch {
        0
    } else {
        o.subdivisions
    };
    let rules = LevelRules::new(problem, depth);
    let sub = (depth > 0).then(|| Subdivider::new(problem, &rules, &pf, o, estimate));
    let stateful = pf.stateful();
    if stateful {
        pf.commit(base.q0, base.v0, base.time(0), true)
            .map_err(fail)?;
        if let Some(state) = problem.element_state {
            pf.set_element_state(state).map_err(fail)?;
        }
    }
    // An element that cannot be evaluated at the start is left to the first step, which
    // reports the failure with the initial state kept.
    let stiffness = if watch {
        let start = pf.tangent_stiffness(base.q0, base.v0, base.time(0));
        let start = start.map_or(0.0, |(lambda, _)| lambda);
        Some(Watch::new((start, pf.space().background())))
    } else {
        None
    };
    let guard = growth_guard(&mut pf, base, o.growth_limit, problem.guard_state);
    let loads = BlockLoads::new(base, true, forcing.is_some(), 3 * n).map_err(fail)?;
    let cells = size(loads.n_saved(), n, "the modal history").map_err(fail)?;
    let buffer = |what| zeroed(cells, what).map_err(fail);
    let widths = pf.element_widths();
    let width = widths.iter().sum();
    let tap = energy_tap(problem, &mut pf, &widths, loads.n_saved()).map_err(fail)?;
    let element_cells = size(loads.n_saved(), width, "the element history").map_err(fail)?;
    let element_buffer = |what| zeroed(element_cells, what).map_err(fail);
    let he = ElementRows {
        width,
        widths,
        x: element_buffer("the element displacements")?,
        v: element_buffer("the element velocities")?,
        r: element_buffer("the element forces")?,
    };
    let mut route = PseudoRoute {
        rows: step_rows(&transfers),
        pf,
        solver,
        estimate,
        stateful,
        sub,
        stiffness,
        guard,
        state: StepBuffers::new(base.q0, base.v0),
        hq: buffer("the modal history (q)")?,
        hv: buffer("the modal history (v)")?,
        hp: buffer("the pseudo-force")?,
        energy: tap,
        he,
        stats: Stats::default(),
    };
    let (loads, ending) = drive_modal(base, &mut route, loads, forcing, control);
    let kept = History {
        n_modes: n,
        coordinates: Coordinates::Modal {
            q: route.hq,
            v: route.hv,
        },
        pseudo: Some(route.hp),
        elements: (route.he.width > 0).then_some(route.he),
        element_state: stateful.then(|| route.pf.element_state()),
        guard_state: route.guard.as_ref().map(|g| g.state()),
        energy: route.energy.map(|tap| tap.acc.into_rows()),
        ..History::default()
    };
    let mut stats = route.stats;
    if let Some(sub) = &route.sub {
        (stats.subdivided_steps, stats.subdivision_depth) = (sub.steps, sub.deepest);
    }
    // A failed run keeps its statistics too: how often it subdivided before it stopped.
    finish(base, loads, kept, ending)
        .map(|h| (h, stats))
        .map_err(|mut failure| {
            failure.stats = stats;
            failure
        })
}
