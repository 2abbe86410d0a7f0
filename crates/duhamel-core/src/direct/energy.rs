//! The direct integrators' energy integrals ([`crate::energy`]), in physical coordinates:
//! the accumulator fed with every step's end state, and the state functions and the
//! elements' local states at the saved instants (a direct run keeps only its output dofs).

use super::model::Model;
use crate::energy::{EnergyAccumulator, EnergyRows, EnergySpec, StepEnd};
use crate::error::CoreError;
use crate::loads::ModalForcing;

/// The energy of a direct run (see the module docs).
pub(super) struct DirectTap {
    acc: EnergyAccumulator,
    n: usize,
    base_w: Vec<f64>,
    width: usize,
    /// The external load at the step's start and end.
    f: [Vec<f64>; 2],
    tmp: Vec<f64>,
    u: Vec<f64>,
    r: Vec<f64>,
    basis: Vec<[f64; 3]>,
    /// Per saved instant: kinetic energy, linear strain energy, `w_b . v` per base, the
    /// elements' local displacements, then their forces.
    states: Vec<f64>,
    n_state: usize,
}

type Forcing<'f, 'g> = Option<&'f mut (dyn ModalForcing + 'g)>;

impl DirectTap {
    /// The tap of `spec` (its damping matrix empty: the damping power comes from the
    /// problem's `C`) for `model`, saving `n_saved` rows.
    pub(super) fn new(spec: &EnergySpec, model: &Model, n_saved: usize) -> Result<Self, CoreError> {
        let n = model.n;
        let widths: Vec<usize> = model.slots.iter().map(|s| s.element.dofs().len()).collect();
        spec.check(n, model.p.loads.len(), &widths)?;
        if !spec.damping.is_empty() || !spec.linear.is_empty() {
            return Err(CoreError::InvalidInput {
                name: "energy",
                problem: "a direct run takes no modal damping matrix nor linear parts".into(),
            });
        }
        let width: usize = widths.iter().sum();
        let nb = spec.base_loads.len();
        let n_state = 2 + nb + 2 * width;
        Ok(DirectTap {
            acc: EnergyAccumulator::new(spec, n, widths, n_saved),
            n,
            base_w: spec.base_w.to_vec(),
            width,
            f: [vec![0.0; n], vec![0.0; n]],
            tmp: vec![0.0; n],
            u: vec![0.0; width],
            r: vec![0.0; width],
            basis: vec![[0.0; 3]; model.p.loads.len()],
            states: vec![0.0; n_saved * n_state],
            n_state,
        })
    }

    /// The elements' local displacements and forces at `(x, v, t)` (from their committed
    /// variables) into `u`, `r`.
    fn elements(
        &mut self,
        model: &mut Model,
        x: &[f64],
        v: &[f64],
        t: f64,
    ) -> Result<(), CoreError> {
        if self.width == 0 {
            return Ok(());
        }
        self.tmp.fill(0.0);
        model.element_force(x, v, t, false, &mut self.tmp)?;
        let mut at = 0;
        for slot in &model.slots {
            let w = slot.x.len();
            self.u[at..at + w].copy_from_slice(&slot.x);
            self.r[at..at + w].copy_from_slice(&slot.r);
            at += w;
        }
        Ok(())
    }

    /// `0.5 y^T A y` of a problem matrix.
    fn quadratic(&mut self, a: Option<&super::assembly::Matrix>, y: &[f64]) -> f64 {
        self.tmp.fill(0.0);
        if let Some(a) = a {
            a.mul_add(1.0, y, &mut self.tmp);
        }
        0.5 * crate::dense::dot(y, &self.tmp)
    }

    /// Starts the integrals at the initial state (the elements' variables initialised).
    pub(super) fn start(
        &mut self,
        model: &mut Model,
        forcing: Forcing,
        (x, v): (&[f64], &[f64]),
        t0: f64,
    ) -> Result<(), CoreError> {
        model.external(&[t0], forcing, &mut self.f[0])?;
        self.elements(model, x, v, t0)?;
        let power = 2.0 * self.quadratic(model.p.c, v);
        self.acc.start_with(v, (&self.u, &self.r), Some(power));
        Ok(())
    }

    /// Adds the step `[t, t + dt]` ending at `(x1, v1)` (the elements committed there).
    pub(super) fn step(
        &mut self,
        model: &mut Model,
        forcing: Forcing,
        (t, dt): (f64, f64),
        (x1, v1): (&[f64], &[f64]),
    ) -> Result<(), CoreError> {
        model.external(&[t + dt], forcing, &mut self.f[1])?;
        for (b, load) in self.basis.iter_mut().zip(model.p.loads) {
            *b = load.time.basis(t, dt);
        }
        self.elements(model, x1, v1, t + dt)?;
        let power = 2.0 * self.quadratic(model.p.c, v1);
        let end = StepEnd {
            v: v1,
            p: (&self.f[0], &self.f[1]),
            load_basis: &self.basis,
            elements: (&self.u, &self.r),
            damping_power: Some(power),
        };
        self.acc.step(dt, &end);
        self.f.swap(0, 1);
        Ok(())
    }

    /// Saves the integrals and the state functions at `(x, v, t)` in row `slot`.
    pub(super) fn save(
        &mut self,
        model: &mut Model,
        slot: usize,
        (x, v): (&[f64], &[f64]),
        t: f64,
    ) -> Result<(), CoreError> {
        self.acc.save(slot);
        let kinetic = self.quadratic(Some(model.p.m), v);
        let mut strain = self.quadratic(Some(model.p.k), x);
        if model.p.k_fixed.is_some() {
            strain += self.quadratic(model.p.k_fixed, x);
        }
        self.elements(model, x, v, t)?;
        let n_state = self.n_state;
        let Some(row) = self.states.get_mut(slot * n_state..(slot + 1) * n_state) else {
            return Ok(());
        };
        row[0] = kinetic;
        row[1] = strain;
        let nb = self.base_w.len() / self.n.max(1);
        for (o, w) in row[2..2 + nb]
            .iter_mut()
            .zip(self.base_w.chunks_exact(self.n.max(1)))
        {
            *o = crate::dense::dot(w, v);
        }
        let w = self.width;
        row[2 + nb..2 + nb + w].copy_from_slice(&self.u);
        row[2 + nb + w..].copy_from_slice(&self.r);
        Ok(())
    }

    /// The rows of the first `kept` saved instants: the accumulator's columns, then the
    /// state columns.
    pub(super) fn into_rows(self, kept: usize) -> EnergyRows {
        let core = self.acc.into_rows();
        let n_cols = core.n_cols + self.n_state;
        let mut values = Vec::with_capacity(kept * n_cols);
        for s in 0..kept {
            values.extend_from_slice(&core.values[s * core.n_cols..(s + 1) * core.n_cols]);
            values.extend_from_slice(&self.states[s * self.n_state..(s + 1) * self.n_state]);
        }
        EnergyRows { n_cols, values }
    }
}
