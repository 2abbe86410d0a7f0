//! An element evaluated by the integrators: its buffers, its committed and trial internal
//! variables, and the call of its force (directly for a built-in element).

use super::builtin::Dispatch;
use super::element::{Element, PathState, Tangent};
use super::hysteretic::common::{finite, relative};
use super::registry::Runtime;
use super::registry::ScalarLaw;
use super::shifted::Shifted;
use crate::error::CoreError;

/// An element with buffers for its local state, force and tangents, and for a hysteretic
/// element its committed and trial variables: what the integrators evaluate per element.
pub(crate) struct Evaluation<'a> {
    pub element: &'a dyn Element,
    /// How `element` is called (directly when it is a built-in one), and whether it has
    /// analytic tangents and uses the velocities (asked once: they are the element's kind).
    dispatch: Dispatch<'a>,
    has_tangent: bool,
    uses_velocity: bool,
    stiffness_reads_velocity: bool,
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    pub r: Vec<f64>,
    pub kx: Vec<f64>,
    pub cv: Vec<f64>,
    committed: Vec<f64>,
    trial: Vec<f64>,
    /// The number of evaluations so far, and whether the last one computed `kx`, `cv`
    /// (what lets the stiffness watch reuse an evaluation at the state it would evaluate).
    evaluations: u64,
    with_tangent: bool,
    /// For a built-in hysteretic element: what its trial variables read besides the
    /// displacements (`(velocity, time)`, see [`Element::path_reads`]), and the state of
    /// its last successful evaluation while the trial variables are still that one's
    /// (`seen`): a commit at the same state then keeps them instead of evaluating again.
    reads: Option<(bool, bool)>,
    seen: bool,
    seen_x: Vec<f64>,
    seen_v: Vec<f64>,
    seen_t: f64,
}

impl<'a> Evaluation<'a> {
    pub fn new(element: &'a dyn Element) -> Self {
        let nl = element.dofs().len();
        let ns = element.state_len();
        let mut committed = vec![0.0; ns];
        element.initial_state(&vec![0.0; nl], &vec![0.0; nl], &mut committed);
        let dispatch = Dispatch::of(element);
        Evaluation {
            element,
            dispatch,
            has_tangent: element.has_tangent(),
            uses_velocity: element.uses_velocity(),
            stiffness_reads_velocity: element.stiffness_reads_velocity(),
            x: vec![0.0; nl],
            v: vec![0.0; nl],
            r: vec![0.0; nl],
            kx: vec![0.0; nl * nl],
            cv: vec![0.0; nl * nl],
            trial: committed.clone(),
            committed,
            evaluations: 0,
            with_tangent: false,
            reads: element.path_reads().filter(|_| ns > 0),
            seen: false,
            seen_x: vec![0.0; nl],
            seen_v: vec![0.0; nl],
            seen_t: 0.0,
        }
    }

    /// Whether the element has internal variables to commit.
    pub fn stateful(&self) -> bool {
        !self.committed.is_empty()
    }

    /// The committed internal variables.
    pub fn committed(&self) -> &[f64] {
        &self.committed
    }

    /// Sets the committed (and trial) internal variables, e.g. from a checkpoint.
    pub fn set_committed(&mut self, state: &[f64]) {
        self.seen = false;
        self.committed.copy_from_slice(state);
        self.trial.copy_from_slice(state);
    }

    /// Sets the internal variables to their initial values at the stored local state (the
    /// run's initial state) and initial time `t0`.
    pub fn start(&mut self, t0: f64) {
        self.seen = false;
        if self.stateful() {
            self.element
                .initial_state(&self.x, &self.v, &mut self.committed);
            self.element.initial_time(t0, &mut self.committed);
            self.trial.copy_from_slice(&self.committed);
        }
    }

    /// Evaluates the force at the stored local state and commits the trial variables it
    /// reaches (once per accepted step, at the step's end state). A built-in element whose
    /// last evaluation was at this state (bit for bit in what its path reads) already holds
    /// those trial variables (its arithmetic is deterministic): they are committed as they
    /// are, without evaluating again (for a one-dof `Bilinear`, one of its four evaluations
    /// per step).
    pub fn commit(&mut self, t: f64) -> Result<(), CoreError> {
        if self.stateful() {
            if !self.holds(t) {
                self.evaluate(t, false)?;
            }
            copy(&mut self.committed, &self.trial);
            // the trial variables are now the committed ones, no evaluation's from them
            self.seen = false;
        }
        Ok(())
    }

    /// Whether the trial variables are those an evaluation at the stored state and `t`
    /// would reach (see [`Evaluation::commit`]).
    fn holds(&self, t: f64) -> bool {
        let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(p, q)| p.to_bits() == q.to_bits());
        match self.reads {
            Some((velocity, time)) if self.seen => {
                same(&self.x, &self.seen_x)
                    && (!velocity || same(&self.v, &self.seen_v))
                    && (!time || t.to_bits() == self.seen_t.to_bits())
            }
            _ => false,
        }
    }

    /// The force at the stored local state (overwrites `r`) and, with `tangent`, its
    /// tangents (analytic, or central differences for an element without them).
    #[inline]
    pub fn evaluate(&mut self, t: f64, tangent: bool) -> Result<(), CoreError> {
        self.evaluations += 1;
        self.with_tangent = false;
        self.seen = false;
        zero(&mut self.r);
        let analytic = tangent && self.has_tangent;
        if analytic {
            zero(&mut self.kx);
            zero(&mut self.cv);
        }
        let tan = analytic.then(|| Tangent {
            kx: &mut self.kx,
            cv: &mut self.cv,
        });
        let history = PathState {
            committed: &self.committed,
            trial: &mut self.trial,
        };
        let state = (&self.x[..], &self.v[..], t);
        self.dispatch
            .eval_path(self.element, state, history, &mut self.r, tan)?;
        if tangent && !analytic {
            let history = (&self.committed[..], &mut self.trial[..]);
            numeric_tangent(
                self.element,
                (&self.x, &self.v, t),
                history,
                &mut self.kx,
                &mut self.cv,
            )?;
        }
        self.finished(t, tangent);
        Ok(())
    }

    /// [`Evaluation::evaluate`] of a scalar two-node element (one or two local dofs) at the
    /// deformation state `x = (u, 0)`, `v = (ud, 0)` (`x = u`, `v = ud` when grounded):
    /// `(r_0, kx_00, cv_00)`, the last two as `evaluate` leaves them (the last ones computed
    /// without `tangent`). A built-in `Bilinear` with its analytic tangent is evaluated here
    /// directly, every buffer written as `evaluate` writes it (the same arithmetic: zeroed
    /// entries plus the force, signed zeros included); any other element through `evaluate`.
    #[inline]
    pub fn evaluate_deformation(
        &mut self,
        (u, ud): (f64, f64),
        t: f64,
        tangent: bool,
    ) -> Result<(f64, f64, f64), CoreError> {
        let nl = self.x.len();
        self.x[0] = u;
        self.v[0] = ud;
        if nl == 2 {
            (self.x[1], self.v[1]) = (0.0, 0.0);
        }
        let (runtime, shifted) = match self.dispatch {
            Dispatch::Direct(r) if self.has_tangent && nl <= 2 => (Some(r), None),
            Dispatch::Shifted(s, r) if self.has_tangent && nl <= 2 => (Some(r), Some(s)),
            _ => (None, None),
        };
        match runtime.and_then(Runtime::scalar_law) {
            Some(law) => self.scalar_law((law, shifted), t, tangent)?,
            None => self.evaluate(t, tangent)?,
        }
        Ok((self.r[0], self.kx[0], self.cv[0]))
    }

    /// [`Evaluation::evaluate`] of a `Bilinear` on one or two local dofs, itself or with its
    /// linear part taken out ([`Shifted`]), inlined: the same fields written with the same
    /// numbers (`r`, `kx` zeroed and the force and its tangent scattered onto them as
    /// `scatter` does, `cv` zero, then the linear part subtracted by `Shifted`'s own code;
    /// the trial variables, the counters and the state seen).
    #[inline(always)]
    fn scalar_law(
        &mut self,
        (b, shifted): (&impl ScalarLaw, Option<&Shifted>),
        t: f64,
        tangent: bool,
    ) -> Result<(), CoreError> {
        self.evaluations += 1;
        self.with_tangent = false;
        self.seen = false;
        let two = self.x.len() == 2;
        let u = relative(&self.x);
        let (f, kt) = b.path_response((self.committed[0], self.committed[1]), u);
        if !(f.is_finite() && kt.is_finite()) {
            // as `evaluate` leaves the buffers before the element's error
            zero(&mut self.r);
            if tangent {
                zero(&mut self.kx);
                zero(&mut self.cv);
            }
            return finite(t, &[f, kt]);
        }
        (self.trial[0], self.trial[1]) = (u, f);
        if two {
            (self.r[0], self.r[1]) = (0.0 + f, 0.0 - f);
        } else {
            self.r[0] = 0.0 + f;
        }
        if tangent {
            if two {
                let (p, m) = (0.0 + kt, 0.0 - kt);
                (self.kx[0], self.kx[1], self.kx[2], self.kx[3]) = (p, m, m, p);
            } else {
                self.kx[0] = 0.0 + kt;
            }
            zero(&mut self.cv);
        }
        if let Some(s) = shifted {
            let tan = tangent.then_some(Tangent {
                kx: &mut self.kx,
                cv: &mut self.cv,
            });
            s.subtract(&self.x, &self.v, &mut self.r, tan);
        }
        self.finished(t, tangent);
        Ok(())
    }

    /// What an evaluation at time `t` leaves besides its buffers: whether it holds a
    /// tangent, and the state seen (for an element that reads its path).
    #[inline(always)]
    fn finished(&mut self, t: f64, tangent: bool) {
        self.with_tangent = tangent;
        if self.reads.is_some() {
            copy(&mut self.seen_x, &self.x);
            copy(&mut self.seen_v, &self.v);
            self.seen_t = t;
            self.seen = true;
        }
    }

    /// Whether the force at the committed state is that of the evaluation committed there,
    /// whatever the time and velocities ([`Element::restarts_exactly`], velocity-free).
    pub fn restarts_exactly(&self) -> bool {
        self.element.restarts_exactly() && !self.uses_velocity
    }

    /// Whether the element's force depends on the velocities.
    pub fn uses_velocity(&self) -> bool {
        self.uses_velocity
    }

    /// Whether the element's stiffness tangent `kx` depends on the velocities
    /// ([`Element::stiffness_reads_velocity`]).
    pub fn stiffness_reads_velocity(&self) -> bool {
        self.stiffness_reads_velocity
    }

    /// The number of evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// Whether the last evaluation computed the tangents `kx`, `cv` (and succeeded).
    pub fn with_tangent(&self) -> bool {
        self.with_tangent
    }
}

/// `x.fill(0.0)`, the entries of a one- or two-dof element (and its 2 x 2 tangents) written
/// directly (a `memset` call for eight bytes was 3 % of a one-dof device's step, for 16 and
/// 32 bytes 1.7 % of a bidirectional bearing's).
#[inline(always)]
fn zero(x: &mut [f64]) {
    match x {
        [only] => *only = 0.0,
        [a, b] => (*a, *b) = (0.0, 0.0),
        [a, b, c, d] => (*a, *b, *c, *d) = (0.0, 0.0, 0.0, 0.0),
        _ => x.fill(0.0),
    }
}

/// `to.copy_from_slice(from)`, a one- or two-dof element's entries written directly (a
/// `memcpy` call for 8 or 16 bytes, as `zero`'s `memset`).
#[inline(always)]
fn copy(to: &mut [f64], from: &[f64]) {
    match (to, from) {
        ([a], [x]) => *a = *x,
        ([a, b], [x, y]) => (*a, *b) = (*x, *y),
        (to, from) => to.copy_from_slice(from),
    }
}

/// Central-difference tangents `dr/dx`, `dr/dx'` (row-major, overwritten) of an element that
/// has none (a Python callable without a Jacobian): `2 n_loc` extra evaluations per direction.
pub(crate) fn numeric_tangent(
    element: &dyn Element,
    (x, v, t): (&[f64], &[f64], f64),
    (committed, trial): (&[f64], &mut [f64]),
    kx: &mut [f64],
    cv: &mut [f64],
) -> Result<(), CoreError> {
    let nl = x.len();
    let mut rp = vec![0.0; nl];
    let mut rm = vec![0.0; nl];
    // the trial variables of the evaluated state are kept: the perturbed ones go here
    let mut scratch = trial.to_vec();
    let (mut xs, mut vs) = (x.to_vec(), v.to_vec());
    kx.fill(0.0);
    cv.fill(0.0);
    for which in 0..2 {
        for j in 0..nl {
            let base = if which == 0 { x[j] } else { v[j] };
            let h = f64::EPSILON.cbrt() * (1.0 + base.abs());
            for (value, out) in [(base + h, &mut rp), (base - h, &mut rm)] {
                if which == 0 {
                    xs[j] = value;
                } else {
                    vs[j] = value;
                }
                out.fill(0.0);
                let history = PathState {
                    committed,
                    trial: &mut scratch,
                };
                element.eval_path(&xs, &vs, t, history, out, None)?;
            }
            xs[j] = x[j];
            vs[j] = v[j];
            let dst = if which == 0 { &mut *kx } else { &mut *cv };
            for i in 0..nl {
                dst[i * nl + j] = (rp[i] - rm[i]) / (2.0 * h);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{Dispatch, Evaluation};
    use crate::elements::hysteretic::bilinear::Bilinear;
    use crate::elements::{Element, Runtime, Shifted};

    /// Every buffer, counter and flag of an evaluation, as bits.
    fn state(e: &Evaluation) -> (Vec<u64>, u64, bool, bool) {
        let bufs = [&e.x, &e.v, &e.r, &e.kx, &e.cv, &e.committed, &e.trial];
        let mut bits: Vec<u64> = bufs
            .iter()
            .flat_map(|b| b.iter().map(|x| x.to_bits()))
            .collect();
        if e.seen {
            bits.extend(e.seen_x.iter().chain(&e.seen_v).map(|x| x.to_bits()));
            bits.push(e.seen_t.to_bits());
        }
        (bits, e.evaluations, e.with_tangent, e.seen)
    }

    /// A `Bilinear` on two dofs, grounded, and with its initial stiffness taken out, along a
    /// path through yield and reversal, with and without tangents, with commits: the direct
    /// evaluation at `(u, 0)` leaves every buffer as `evaluate` does, bit for bit.
    #[test]
    fn deformation_evaluation_of_a_bilinear_is_evaluate_bit_for_bit() {
        let pair = || Runtime::Bilinear(Bilinear::new(0, Some(1), 2e3, 5.0, 0.05).unwrap());
        let grounded = Runtime::Bilinear(Bilinear::new(0, None, 2e3, 5.0, 0.05).unwrap());
        let inner: Box<dyn Element> = Box::new(pair());
        let shifted = Shifted::new(inner, vec![2e3, -2e3, -2e3, 2e3], vec![0.0; 4]).unwrap();
        let plain = pair();
        let elements: [&dyn Element; 3] = [&plain, &grounded, &shifted];
        for element in elements {
            let (mut fast, mut slow) = (Evaluation::new(element), Evaluation::new(element));
            let direct = matches!(
                fast.dispatch,
                Dispatch::Direct(Runtime::Bilinear(_)) | Dispatch::Shifted(_, Runtime::Bilinear(_))
            );
            assert!(direct);
            fast.start(0.0);
            slow.start(0.0);
            for step in 1..=300 {
                let t = step as f64 * 1e-3;
                let u = 0.01 * (t * 9.0).sin() * (1.0 + 3.0 * t);
                let tangent = step % 3 != 0;
                let (r, k, c) = fast.evaluate_deformation((u, 0.5), t, tangent).unwrap();
                slow.x[0] = u;
                slow.v[0] = 0.5;
                if slow.x.len() == 2 {
                    (slow.x[1], slow.v[1]) = (0.0, 0.0);
                }
                slow.evaluate(t, tangent).unwrap();
                let first = |e: &Evaluation| [e.r[0], e.kx[0], e.cv[0]].map(f64::to_bits);
                assert_eq!([r, k, c].map(f64::to_bits), first(&slow), "step {step}");
                assert_eq!(state(&fast), state(&slow), "step {step}");
                if step % 2 == 0 {
                    fast.commit(t).unwrap();
                    slow.commit(t).unwrap();
                    assert_eq!(state(&fast), state(&slow), "step {step}");
                }
            }
        }
    }

    /// Along a path through yield and reversal: a commit that keeps the trial variables of
    /// the evaluation at the committed state leaves the same committed variables as one
    /// that evaluates again, and the force at a committed state is the force that
    /// committed it (what `Element::restarts_exactly` says of the `Bilinear`).
    #[test]
    fn kept_commits_and_restarts_are_the_evaluated_ones_bit_for_bit() {
        let element = Bilinear::new(0, None, 2e3, 5.0, 0.05).unwrap();
        let (mut kept, mut fresh) = (Evaluation::new(&element), Evaluation::new(&element));
        kept.start(0.0);
        fresh.start(0.0);
        let mut reuse = 0;
        for step in 1..=400 {
            let t = step as f64 * 1e-3;
            let u = 0.01 * (t * 9.0).sin() * (1.0 + 3.0 * t);
            kept.x[0] = u;
            kept.evaluate(t, true).unwrap();
            let force = kept.r[0];
            reuse += usize::from(kept.holds(t));
            kept.commit(t).unwrap();
            fresh.x[0] = u;
            fresh.commit(t).unwrap();
            assert_eq!(kept.committed(), fresh.committed(), "step {step}");
            // the force at the committed state, evaluated from it again
            kept.evaluate(t, false).unwrap();
            assert_eq!(kept.r[0].to_bits(), force.to_bits(), "step {step}");
        }
        assert_eq!(reuse, 400);
        // a state other than the one evaluated is evaluated again
        kept.x[0] = 0.5;
        kept.evaluate(1.0, false).unwrap();
        kept.x[0] = 0.25;
        assert!(!kept.holds(1.0));
    }
}
