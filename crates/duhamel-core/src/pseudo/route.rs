//! The pseudo-force route: the uncoupled background stepped exactly, mode by mode, and the
//! implicit step equation of the pseudo-force (elements, couplings, mass law) solved every
//! step ([`super::newton`]).

use super::force::PseudoForce;
use super::newton::Stepper;
use super::problem::{validate, NonlinearProblem};
use super::scheme::{Rule, StepInput};
use crate::driver::{conclude, drive, Control, Route, StepFailure};
use crate::error::CoreError;
use crate::history::{size, zeroed, Coordinates, Failure, History, Stats};
use crate::kernel::oscillator::Transfer;
use crate::loads::block::BlockLoads;
use crate::loads::ModalForcing;
use crate::mass::MassTreatment;
use crate::problem::ModalProblem;

/// The state and buffers of the pseudo-force route.
struct PseudoRoute<'r, 'a> {
    transfers: &'r [Transfer],
    b: Vec<[[f64; 3]; 2]>,
    pf: PseudoForce<'a>,
    stepper: Stepper<'r>,
    /// The estimated-mass treatment (the saved pseudo-force is then evaluated anew).
    estimate: bool,
    q: Vec<f64>,
    v: Vec<f64>,
    q1: Vec<f64>,
    v1: Vec<f64>,
    ql: Vec<f64>,
    vl: Vec<f64>,
    /// The modal external load basis `(p0, Dp, DDp)` of the current step.
    pb: [Vec<f64>; 3],
    hq: Vec<f64>,
    hv: Vec<f64>,
    hp: Vec<f64>,
    stats: Stats,
}

impl PseudoRoute<'_, '_> {
    /// The modal external load basis of local step `s` (row `s = len`: the end value).
    fn load_basis(&mut self, problem: &ModalProblem, loads: &BlockLoads, s: usize) {
        let n = problem.n_modes();
        let n_loads = problem.loads.len();
        for (j, pj) in self.pb.iter_mut().enumerate() {
            for (m, p) in pj.iter_mut().enumerate() {
                *p = problem
                    .loads
                    .iter()
                    .enumerate()
                    .map(|(l, load)| load.pattern[m] * loads.basis[s * n_loads + l][j])
                    .sum();
            }
        }
        if !loads.forcing.is_empty() {
            let row = |h: usize| &loads.forcing[(2 * s + h).min(2 * loads.len) * n..][..n];
            let (f0, fm, f1) = (row(0), row(1), row(2));
            for m in 0..n {
                self.pb[0][m] += f0[m];
                self.pb[1][m] += f1[m] - f0[m];
                self.pb[2][m] += fm[m] - 0.5 * (f0[m] + f1[m]);
            }
        }
    }

    /// Saves the current state and its pseudo-force (evaluated unless `known`) in `slot`.
    fn save(&mut self, slot: usize, t: f64, known: bool) -> Result<(), CoreError> {
        let n = self.q.len();
        let r = slot * n..(slot + 1) * n;
        self.hq[r.clone()].copy_from_slice(&self.q);
        self.hv[r.clone()].copy_from_slice(&self.v);
        match self.stepper.start_pseudo().filter(|_| known) {
            Some(k) => {
                self.hp[r].copy_from_slice(k);
                Ok(())
            }
            None => self
                .pf
                .at_state(&self.q, &self.v, t, &self.pb[0], &mut self.hp[r]),
        }
    }

    /// The linear step of every mode (background and external loads only) into `ql`, `vl`.
    fn predict(&mut self, loads: &BlockLoads, s: usize) {
        let pb = &self.pb;
        #[allow(clippy::needless_range_loop)] // one index over six arrays
        for m in 0..self.q.len() {
            let a = &self.transfers[m].a;
            let bm = &self.b[m];
            let (q, v) = (self.q[m], self.v[m]);
            self.ql[m] = a[0][0] * q
                + a[0][1] * v
                + bm[0][0] * pb[0][m]
                + bm[0][1] * pb[1][m]
                + bm[0][2] * pb[2][m];
            self.vl[m] = a[1][0] * q
                + a[1][1] * v
                + bm[1][0] * pb[0][m]
                + bm[1][1] * pb[1][m]
                + bm[1][2] * pb[2][m];
        }
        for (_, dx, dv) in loads.jumps.iter().filter(|j| j.0 == s) {
            for (x, d) in self.ql.iter_mut().zip(dx) {
                *x += d;
            }
            for (x, d) in self.vl.iter_mut().zip(dv) {
                *x += d;
            }
        }
    }
}

impl Route for PseudoRoute<'_, '_> {
    fn block(&mut self, problem: &ModalProblem, loads: &BlockLoads) -> Result<(), StepFailure> {
        for s in 0..loads.len {
            let step = loads.n0 + s;
            let t = problem.time(step);
            self.load_basis(problem, loads, s);
            self.predict(loads, s);
            let input = StepInput {
                t,
                q0: &self.q,
                v0: &self.v,
                q_lin: &self.ql,
                v_lin: &self.vl,
                pb: [&self.pb[0], &self.pb[1], &self.pb[2]],
            };
            let solved = self
                .stepper
                .solve(&mut self.pf, &input, &mut self.q1, &mut self.v1);
            // The start state is saved after its step: the step has usually evaluated the
            // start state's pseudo-force already.
            if let Some(slot) = loads.slot[s] {
                self.save(slot, t, !self.estimate)
                    .map_err(StepFailure::at(step))?;
            }
            let iters = solved.map_err(StepFailure::at(step + 1))?;
            self.stats.newton_iterations += iters;
            if iters == 0 && self.stepper.analytic() {
                self.stats.closed_form_steps += 1;
            }
            if !self.q1.iter().chain(&self.v1).all(|x| x.is_finite()) {
                let error = CoreError::NonFinite {
                    time: 0.0,
                    step: step + 1,
                    last_good_time: 0.0,
                };
                return Err(StepFailure {
                    error,
                    step: step + 1,
                });
            }
            std::mem::swap(&mut self.q, &mut self.q1);
            std::mem::swap(&mut self.v, &mut self.v1);
        }
        Ok(())
    }

    fn save_current(
        &mut self,
        problem: &ModalProblem,
        loads: &BlockLoads,
        slot: usize,
    ) -> Result<(), CoreError> {
        self.load_basis(problem, loads, loads.len);
        self.save(slot, problem.time(loads.n0 + loads.len), false)
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
    let transfers: Vec<Transfer> = base
        .k
        .iter()
        .zip(base.c)
        .map(|(&k, &c)| Transfer::new(k, c, dt))
        .collect();
    let o = problem.options;
    let rule = Rule::new(o.scheme, o.quadrature, dt, &transfers);
    let pf = PseudoForce::new(
        problem.phi,
        problem.n_dof,
        problem.elements,
        problem.coupling_k,
        problem.coupling_c,
        problem.scaled,
        problem.mass,
        base.k,
        base.c,
    )
    .map_err(fail)?;
    let estimate = problem
        .mass
        .is_some_and(|m| m.treatment == MassTreatment::Estimate);
    let stepper = Stepper::new(
        &rule, o.scheme, dt, o.tol, o.max_iter, o.solver, &pf, estimate,
    );
    let loads = BlockLoads::new(base, true, forcing.is_some()).map_err(fail)?;
    let cells = size(loads.n_saved(), n, "the modal history").map_err(fail)?;
    let buffer = |what| zeroed(cells, what).map_err(fail);
    let mut route = PseudoRoute {
        b: transfers.iter().map(Transfer::b).collect(),
        transfers: &transfers,
        pf,
        stepper,
        estimate,
        q: base.q0.to_vec(),
        v: base.v0.to_vec(),
        q1: vec![0.0; n],
        v1: vec![0.0; n],
        ql: vec![0.0; n],
        vl: vec![0.0; n],
        pb: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
        hq: buffer("the modal history (q)")?,
        hv: buffer("the modal history (v)")?,
        hp: buffer("the pseudo-force")?,
        stats: Stats::default(),
    };
    let (loads, ending) = drive(base, &mut route, loads, forcing, control);
    let (t, load_values, forcing) = loads.into_saved(base).map_err(fail)?;
    let history = History {
        n_modes: n,
        n_loads: base.loads.len(),
        n_outputs: 0,
        t,
        coordinates: Coordinates::Modal {
            q: route.hq,
            v: route.hv,
        },
        load_values,
        forcing,
        pseudo: Some(route.hp),
        outputs: None,
    };
    let stats = route.stats;
    conclude(history, ending).map(|h| (h, stats))
}
