//! Direct time integration of the physical equations of motion,
//!
//! `mu(t) M x'' + [momentum] mu'(t) M x' + C x' + s(t) K x + Kc x
//! + sum_j w_j(t) (K_j x + C_j x') + r(x, x', t) = f(t)`
//!
//! (`w_j` speed laws scaling linear couplings), on the same elements, loads and mass laws as the semi-analytic integrator: the reference
//! methods users compare against. Two families share the problem, the assembly (dense or
//! sparse, [`assembly`]) and the driver here:
//!
//! * the generalized-alpha family ([`Method::Alpha`]: Newmark, HHT, Chung-Hulbert, central
//!   difference), one step equation for the end acceleration;
//! * the cubic Hermite time element ([`Method::CubicHermite`]), one step equation for the end
//!   displacement and velocity.
//!
//! Implicit steps use Newton with the elements' tangents, the iteration matrix factorised once
//! per step (modified Newton, refreshed only when it contracts too slowly) or once per run when
//! it cannot change (no elements, constant mass).

pub mod assembly;

mod alpha;
mod hermite;
mod model;

use crate::driver::{Control, Pacer};
use crate::elements::Element;
use crate::error::CoreError;
use crate::history::{size, zeroed, Failure};
use crate::loads::ModalForcing;
use crate::loads::ModalLoad;
use crate::mass::TimeVaryingMass;
use crate::problem::SaveGrid;
use crate::speed::SpeedLaw;
use assembly::{IterationMatrix, Matrix};
use model::Model;

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
    pub scaled: &'a [ScaledCoupling<'a>],
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
}

/// Physical coupling matrices multiplied by a speed law `s(t)`.
#[derive(Debug, Clone, Copy)]
pub struct ScaledCoupling<'a> {
    /// Stiffness part, if any.
    pub k: Option<&'a Matrix>,
    /// Damping part, if any.
    pub c: Option<&'a Matrix>,
    /// The time scale.
    pub law: SpeedLaw,
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
}

/// Run statistics.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    /// Newton corrections over the run (0 when every step equation is linear).
    pub newton_iterations: usize,
    /// Factorisations of the iteration matrix (the mass matrix factorised once for the
    /// initial acceleration is not counted).
    pub factorizations: usize,
}

/// One step of a method.
pub(crate) trait Stepper {
    /// Advances `[x, v, a]` from `t` to `t + dt`; returns the Newton corrections taken.
    fn step(
        &mut self,
        model: &mut Model,
        forcing: Option<&mut (dyn ModalForcing + '_)>,
        t: f64,
        state: [&mut [f64]; 3],
    ) -> Result<usize, CoreError>;

    /// Factorisations of the iteration matrix so far.
    fn factorizations(&self) -> usize;

    /// Whether the saved acceleration is recomputed from the equation of motion (the state's
    /// `a` is then only a predictor).
    fn equation_acceleration(&self) -> bool;
}

fn validate(p: &DirectProblem) -> Result<(), CoreError> {
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
    for load in p.loads {
        if load.pattern.len() != n {
            return Err(CoreError::LengthMismatch {
                name: "load pattern",
                got: load.pattern.len(),
                expected: n,
            });
        }
        load.time.validate()?;
    }
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
            if !(2..=hermite::MAX_POINTS).contains(&points) {
                return bad(
                    "points",
                    format!(
                        "must be between 2 and {}, got {points}",
                        hermite::MAX_POINTS
                    ),
                );
            }
        }
    }
    Ok(())
}

/// Where the saved rows go.
struct Recorder {
    grid: SaveGrid,
    next: usize,
    h: DirectHistory,
}

impl Recorder {
    fn wants(&self, step: usize) -> bool {
        self.next < self.grid.count() && self.grid.step(self.next) == step
    }

    fn push(&mut self, out: &[usize], t: f64, x: &[f64], v: &[f64], a: &[f64]) {
        let h = &mut self.h;
        h.t.push(t);
        let row = self.next * out.len();
        for (j, &d) in out.iter().enumerate() {
            h.x[row + j] = x[d];
            h.v[row + j] = v[d];
            h.a[row + j] = a[d];
        }
        self.next += 1;
    }

    fn finish(mut self) -> DirectHistory {
        let keep = self.next * self.h.n_out;
        self.h.x.truncate(keep);
        self.h.v.truncate(keep);
        self.h.a.truncate(keep);
        self.h
    }
}

/// Integrates the problem; `forcing` adds physical loads computed outside the engine (its
/// rows have `n_dof` entries); `control` may stop or watch the run (checked about every
/// [`crate::driver::CHECK_INTERVAL`]).
pub fn integrate(
    problem: &DirectProblem,
    mut forcing: Option<&mut dyn ModalForcing>,
    control: &mut dyn Control,
) -> Result<(DirectHistory, Stats), Box<Failure<DirectHistory>>> {
    let fail = |e: CoreError| Box::new(Failure::from(e));
    validate(problem).map_err(fail)?;
    let n = problem.x0.len();
    let n_out = problem.out_dofs.len();
    let grid = SaveGrid::new(problem.n_steps, problem.save_every);
    let cells = size(grid.count(), n_out, "the history").map_err(fail)?;
    let buffer = |what| zeroed(cells, what).map_err(fail);
    let mut rec = Recorder {
        h: DirectHistory {
            n_out,
            t: Vec::new(),
            x: buffer("the displacement history")?,
            v: buffer("the velocity history")?,
            a: buffer("the acceleration history")?,
        },
        grid,
        next: 0,
    };
    let mut model = Model::new(problem);
    let mut stats = Stats::default();
    let dt = problem.dt;
    let time = |n: usize| problem.t0 + n as f64 * dt;

    let outcome = (|| -> Result<(), (CoreError, usize)> {
        let at0 = |e| (e, 0);
        let t0 = time(0);
        // The mass matrix, factorised once: the initial acceleration (and the saved ones of
        // the Hermite element) from the equation of motion.
        let mut mm = IterationMatrix::new(n, 1, &[problem.m], &[]).map_err(at0)?;
        mm.add_matrix(0, (0, 0), 1.0);
        let m_lu = mm.factorize().map_err(at0)?;
        let (mut x, mut v, mut a) = (problem.x0.to_vec(), problem.v0.to_vec(), vec![0.0; n]);
        let mut f = vec![0.0; n];
        model
            .external(&[t0], forcing.as_deref_mut(), &mut f)
            .map_err(at0)?;
        let k0 = model.coefs(t0, false);
        match problem.a0 {
            Some(a0) => a.copy_from_slice(a0),
            None => model
                .acceleration(&m_lu, &x, &v, t0, k0, &f, &mut a)
                .map_err(at0)?,
        }
        if !a.iter().all(|u| u.is_finite()) {
            return Err(at0(CoreError::NonFinite {
                time: t0,
                step: 0,
                last_good_time: t0,
            }));
        }
        let mut stepper: Box<dyn Stepper> = match problem.method {
            Method::Alpha(par) => {
                Box::new(alpha::Alpha::new(&mut model, par, [&x, &v, &a], &f).map_err(at0)?)
            }
            Method::CubicHermite { points } => {
                Box::new(hermite::Hermite::new(&model, points).map_err(at0)?)
            }
        };
        let mut a_out = a.clone();
        let mut pacer = Pacer::default();
        let (mut block_end, mut block_len) = (0, 0);
        for step in 0..=problem.n_steps {
            let t = time(step);
            if rec.wants(step) {
                if stepper.equation_acceleration() && step > 0 {
                    let k = model.coefs(t, true);
                    model
                        .external(&[t], forcing.as_deref_mut(), &mut f)
                        .map_err(|e| (e, step))?;
                    model
                        .acceleration(&m_lu, &x, &v, t, k, &f, &mut a_out)
                        .map_err(|e| (e, step))?;
                } else {
                    a_out.copy_from_slice(&a);
                }
                rec.push(problem.out_dofs, t, &x, &v, &a_out);
            }
            if step == block_end {
                // A block boundary: watch, and stop if asked.
                control.progress(step, problem.n_steps, t);
                if step > 0 {
                    pacer.done(block_len);
                }
                if step == problem.n_steps {
                    break;
                }
                if step > 0 && control.interrupted() {
                    let e = CoreError::Interrupted { time: 0.0, step: 0 };
                    return Err((e, step + 1));
                }
                block_len = pacer.next(problem.n_steps - step);
                block_end = step + block_len;
            }
            let iters = stepper
                .step(
                    &mut model,
                    forcing.as_deref_mut(),
                    t,
                    [&mut x, &mut v, &mut a],
                )
                .map_err(|e| (e, step + 1))?;
            stats.newton_iterations += iters;
            stats.factorizations = stepper.factorizations();
            if !x.iter().chain(&v).chain(&a).all(|u| u.is_finite()) {
                let e = CoreError::NonFinite {
                    time: 0.0,
                    step: 0,
                    last_good_time: 0.0,
                };
                return Err((e, step + 1));
            }
        }
        Ok(())
    })();
    match outcome {
        Ok(()) => Ok((rec.finish(), stats)),
        Err((error, step)) => Err(Box::new(Failure {
            // Failures of the initial state (step 0) keep their own times.
            error: if step > 0 {
                error.located(step, time)
            } else {
                error
            },
            partial: rec.finish(),
        })),
    }
}
