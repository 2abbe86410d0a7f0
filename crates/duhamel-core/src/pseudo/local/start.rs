//! The record of a saved state from the element-space step's own evaluation of it: the
//! step evaluates every element at its start state (the first quadrature node), and the
//! route then saves that state, evaluating every element there again for its record (a
//! pass over the modes per element dof and an evaluation per element, at every saved
//! step). The step keeps what it computed; the record takes it when it is that state's.
//! A record also keeps the stiffness watch's mark of the converged end state's tangents.

use super::ElementSpace;

/// The members' local displacements, velocities and forces (each member's in member order,
/// as [`crate::pseudo::force::PseudoForce::record`] writes them) evaluated at the modal
/// state at the addresses `key` and time `t`, when `valid`.
#[derive(Default)]
pub(super) struct Start {
    pub(super) valid: bool,
    t: f64,
    key: (usize, usize),
    x: Vec<f64>,
    v: Vec<f64>,
    r: Vec<f64>,
}

impl ElementSpace<'_> {
    /// Whether the end mark of [`ElementSpace::mark_end`] still holds (no evaluation since).
    pub fn end_marked(&self) -> bool {
        self.end_mark.is_some() && self.end_mark == Some(self.evaluations())
    }

    /// Keeps the end mark across evaluations without tangents that left the members'
    /// tangents `kx`, `cv` as they were (the record of a saved state): the watch then still
    /// reuses the converged end state's tangents, as it does on a step that saves nothing.
    pub fn keep_end_mark(&mut self, marked: bool) {
        if marked {
            self.end_mark = Some(self.evaluations());
        }
    }

    /// Forgets the kept start state ([`ElementSpace::keep_start`]).
    pub fn drop_start(&mut self) {
        self.start.valid = false;
    }

    /// Keeps the members' last evaluation as that of the modal state `(q, v)` at `t` (the
    /// key: their addresses and `t`), whose element coordinates are `(pq, pv)` = `Phi_D q`,
    /// `Phi_D v` bit for bit as [`crate::dense::dot`] forms them. The caller has just
    /// evaluated every member at `t` and at the displacements `pq`, without changing the
    /// committed variables since; at the velocities `pv` too unless `velocity_differs`,
    /// in which case nothing is kept when a member's force depends on the velocities.
    /// [`ElementSpace::record_start`] then gives that state's record without evaluating it
    /// again, until the next commit.
    pub fn keep_start(
        &mut self,
        (q, v): (&[f64], &[f64]),
        t: f64,
        (pq, pv): (&[f64], &[f64]),
        velocity_differs: bool,
    ) {
        let st = &mut self.start;
        st.valid = false;
        if velocity_differs && self.members.iter().any(|m| m.eval.uses_velocity()) {
            return;
        }
        let one = (&self.members[..], st.x.len(), st.v.len(), st.r.len());
        if let ([m], 1, 1, 1) = one {
            // one member on one dof, kept before: its entries written in place
            if let ([a], [r]) = (&m.at[..], &m.eval.r[..]) {
                (st.x[0], st.v[0], st.r[0]) = (pq[*a], pv[*a], *r);
                st.t = t;
                st.key = (q.as_ptr() as usize, v.as_ptr() as usize);
                st.valid = true;
                return;
            }
        }
        st.x.clear();
        st.v.clear();
        st.r.clear();
        for m in &self.members {
            st.x.extend(m.at.iter().map(|&a| pq[a]));
            st.v.extend(m.at.iter().map(|&a| pv[a]));
            st.r.extend_from_slice(&m.eval.r);
        }
        st.t = t;
        st.key = (q.as_ptr() as usize, v.as_ptr() as usize);
        st.valid = true;
    }

    /// The kept start state's record ([`ElementSpace::keep_start`]) into `x`, `v`, `r`
    /// (the members' widths summed), when it is that of `(q, v)` at `t`: whether it was.
    pub fn record_start(
        &self,
        (q, v): (&[f64], &[f64]),
        t: f64,
        (x, v_out, r): (&mut [f64], &mut [f64], &mut [f64]),
    ) -> bool {
        let st = &self.start;
        let key = (q.as_ptr() as usize, v.as_ptr() as usize);
        if !(st.valid && st.key == key && st.t.to_bits() == t.to_bits() && st.x.len() == x.len()) {
            return false;
        }
        x.copy_from_slice(&st.x);
        v_out.copy_from_slice(&st.v);
        r.copy_from_slice(&st.r);
        true
    }
}
