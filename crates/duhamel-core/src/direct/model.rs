//! The physical equation of motion, term by term:
//!
//! `mu M x'' + [momentum] mu' M x' + C x' + s K x + Kc x + sum_j w_j (K_j x + C_j x')
//! + r(x, x', t) = f(t)`
//!
//! with `mu(t)` the mass law (1 without one), `s = mu` when the stiffness scales with the
//! mass (else 1), `Kc` the stiffness that does not scale (linear couplings) and `w_j(t)` the
//! speed laws of the scaled couplings `(K_j, C_j)`.

use super::assembly::{IterationMatrix, Matrix};
use super::problem::DirectProblem;
use crate::elements::Evaluation;
use crate::error::CoreError;
use crate::loads::ModalForcing;
use crate::mass::MassForm;

/// Index of each constant matrix in the iteration matrix's sources.
pub(crate) const M: usize = 0;
pub(crate) const K: usize = 1;
pub(crate) const C: usize = 2;
pub(crate) const KC: usize = 3;

/// Mass-law coefficients at one time: `mu`, the momentum term's `mu'` (0 in the acceleration
/// form) and the stiffness scale `s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Coefs {
    pub mu: f64,
    pub dmu: f64,
    pub s: f64,
}

/// A physical state at one instant: displacements `x` and velocities `v` at time `t`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct State<'s> {
    pub x: &'s [f64],
    pub v: &'s [f64],
    pub t: f64,
}

/// Evaluates the terms of the equation of motion.
pub(crate) struct Model<'a> {
    pub p: &'a DirectProblem<'a>,
    pub n: usize,
    pub slots: Vec<Evaluation<'a>>,
    /// Whether any element force depends on the velocities.
    pub velocity_elements: bool,
    /// Whether a scaled coupling's speed law varies in time (the iteration matrix then
    /// changes from step to step).
    pub varying_scale: bool,
    /// Index among [`Model::matrices`] of each scaled coupling's `K` and `C`.
    scaled_index: Vec<(Option<usize>, Option<usize>)>,
    scratch: Vec<f64>,
}

impl<'a> Model<'a> {
    pub fn new(p: &'a DirectProblem<'a>) -> Self {
        let slots = p
            .elements
            .iter()
            .map(|&element| Evaluation::new(element))
            .collect();
        let n = p.x0.len();
        let mut next = 2 + usize::from(p.c.is_some()) + usize::from(p.k_fixed.is_some());
        let mut take = |present: bool| {
            present.then(|| {
                next += 1;
                next - 1
            })
        };
        let scaled_index = p
            .scaled
            .iter()
            .map(|s| (take(s.k.is_some()), take(s.c.is_some())))
            .collect();
        Model {
            p,
            n,
            slots,
            velocity_elements: p.elements.iter().any(|e| e.uses_velocity()),
            varying_scale: p.scaled.iter().any(|s| s.law.constant_value().is_none()),
            scaled_index,
            scratch: vec![0.0; n],
        }
    }

    /// The constant matrices in the order of [`M`], [`K`], [`C`], [`KC`] (absent ones left
    /// out), then each scaled coupling's `K` and `C`, for an iteration matrix.
    pub fn matrices(&self) -> Vec<&'a Matrix> {
        let mut out = vec![self.p.m, self.p.k];
        out.extend(self.p.c);
        out.extend(self.p.k_fixed);
        for s in self.p.scaled {
            out.extend(s.k);
            out.extend(s.c);
        }
        out
    }

    /// Adds `ck K_j + cc C_j` of scaled coupling `j` into block `block` (the caller includes
    /// the speed law's value in the coefficients).
    pub fn add_scaled(
        &self,
        it: &mut IterationMatrix,
        j: usize,
        block: (usize, usize),
        ck: f64,
        cc: f64,
    ) {
        let (ik, ic) = self.scaled_index[j];
        if let Some(i) = ik {
            it.add_matrix(i, block, ck);
        }
        if let Some(i) = ic {
            it.add_matrix(i, block, cc);
        }
    }

    /// The speed laws' values at `t`, one per scaled coupling.
    pub fn scales(&self, t: f64) -> impl Iterator<Item = f64> + '_ {
        self.p.scaled.iter().map(move |s| s.law.omega(t))
    }

    /// Index of the optional matrices among [`Model::matrices`].
    pub fn index(&self, which: usize) -> Option<usize> {
        match which {
            M => Some(0),
            K => Some(1),
            C => self.p.c.map(|_| 2),
            KC => self.p.k_fixed.map(|_| 2 + usize::from(self.p.c.is_some())),
            _ => None,
        }
    }

    /// An iteration matrix of `nb x nb` blocks fed by these matrices and elements.
    pub fn iteration_matrix(&self, nb: usize) -> Result<IterationMatrix<'a>, CoreError> {
        let dofs: Vec<&[usize]> = self.p.elements.iter().map(|e| e.dofs()).collect();
        IterationMatrix::new(self.n, nb, &self.matrices(), &dofs)
    }

    /// Adds `coef` times constant matrix `which` (if present) into block `block`.
    pub fn add(&self, it: &mut IterationMatrix, which: usize, block: (usize, usize), coef: f64) {
        if let Some(i) = self.index(which) {
            it.add_matrix(i, block, coef);
        }
    }

    /// Adds the elements' last evaluated tangents: `ck dr/dx + cc dr/dx'`.
    pub fn add_tangents(&self, it: &mut IterationMatrix, block: (usize, usize), ck: f64, cc: f64) {
        for (e, slot) in self.slots.iter().enumerate() {
            let dofs = slot.element.dofs();
            it.add_local(e, dofs, &slot.kx, block, ck);
            it.add_local(e, dofs, &slot.cv, block, cc);
        }
    }

    /// Mass-law coefficients at `t` (the derivative from the left when `left`: the end of a
    /// step that ends on a breakpoint of a tabulated law belongs to the segment before it).
    pub fn coefs(&self, t: f64, left: bool) -> Coefs {
        match self.p.mass {
            None => Coefs {
                mu: 1.0,
                dmu: 0.0,
                s: 1.0,
            },
            Some(m) => {
                let (mu, dmu) = m.law.eval_side(t, left && t > 0.0);
                Coefs {
                    mu,
                    dmu: if m.form == MassForm::Momentum {
                        dmu
                    } else {
                        0.0
                    },
                    s: if m.scale_stiffness { mu } else { 1.0 },
                }
            }
        }
    }

    /// `out += mu' M v + C v + s K x + Kc x + sum_j w_j(t) (K_j x + C_j v)` (the linear part
    /// of the internal force).
    pub fn linear_force(&self, x: &[f64], v: &[f64], t: f64, k: Coefs, out: &mut [f64]) {
        let p = self.p;
        p.m.mul_add(k.dmu, v, out);
        if let Some(c) = p.c {
            c.mul_add(1.0, v, out);
        }
        p.k.mul_add(k.s, x, out);
        if let Some(kc) = p.k_fixed {
            kc.mul_add(1.0, x, out);
        }
        for s in p.scaled {
            let w = s.law.omega(t);
            if let Some(m) = s.k {
                m.mul_add(w, x, out);
            }
            if let Some(m) = s.c {
                m.mul_add(w, v, out);
            }
        }
    }

    /// `out += r(x, v, t)`; with `tangent`, leaves `dr/dx`, `dr/dx'` of each element in its
    /// slot (central differences for elements without analytic tangents).
    pub fn element_force(
        &mut self,
        x: &[f64],
        v: &[f64],
        t: f64,
        tangent: bool,
        out: &mut [f64],
    ) -> Result<(), CoreError> {
        self.gather(x, v);
        for slot in &mut self.slots {
            let dofs = slot.element.dofs();
            slot.evaluate(t, tangent)?;
            for (j, &d) in dofs.iter().enumerate() {
                out[d] += slot.r[j];
            }
        }
        Ok(())
    }

    /// Gathers each element's local state from the global `(x, v)`.
    fn gather(&mut self, x: &[f64], v: &[f64]) {
        for slot in &mut self.slots {
            for (j, &d) in slot.element.dofs().iter().enumerate() {
                slot.x[j] = x[d];
                slot.v[j] = v[d];
            }
        }
    }

    /// Sets the path-dependent elements' internal variables to their initial values at the
    /// run's initial state `(x, v)` at time `t0`.
    pub fn start(&mut self, x: &[f64], v: &[f64], t0: f64) {
        self.gather(x, v);
        for slot in &mut self.slots {
            slot.start(t0);
        }
    }

    /// Commits the path-dependent elements' internal variables at the accepted step's end
    /// state `(x, v)` and time `t` (once per step; the Newton iterations inside a step
    /// evaluate trial states from the committed ones).
    pub fn commit(&mut self, x: &[f64], v: &[f64], t: f64) -> Result<(), CoreError> {
        if self.slots.iter().any(|s| s.stateful()) {
            self.gather(x, v);
            for slot in &mut self.slots {
                slot.commit(t)?;
            }
        }
        Ok(())
    }

    /// The internal force `F = mu' M v + C v + s K x + Kc x + sum_j w_j (K_j x + C_j v)
    /// + r(x, v, t)` into `out`.
    pub fn internal(
        &mut self,
        x: &[f64],
        v: &[f64],
        t: f64,
        k: Coefs,
        tangent: bool,
        out: &mut [f64],
    ) -> Result<(), CoreError> {
        out.fill(0.0);
        self.linear_force(x, v, t, k, out);
        self.element_force(x, v, t, tangent, out)
    }

    /// The external load at each of `times` into consecutive rows of `out` (`n` each): the
    /// built-in loads' values (right-continuous) plus the Python forcing, if any.
    pub fn external(
        &self,
        times: &[f64],
        forcing: Option<&mut (dyn ModalForcing + '_)>,
        out: &mut [f64],
    ) -> Result<(), CoreError> {
        let n = self.n;
        match forcing {
            Some(f) => f.modal_loads(times, out)?,
            None => out.fill(0.0),
        }
        for (row, &t) in out.chunks_exact_mut(n).zip(times) {
            for load in self.p.loads {
                let s = load.time.eval(t);
                if s != 0.0 {
                    for (o, p) in row.iter_mut().zip(&load.pattern) {
                        *o += s * p;
                    }
                }
            }
        }
        Ok(())
    }

    /// The acceleration from the equation of motion at a state:
    /// `a = M^-1 (f - F(x, v, t)) / mu`, with `m_lu` the factorised constant `M`.
    pub fn acceleration(
        &mut self,
        m_lu: &super::assembly::Factorization,
        State { x, v, t }: State,
        k: Coefs,
        f: &[f64],
        out: &mut [f64],
    ) -> Result<(), CoreError> {
        let mut scratch = std::mem::take(&mut self.scratch);
        let res = self.internal(x, v, t, k, false, &mut scratch);
        if res.is_ok() {
            for ((o, fi), s) in out.iter_mut().zip(f).zip(&scratch) {
                *o = (fi - s) / k.mu;
            }
            m_lu.solve_in_place(out);
        }
        self.scratch = scratch;
        res
    }
}
