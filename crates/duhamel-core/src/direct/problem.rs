//! A direct-integration problem, its history, and what a method's step is.

use super::assembly::Matrix;
use crate::elements::Element;
use crate::error::CoreError;
use crate::loads::{check_loads, ModalLoad};
use crate::mass::TimeVaryingMass;
use crate::speed::ScaledCoupling;

/// Most Gauss points per step of the cubic Hermite element.
pub const MAX_POINTS: usize = 8;

/// Parameters of the generalized-alpha family, in Chung and Hulbert's convention: the
/// equation of motion is enforced with inertia weighted `(1 - alpha_m, alpha_m)` and forces
/// weighted `(1 - alpha_f, alpha_f)` between the end and the start of the step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlphaParams {
    pub alpha_m: f64,
    pub alpha_f: f64,
    pub gamma: f64,
    pub beta: f64,
}

/// The time integration method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// The generalized-alpha family.
    Alpha(AlphaParams),
    /// The C1 cubic Hermite time element, residual weighted by `{1, t}`, integrated with
    /// `points`-point Gauss-Legendre quadrature.
    CubicHermite { points: usize },
}

/// A direct-integration problem in physical coordinates.
pub struct DirectProblem<'a> {
    /// Mass matrix (constant part `M0` of `M(t) = M0 mu(t)`).
    pub m: &'a Matrix,
    /// Stiffness that scales with the mass law when `scale_stiffness` is set.
    pub k: &'a Matrix,
    /// Viscous damping (physical, any pattern), if any.
    pub c: Option<&'a Matrix>,
    /// Stiffness that never scales (linear couplings), if any.
    pub k_fixed: Option<&'a Matrix>,
    /// Couplings multiplied by a speed law: the force `s(t) (K x + C x')` (the gyroscopic
    /// `omega(t) G x'` of a run-up). They never scale with the mass law.
    pub scaled: &'a [ScaledCoupling<'a, Matrix>],
    /// Force elements.
    pub elements: &'a [&'a dyn Element],
    /// Built-in loads with physical patterns (`n_dof` entries).
    pub loads: &'a [ModalLoad],
    /// Time-varying mass, if any (its treatment field is ignored: the mass law enters the
    /// equation as it is).
    pub mass: Option<&'a TimeVaryingMass>,
    /// Initial displacements and velocities.
    pub x0: &'a [f64],
    pub v0: &'a [f64],
    /// Initial acceleration of the generalized-alpha methods, whose steps carry it as a third
    /// state variable; `None` (the usual case) takes it from the equation of motion. Setting
    /// it lets the amplification matrix on `(x, v, a)` be found by stepping unit states.
    pub a0: Option<&'a [f64]>,
    /// Start time.
    pub t0: f64,
    /// Step length (> 0).
    pub dt: f64,
    /// Number of steps (>= 1).
    pub n_steps: usize,
    /// Keep every `save_every`-th step (and always the last).
    pub save_every: usize,
    /// Degrees of freedom whose history is kept.
    pub out_dofs: &'a [usize],
    /// Method.
    pub method: Method,
    /// Relative size of the last Newton update at convergence.
    pub tol: f64,
    /// Newton iterations per step before giving up.
    pub max_iter: usize,
    /// The energy integrals to accumulate ([`crate::energy`], the damping matrix empty: the
    /// power is `v^T C v` of `c`); None: none.
    pub energy: Option<crate::energy::EnergySpec<'a>>,
}

/// Saved history of a direct integration, time-major `(n_saved, n_out)` arrays.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DirectHistory {
    /// Number of output degrees of freedom.
    pub n_out: usize,
    /// Saved times.
    pub t: Vec<f64>,
    /// Displacements, velocities and accelerations of the output dofs.
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    /// The energy rows at the saved instants, when asked for: the accumulator's columns,
    /// then the kinetic and linear strain energies, `M r_b . v` per base, the elements'
    /// local displacements and forces.
    pub energy: Option<crate::energy::EnergyRows>,
}

pub(super) fn validate(p: &DirectProblem) -> Result<(), CoreError> {
    let n = p.x0.len();
    let bad = |name: &'static str, problem: String| Err(CoreError::InvalidInput { name, problem });
    if n == 0 {
        return bad("M", "must have at least one degree of freedom".into());
    }
    if p.v0.len() != n {
        return Err(CoreError::LengthMismatch {
            name: "v0",
            got: p.v0.len(),
            expected: n,
        });
    }
    p.m.validate("M", n)?;
    p.k.validate("K", n)?;
    if let Some(c) = p.c {
        c.validate("C", n)?;
    }
    if let Some(k) = p.k_fixed {
        k.validate("K", n)?;
    }
    for s in p.scaled {
        if let Some(k) = s.k {
            k.validate("K", n)?;
        }
        if let Some(c) = s.c {
            c.validate("C", n)?;
        }
        if s.k.is_none() && s.c.is_none() {
            return bad("scale", "belongs to a coupling without `K` or `C`".into());
        }
        s.law.validate()?;
    }
    if let Some(a0) = p.a0 {
        if a0.len() != n {
            return Err(CoreError::LengthMismatch {
                name: "a0",
                got: a0.len(),
                expected: n,
            });
        }
    }
    if p.x0
        .iter()
        .chain(p.v0)
        .chain(p.a0.unwrap_or(&[]))
        .any(|v| !v.is_finite())
    {
        return bad("x0", "(initial state) must be finite".into());
    }
    if !(p.dt.is_finite() && p.dt > 0.0) {
        return bad("dt", "must be a positive finite number".into());
    }
    if !p.t0.is_finite() {
        return bad("t0", "must be finite".into());
    }
    if p.n_steps == 0 {
        return bad("t_end", "must be at least one step `dt`".into());
    }
    if !(p.t0 + p.n_steps as f64 * p.dt).is_finite() {
        return bad("t_end", "is too large: the end time overflows".into());
    }
    if p.save_every == 0 {
        return bad("save_every", "must be a positive integer".into());
    }
    if let Some(&d) = p.out_dofs.iter().find(|&&d| d >= n) {
        return bad(
            "dofs",
            format!("{d} is not a degree of freedom (n_dof = {n})"),
        );
    }
    for e in p.elements {
        if let Some(&d) = e.dofs().iter().find(|&&d| d >= n) {
            return bad(
                "dof",
                format!("{d} of an element is not a degree of freedom (n_dof = {n})"),
            );
        }
    }
    check_loads(p.loads, n)?;
    if let Some(mass) = p.mass {
        mass.law.validate(p.t0 + p.dt * p.n_steps as f64)?;
    }
    if !(p.tol.is_finite() && p.tol > 0.0) {
        return bad("tol", format!("must be a positive number, got {}", p.tol));
    }
    if p.max_iter == 0 {
        return bad("max_iter", "must be at least 1".into());
    }
    match p.method {
        Method::Alpha(a) => {
            let all = [a.alpha_m, a.alpha_f, a.gamma, a.beta];
            if all.iter().any(|v| !v.is_finite()) || a.beta < 0.0 || a.alpha_m >= 1.0 {
                return bad(
                    "integrator",
                    format!("has invalid generalized-alpha parameters {a:?}"),
                );
            }
            if a.alpha_f >= 1.0 {
                return bad("integrator", format!("needs alpha_f < 1, got {a:?}"));
            }
        }
        Method::CubicHermite { points } => {
            if !(2..=MAX_POINTS).contains(&points) {
                return bad(
                    "points",
                    format!("must be between 2 and {}, got {points}", MAX_POINTS),
                );
            }
        }
    }
    Ok(())
}
