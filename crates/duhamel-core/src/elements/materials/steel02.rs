//! `Steel02`: the Giuffré-Menegotto-Pinto steel law with Filippou's isotropic hardening,
//! operation for operation as OpenSees' `Steel02` (itself the FEDEAS `Steel02.f` of Mohd
//! Yassin 1993, Spacone, Monti & Filippou 1994; initial stress by C.-P. Lamarche 2006).
//!
//! Between two reversals the stress follows the Menegotto-Pinto curve
//!
//! ```text
//! s* = b e* + (1 - b) e* / (1 + |e*|^R)^(1/R),   e* = (e - er)/(e0 - er),  s* = (s - sr)/(s0 - sr)
//! ```
//!
//! from the last reversal `(er, sr)` to the intersection `(e0, s0)` of the elastic line
//! through it with the hardening asymptote (slope `b E`), shifted by the isotropic hardening
//! `fy a1 ((emax - emin)/(2 a2 ey))^0.8` (compression; `a3`, `a4` in tension); the curvature
//! `R = R0 (1 - cR1 xi / (cR2 + xi))` decreases with the plastic excursion `xi` of the last
//! half cycle. The tangent is the curve's exact derivative.

use serde::{Deserialize, Serialize};

use super::uniaxial::{initial_deformation_doc, uniaxial_methods, Uniaxial, UniaxialDefinition};
use super::Material;
use crate::elements::definition::{Definition, Pair};
use crate::elements::element::check;
use crate::error::CoreError;

/// `duhamel.elements.Steel02`: the definition of a [`Steel02`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Steel02Def {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub fy: f64,
    #[serde(rename = "E")]
    pub e: f64,
    pub b: f64,
    #[serde(rename = "R0", default = "r0")]
    pub r0: f64,
    #[serde(rename = "cR1", default = "cr1")]
    pub cr1: f64,
    #[serde(rename = "cR2", default = "cr2")]
    pub cr2: f64,
    #[serde(default)]
    pub a1: f64,
    #[serde(default = "one")]
    pub a2: f64,
    #[serde(default)]
    pub a3: f64,
    #[serde(default = "one")]
    pub a4: f64,
    #[serde(default)]
    pub sig_init: f64,
    #[serde(default)]
    pub initial_deformation: f64,
}

fn r0() -> f64 {
    15.0
}
fn cr1() -> f64 {
    0.925
}
fn cr2() -> f64 {
    0.15
}
fn one() -> f64 {
    1.0
}

impl UniaxialDefinition for Steel02Def {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = Steel02;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<Steel02, CoreError> {
        let a = [self.a1, self.a2, self.a3, self.a4];
        let transition = Transition {
            r0: self.r0,
            cr1: self.cr1,
            cr2: self.cr2,
        };
        Steel02::new(self.fy, self.e, self.b, transition, a, self.sig_init)
    }
}

impl Definition for Steel02Def {
    const NAME: &'static str = "Steel02";
    const SIGNATURE: &'static str = "(i, j=None, *, fy, E, b, R0=15.0, cR1=0.925, cR2=0.15, \
        a1=0.0, a2=1.0, a3=0.0, a4=1.0, sig_init=0.0, initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"Giuffré-Menegotto-Pinto steel with Filippou's isotropic hardening on the deformation
``u = x_i - x_j`` (``j=None``: to the ground), operation for operation as OpenSees'
``uniaxialMaterial Steel02 tag fy E b R0 cR1 cR2 a1 a2 a3 a4 sigInit`` (defaults: its
3-argument form). Between reversals the force follows the Menegotto-Pinto curve from the last
reversal towards the asymptote of slope ``b E``, with the curvature ``R`` decreasing with the
plastic excursion; ``a1``, ``a2`` (compression) and ``a3``, ``a4`` (tension) shift the
asymptotes with the largest excursion. The tangent is the curve's exact derivative (never
above ``E``). Force and deformation are the element's (a strain and a stress when the
element is a unit fibre). Linear part for ``Semianalytic(linear_parts="background")``: ``E``.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
fy : float
    Yield force, > 0.
E : float
    Initial stiffness, > 0.
b : float
    Hardening ratio (post-yield stiffness ``b E``), in [0, 1).
R0, cR1, cR2 : float
    Curvature of the transition: ``R = R0 (1 - cR1 xi / (cR2 + xi))``; ``cR1`` in [0, 1).
a1, a2, a3, a4 : float
    Isotropic hardening (OpenSees' meaning; ``a1 = a3 = 0``: none); ``a2``, ``a4`` > 0.
sig_init : float
    Initial force (OpenSees' ``sigInit``).
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import numpy as np, duhamel
>>> brace = duhamel.elements.Steel02(0, fy=1.0, E=100.0, b=0.02)
>>> loop = duhamel.elements.drive(brace, 0.05 * np.sin(np.linspace(0.0, 4 * np.pi, 201)))
>>> bool(0.0 < loop.dissipated and abs(loop.force).max() < 1.0 + 0.02 * 100 * 0.05)
True
"#
    );
    type Runtime = Uniaxial<Steel02>;
    uniaxial_methods!();
}

/// OpenSees' `Steel02` (force `fy`, stiffness `E` in the units of the element's force and
/// deformation).
#[derive(Debug, Clone)]
pub struct Steel02 {
    fy: f64,
    e0: f64,
    b: f64,
    r0: f64,
    cr1: f64,
    cr2: f64,
    a: [f64; 4],
    sig_init: f64,
}

// state layout (OpenSees' committed variables)
const EPS_MIN: usize = 0;
const EPS_MAX: usize = 1;
const EPS_PL: usize = 2;
const EPS_S0: usize = 3;
const SIG_S0: usize = 4;
const EPS_R: usize = 5;
const SIG_R: usize = 6;
const KON: usize = 7;
const EPS: usize = 8;
const SIG: usize = 9;
const TANGENT: usize = 10;
const LEN: usize = 11;

/// Menegotto-Pinto's transition between the elastic and the plastic asymptote, which
/// travels as one value: `R = R0 - cR1 xi / (cR2 + xi)` (OpenSees' `R0 cR1 cR2`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transition {
    pub r0: f64,
    pub cr1: f64,
    pub cr2: f64,
}

impl Steel02 {
    /// OpenSees' `uniaxialMaterial Steel02 tag fy E b R0 cR1 cR2 a1 a2 a3 a4 sigInit`
    /// (OpenSees' defaults: `R0 = 15, cR1 = 0.925, cR2 = 0.15`, no isotropic hardening
    /// `a = [0, 1, 0, 1]`, `sig_init = 0`). Errors name the parameter.
    pub fn new(
        fy: f64,
        e: f64,
        b: f64,
        transition: Transition,
        a: [f64; 4],
        sig_init: f64,
    ) -> Result<Self, CoreError> {
        let Transition { r0, cr1, cr2 } = transition;
        check("fy", fy, true)?;
        check("E", e, true)?;
        if !(b.is_finite() && (0.0..1.0).contains(&b)) {
            return Err(invalid("b", format!("must be in [0, 1), got {b}")));
        }
        check("R0", r0, true)?;
        if !(cr1.is_finite() && (0.0..1.0).contains(&cr1)) {
            return Err(invalid(
                "cR1",
                format!("must be in [0, 1) (R stays > 0), got {cr1}"),
            ));
        }
        check("cR2", cr2, true)?;
        for (name, v, positive) in [
            ("a1", a[0], false),
            ("a2", a[1], true),
            ("a3", a[2], false),
            ("a4", a[3], true),
        ] {
            if positive {
                check(name, v, true)?;
            } else if !v.is_finite() {
                return Err(invalid(name, format!("must be finite, got {v}")));
            }
        }
        if !sig_init.is_finite() {
            return Err(invalid(
                "sig_init",
                format!("must be finite, got {sig_init}"),
            ));
        }
        Ok(Self {
            fy,
            e0: e,
            b,
            r0,
            cr1,
            cr2,
            a,
            sig_init,
        })
    }
}

fn invalid(name: &'static str, problem: String) -> CoreError {
    CoreError::InvalidInput { name, problem }
}

impl Material for Steel02 {
    /// A zero increment leaves the committed variables and force as they are (checked in
    /// `restart_tests.rs`).
    fn restarts_exactly(&self) -> bool {
        true
    }

    fn state_len(&self) -> usize {
        LEN
    }

    fn initial_state(&self, s: &mut [f64]) {
        let epsy = self.fy / self.e0;
        s[EPS_MIN] = -epsy;
        s[EPS_MAX] = epsy;
        s[EPS_PL] = 0.0;
        s[EPS_S0] = 0.0;
        s[SIG_S0] = 0.0;
        s[EPS_R] = 0.0;
        s[SIG_R] = 0.0;
        s[KON] = 0.0;
        s[EPS] = self.sig_init / self.e0;
        s[SIG] = self.sig_init;
        s[TANGENT] = self.e0;
    }

    fn response(
        &self,
        u: f64,
        _rate: f64,
        c: &[f64],
        t: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        let (fy, e0, b) = (self.fy, self.e0, self.b);
        let esh = b * e0;
        let epsy = fy / e0;
        let eps = if self.sig_init != 0.0 {
            u + self.sig_init / e0
        } else {
            u
        };
        let (eps_p, sig_p) = (c[EPS], c[SIG]);
        let deps = eps - eps_p;
        let mut epsmax = c[EPS_MAX];
        let mut epsmin = c[EPS_MIN];
        let mut epspl = c[EPS_PL];
        let mut epss0 = c[EPS_S0];
        let mut sigs0 = c[SIG_S0];
        let mut epsr = c[EPS_R];
        let mut sigr = c[SIG_R];
        let mut kon = c[KON];

        let store = |t: &mut [f64], v: [f64; 8], sig: f64, e: f64| {
            t[..8].copy_from_slice(&v);
            t[EPS] = eps;
            t[SIG] = sig;
            t[TANGENT] = e;
        };

        if kon == 0.0 || kon == 3.0 {
            if deps.abs() < 10.0 * f64::EPSILON {
                // OpenSees: no increment from the initial state keeps the initial stress
                let v = [epsmin, epsmax, epspl, epss0, sigs0, epsr, sigr, 3.0];
                store(t, v, self.sig_init, e0);
                return Ok((self.sig_init, e0));
            }
            epsmax = epsy;
            epsmin = -epsy;
            if deps < 0.0 {
                kon = 2.0;
                epss0 = epsmin;
                sigs0 = -fy;
                epspl = epsmin;
            } else {
                kon = 1.0;
                epss0 = epsmax;
                sigs0 = fy;
                epspl = epsmax;
            }
        }

        let [a1, a2, a3, a4] = self.a;
        if kon == 2.0 && deps > 0.0 {
            // reversal from compression to tension
            kon = 1.0;
            epsr = eps_p;
            sigr = sig_p;
            if eps_p < epsmin {
                epsmin = eps_p;
            }
            let d1 = (epsmax - epsmin) / (2.0 * (a4 * epsy));
            let shft = 1.0 + a3 * d1.powf(0.8);
            epss0 = (fy * shft - esh * epsy * shft - sigr + e0 * epsr) / (e0 - esh);
            sigs0 = fy * shft + esh * (epss0 - epsy * shft);
            epspl = epsmax;
        } else if kon == 1.0 && deps < 0.0 {
            // reversal from tension to compression
            kon = 2.0;
            epsr = eps_p;
            sigr = sig_p;
            if eps_p > epsmax {
                epsmax = eps_p;
            }
            let d1 = (epsmax - epsmin) / (2.0 * (a2 * epsy));
            let shft = 1.0 + a1 * d1.powf(0.8);
            epss0 = (-fy * shft + esh * epsy * shft - sigr + e0 * epsr) / (e0 - esh);
            sigs0 = -fy * shft + esh * (epss0 + epsy * shft);
            epspl = epsmin;
        }

        let xi = ((epspl - epss0) / epsy).abs();
        let r = self.r0 * (1.0 - (self.cr1 * xi) / (self.cr2 + xi));
        let epsrat = (eps - epsr) / (epss0 - epsr);
        let dum1 = 1.0 + epsrat.abs().powf(r);
        let dum2 = dum1.powf(1.0 / r);
        let sig = (b * epsrat + (1.0 - b) * epsrat / dum2) * (sigs0 - sigr) + sigr;
        let e = (b + (1.0 - b) / (dum1 * dum2)) * (sigs0 - sigr) / (epss0 - epsr);
        let v = [epsmin, epsmax, epspl, epss0, sigs0, epsr, sigr, kon];
        store(t, v, sig, e);
        Ok((sig, e))
    }

    fn initial_tangent(&self) -> f64 {
        self.e0
    }

    fn tangent_bound(&self) -> Option<f64> {
        // every branch runs from its reversal point along the elastic line's direction to
        // the asymptotes' intersection: (s0 - sr)/(e0 - er) = E, times a factor in [b, 1]
        Some(self.e0)
    }
}

#[cfg(test)]
#[path = "steel02_tests.rs"]
mod tests;
