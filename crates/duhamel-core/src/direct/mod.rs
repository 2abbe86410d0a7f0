//! Direct time integration of the physical equations of motion,
//!
//! `mu(t) M x'' + [momentum] mu'(t) M x' + C x' + s(t) K x + Kc x
//! + sum_j w_j(t) (K_j x + C_j x') + r(x, x', t) = f(t)`
//!
//! (`w_j` speed laws scaling linear couplings), on the same elements, loads and mass laws as
//! the semi-analytic integrator: the reference methods users compare against. Two families
//! share the problem, the assembly (dense or sparse, [`assembly`]) and the route here, a
//! [`crate::driver::Route`] that the one driver ([`crate::driver::drive`]) runs as it runs
//! every modal route:
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
mod energy;
mod hermite;
mod lowrank;
mod model;
mod problem;
mod stepper;

pub use crate::speed::ScaledCoupling;
pub use problem::{AlphaParams, DirectHistory, DirectProblem, Method};

use crate::driver::{drive, Clock, Control, Forcing, Halt, Route, StepFailure};
use crate::error::CoreError;
use crate::history::{reserve, size, zeroed, Failure, Stats};
use crate::loads::ModalForcing;
use crate::problem::SaveGrid;
use assembly::{Factorization, IterationMatrix};
use energy::DirectTap;
use model::{Model, State};
use problem::validate;
use stepper::Stepper;

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

/// A direct integrator as the driver runs it: the model, the method's stepper, the state
/// and what is saved of it.
struct Direct<'a> {
    p: &'a DirectProblem<'a>,
    model: Model<'a>,
    stepper: Box<dyn Stepper + 'a>,
    rec: Recorder,
    tap: Option<DirectTap>,
    x: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    /// The saved acceleration (from the equation of motion where the method asks for it).
    a_out: Vec<f64>,
    f: Vec<f64>,
    /// The mass matrix, factorised once when it is needed.
    m_lu: Option<Factorization>,
    stats: Stats,
}

/// The mass matrix of `problem`, factorised.
fn factor_mass(problem: &DirectProblem, n: usize) -> Result<Factorization, CoreError> {
    let mut mm = IterationMatrix::new(n, 1, &[problem.m], &[])?;
    mm.add_matrix(0, (0, 0), 1.0);
    mm.factorize()
}

impl Direct<'_> {
    fn time(&self, n: usize) -> f64 {
        self.p.t0 + n as f64 * self.p.dt
    }

    /// Saves the state at grid point `step` (its acceleration from the equation of motion
    /// where the method's state holds only a predictor).
    fn save(&mut self, step: usize, forcing: Forcing) -> Result<(), CoreError> {
        let t = self.time(step);
        let (x, v) = (&self.x, &self.v);
        if self.stepper.equation_acceleration() && step > 0 {
            let k = self.model.coefs(t, true);
            self.model.external(&[t], forcing, &mut self.f)?;
            let lu = match &mut self.m_lu {
                Some(lu) => lu,
                slot => slot.insert(factor_mass(self.p, self.model.n)?),
            };
            let state = State { x, v, t };
            self.model
                .acceleration(lu, state, k, &self.f, &mut self.a_out)?;
        } else {
            self.a_out.copy_from_slice(&self.a);
        }
        if let Some(tap) = self.tap.as_mut() {
            tap.save(&mut self.model, self.rec.next, (x, v), t)?;
        }
        self.rec.push(self.p.out_dofs, t, x, v, &self.a_out);
        Ok(())
    }
}

impl Route for Direct<'_> {
    fn block(&mut self, n0: usize, len: usize, mut forcing: Forcing) -> Result<(), Halt> {
        for step in n0..n0 + len {
            if self.rec.wants(step) {
                self.save(step, forcing.as_deref_mut())
                    .map_err(StepFailure::at(step))?;
            }
            let t = self.time(step);
            let end = StepFailure::at(step + 1);
            let iters = self
                .stepper
                .step(
                    &mut self.model,
                    forcing.as_deref_mut(),
                    t,
                    [&mut self.x, &mut self.v, &mut self.a],
                )
                .map_err(StepFailure::at(step + 1))?;
            let t1 = self.time(step + 1);
            self.model.commit(&self.x, &self.v, t1).map_err(end)?;
            if let Some(tap) = self.tap.as_mut() {
                let span = (t, self.p.dt);
                tap.step(
                    &mut self.model,
                    forcing.as_deref_mut(),
                    span,
                    (&self.x, &self.v),
                )
                .map_err(StepFailure::at(step + 1))?;
            }
            self.stats.newton_iterations += iters;
            self.stats.factorizations = self.stepper.factorizations();
            let state = self.x.iter().chain(&self.v).chain(&self.a);
            if !state.into_iter().all(|u| u.is_finite()) {
                let e = CoreError::NonFinite {
                    time: 0.0,
                    step: 0,
                    last_good_time: None,
                };
                return Err(StepFailure::at(step + 1)(e).into());
            }
        }
        Ok(())
    }

    fn save_end(&mut self, n: usize, forcing: Forcing) -> Result<(), CoreError> {
        if self.rec.wants(n) {
            self.save(n, forcing)?;
        }
        Ok(())
    }
}

/// Integrates the problem; `forcing` adds physical loads computed outside the engine (its
/// rows have `n_dof` entries); `control` may stop or watch the run (checked about every
/// [`crate::driver::CHECK_INTERVAL`]). The steps run in the driver ([`drive`]), as every
/// modal route's do.
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
    reserve(grid.count().saturating_mul(3 * n_out + 1)).map_err(fail)?;
    let cells = size(grid.count(), n_out, "the history").map_err(fail)?;
    let buffer = |what| zeroed(cells, what).map_err(fail);
    let rec = Recorder {
        h: DirectHistory {
            n_out,
            t: Vec::new(),
            x: buffer("the displacement history")?,
            v: buffer("the velocity history")?,
            a: buffer("the acceleration history")?,
            energy: None,
        },
        grid,
        next: 0,
    };
    let mut model = Model::new(problem);
    let t0 = problem.t0;
    // The initial state: its load, the elements started there, the initial acceleration
    // (unless given: a singular mass with massless dofs has none from the equation of
    // motion), the energy integrals' start and the method's stepper. Failures here keep
    // their own times (step 0).
    let start = (|| -> Result<_, CoreError> {
        let (x, v) = (problem.x0.to_vec(), problem.v0.to_vec());
        let mut a = vec![0.0; n];
        let mut f = vec![0.0; n];
        model.external(&[t0], forcing.as_deref_mut(), &mut f)?;
        let k0 = model.coefs(t0, false);
        model.start(&x, &v, t0);
        let mut m_lu = None;
        match problem.a0 {
            Some(a0) => a.copy_from_slice(a0),
            None => {
                let lu = m_lu.insert(factor_mass(problem, n)?);
                let state = State {
                    x: &x,
                    v: &v,
                    t: t0,
                };
                model.acceleration(lu, state, k0, &f, &mut a)?;
            }
        }
        if !a.iter().all(|u| u.is_finite()) {
            return Err(CoreError::NonFinite {
                time: t0,
                step: 0,
                last_good_time: None,
            });
        }
        let tap = match &problem.energy {
            Some(spec) => {
                let mut t = DirectTap::new(spec, &model, rec.grid.count())?;
                t.start(&mut model, forcing.as_deref_mut(), (&x, &v), t0)?;
                Some(t)
            }
            None => None,
        };
        let stepper: Box<dyn Stepper> = match problem.method {
            Method::Alpha(par) => Box::new(alpha::Alpha::new(&mut model, par, [&x, &v, &a], &f)?),
            Method::CubicHermite { points } => Box::new(hermite::Hermite::new(&model, points)?),
        };
        Ok((x, v, a, f, m_lu, tap, stepper))
    })();
    let (x, v, a, f, m_lu, tap, stepper) = match start {
        Ok(s) => s,
        Err(error) => {
            return Err(Box::new(Failure {
                error,
                partial: rec.finish(),
                stats: Stats::default(),
            }))
        }
    };
    let mut route = Direct {
        p: problem,
        model,
        stepper,
        rec,
        tap,
        a_out: a.clone(),
        x,
        v,
        a,
        f,
        m_lu,
        stats: Stats::default(),
    };
    let clock = Clock {
        t0,
        step0: 0,
        dt: problem.dt,
        n_steps: problem.n_steps,
        save_every: problem.save_every,
    };
    let ending = drive(&clock, &mut route, forcing, control);
    let Direct {
        rec, tap, stats, ..
    } = route;
    let mut h = rec.finish();
    h.energy = tap.map(|tap| tap.into_rows(h.t.len()));
    match ending {
        None => Ok((h, stats)),
        Some((error, _)) => Err(Box::new(Failure {
            error,
            partial: h,
            stats,
        })),
    }
}
