//! The elements' side of the pseudo-force: their internal variables (hysteresis) and their
//! saved local states and forces.

use super::PseudoForce;
use crate::elements::Evaluation;
use crate::error::CoreError;

impl PseudoForce<'_> {
    /// Whether an element has internal variables (hysteresis) to commit after each step.
    pub fn stateful(&self) -> bool {
        self.slots.iter().any(|s| s.eval.stateful())
    }

    /// The hysteretic elements' variables at the modal state `(q, v)`: set to their initial
    /// values (`initial`, the run's start) or committed after evaluating there at `t` (the
    /// end of an accepted step).
    pub fn commit(&mut self, q: &[f64], v: &[f64], t: f64, initial: bool) -> Result<(), CoreError> {
        let n = self.n;
        for slot in self.slots.iter_mut().filter(|s| s.eval.stateful()) {
            let e = &mut slot.eval;
            for (j, row) in slot.phi_e.chunks_exact(n).enumerate() {
                e.x[j] = crate::dense::dot(row, q);
                e.v[j] = crate::dense::dot(row, v);
            }
            if initial {
                e.start();
            } else {
                e.commit(t)?;
            }
        }
        Ok(())
    }

    /// The committed internal variables of every element, concatenated in element order.
    pub fn element_state(&self) -> Vec<f64> {
        self.slots
            .iter()
            .flat_map(|s| s.eval.committed().iter().copied())
            .collect()
    }

    /// Sets them (the layout of [`PseudoForce::element_state`]), e.g. from a checkpoint.
    pub fn set_element_state(&mut self, state: &[f64]) -> Result<(), CoreError> {
        let mut evals: Vec<_> = self.slots.iter_mut().map(|s| &mut s.eval).collect();
        set_states(&mut evals, state)
    }

    /// The elements' numbers of local dofs (their saved rows hold the sum).
    pub fn element_widths(&self) -> Vec<usize> {
        self.slots.iter().map(|s| s.eval.x.len()).collect()
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
        let n = self.n;
        let mut at = 0;
        for slot in &mut self.slots {
            let e = &mut slot.eval;
            for (j, row) in slot.phi_e.chunks_exact(n).enumerate() {
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
        Ok(())
    }
}

/// Distributes `state` (the committed variables of the elements, concatenated) over `evals`.
pub(crate) fn set_states(evals: &mut [&mut Evaluation], state: &[f64]) -> Result<(), CoreError> {
    let expected: usize = evals.iter().map(|e| e.committed().len()).sum();
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
    let mut at = 0;
    for e in evals.iter_mut() {
        let len = e.committed().len();
        e.set_committed(&state[at..at + len]);
        at += len;
    }
    Ok(())
}
