//! One implicit step: `z = z_lin + sum_i W_i Q_i(z)` for the end state `z = (q1, v1)`.
//!
//! Which half of `z` is unknown depends on the scheme: the pseudo-force along schemes b and
//! c depends on `q1` only, along scheme a on `v1` only; the other half then follows
//! explicitly. The estimated-mass treatment depends on both. The equation is solved by
//! Newton's method with the elements' analytic tangents, or, for one mode with polynomial
//! forces of degree <= 3, as the cubic it is (the paper's closed form).

mod cubic;
mod damping;
mod few;
mod hermite;
mod local;
mod modal;
mod one;
mod setting;

use super::closed::{scalar_step, ScalarPlan};
use super::force::PseudoForce;
use super::problem::{Options, Solver};
use super::scheme::{Rule, Scheme, StepInput, Unknown};
use crate::error::CoreError;
use few::Few;
use hermite::Hermite;
use local::{End, LocalNewton};
use modal::{Modal, Start};
use one::OneMode;
use setting::Setting;

/// How the step equation is solved, chosen once per run.
enum Strategy {
    /// One mode with polynomial forces of degree <= 3 (the paper's closed form): the cubic
    /// written down from the modal force's coefficients; when it has no real root, the
    /// closed form of [`Strategy::ClosedForm`], then Newton.
    Scalar(ScalarPlan, Modal),
    /// One mode with polynomial forces whose coefficients are not fixed (a coupling scaled
    /// by a time-varying speed, a mass law): the cubic from two evaluations of the residual
    /// (values and slopes), Newton when it has no real root.
    ClosedForm(Modal),
    /// Newton on all the modal coordinates.
    ModalNewton(Modal),
    /// The same for one mode, on scalars ([`one`]).
    OneMode(OneMode),
    /// The same for two and three modes, on fixed-size arrays ([`few`]).
    TwoModes(Box<Few<2>>),
    ThreeModes(Box<Few<3>>),
    /// One mode along the Hermite scheme (both halves of the end state unknown), on
    /// scalars ([`hermite`]).
    Hermite(Box<Hermite>),
    /// Newton in the elements' space, where the pseudo-force allows it and it is smaller.
    ElementSpace(Box<LocalNewton>),
}

/// The solver of the step equation: the step's setting, the strategy and the pseudo-force
/// at the last step's start state.
pub struct StepSolver<'r> {
    set: Setting<'r>,
    strategy: Strategy,
    start: Start,
}

impl<'r> StepSolver<'r> {
    /// The solver of the step equation of `pf` over steps `dt` with the quadrature `rule`
    /// (with the estimated-mass treatment when `estimate`), set by `options` (scheme,
    /// Newton's tolerance and iterations, solver).
    pub fn new(
        rule: &'r Rule,
        dt: f64,
        options: &Options,
        pf: &PseudoForce,
        estimate: bool,
    ) -> Result<Self, CoreError> {
        let Options {
            scheme,
            tol,
            max_iter,
            solver,
            ..
        } = *options;
        let n = rule.wx[0].len();
        let unknown = match (estimate, scheme) {
            (true, _) => Unknown::Both,
            (false, Scheme::A) => Unknown::V1,
            (false, Scheme::H) => Unknown::Both,
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
                    // the estimated mass reads the step's acceleration at every node
                    Unknown::Both => !estimate && node.d == [0.0; 4],
                }
            })
            .collect();
        let nodes = rule.nodes.len();
        let set = Setting {
            n,
            rule,
            scheme,
            dt,
            unknown,
            constant,
            tol,
            max_iter,
            linear: pf.linear,
            smooth: pf.polynomial,
            acceleration: estimate,
        };
        let local = solver != Solver::ModalNewton
            && unknown != Unknown::Both
            && pf.local()
            && pf.space().len() < n;
        let scalar = if solver == Solver::Auto && unknown != Unknown::Both {
            pf.scalar_model()
                .map(|a| ScalarPlan::new(a, rule, scheme, dt, unknown == Unknown::V1))
        } else {
            None
        };
        let closed_form =
            solver == Solver::Auto && n == 1 && unknown != Unknown::Both && pf.polynomial;
        // The modal Newton's dense matrices, only where it runs.
        let m = match (local, unknown) {
            (true, _) => 0,
            (false, Unknown::Both) => 2 * n,
            (false, _) => n,
        };
        let dense = if m > 0 { n } else { 0 };
        let (mf, nf) = (m as f64, dense as f64);
        crate::history::working(
            mf * mf + (2.0 * nodes as f64 + 2.0) * nf * nf,
            "the Newton iteration on all modal coordinates",
        )?;
        let modal = || Modal::new(n, nodes, m, dense);
        // A modal cubic is given for polynomials of degree <= 3 with tangents only: where
        // the scalar plan exists, so does the closed form it falls back on (and one mode
        // leaves no smaller element space).
        let strategy = match scalar {
            Some(plan) => {
                debug_assert!(closed_form && !local);
                Strategy::Scalar(plan, modal())
            }
            None if local => Strategy::ElementSpace(Box::new(LocalNewton::new(pf, &set, n))),
            None if closed_form => Strategy::ClosedForm(modal()),
            None if solver != Solver::ModalNewton && Hermite::applies(&set, pf) => {
                Strategy::Hermite(Box::new(Hermite::new(&set)))
            }
            // the dense reference stays the generic modal Newton
            None if solver != Solver::ModalNewton && OneMode::applies(&set, pf) => {
                Strategy::OneMode(OneMode::new(&set))
            }
            None if solver != Solver::ModalNewton && Few::<2>::applies(&set, pf) => {
                Strategy::TwoModes(Box::new(Few::new(&set)))
            }
            None if solver != Solver::ModalNewton && Few::<3>::applies(&set, pf) => {
                Strategy::ThreeModes(Box::new(Few::new(&set)))
            }
            None => {
                let mut modal = modal();
                // Affine without a mass law or a varying coupling: the same tangents, weights
                // and so matrix at every step.
                modal.constant_matrix = set.linear
                    && !pf.has_mass()
                    && !pf.varying_couplings()
                    && set.unknown != Unknown::Both;
                Strategy::ModalNewton(modal)
            }
        };
        Ok(StepSolver {
            set,
            strategy,
            start: Start {
                known: false,
                values: vec![0.0; n],
            },
        })
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
        let (set, start) = (&self.set, &mut self.start);
        let (modal, closed) = match &mut self.strategy {
            Strategy::Scalar(plan, modal) => {
                if let Some((q1, v1, q_start)) = scalar_step(plan, set.dt, set.unknown, pf, inp) {
                    (modal.q1[0], modal.v1[0], start.values[0]) = (q1, v1, q_start);
                    start.known = true;
                    q_out.copy_from_slice(&modal.q1);
                    v_out.copy_from_slice(&modal.v1);
                    return Ok(0);
                }
                (modal, true)
            }
            Strategy::ClosedForm(modal) => (modal, true),
            Strategy::ModalNewton(modal) => (modal, false),
            Strategy::OneMode(one) => {
                start.known = set.constant[0];
                return one.solve(set, pf, inp, (q_out, v_out), &mut start.values[0]);
            }
            Strategy::TwoModes(few) => {
                start.known = set.constant[0];
                return few.solve(set, pf, inp, (q_out, v_out), &mut start.values);
            }
            Strategy::ThreeModes(few) => {
                start.known = set.constant[0];
                return few.solve(set, pf, inp, (q_out, v_out), &mut start.values);
            }
            Strategy::Hermite(one) => {
                start.known = set.constant[0];
                return one.solve(set, pf, inp, (q_out, v_out), &mut start.values[0]);
            }
            Strategy::ElementSpace(newton) => {
                // A constant first node is the start state itself (see Modal::solve).
                start.known = set.constant[0];
                let start = start.known.then_some(&mut start.values[..]);
                // z: the unknown half (q1 for schemes b and c), w the other
                let (z, w) = if set.unknown == Unknown::V1 {
                    (v_out, q_out)
                } else {
                    (q_out, v_out)
                };
                return newton.step(pf, set, inp, End { z, w, start });
            }
        };
        let iterations = modal.solve(set, closed, pf, inp, start)?;
        q_out.copy_from_slice(&modal.q1);
        v_out.copy_from_slice(&modal.v1);
        Ok(iterations)
    }

    /// The pseudo-force start values of the last step (the start state's `Q`), when the
    /// first node was that state: saves an evaluation for the saved history.
    pub fn start_pseudo(&self) -> Option<&[f64]> {
        self.start.known.then_some(&self.start.values[..])
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
        match &mut self.strategy {
            Strategy::ElementSpace(newton) => newton.start_value(pf, state, t, out),
            _ => false,
        }
    }

    /// Whether steps are solved analytically (closed form, no Newton).
    pub fn analytic(&self) -> bool {
        matches!(
            self.strategy,
            Strategy::Scalar(..) | Strategy::ClosedForm(_)
        )
    }
}
