//! One implicit step: `z = z_lin + sum_i W_i Q_i(z)` for the end state `z = (q1, v1)`.
//!
//! Which half of `z` is unknown depends on the scheme: the pseudo-force along schemes b and
//! c depends on `q1` only, along scheme a on `v1` only; the other half then follows
//! explicitly. The estimated-mass treatment depends on both. The equation is solved by
//! Newton's method with the elements' analytic tangents, or, for one mode with polynomial
//! forces of degree <= 3, as the cubic it is (the paper's closed form).

mod cubic;
mod damping;
mod local;
mod modal;

use super::closed::{scalar_step, ScalarPlan};
use super::force::{At, Jacobian, PseudoForce};
use super::local::ElementSpace;
use super::problem::Solver;
use super::scheme::{Rule, Scheme, StepInput, Unknown};
use crate::error::CoreError;

/// Which nodes to evaluate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Nodes {
    /// Those whose state does not depend on the unknowns (once per step).
    Constant,
    /// Those whose state does.
    Varying,
}

/// The solver of the step equation: its settings, strategies and reusable buffers.
pub struct StepSolver<'r> {
    n: usize,
    rule: &'r Rule,
    scheme: Scheme,
    dt: f64,
    tol: f64,
    max_iter: usize,
    unknown: Unknown,
    /// The step equation is linear (affine pseudo-force): one Newton step is exact.
    linear: bool,
    closed_form: bool,
    /// One mode with polynomial forces: the fully analytic step.
    scalar: Option<ScalarPlan>,
    /// Whether the last step left the start state's pseudo-force in `start`.
    start_known: bool,
    constant: Vec<bool>,
    q1: Vec<f64>,
    v1: Vec<f64>,
    qn: Vec<f64>,
    vn: Vec<f64>,
    pn: Vec<f64>,
    acc: Vec<f64>,
    start: Vec<f64>,
    values: Vec<Vec<f64>>,
    jacs: Vec<Jacobian>,
    res: Vec<f64>,
    mat: Vec<f64>,
    /// Newton's buffers, kept between steps.
    z0: Vec<f64>,
    delta: Vec<f64>,
    /// Newton in the elements' space, where the pseudo-force allows it and it is smaller.
    local: Option<(ElementSpace<'r>, local::LocalNewton)>,
}

/// How a step solver steps: the rule and scheme of the step `dt` and Newton's settings.
#[derive(Clone, Copy)]
pub struct Settings<'r> {
    /// The quadrature rule of the step (nodes and weights).
    pub rule: &'r Rule,
    /// The state approximation inside the step.
    pub scheme: Scheme,
    /// The step.
    pub dt: f64,
    /// Relative tolerance of the Newton updates.
    pub tol: f64,
    /// Newton iterations before giving up.
    pub max_iter: usize,
    /// Closed form where possible, or always Newton (and where).
    pub solver: Solver,
}

impl<'r> StepSolver<'r> {
    /// The solver of the step equation of `pf` (with the estimated-mass treatment when
    /// `estimate`) on the elements' space `space`.
    pub fn new(
        settings: Settings<'r>,
        pf: &PseudoForce,
        estimate: bool,
        space: ElementSpace<'r>,
    ) -> Result<Self, CoreError> {
        let Settings {
            rule,
            scheme,
            dt,
            tol,
            max_iter,
            solver,
        } = settings;
        let n = rule.wx[0].len();
        let unknown = match (estimate, scheme) {
            (true, _) => Unknown::Both,
            (false, Scheme::A) => Unknown::V1,
            (false, _) => Unknown::Q1,
        };
        // A node whose state does not depend on the unknowns is evaluated once per step.
        let constant: Vec<bool> = rule
            .nodes
            .iter()
            .map(|node| {
                let [dqq, dqv, dvq, dvv] = node.d;
                match unknown {
                    Unknown::Q1 => dqq == 0.0 && (dvq == 0.0 || !pf.uses_velocity),
                    Unknown::V1 => dqv == 0.0 && (dvv == 0.0 || !pf.uses_velocity),
                    Unknown::Both => false,
                }
            })
            .collect();
        let nodes = rule.nodes.len();
        let nd = space.len();
        let local =
            (solver != Solver::ModalNewton && unknown != Unknown::Both && pf.local() && nd < n)
                .then(|| {
                    let set = local::Setting {
                        rule,
                        scheme,
                        dt,
                        unknown,
                        constant: &constant,
                        tol,
                        max_iter,
                        linear: pf.linear,
                    };
                    let newton = local::LocalNewton::new(&space, pf, &set, n);
                    (space, newton)
                });
        // The modal Newton's dense matrices, only where it runs.
        let m = match (&local, unknown) {
            (Some(_), _) => 0,
            (None, Unknown::Both) => 2 * n,
            (None, _) => n,
        };
        let dense = if m > 0 { n } else { 0 };
        let (mf, nf) = (m as f64, dense as f64);
        crate::history::working(
            mf * mf + (2.0 * nodes as f64 + 2.0) * nf * nf,
            "the Newton iteration on all modal coordinates",
        )?;
        Ok(StepSolver {
            n,
            rule,
            scheme,
            dt,
            tol,
            max_iter,
            unknown,
            linear: pf.linear,
            closed_form: solver == Solver::Auto
                && n == 1
                && unknown != Unknown::Both
                && pf.polynomial,
            scalar: if solver == Solver::Auto && unknown != Unknown::Both {
                pf.scalar_model()
                    .map(|a| ScalarPlan::new(a, rule, scheme, dt, unknown == Unknown::V1))
            } else {
                None
            },
            start_known: false,
            constant,
            q1: vec![0.0; n],
            v1: vec![0.0; n],
            qn: vec![0.0; n],
            vn: vec![0.0; n],
            pn: vec![0.0; n],
            acc: vec![0.0; n],
            start: vec![0.0; n],
            values: vec![vec![0.0; n]; nodes],
            jacs: (0..nodes).map(|_| Jacobian::new(dense)).collect(),
            res: vec![0.0; m],
            mat: vec![0.0; m * m],
            z0: Vec::with_capacity(m),
            delta: vec![0.0; m],
            local,
        })
    }

    /// Evaluates the pseudo-force at the selected nodes for the current `(q1, v1)`.
    fn nodes(
        &mut self,
        pf: &mut PseudoForce,
        inp: &StepInput,
        tangent: bool,
        which: Nodes,
    ) -> Result<(), CoreError> {
        let dt = self.dt;
        for (i, node) in self.rule.nodes.iter().enumerate() {
            if self.constant[i] != (which == Nodes::Constant) {
                continue;
            }
            let s = node.s;
            for m in 0..self.n {
                (self.qn[m], self.vn[m]) = self
                    .scheme
                    .state(s, dt, inp.q0[m], inp.v0[m], self.q1[m], self.v1[m]);
                self.pn[m] = inp.pb[0][m] + inp.pb[1][m] * s + 4.0 * inp.pb[2][m] * s * (1.0 - s);
                self.acc[m] = (self.v1[m] - inp.v0[m]) / dt;
            }
            let jac = if tangent {
                Some(&mut self.jacs[i])
            } else {
                None
            };
            let a = (self.unknown == Unknown::Both).then_some(&self.acc[..]);
            let at = At {
                q: &self.qn,
                v: &self.vn,
                t: inp.t + s * dt,
                p: &self.pn,
                a,
            };
            pf.eval(at, &mut self.values[i], jac)?;
        }
        Ok(())
    }

    /// `row` 0: `q_lin + sum wx Q`; row 1: `v_lin + sum wv Q`, for mode `m`.
    fn explicit(&self, inp: &StepInput, row: usize, m: usize) -> f64 {
        let (base, w) = if row == 0 {
            (inp.q_lin, &self.rule.wx)
        } else {
            (inp.v_lin, &self.rule.wv)
        };
        base[m]
            + w.iter()
                .zip(&self.values)
                .map(|(wi, qi)| wi[m] * qi[m])
                .sum::<f64>()
    }

    /// Solves the step; writes the end state into `q_out`, `v_out`. Returns the Newton
    /// iterations used (0 for the closed form).
    pub fn solve(
        &mut self,
        pf: &mut PseudoForce,
        inp: &StepInput,
        q_out: &mut [f64],
        v_out: &mut [f64],
    ) -> Result<usize, CoreError> {
        let n = self.n;
        if let Some(plan) = &self.scalar {
            if let Some((q1, v1, q_start)) = scalar_step(plan, self.dt, self.unknown, pf, inp) {
                (self.q1[0], self.v1[0], self.start[0]) = (q1, v1, q_start);
                self.start_known = true;
                q_out.copy_from_slice(&self.q1);
                v_out.copy_from_slice(&self.v1);
                return Ok(0);
            }
        }
        if let Some((space, newton)) = &mut self.local {
            let set = local::Setting {
                rule: self.rule,
                scheme: self.scheme,
                dt: self.dt,
                unknown: self.unknown,
                constant: &self.constant,
                tol: self.tol,
                max_iter: self.max_iter,
                linear: self.linear,
            };
            // A constant first node is the start state itself (see below).
            self.start_known = self.constant[0];
            let start = self.start_known.then_some(&mut self.start[..]);
            // z: the unknown half (q1 for schemes b and c), w the other
            let (z, w) = if self.unknown == Unknown::V1 {
                (v_out, q_out)
            } else {
                (q_out, v_out)
            };
            return newton.step(space, pf, &set, inp, local::End { z, w, start });
        }
        // Predictor: the linear step plus the pseudo-force of the start state held constant.
        // A constant first node is the start state itself (s = 0, and the force does not
        // depend on the only thing that differs, the velocity of schemes a and b).
        self.q1.copy_from_slice(inp.q0);
        self.v1.copy_from_slice(inp.v0);
        self.nodes(pf, inp, false, Nodes::Constant)?;
        self.start_known = self.constant[0];
        if self.constant[0] {
            self.start.copy_from_slice(&self.values[0]);
        } else {
            self.acc.fill(0.0);
            pf.set_left_limit(false);
            let at = At {
                q: inp.q0,
                v: inp.v0,
                t: inp.t,
                p: inp.pb[0],
                a: Some(&self.acc),
            };
            pf.eval(at, &mut self.start, None)?;
        }
        for m in 0..n {
            let wx: f64 = self.rule.wx.iter().map(|w| w[m]).sum();
            let wv: f64 = self.rule.wv.iter().map(|w| w[m]).sum();
            self.q1[m] = inp.q_lin[m] + wx * self.start[m];
            self.v1[m] = inp.v_lin[m] + wv * self.start[m];
        }
        let iterations = if self.closed_form && self.closed(pf, inp)? {
            0
        } else {
            let it = self.newton(pf, inp)?;
            // Node values at the converged state (Newton's last ones precede its update).
            self.nodes(pf, inp, false, Nodes::Varying)?;
            it
        };
        // The other half of the end state, explicitly, from the node values.
        for m in 0..n {
            match self.unknown {
                Unknown::Q1 => self.v1[m] = self.explicit(inp, 1, m),
                Unknown::V1 => self.q1[m] = self.explicit(inp, 0, m),
                Unknown::Both => {}
            }
        }
        q_out.copy_from_slice(&self.q1);
        v_out.copy_from_slice(&self.v1);
        Ok(iterations)
    }

    /// The pseudo-force start values of the last step (the start state's `Q`), when the
    /// first node was that state: saves an evaluation for the saved history.
    pub fn start_pseudo(&self) -> Option<&[f64]> {
        self.start_known.then_some(&self.start[..])
    }

    /// The pseudo-force at the start state of the last step, `(q0, v0, p0)` at `t`, from
    /// what the element-space step kept (its start force): `false` when it cannot.
    pub fn local_start(
        &mut self,
        pf: &PseudoForce,
        state: (&[f64], &[f64], &[f64]),
        t: f64,
        out: &mut [f64],
    ) -> bool {
        match &mut self.local {
            Some((space, newton)) => newton.start_value(space, pf, state, t, out),
            None => false,
        }
    }

    /// The hysteretic elements' variables at the modal state `(q, v)` (see
    /// [`PseudoForce::commit`]), in every copy of the elements the step uses.
    pub fn commit(
        &mut self,
        pf: &mut PseudoForce,
        (q, v): (&[f64], &[f64]),
        t: f64,
        initial: bool,
    ) -> Result<(), CoreError> {
        if let Some((space, _)) = &mut self.local {
            if space.stateful() {
                space.commit(q, v, t, initial)?;
            }
        }
        if pf.stateful() {
            pf.commit(q, v, t, initial)?;
        }
        Ok(())
    }

    /// The hysteretic elements' variables in this step solver's own copy of the elements
    /// (the element space), not in the shared pseudo-force.
    pub fn commit_space(
        &mut self,
        _pf: &PseudoForce,
        (q, v): (&[f64], &[f64]),
        t: f64,
        initial: bool,
    ) -> Result<(), CoreError> {
        match &mut self.local {
            Some((space, _)) if space.stateful() => space.commit(q, v, t, initial),
            _ => Ok(()),
        }
    }

    /// Sets the committed variables of this step solver's copy of the elements.
    pub fn set_element_state(&mut self, state: &[f64]) -> Result<(), CoreError> {
        match &mut self.local {
            Some((space, _)) => space.set_element_state(state),
            None => Ok(()),
        }
    }

    /// Whether steps are solved analytically (closed form, no Newton).
    pub fn analytic(&self) -> bool {
        self.scalar.is_some() || self.closed_form
    }

    fn unknown_value(&self, m: usize) -> f64 {
        if self.unknown == Unknown::V1 {
            self.v1[m]
        } else {
            self.q1[m]
        }
    }

    fn set_unknown(&mut self, m: usize, u: f64) {
        if self.unknown == Unknown::V1 {
            self.v1[m] = u;
        } else {
            self.q1[m] = u;
        }
    }
}
