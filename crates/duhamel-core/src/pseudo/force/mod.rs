//! The modal pseudo-force: everything that is not the constant symmetric background.
//!
//! With `rho = Phi^T r(Phi q, Phi v, t) + Kc q + Cc v + sum_j s_j(t) (K_j q + C_j v)`
//! (elements, constant linear couplings and couplings scaled by a speed law `s_j`), the modal
//! equations are `q'' + c q' + k q = p + Q` with
//!
//! * constant mass: `Q = -rho`;
//! * mass `M0 mu(t)`, eliminated (divide by `mu`; NOTES.md section 3):
//!   `Q = (1/mu - 1)(p - c v - k q) - rho/mu - [momentum] (mu'/mu) v`, without the `k q` term
//!   when the stiffness scales with the mass;
//! * mass estimated: `Q = -rho - (mu - 1) a - [momentum] mu' v - [scaled] (mu - 1) k q`, with
//!   `a` an estimate of the acceleration.

use super::local::ElementSpace;
use crate::elements::Element;
use crate::error::CoreError;
use crate::mass::{MassForm, MassTreatment, TimeVaryingMass};

use crate::speed::ScaledCoupling;

pub(crate) mod elements;
mod single;

/// Modal tangents of a pseudo-force: `dQ/dq`, `dQ/dv` (row-major `n x n`) and `dQ/da`.
#[derive(Default)]
pub struct Jacobian {
    pub kq: Vec<f64>,
    pub cq: Vec<f64>,
    pub da: f64,
}

impl Jacobian {
    pub fn new(n: usize) -> Self {
        Jacobian {
            kq: vec![0.0; n * n],
            cq: vec![0.0; n * n],
            da: 0.0,
        }
    }
}

/// Evaluates the modal pseudo-force and its tangents.
pub struct PseudoForce<'a> {
    n: usize,
    /// The elements on their dofs' mode-shape rows: the one owner of their committed and
    /// trial internal variables, whichever strategy or subdivision level evaluates them.
    space: ElementSpace<'a>,
    coupling_k: Option<&'a [f64]>,
    coupling_c: Option<&'a [f64]>,
    scaled: &'a [ScaledCoupling<'a>],
    mass: Option<&'a TimeVaryingMass>,
    k: &'a [f64],
    c: &'a [f64],
    rho: Vec<f64>,
    jac_rho: Jacobian,
    /// Whether the pseudo-force depends on the velocities at all.
    pub uses_velocity: bool,
    /// Whether every force is a polynomial of degree <= 3 with analytic tangents.
    pub polynomial: bool,
    /// Whether the pseudo-force is affine in the state (linear elements and couplings, any
    /// mass law): the step equation is then linear and one Newton step solves it.
    pub linear: bool,
    /// Evaluate the mass law's derivative from the left (at the end of a step).
    left: bool,
}

/// What a modal pseudo-force is made of: the elements on the mode shapes, the linear
/// couplings, the mass law and the background they are measured against.
#[derive(Clone, Copy)]
pub struct Parts<'a> {
    /// The mode shapes, `n_dof x n_modes` (row-major).
    pub phi: &'a [f64],
    /// The number of physical degrees of freedom.
    pub n_dof: usize,
    /// The force elements.
    pub elements: &'a [&'a dyn Element],
    /// The constant modal stiffness coupling `Phi^T K_c Phi` (`n_modes x n_modes`), if any.
    pub coupling_k: Option<&'a [f64]>,
    /// The constant modal damping coupling `Phi^T C_c Phi`, if any.
    pub coupling_c: Option<&'a [f64]>,
    /// The couplings multiplied by a speed law.
    pub scaled: &'a [ScaledCoupling<'a>],
    /// The time-varying mass, if any.
    pub mass: Option<&'a TimeVaryingMass>,
    /// The background's modal stiffness per unit modal mass (one per mode).
    pub k: &'a [f64],
    /// The background's modal damping per unit modal mass.
    pub c: &'a [f64],
}

/// Where a pseudo-force is evaluated: the modal state `(q, v)` at time `t`, with the modal
/// external load `p` there and, for the estimated-mass treatment, the acceleration
/// estimate `a`.
#[derive(Clone, Copy)]
pub struct At<'s> {
    /// Modal displacements.
    pub q: &'s [f64],
    /// Modal velocities.
    pub v: &'s [f64],
    /// Time.
    pub t: f64,
    /// Modal external load.
    pub p: &'s [f64],
    /// Modal acceleration estimate (estimated mass only).
    pub a: Option<&'s [f64]>,
}

impl<'a> PseudoForce<'a> {
    /// The pseudo-force of `parts`; errors name an element dof outside the model or a
    /// coupling of the wrong size.
    pub fn new(parts: Parts<'a>) -> Result<Self, CoreError> {
        let Parts {
            phi,
            n_dof,
            elements,
            coupling_k,
            coupling_c,
            scaled,
            mass,
            k,
            c,
        } = parts;
        let n = k.len();
        for &element in elements {
            let dofs = element.dofs();
            if let Some(&d) = dofs.iter().find(|&&d| d >= n_dof) {
                return Err(CoreError::InvalidInput {
                    name: "dof",
                    problem: format!(
                        "{d} of an element is not a degree of freedom (n_dof = {n_dof})"
                    ),
                });
            }
        }
        let pairs = [("coupling K", coupling_k), ("coupling C", coupling_c)]
            .into_iter()
            .chain(
                scaled
                    .iter()
                    .flat_map(|s| [("scaled coupling K", s.k), ("scaled coupling C", s.c)]),
            );
        for (name, m) in pairs {
            if let Some(m) = m {
                if m.len() != n * n {
                    return Err(CoreError::LengthMismatch {
                        name,
                        got: m.len(),
                        expected: n * n,
                    });
                }
            }
        }
        let uses_velocity = elements.iter().any(|e| e.uses_velocity())
            || coupling_c.is_some()
            || scaled.iter().any(|s| s.c.is_some())
            || mass.is_some_and(|m| {
                m.form == MassForm::Momentum
                    || (m.treatment == MassTreatment::Eliminate && c.iter().any(|&x| x != 0.0))
            });
        let polynomial = elements
            .iter()
            .all(|e| e.has_tangent() && e.polynomial_degree().is_some_and(|d| d <= 3));
        let linear = elements
            .iter()
            .all(|e| e.has_tangent() && e.polynomial_degree().is_some_and(|d| d <= 1));
        Ok(PseudoForce {
            n,
            space: ElementSpace::new(phi, n, elements),
            coupling_k,
            coupling_c,
            scaled,
            mass,
            k,
            c,
            rho: vec![0.0; n],
            // sized on the first tangent evaluation (only the modal Newton asks for them)
            jac_rho: Jacobian::new(0),
            uses_velocity,
            polynomial,
            linear,
            left: false,
        })
    }

    /// `rho` (and its tangents when `tangent`) at the modal state `(q, v)`.
    fn rho(&mut self, q: &[f64], v: &[f64], t: f64, tangent: bool) -> Result<(), CoreError> {
        let n = self.n;
        self.rho.fill(0.0);
        if tangent {
            if self.jac_rho.kq.len() != n * n {
                self.jac_rho = Jacobian::new(n);
            }
            self.jac_rho.kq.fill(0.0);
            self.jac_rho.cq.fill(0.0);
        }
        let (phi, members) = self.space.members_mut();
        let row = |a: usize| &phi[a * n..(a + 1) * n];
        for (e, at) in members {
            for (j, &a) in at.iter().enumerate() {
                e.x[j] = row(a).iter().zip(q).map(|(p, x)| p * x).sum();
                e.v[j] = row(a).iter().zip(v).map(|(p, x)| p * x).sum();
            }
            e.evaluate(t, tangent)?;
            project(row, at, &e.r, &mut self.rho);
            if tangent {
                congruence(row, at, n, &e.kx, &mut self.jac_rho.kq);
                congruence(row, at, n, &e.cv, &mut self.jac_rho.cq);
            }
        }
        let constant = [(1.0, self.coupling_k, self.coupling_c)];
        let scaled = self.scaled.iter().map(|s| (s.law.omega(t), s.k, s.c));
        for (factor, mk, mc) in constant.into_iter().chain(scaled) {
            for (mat, state, jac) in [(mk, q, &mut self.jac_rho.kq), (mc, v, &mut self.jac_rho.cq)]
            {
                if let Some(mat) = mat {
                    for (i, ri) in self.rho.iter_mut().enumerate() {
                        *ri += factor
                            * mat[i * n..(i + 1) * n]
                                .iter()
                                .zip(state)
                                .map(|(a, b)| a * b)
                                .sum::<f64>();
                    }
                    if tangent {
                        for (j, m) in jac.iter_mut().zip(mat) {
                            *j += factor * m;
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// The element space: the elements, their dofs' mode-shape rows and their state.
    pub(in super::super) fn space(&self) -> &ElementSpace<'a> {
        &self.space
    }

    /// The background of the last [`PseudoForce::tangent_stiffness`] (0: none dominated).
    pub fn bg(&self) -> f64 {
        self.space.background()
    }

    /// The modal stiffness the elements' tangents add at `(q, v, t)`, with the element
    /// adding most ([`ElementSpace::tangent_stiffness`] against this background).
    pub fn tangent_stiffness(
        &mut self,
        q: &[f64],
        v: &[f64],
        t: f64,
    ) -> Result<(f64, usize), CoreError> {
        self.space.tangent_stiffness(self.k, q, v, t)
    }

    /// The element space, to evaluate the elements in it.
    pub(in super::super) fn space_mut(&mut self) -> &mut ElementSpace<'a> {
        &mut self.space
    }

    /// Whether a mass law is attached.
    pub fn has_mass(&self) -> bool {
        self.mass.is_some()
    }

    /// Whether the pseudo-force is the elements' (projected) force plus terms linear in the
    /// state (couplings, an eliminated mass law): its step equation can then be solved in the
    /// elements' space, the linear terms once per step.
    pub fn local(&self) -> bool {
        self.space.element_count() > 0
            && self
                .mass
                .is_none_or(|m| m.treatment == MassTreatment::Eliminate)
    }

    /// Whether linear couplings (constant or scaled by a speed law) are part of it.
    pub fn has_couplings(&self) -> bool {
        self.coupling_k.is_some() || self.coupling_c.is_some() || !self.scaled.is_empty()
    }

    /// Whether a coupling's scale varies in time.
    pub fn varying_couplings(&self) -> bool {
        self.scaled.iter().any(|s| s.law.constant_value().is_none())
    }

    /// The couplings' stiffness and damping at `t`, summed into `k` and `c` (row-major
    /// `n x n`, overwritten); whether each is present.
    pub fn couplings_at(&self, t: f64, k: &mut [f64], c: &mut [f64]) -> (bool, bool) {
        k.fill(0.0);
        c.fill(0.0);
        let mut has = (false, false);
        let constant = [(1.0, self.coupling_k, self.coupling_c)];
        let scaled = self.scaled.iter().map(|s| (s.law.omega(t), s.k, s.c));
        for (factor, mk, mc) in constant.into_iter().chain(scaled) {
            for (mat, out, flag) in [(mk, &mut *k, &mut has.0), (mc, &mut *c, &mut has.1)] {
                if let Some(mat) = mat {
                    *flag = true;
                    for (o, m) in out.iter_mut().zip(mat) {
                        *o += factor * m;
                    }
                }
            }
        }
        has
    }

    /// The background's modal stiffness and damping per unit modal mass.
    pub fn modal_kc(&self) -> (&[f64], &[f64]) {
        (self.k, self.c)
    }

    /// `[mu, g, mom, kappa]` of the eliminated mass law at `t` (see the module
    /// documentation): `Q = g (p - c v - kappa k q) - mom v - rho / mu`.
    pub fn node_mass(&self, t: f64) -> [f64; 4] {
        let Some(mass) = self.mass else {
            return [1.0, 0.0, 0.0, 1.0];
        };
        let (mu, dmu) = mass.law.eval_side(t, self.left);
        let mom = if mass.form == MassForm::Momentum {
            dmu / mu
        } else {
            0.0
        };
        let kappa = if mass.scale_stiffness { 0.0 } else { 1.0 };
        [mu, 1.0 / mu - 1.0, mom, kappa]
    }

    /// Whether the next evaluations are at the end of a step (the mass law's derivative is
    /// then taken from the left, where it jumps).
    pub fn set_left_limit(&mut self, left: bool) {
        self.left = left;
    }

    /// The pseudo-force `Q` at `at` into `out`; with `jac`, its tangents.
    pub fn eval(
        &mut self,
        at: At,
        out: &mut [f64],
        jac: Option<&mut Jacobian>,
    ) -> Result<(), CoreError> {
        let treatment = self.mass.map(|m| m.treatment);
        self.eval_as(treatment, at, out, jac)
    }

    fn eval_as(
        &mut self,
        treatment: Option<MassTreatment>,
        At { q, v, t, p, a }: At,
        out: &mut [f64],
        jac: Option<&mut Jacobian>,
    ) -> Result<(), CoreError> {
        let n = self.n;
        let want = jac.is_some();
        self.rho(q, v, t, want)?;
        let Some(mass) = self.mass else {
            for (o, r) in out.iter_mut().zip(&self.rho) {
                *o = -r;
            }
            if let Some(j) = jac {
                for (d, s) in j.kq.iter_mut().zip(&self.jac_rho.kq) {
                    *d = -s;
                }
                for (d, s) in j.cq.iter_mut().zip(&self.jac_rho.cq) {
                    *d = -s;
                }
                j.da = 0.0;
            }
            return Ok(());
        };
        let (mu, dmu) = mass.law.eval_side(t, self.left);
        let momentum = mass.form == MassForm::Momentum;
        let scaled = mass.scale_stiffness;
        match treatment.unwrap_or(MassTreatment::Eliminate) {
            MassTreatment::Eliminate => {
                let g = 1.0 / mu - 1.0;
                for i in 0..n {
                    let kq = if scaled { 0.0 } else { self.k[i] * q[i] };
                    let mom = if momentum { dmu / mu * v[i] } else { 0.0 };
                    out[i] = g * (p[i] - self.c[i] * v[i] - kq) - self.rho[i] / mu - mom;
                }
                if let Some(j) = jac {
                    scale_into(&mut j.kq, &self.jac_rho.kq, -1.0 / mu);
                    scale_into(&mut j.cq, &self.jac_rho.cq, -1.0 / mu);
                    for i in 0..n {
                        if !scaled {
                            j.kq[i * n + i] -= g * self.k[i];
                        }
                        j.cq[i * n + i] -= g * self.c[i] + if momentum { dmu / mu } else { 0.0 };
                    }
                    j.da = 0.0;
                }
            }
            MassTreatment::Estimate => {
                let a = a.ok_or(CoreError::InvalidInput {
                    name: "mass_treatment",
                    problem: "'estimate' needs an acceleration estimate".into(),
                })?;
                for i in 0..n {
                    let kq = if scaled {
                        (mu - 1.0) * self.k[i] * q[i]
                    } else {
                        0.0
                    };
                    let mom = if momentum { dmu * v[i] } else { 0.0 };
                    out[i] = -self.rho[i] - (mu - 1.0) * a[i] - mom - kq;
                }
                if let Some(j) = jac {
                    scale_into(&mut j.kq, &self.jac_rho.kq, -1.0);
                    scale_into(&mut j.cq, &self.jac_rho.cq, -1.0);
                    for i in 0..n {
                        if scaled {
                            j.kq[i * n + i] -= (mu - 1.0) * self.k[i];
                        }
                        if momentum {
                            j.cq[i * n + i] -= dmu;
                        }
                    }
                    j.da = -(mu - 1.0);
                }
            }
        }
        Ok(())
    }

    /// The pseudo-force that makes `q'' = p + Q - c v - k q` the true acceleration at a
    /// state (the eliminated form, whatever the treatment used for stepping).
    pub fn at_state(
        &mut self,
        q: &[f64],
        v: &[f64],
        t: f64,
        p: &[f64],
        out: &mut [f64],
    ) -> Result<(), CoreError> {
        self.left = false;
        let at = At {
            q,
            v,
            t,
            p,
            a: None,
        };
        self.eval_as(Some(MassTreatment::Eliminate), at, out, None)
    }
}

fn scale_into(dst: &mut [f64], src: &[f64], f: f64) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d = f * s;
    }
}

/// `out += Phi_e^T r` (modal projection of a local force), `row(at[j])` the mode-shape row
/// of the element's local dof `j`.
fn project<'p>(row: impl Fn(usize) -> &'p [f64], at: &[usize], r: &[f64], out: &mut [f64]) {
    for (j, &a) in at.iter().enumerate() {
        for (o, p) in out.iter_mut().zip(row(a)) {
            *o += p * r[j];
        }
    }
}

/// `out += Phi_e^T T Phi_e` (modal projection of a local tangent), rows as in [`project`].
fn congruence<'p>(
    row: impl Fn(usize) -> &'p [f64],
    at: &[usize],
    n: usize,
    t: &[f64],
    out: &mut [f64],
) {
    let nl = at.len();
    for a in 0..nl {
        for b in 0..nl {
            let tab = t[a * nl + b];
            if tab == 0.0 {
                continue;
            }
            let (ra, rb) = (row(at[a]), row(at[b]));
            for (i, &pa) in ra.iter().enumerate() {
                let f = pa * tab;
                for (o, &pb) in out[i * n..(i + 1) * n].iter_mut().zip(rb) {
                    *o += f * pb;
                }
            }
        }
    }
}
