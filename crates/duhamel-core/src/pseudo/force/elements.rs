//! The elements' side of the pseudo-force: their internal variables (hysteresis), kept by
//! the element space, and their saved local states and forces.

use super::PseudoForce;
use crate::error::CoreError;

impl PseudoForce<'_> {
    /// Whether an element has internal variables (hysteresis) to commit after each step.
    pub fn stateful(&self) -> bool {
        self.space.stateful()
    }

    /// The hysteretic elements' variables at the modal state `(q, v)`: set to their initial
    /// values (`initial`, the run's start) or committed after evaluating there at `t` (the
    /// end of an accepted step or substep). The one commit of a run: every strategy and
    /// subdivision level evaluates the same elements.
    pub fn commit(&mut self, q: &[f64], v: &[f64], t: f64, initial: bool) -> Result<(), CoreError> {
        self.space.commit(q, v, t, initial)
    }

    /// The committed internal variables of every element, concatenated in element order.
    pub fn element_state(&self) -> Vec<f64> {
        self.space.element_state()
    }

    /// Sets them (the layout of [`PseudoForce::element_state`]), e.g. from a checkpoint.
    pub fn set_element_state(&mut self, state: &[f64]) -> Result<(), CoreError> {
        self.space.set_element_state(state)
    }

    /// The elements' numbers of local dofs (their saved rows hold the sum).
    pub fn element_widths(&self) -> Vec<usize> {
        self.space.element_widths()
    }

    /// Every element's local displacements, velocities and restoring force at the modal
    /// state `(q, v)` and `t` — a hysteretic one from its committed variables — into
    /// `x`, `v_out`, `r` (the sum of `element_widths()` each, the elements in order).
    pub fn record(
        &mut self,
        (q, v): (&[f64], &[f64]),
        t: f64,
        (x, v_out, r): (&mut [f64], &mut [f64], &mut [f64]),
    ) -> Result<(), CoreError> {
        if self
            .space
            .record_start((q, v), t, (&mut *x, &mut *v_out, &mut *r))
        {
            return Ok(());
        }
        let n = self.n;
        // the evaluations here compute no tangents: the end state's, which the stiffness
        // watch reuses, stay in the members' buffers
        let marked = self.space.end_marked();
        let (phi, members) = self.space.members_mut();
        let mut at = 0;
        for (e, dofs) in members {
            for (j, &a) in dofs.iter().enumerate() {
                let row = &phi[a * n..(a + 1) * n];
                e.x[j] = crate::dense::dot(row, q);
                e.v[j] = crate::dense::dot(row, v);
            }
            e.evaluate(t, false)?;
            let nl = e.x.len();
            x[at..at + nl].copy_from_slice(&e.x);
            v_out[at..at + nl].copy_from_slice(&e.v);
            r[at..at + nl].copy_from_slice(&e.r);
            at += nl;
        }
        self.space.keep_end_mark(marked);
        Ok(())
    }
}
