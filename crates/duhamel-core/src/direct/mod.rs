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
mod energy;
mod hermite;
mod lowrank;
mod model;
mod problem;
mod stepper;

pub use crate::speed::ScaledCoupling;
pub use problem::{AlphaParams, DirectHistory, DirectProblem, Method};

use crate::driver::{Control, Pacer};
use crate::error::CoreError;
use crate::history::{reserve, size, zeroed, Failure, Stats};
use crate::loads::ModalForcing;
use crate::problem::SaveGrid;
use assembly::IterationMatrix;
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
    reserve(grid.count().saturating_mul(3 * n_out + 1)).map_err(fail)?;
    let cells = size(grid.count(), n_out, "the history").map_err(fail)?;
    let buffer = |what| zeroed(cells, what).map_err(fail);
    let mut rec = Recorder {
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
    let mut stats = Stats::default();
    let dt = problem.dt;
    let time = |n: usize| problem.t0 + n as f64 * dt;
    let mut tap: Option<DirectTap> = None;

    let outcome = (|| -> Result<(), (CoreError, usize)> {
        let at0 = |e| (e, 0);
        let t0 = time(0);
        // The mass matrix, factorised once when it is needed: the initial acceleration
        // (unless given: a singular mass with massless dofs has none from the equation of
        // motion) and the saved ones of the Hermite element.
        let factor_mass = || -> Result<_, CoreError> {
            let mut mm = IterationMatrix::new(n, 1, &[problem.m], &[])?;
            mm.add_matrix(0, (0, 0), 1.0);
            mm.factorize()
        };
        let mut m_lu = None;
        let (mut x, mut v, mut a) = (problem.x0.to_vec(), problem.v0.to_vec(), vec![0.0; n]);
        let mut f = vec![0.0; n];
        model
            .external(&[t0], forcing.as_deref_mut(), &mut f)
            .map_err(at0)?;
        let k0 = model.coefs(t0, false);
        model.start(&x, &v, t0);
        match problem.a0 {
            Some(a0) => a.copy_from_slice(a0),
            None => model
                .acceleration(
                    m_lu.insert(factor_mass().map_err(at0)?),
                    State {
                        x: &x,
                        v: &v,
                        t: t0,
                    },
                    k0,
                    &f,
                    &mut a,
                )
                .map_err(at0)?,
        }
        if !a.iter().all(|u| u.is_finite()) {
            return Err(at0(CoreError::NonFinite {
                time: t0,
                step: 0,
                last_good_time: None,
            }));
        }
        if let Some(spec) = &problem.energy {
            let mut t = DirectTap::new(spec, &model, rec.grid.count()).map_err(at0)?;
            t.start(&mut model, forcing.as_deref_mut(), (&x, &v), t0)
                .map_err(at0)?;
            tap = Some(t);
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
                        .acceleration(
                            match &mut m_lu {
                                Some(lu) => lu,
                                slot => slot.insert(factor_mass().map_err(|e| (e, step))?),
                            },
                            State { x: &x, v: &v, t },
                            k,
                            &f,
                            &mut a_out,
                        )
                        .map_err(|e| (e, step))?;
                } else {
                    a_out.copy_from_slice(&a);
                }
                if let Some(tap) = tap.as_mut() {
                    tap.save(&mut model, rec.next, (&x, &v), t)
                        .map_err(|e| (e, step))?;
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
            model
                .commit(&x, &v, time(step + 1))
                .map_err(|e| (e, step + 1))?;
            if let Some(tap) = tap.as_mut() {
                tap.step(&mut model, forcing.as_deref_mut(), (t, dt), (&x, &v))
                    .map_err(|e| (e, step + 1))?;
            }
            stats.newton_iterations += iters;
            stats.factorizations = stepper.factorizations();
            if !x.iter().chain(&v).chain(&a).all(|u| u.is_finite()) {
                let e = CoreError::NonFinite {
                    time: 0.0,
                    step: 0,
                    last_good_time: None,
                };
                return Err((e, step + 1));
            }
        }
        Ok(())
    })();
    let finish = |rec: Recorder| {
        let mut h = rec.finish();
        h.energy = tap.map(|tap| tap.into_rows(h.t.len()));
        h
    };
    match outcome {
        Ok(()) => Ok((finish(rec), stats)),
        Err((error, step)) => Err(Box::new(Failure {
            // Failures of the initial state (step 0) keep their own times.
            error: if step > 0 {
                error.located(step, time)
            } else {
                error
            },
            partial: finish(rec),
            stats,
        })),
    }
}
