//! The element interface: force, tangents and what the step solvers need to know.

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

    /// Whether the stiffness tangent `dr/dx` depends on the velocities (default: whether the
    /// force does). An element whose velocities enter only through a constant damping
    /// matrix ([`crate::elements::Shifted`]'s linear part) has a stiffness tangent that the
    /// stiffness watch may take from any evaluation at the same displacements.
    fn stiffness_reads_velocity(&self) -> bool {
        self.uses_velocity()
    }

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

    /// For an element whose arithmetic is deterministic and known: what its trial variables
    /// depend on besides the committed ones and the displacements, `Some((velocity, time))`
    /// (a commit at the state last evaluated then keeps that evaluation's trial variables);
    /// None (the default): nothing is assumed.
    fn path_reads(&self) -> Option<(bool, bool)> {
        None
    }

    /// Whether the force at a committed state is, bit for bit, the force of the evaluation
    /// whose trial variables were committed there (for the force alone, given the same
    /// displacements). False by default.
    fn restarts_exactly(&self) -> bool {
        false
    }

    /// The local displacement below which the element's force is not resolved: the
    /// round-off of its deformation when that is measured from a loaded start (a material's
    /// `initial_deformation` `d0` added to `x`: a few ulps of `d0`). Newton's iterations
    /// accept corrections below it (they cannot contract further). 0 by default.
    fn resolution(&self) -> f64 {
        0.0
    }

    /// The element as `Any`, for a built-in element: the integrators then resolve its type
    /// once and call it without dynamic dispatch (`elements/builtin.rs`). None (the
    /// default) for any other element.
    fn as_any(&self) -> Option<&dyn std::any::Any> {
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
