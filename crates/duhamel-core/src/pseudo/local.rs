//! The space of the nonlinear elements: the physical degrees of freedom they act on.
//!
//! A model with a few local nonlinearities (bearings, isolators, gaps) has many modes but few
//! element dofs `D`. The elements see the modal state only through `u = Phi_D q` and act on it
//! only through `Phi_D^T r(u, u')`, so their step equation can be written and solved in the
//! `n_d = |D|` physical coordinates instead of the `n` modal ones (see [`super::newton`]).
//!
//! The space is also the one owner of the elements' evaluations: their buffers and, for a
//! hysteretic element, its committed and trial internal variables. The pseudo-force holds
//! the space; the modal Newton, the element-space Newton and every subdivision level
//! evaluate the same elements, and the route commits them once per accepted (sub)step.

mod deform;
mod start;
mod stiffness;

use crate::elements::{Element, Evaluation};
use crate::error::CoreError;

/// The ratio of an element's tangent stiffness to the modal stiffness of the background it
/// loads from which the element is said to dominate it and its tangent is watched. Below
/// it the step's limit (omega_c dt = 3.21 - 3.30 at a ratio of 0.3, 3.30 - 3.32 at 1,
/// 3.38 - 3.39 at 3, zeta 0 - 0.05: a window that closes again at larger steps when damped,
/// the lightly damped background's own property; the paper's stability charts run such
/// steps on purpose) is left to the user; from it up the limit approaches the
/// linear-acceleration method's 2 sqrt(3). Measured: the paper's rotor (cubic bearings
/// about as stiff as their modes, ratio 1.05) stays on its plain steps.
pub const DOMINANT: f64 = 2.0;

/// `x.fill(0.0)`, a single entry written directly (a `memset` call for one number costs
/// more than the element dof's whole force evaluation).
#[inline(always)]
pub(super) fn zero(x: &mut [f64]) {
    if let [only] = x {
        *only = 0.0;
    } else {
        x.fill(0.0);
    }
}

/// An element evaluated in the element space: its buffers and where its local dofs sit in `D`.
struct Member<'a> {
    eval: Evaluation<'a>,
    at: Vec<usize>,
    /// `Phi_e Phi_e^T` (`nl x nl`, row-major): fixed for the run, formed once for the
    /// stiffness watch (the same dot products it formed at every step).
    gram: Vec<f64>,
    /// One-dof elements: `(sum phi^2, sum phi^2 max(k_m, 0))` over the modes, the element's
    /// share of the background per unit tangent (fixed for the run's modal stiffnesses;
    /// formed at the first watch instead of a pass over the modes at every step).
    share: Option<(f64, f64)>,
    /// Wider elements: the coordinates without mass (modal stiffness `+inf`) their dofs'
    /// mode-shape rows reach, formed with `share`. Where the element's tangent loads one of
    /// them, its background is infinite and it never dominates: the watch stops there.
    massless: Option<Vec<usize>>,
    /// Two-dof elements: the stiffness watch's outcome for the tangent `kx` (its bits) it
    /// last measured with the current modal stiffnesses: `(lambda, share, weighted)`, or
    /// None when the element adds nothing or does not dominate (a hinge's tangent takes
    /// two values, elastic and yielded: measured again only when it changes).
    measured: Option<([u64; 4], Outcome)>,
}

/// A member's part of the stiffness watch: `(lambda, share, weighted)` when it adds to the
/// closed state's stiffness, None otherwise (`stiffness.rs`).
type Outcome = Option<(f64, f64, f64)>;

/// The element dofs `D`, their mode-shape rows and the elements acting on them.
pub struct ElementSpace<'a> {
    n_modes: usize,
    /// `Phi_D`, row-major `n_d x n_modes`.
    phi: Vec<f64>,
    members: Vec<Member<'a>>,
    /// Set by a step solver whose last evaluation (with tangents) was at its converged end
    /// state: the evaluations the members had counted then. The stiffness watch reuses
    /// those tangents when no evaluation came in between.
    end_mark: Option<u64>,
    /// Set by the element-space step whose last evaluation of every member was at its
    /// converged end state (the end node, no element reading the velocity): the
    /// evaluations counted then. The route's commit right after it commits those trial
    /// variables as they are ([`ElementSpace::commit`]).
    end_trial: Option<u64>,
    /// The background of the last [`ElementSpace::tangent_stiffness`] (0 when no element
    /// dominated).
    background: f64,
    /// The modal stiffnesses the members' `share` were formed with (address and length).
    share_key: (usize, usize),
    /// The stiffness watch's scratch: a wide member's `diag(Phi_e^T K_e Phi_e)` per mode.
    diag: Vec<f64>,
    /// How many times the members' committed variables were set (commits, starts,
    /// restores): what tells a step solver that nothing but one commit came between two
    /// steps.
    generation: u64,
    /// Whether the space is one element on one dof ([`ElementSpace::eval_one`]).
    single: bool,
    /// The largest member's [`Element::resolution`] (constant: from its loaded start).
    resolution: f64,
    /// The members' local states and forces at the start state of the last element-space
    /// step ([`ElementSpace::keep_start`]), for the record of that state.
    start: start::Start,
    /// The members' deformations, when each is a scalar two-node element
    /// ([`deform::Deformations::of`]).
    deform: Option<deform::Deformations>,
}

impl<'a> ElementSpace<'a> {
    /// The space of `elements` (whose dofs are known to be `< n_dof`) for the mode shapes
    /// `phi` (`n_dof x n_modes`, row-major).
    pub fn new(phi: &[f64], n_modes: usize, elements: &'a [&'a dyn Element]) -> Self {
        let mut dofs: Vec<usize> = elements.iter().flat_map(|e| e.dofs().to_vec()).collect();
        dofs.sort_unstable();
        dofs.dedup();
        let position = |d: usize| dofs.binary_search(&d).unwrap_or(0);
        let phi: Vec<f64> = dofs
            .iter()
            .flat_map(|&d| phi[d * n_modes..(d + 1) * n_modes].iter().copied())
            .collect();
        let row = |a: usize| &phi[a * n_modes..(a + 1) * n_modes];
        let members = elements
            .iter()
            .map(|&e| {
                let at: Vec<usize> = e.dofs().iter().map(|&d| position(d)).collect();
                let gram = at
                    .iter()
                    .flat_map(|&a| at.iter().map(move |&b| (a, b)))
                    .map(|(a, b)| crate::dense::dot(row(a), row(b)))
                    .collect();
                Member {
                    eval: Evaluation::new(e),
                    at,
                    gram,
                    share: None,
                    massless: None,
                    measured: None,
                }
            })
            .collect::<Vec<Member>>();
        let single = matches!(&members[..], [m] if m.at.len() == 1);
        let resolution = elements.iter().fold(0.0_f64, |a, e| a.max(e.resolution()));
        let deform = deform::Deformations::of(
            members.iter().map(|m| (m.eval.element, &m.at[..])),
            &phi,
            n_modes,
        );
        ElementSpace {
            n_modes,
            phi,
            members,
            end_mark: None,
            end_trial: None,
            background: 0.0,
            share_key: (0, 0),
            diag: Vec::new(),
            generation: 0,
            single,
            resolution,
            start: start::Start::default(),
            deform,
        }
    }

    /// Whether an element reads the velocity of its dofs.
    pub fn uses_velocity(&self) -> bool {
        self.members.iter().any(|m| m.eval.uses_velocity())
    }

    /// How many times the committed variables were set so far.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The largest member's [`Element::resolution`]: the displacement correction Newton
    /// cannot resolve below.
    pub fn resolution(&self) -> f64 {
        self.resolution
    }

    /// Whether every member's force at a committed state is that of the evaluation
    /// committed there ([`Evaluation::restarts_exactly`]).
    pub fn restarts_exactly(&self) -> bool {
        self.members.iter().all(|m| m.eval.restarts_exactly())
    }

    /// The evaluations all members have counted.
    fn evaluations(&self) -> u64 {
        self.members.iter().map(|m| m.eval.evaluations()).sum()
    }

    /// Marks the members' last evaluations as the converged end state's, with tangents (a
    /// step solver calls this right after evaluating there with tangents). Only when no
    /// element's stiffness tangent depends on the velocity: the solver's node velocity at
    /// the end is not the end state's (the explicit half of the step is computed after it),
    /// and a stiffness that depends on it (a contact's damping) is not the one at the end
    /// state; a constant damping matrix taken out ([`crate::elements::Shifted`]) leaves the
    /// stiffness the displacements' alone.
    pub fn mark_end(&mut self) {
        let fresh = self
            .members
            .iter()
            .all(|m| m.eval.with_tangent() && !m.eval.stiffness_reads_velocity());
        self.end_mark = fresh.then(|| self.evaluations());
    }

    /// Marks the members' last evaluations as those of the converged end state of an
    /// element-space step (its end node, at the element coordinates Newton converged to):
    /// the commit that follows with no evaluation in between takes their trial variables
    /// as they are instead of evaluating again at `Phi_D q1`, which differs from those
    /// coordinates by rounding only (a fifth of a chain's elastic `Bilinear` step).
    /// Only when no element reads the velocity (the node's velocity is not the end
    /// state's).
    pub fn mark_end_trial(&mut self) {
        let free = self.members.iter().all(|m| !m.eval.uses_velocity());
        self.end_trial = free.then(|| self.evaluations());
    }

    /// Whether an element has internal variables (hysteresis) to commit after each step.
    pub fn stateful(&self) -> bool {
        self.members.iter().any(|m| m.eval.stateful())
    }

    /// The hysteretic elements' variables at the modal state `(q, v)`: set to their initial
    /// values (`initial`) or committed after evaluating there at `t`.
    pub fn commit(&mut self, q: &[f64], v: &[f64], t: f64, initial: bool) -> Result<(), CoreError> {
        self.generation += 1;
        let n = self.n_modes;
        // a kept start state was evaluated from the variables committed before
        self.start.valid = false;
        // the members last evaluated at the step's converged end (mark_end_trial): their
        // local state is that end's, and each commits the trial variables it holds
        let marked = self.end_trial.take();
        let held = !initial && marked.is_some() && marked == Some(self.evaluations());
        let phi = &self.phi;
        if let [m] = &mut self.members[..] {
            // one member (a one-dof device): the loop below without its iterators
            let e = &mut m.eval;
            if !e.stateful() {
                return Ok(());
            }
            if let ([a], false) = (&m.at[..], held) {
                let row = &phi[a * n..(a + 1) * n];
                (e.x[0], e.v[0]) = (crate::dense::dot(row, q), crate::dense::dot(row, v));
            } else if !held {
                for (j, &a) in m.at.iter().enumerate() {
                    let row = &phi[a * n..(a + 1) * n];
                    e.x[j] = crate::dense::dot(row, q);
                    e.v[j] = crate::dense::dot(row, v);
                }
            }
            return if initial {
                e.start(t);
                Ok(())
            } else {
                e.commit(t)
            };
        }
        for m in self.members.iter_mut().filter(|m| m.eval.stateful()) {
            let e = &mut m.eval;
            for (j, &a) in m.at.iter().enumerate().filter(|_| !held) {
                let row = &phi[a * n..(a + 1) * n];
                e.x[j] = crate::dense::dot(row, q);
                e.v[j] = crate::dense::dot(row, v);
            }
            if initial {
                e.start(t);
            } else {
                e.commit(t)?;
            }
        }
        Ok(())
    }

    /// The committed internal variables of every element, concatenated in element order.
    pub fn element_state(&self) -> Vec<f64> {
        self.members
            .iter()
            .flat_map(|m| m.eval.committed().iter().copied())
            .collect()
    }

    /// Sets them (the layout of [`ElementSpace::element_state`]), e.g. from a checkpoint.
    pub fn set_element_state(&mut self, state: &[f64]) -> Result<(), CoreError> {
        let expected: usize = self.members.iter().map(|m| m.eval.committed().len()).sum();
        if state.len() != expected {
            return Err(CoreError::LengthMismatch {
                name: "element_state",
                got: state.len(),
                expected,
            });
        }
        if let Some(i) = state.iter().position(|x| !x.is_finite()) {
            return Err(CoreError::InvalidInput {
                name: "element_state",
                problem: format!("must be finite (entry {i} is {})", state[i]),
            });
        }
        self.generation += 1;
        self.start.valid = false;
        let mut at = 0;
        for m in &mut self.members {
            let len = m.eval.committed().len();
            m.eval.set_committed(&state[at..at + len]);
            at += len;
        }
        Ok(())
    }

    /// The modal stiffness of the background the last
    /// [`ElementSpace::tangent_stiffness`] counted (0 when no element dominated it).
    pub fn background(&self) -> f64 {
        self.background
    }

    /// Whether [`ElementSpace::tangent_stiffness`] watches any element.
    pub fn watched(&self) -> bool {
        self.members.iter().any(|m| !m.at.is_empty())
    }

    /// The dofs of element `index`.
    pub fn element_dofs(&self, index: usize) -> &[usize] {
        self.members[index].eval.element.dofs()
    }

    /// The elements' numbers of local dofs.
    pub fn element_widths(&self) -> Vec<usize> {
        self.members.iter().map(|m| m.at.len()).collect()
    }

    /// The number of elements.
    pub fn element_count(&self) -> usize {
        self.members.len()
    }

    /// Each element with its local dofs' mode-shape rows, `phi_e[j * n_modes + m]`.
    pub fn element_rows(&self) -> impl Iterator<Item = (&'a dyn Element, Vec<f64>)> + '_ {
        let n = self.n_modes;
        self.members.iter().map(move |m| {
            let rows =
                m.at.iter()
                    .flat_map(|&a| self.phi[a * n..(a + 1) * n].iter().copied())
                    .collect();
            (m.eval.element, rows)
        })
    }

    /// `Phi_D` and every element's evaluation with the positions of its local dofs in `D`.
    pub fn members_mut(
        &mut self,
    ) -> (
        &[f64],
        impl Iterator<Item = (&mut Evaluation<'a>, &[usize])> + '_,
    ) {
        let members = self.members.iter_mut().map(|m| (&mut m.eval, &m.at[..]));
        (&self.phi, members)
    }

    /// The one member of a space of one element on one dof ([`ElementSpace::single`]) with
    /// its dof's mode-shape entry of the first mode.
    #[inline(always)]
    pub fn single_member(&mut self) -> (f64, &mut Evaluation<'a>) {
        debug_assert!(self.single);
        (self.phi[0], &mut self.members[0].eval)
    }

    /// `n_d`, the number of element dofs.
    pub fn len(&self) -> usize {
        self.phi.len() / self.n_modes.max(1)
    }

    /// For each element dof, the element dofs an element couples it with (itself included):
    /// the sparsity of the assembled tangents' rows.
    pub fn pattern(&self) -> Vec<Vec<usize>> {
        let mut rows = vec![Vec::new(); self.len()];
        for m in &self.members {
            for &a in &m.at {
                rows[a].extend_from_slice(&m.at);
            }
        }
        for row in &mut rows {
            row.sort_unstable();
            row.dedup();
        }
        rows
    }

    /// `Phi_D`, row-major `n_d x n_modes`.
    pub fn phi(&self) -> &[f64] {
        &self.phi
    }

    /// `out = Phi_D q`.
    pub fn to_local(&self, q: &[f64], out: &mut [f64]) {
        // each entry `dot(row, q)` bit for bit, four rows at a time
        crate::dense_rows::matvec(&self.phi, &q[..self.n_modes], out);
    }

    /// `Phi_D x_k` for three vectors at once (one pass over `Phi_D`), into `out_k`.
    pub fn to_local3(&self, x: [&[f64]; 3], out: [&mut [f64]; 3]) {
        let [o0, o1, o2] = out;
        for (a, row) in self.phi.chunks_exact(self.n_modes).enumerate() {
            let (s0, s1, s2) = crate::dense::dot3(row, x);
            (o0[a], o1[a], o2[a]) = (s0, s1, s2);
        }
    }

    /// `out = Phi_D^T r` (length `n_modes`, overwritten).
    pub fn project(&self, r: &[f64], out: &mut [f64]) {
        if let [ra] = r {
            // one element dof: written in one pass, `0 + r phi` as below (a `memset`
            // followed by the read-modify-write of the same lines stalled on the stores:
            // 15 % of a chain's element-space step)
            let ra = *ra;
            for (o, p) in out.iter_mut().zip(&self.phi[..self.n_modes]) {
                *o = if ra != 0.0 { 0.0 + ra * p } else { 0.0 };
            }
            return;
        }
        out.fill(0.0);
        let rows = r.iter().zip(self.phi.chunks_exact(self.n_modes));
        deform::add_rows(
            out,
            rows.filter(|(ra, _)| **ra != 0.0)
                .map(|(ra, row)| (*ra, row)),
        );
    }

    /// Whether the space is one element on one dof: [`ElementSpace::eval_one`] applies.
    pub fn single(&self) -> bool {
        self.single
    }

    /// [`ElementSpace::eval`] of a space of one element on one dof ([`ElementSpace::single`])
    /// on scalars: the force, and with `tangent` its tangents `dr/du`, `dr/du'` (otherwise
    /// the last ones computed), each summed from zero as `eval` assembles them (the same
    /// numbers, signed zeros included).
    #[inline]
    pub fn eval_one(
        &mut self,
        u: f64,
        ud: f64,
        t: f64,
        tangent: bool,
    ) -> Result<(f64, f64, f64), CoreError> {
        debug_assert!(self.single);
        let e = &mut self.members[0].eval;
        (e.x[0], e.v[0]) = (u, ud);
        e.evaluate(t, tangent)?;
        Ok((0.0 + e.r[0], 0.0 + e.kx[0], 0.0 + e.cv[0]))
    }

    /// The assembled element force `r` (length `n_d`, overwritten) at the element-space
    /// state `(u, u')` and time `t`; with `tangent`, `dr/du` and `dr/du'` (row-major
    /// `n_d x n_d`, overwritten).
    pub fn eval(
        &mut self,
        u: &[f64],
        ud: &[f64],
        t: f64,
        r: &mut [f64],
        mut tangent: Option<(&mut [f64], &mut [f64])>,
    ) -> Result<(), CoreError> {
        let nd = r.len();
        if self.single && nd == 1 {
            let (force, k, c) = self.eval_one(u[0], ud[0], t, tangent.is_some())?;
            r[0] = force;
            if let Some((kt, ct)) = tangent {
                (kt[0], ct[0]) = (k, c);
            }
            return Ok(());
        }
        zero(r);
        if let Some((k, c)) = tangent.as_mut() {
            zero(k);
            zero(c);
        }
        for m in &mut self.members {
            let e = &mut m.eval;
            for (j, &a) in m.at.iter().enumerate() {
                e.x[j] = u[a];
                e.v[j] = ud[a];
            }
            e.evaluate(t, tangent.is_some())?;
            let nl = m.at.len();
            for (j, &a) in m.at.iter().enumerate() {
                r[a] += e.r[j];
            }
            if let Some((k, c)) = tangent.as_mut() {
                for (i, &a) in m.at.iter().enumerate() {
                    for (j, &b) in m.at.iter().enumerate() {
                        k[a * nd + b] += e.kx[i * nl + j];
                        c[a * nd + b] += e.cv[i * nl + j];
                    }
                }
            }
        }
        Ok(())
    }
}
