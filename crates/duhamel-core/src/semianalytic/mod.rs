//! Nonlinear semi-analytic stepping (the paper's sections 2-4): every modal oscillator of
//! the linear background is stepped with its exact matrices, and everything else — element
//! forces, linear couplings (non-classical damping, cross-coupled and gyroscopic terms),
//! time-varying mass — enters as a modal pseudo-force approximated over the step.

pub(crate) mod pseudo;
mod scalar;
mod scheme;
mod step;

pub use scheme::{Quadrature, Scheme};
pub use step::Solver;

use crate::elements::Element;
use crate::error::CoreError;
use crate::linear::{check, LinearProblem};
use crate::mass::{MassTreatment, TimeVaryingMass};
use crate::oscillator::Transfer;
use crate::speed::SpeedLaw;
use crate::stepping::{zeroed, BlockLoads, Failure, History, ModalForcing};
use pseudo::PseudoForce;
use step::{StepInput, Stepper};

/// Integrator settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// State approximation inside the step.
    pub scheme: Scheme,
    /// Quadrature of the pseudo-force.
    pub quadrature: Quadrature,
    /// Relative tolerance of the Newton updates.
    pub tol: f64,
    /// Newton iterations before giving up.
    pub max_iter: usize,
    /// Closed form where possible, or always Newton.
    pub solver: Solver,
}

/// A nonlinear modal problem: the linear background plus the pseudo-forces.
pub struct NonlinearProblem<'a> {
    /// Background modes, loads, initial state, step and output.
    pub base: LinearProblem<'a>,
    /// Mode shapes, `n_dof x n_modes` row-major (mass-normalised).
    pub phi: &'a [f64],
    /// Number of physical degrees of freedom.
    pub n_dof: usize,
    /// Force elements.
    pub elements: &'a [&'a dyn Element],
    /// Modal stiffness coupling `Phi^T K_c Phi` (`n_modes x n_modes`), if any.
    pub coupling_k: Option<&'a [f64]>,
    /// Modal damping coupling `Phi^T C_c Phi`, if any.
    pub coupling_c: Option<&'a [f64]>,
    /// Couplings multiplied by a speed law (the gyroscopic `omega(t) G` of a run-up).
    pub scaled: &'a [ScaledCoupling<'a>],
    /// Time-varying mass, if any.
    pub mass: Option<&'a TimeVaryingMass>,
    /// Integrator settings.
    pub options: Options,
}

/// A modal coupling whose pseudo-force is `-s(t) (K q + C v)`, `s` a speed law:
/// `LinearCoupling(K, C, scale=...)`.
#[derive(Debug, Clone, Copy)]
pub struct ScaledCoupling<'a> {
    /// Modal stiffness coupling `Phi^T K Phi` (`n_modes x n_modes`, row-major), if any.
    pub k: Option<&'a [f64]>,
    /// Modal damping coupling `Phi^T C Phi`, if any.
    pub c: Option<&'a [f64]>,
    /// The time scale.
    pub law: SpeedLaw,
}

/// Run statistics of a nonlinear integration.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    /// Newton iterations over the run.
    pub newton_iterations: usize,
    /// Steps solved by the closed-form cubic.
    pub closed_form_steps: usize,
}

fn validate(problem: &NonlinearProblem) -> Result<(), CoreError> {
    check(&problem.base)?;
    let n = problem.base.k.len();
    if problem.phi.len() != problem.n_dof * n {
        return Err(CoreError::LengthMismatch {
            name: "phi",
            got: problem.phi.len(),
            expected: problem.n_dof * n,
        });
    }
    let o = &problem.options;
    if !(o.tol.is_finite() && o.tol > 0.0) {
        return Err(CoreError::InvalidInput {
            name: "tol",
            problem: format!("must be a positive number, got {}", o.tol),
        });
    }
    if o.max_iter == 0 {
        return Err(CoreError::InvalidInput {
            name: "max_iter",
            problem: "must be at least 1".into(),
        });
    }
    if let Some(mass) = problem.mass {
        mass.law
            .validate(problem.base.dt * problem.base.n_steps as f64)?;
    }
    for s in problem.scaled {
        s.law.validate()?;
    }
    Ok(())
}

/// Integrates the problem; `forcing` adds modal loads computed outside the engine.
pub fn integrate(
    problem: &NonlinearProblem,
    mut forcing: Option<&mut dyn ModalForcing>,
) -> Result<(History, Stats), Box<Failure>> {
    validate(problem).map_err(|e| Box::new(Failure::from(e)))?;
    let base = &problem.base;
    let (n, dt) = (base.k.len(), base.dt);
    let transfers: Vec<Transfer> = base
        .k
        .iter()
        .zip(base.c)
        .map(|(&k, &c)| Transfer::new(k, c, dt))
        .collect();
    let b: Vec<[[f64; 3]; 2]> = transfers.iter().map(Transfer::b).collect();
    let rule = scheme::Rule::new(
        problem.options.scheme,
        problem.options.quadrature,
        dt,
        &transfers,
    );
    let mut pf = PseudoForce::new(
        problem.phi,
        problem.n_dof,
        problem.elements,
        problem.coupling_k,
        problem.coupling_c,
        problem.scaled,
        problem.mass,
        base.k,
        base.c,
    )
    .map_err(|e| Box::new(Failure::from(e)))?;
    let estimate = problem
        .mass
        .is_some_and(|m| m.treatment == MassTreatment::Estimate);
    let o = problem.options;
    let mut stepper = Stepper::new(
        &rule, o.scheme, dt, o.tol, o.max_iter, o.solver, &pf, estimate,
    );

    let mut loads = BlockLoads::new(base);
    let n_saved = loads.n_saved();
    let mut hq = zeroed(n * n_saved)?;
    let mut hv = zeroed(n * n_saved)?;
    let mut hp = zeroed(n * n_saved)?;
    let n_loads = base.loads.len();
    let (mut q, mut v) = (base.q0.to_vec(), base.v0.to_vec());
    let (mut q1, mut v1) = (vec![0.0; n], vec![0.0; n]);
    let (mut ql, mut vl) = (vec![0.0; n], vec![0.0; n]);
    let mut pb = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let mut stats = Stats::default();
    let mut failure: Option<(CoreError, usize)> = None;

    // The modal external load basis of local step `s` (row `s = len`: the end value).
    let load_basis = |loads: &BlockLoads, s: usize, pb: &mut [Vec<f64>; 3]| {
        for (j, pj) in pb.iter_mut().enumerate() {
            for (m, p) in pj.iter_mut().enumerate() {
                *p = base
                    .loads
                    .iter()
                    .enumerate()
                    .map(|(l, load)| load.pattern[m] * loads.basis[s * n_loads + l][j])
                    .sum();
            }
        }
        if !loads.forcing.is_empty() {
            let row = |h: usize| &loads.forcing[(2 * s + h).min(2 * loads.len) * n..][..n];
            let (f0, fm, f1) = (row(0), row(1), row(2));
            for m in 0..n {
                pb[0][m] += f0[m];
                pb[1][m] += f1[m] - f0[m];
                pb[2][m] += fm[m] - 0.5 * (f0[m] + f1[m]);
            }
        }
    };

    // Saves a state and its pseudo-force (evaluated unless already known).
    let mut save = |pf: &mut PseudoForce,
                    slot: usize,
                    q: &[f64],
                    v: &[f64],
                    t: f64,
                    p: &[f64],
                    known: Option<&[f64]>| {
        let r = slot * n..(slot + 1) * n;
        hq[r.clone()].copy_from_slice(q);
        hv[r.clone()].copy_from_slice(v);
        match known {
            Some(k) => {
                hp[r].copy_from_slice(k);
                Ok(())
            }
            None => pf.at_state(q, v, t, p, &mut hp[r]),
        }
    };

    let mut n0 = 0;
    'blocks: while n0 < base.n_steps {
        if let Err(e) = loads.prepare(base, n0, forcing.as_deref_mut()) {
            failure = Some((e, n0));
            break;
        }
        for s in 0..=loads.len {
            let step = n0 + s;
            let t = step as f64 * dt;
            load_basis(&loads, s, &mut pb);
            let slot = loads.slot[s];
            if s == loads.len {
                if let Some(slot) = slot {
                    if let Err(e) = save(&mut pf, slot, &q, &v, t, &pb[0], None) {
                        failure = Some((e, step));
                    }
                }
                break;
            }
            for m in 0..n {
                let a = &transfers[m].a;
                let bm = &b[m];
                ql[m] = a[0][0] * q[m]
                    + a[0][1] * v[m]
                    + bm[0][0] * pb[0][m]
                    + bm[0][1] * pb[1][m]
                    + bm[0][2] * pb[2][m];
                vl[m] = a[1][0] * q[m]
                    + a[1][1] * v[m]
                    + bm[1][0] * pb[0][m]
                    + bm[1][1] * pb[1][m]
                    + bm[1][2] * pb[2][m];
            }
            for (_, dx, dv) in loads.jumps.iter().filter(|j| j.0 == s) {
                for m in 0..n {
                    ql[m] += dx[m];
                    vl[m] += dv[m];
                }
            }
            let input = StepInput {
                t,
                q0: &q,
                v0: &v,
                q_lin: &ql,
                v_lin: &vl,
                pb: [&pb[0], &pb[1], &pb[2]],
            };
            let solved = stepper.solve(&mut pf, &input, &mut q1, &mut v1);
            // The start state is saved after its step: the step has usually evaluated the
            // start state's pseudo-force already.
            if let Some(slot) = slot {
                let known = if estimate {
                    None
                } else {
                    stepper.start_pseudo()
                };
                if let Err(e) = save(&mut pf, slot, &q, &v, t, &pb[0], known) {
                    failure = Some((e, step));
                    break 'blocks;
                }
            }
            match solved {
                Ok(iters) => {
                    stats.newton_iterations += iters;
                    if iters == 0 && stepper.analytic() {
                        stats.closed_form_steps += 1;
                    }
                }
                Err(e) => {
                    // A step equation whose residual is no longer finite is a diverging
                    // response (an overflowing state), not a convergence problem.
                    let e = match e {
                        CoreError::NoConvergence { residual, .. } if !residual.is_finite() => {
                            CoreError::NonFinite {
                                time: t + dt,
                                step: step + 1,
                                last_good_time: t,
                            }
                        }
                        other => other,
                    };
                    failure = Some((e, step + 1));
                    break 'blocks;
                }
            }
            if !q1.iter().chain(&v1).all(|x| x.is_finite()) {
                failure = Some((
                    CoreError::NonFinite {
                        time: t + dt,
                        step: step + 1,
                        last_good_time: t,
                    },
                    step + 1,
                ));
                break 'blocks;
            }
            std::mem::swap(&mut q, &mut q1);
            std::mem::swap(&mut v, &mut v1);
        }
        n0 += loads.len;
    }
    loads.finish(n, hq, hv, hp, failure).map(|h| (h, stats))
}
