//! The element interface: force, tangents and what the step solvers need to know.

use super::builtin::{Builtin, Dispatch};
use crate::error::CoreError;

/// Local tangent matrices, row-major `n x n` for an element with `n` dofs.
pub struct Tangent<'a> {
    /// `dr/dx`, added into.
    pub kx: &'a mut [f64],
    /// `dr/dx'`, added into.
    pub cv: &'a mut [f64],
}

/// The internal variables of a path-dependent (hysteretic) element — its plastic
/// deformation, back force, Bouc-Wen variable, the deformation they were committed at...:
/// `committed` at the start of the current step, read only; `trial` at the evaluated state,
/// written by [`Element::eval_path`]. OpenSees' vocabulary: the trial state follows the
/// Newton iterations inside a step, the integrator commits it once per accepted step (after
/// evaluating the element at the step's end state), and a retried step simply evaluates
/// from the committed variables again (nothing to revert).
pub struct PathState<'a> {
    /// The variables at the start of the step.
    pub committed: &'a [f64],
    /// The variables at the evaluated state (overwritten).
    pub trial: &'a mut [f64],
}

/// A force element acting on a few degrees of freedom.
pub trait Element: Send + Sync {
    /// The global degrees of freedom the element acts on, in its local order.
    fn dofs(&self) -> &[usize];

    /// Adds the restoring force at local displacements `x` and velocities `v` (both of length
    /// `dofs().len()`) at time `t` into `r`; with `tangent`, adds `dr/dx` and `dr/dx'`.
    fn eval(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError>;

    /// `Some(d)` when the force is a polynomial of total degree `d` in `(x, x')` with
    /// coefficients independent of `t`: such forces are integrated exactly by the `exact`
    /// quadrature (for `d <= 3` with a linear interpolant) and allow the closed-form cubic.
    fn polynomial_degree(&self) -> Option<u32>;

    /// Whether the force depends on the velocities.
    fn uses_velocity(&self) -> bool;

    /// Whether `eval` fills the tangents; when not, the integrators use finite differences.
    fn has_tangent(&self) -> bool {
        true
    }

    /// The number of internal variables: 0 for an element whose force is a function of the
    /// current state (path-independent), more for a hysteretic one.
    fn state_len(&self) -> usize {
        0
    }

    /// The internal variables before the first step (`state` has `state_len()` entries),
    /// at the initial local state `(x, v)`.
    fn initial_state(&self, _x: &[f64], _v: &[f64], _state: &mut [f64]) {}

    /// Tells the element the run's initial time `t0` after [`Element::initial_state`] (an
    /// element whose internal variables evolve in time, e.g. a damper in series with its
    /// brace, stores it to know the length of its first step). Default: nothing.
    fn initial_time(&self, _t0: f64, _state: &mut [f64]) {}

    /// A path-dependent element's force at the trial state `(x, v, t)` reached from the
    /// committed variables, as [`Element::eval`] adds it, writing the trial variables. The
    /// default (path-independent elements) is [`Element::eval`].
    fn eval_path(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        _history: PathState<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        self.eval(x, v, t, r, tangent)
    }

    /// For one mode whose shape takes the values `phi` at the element's dofs, the
    /// coefficients `a[i][j]` of the modal force `phi^T r(phi q, phi v) = sum a[i][j] q^i v^j`
    /// (`i + j <= 3`), when the force is such a polynomial. Single-mode problems use them to
    /// write the step equation as an explicit cubic (the paper's closed form).
    fn modal_cubic(&self, _phi: &[f64]) -> Option<ModalCubic> {
        None
    }

    /// The element as a built-in type, for the integrators to call it without dynamic
    /// dispatch (see [`Builtin`]); None (the default) for any other element.
    fn builtin(&self) -> Option<Builtin<'_>> {
        None
    }
}

/// Coefficients `a[i][j]` of `sum a[i][j] q^i v^j` (`i + j <= 3`).
pub type ModalCubic = [[f64; 4]; 4];

/// `value` must be finite, and `> 0` (`positive`) or `>= 0` (otherwise); the error names
/// the parameter.
pub(crate) fn check(name: &'static str, value: f64, positive: bool) -> Result<(), CoreError> {
    let ok = value.is_finite() && if positive { value > 0.0 } else { value >= 0.0 };
    if ok {
        Ok(())
    } else {
        let domain = if positive { "> 0" } else { ">= 0" };
        Err(CoreError::InvalidInput {
            name,
            problem: format!("must be finite and {domain}, got {value}"),
        })
    }
}

/// The two lateral dofs of a journal/shaft-centre element must differ (named `"dof_y"`).
pub(crate) fn distinct(dof_x: usize, dof_y: usize) -> Result<(), CoreError> {
    if dof_x == dof_y {
        return Err(CoreError::InvalidInput {
            name: "dof_y",
            problem: format!("must differ from dof_x (both are {dof_x})"),
        });
    }
    Ok(())
}

/// `phi_i - phi_j` for a two-node element (`phi_j = 0` when grounded).
pub(crate) fn relative(phi: &[f64]) -> f64 {
    phi[0] - phi.get(1).copied().unwrap_or(0.0)
}

/// An element with buffers for its local state, force and tangents, and for a hysteretic
/// element its committed and trial variables: what the integrators evaluate per element.
pub(crate) struct Evaluation<'a> {
    pub element: &'a dyn Element,
    /// How `element` is called (directly when it is a built-in one), and whether it has
    /// analytic tangents and uses the velocities (asked once: they are the element's kind).
    dispatch: Dispatch<'a>,
    has_tangent: bool,
    uses_velocity: bool,
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
}

impl<'a> Evaluation<'a> {
    pub fn new(element: &'a dyn Element) -> Self {
        let nl = element.dofs().len();
        let ns = element.state_len();
        let mut committed = vec![0.0; ns];
        element.initial_state(&vec![0.0; nl], &vec![0.0; nl], &mut committed);
        Evaluation {
            element,
            dispatch: Dispatch::of(element),
            has_tangent: element.has_tangent(),
            uses_velocity: element.uses_velocity(),
            x: vec![0.0; nl],
            v: vec![0.0; nl],
            r: vec![0.0; nl],
            kx: vec![0.0; nl * nl],
            cv: vec![0.0; nl * nl],
            trial: committed.clone(),
            committed,
            evaluations: 0,
            with_tangent: false,
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
        self.committed.copy_from_slice(state);
        self.trial.copy_from_slice(state);
    }

    /// Sets the internal variables to their initial values at the stored local state (the
    /// run's initial state) and initial time `t0`.
    pub fn start(&mut self, t0: f64) {
        if self.stateful() {
            self.element
                .initial_state(&self.x, &self.v, &mut self.committed);
            self.element.initial_time(t0, &mut self.committed);
            self.trial.copy_from_slice(&self.committed);
        }
    }

    /// Evaluates the force at the stored local state and commits the trial variables it
    /// reaches (once per accepted step, at the step's end state).
    pub fn commit(&mut self, t: f64) -> Result<(), CoreError> {
        if self.stateful() {
            self.evaluate(t, false)?;
            self.committed.copy_from_slice(&self.trial);
        }
        Ok(())
    }

    /// The force at the stored local state (overwrites `r`) and, with `tangent`, its
    /// tangents (analytic, or central differences for an element without them).
    #[inline]
    pub fn evaluate(&mut self, t: f64, tangent: bool) -> Result<(), CoreError> {
        self.evaluations += 1;
        self.with_tangent = false;
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
        self.with_tangent = tangent;
        Ok(())
    }

    /// Whether the element's force depends on the velocities.
    pub fn uses_velocity(&self) -> bool {
        self.uses_velocity
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

/// `x.fill(0.0)`, a one-dof element's single entry written directly (a `memset` call for
/// eight bytes was 3 % of a one-dof device's step).
#[inline(always)]
fn zero(x: &mut [f64]) {
    if let [only] = x {
        *only = 0.0;
    } else {
        x.fill(0.0);
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
