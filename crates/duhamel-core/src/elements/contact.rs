//! Radial rub/impact contact of a rotor inside a stator ring, with Coulomb friction.
//!
//! The shaft centre `p = (x, y)` moves inside a ring of radial clearance `g`. With
//! `rho = |p|`, the outward normal `n = p / rho`, the tangent `t = (-y, x) / rho` and the
//! penetration `delta = rho - g`, the restoring force (left-hand side) is
//!
//! ```text
//! r = F_n n + F_t t,   F_n = k softplus_eps(delta),   F_t = mu F_n tanh(v_t / v_eps),
//! softplus_eps(d) = eps ln(1 + exp(d / eps)),          v_t = t . v = (x v_y - y v_x) / rho,
//! ```
//!
//! so the ring pushes the shaft back in and friction opposes the whirl (tangential) velocity
//! of the contact point. The two smoothings (`eps` a length, `v_eps` a velocity) make the
//! force `C^inf` away from the centre so Newton iterations converge; as they go to zero the
//! element tends to the penalty contact `k max(delta, 0)` with sign-function friction.
//!
//! Tangents are exact. With `dn/dp = (I - n n^T) / rho`, `dt/dp = (J - t n^T) / rho`
//! (`J` the rotation by +90 degrees), `dF_n/dp = k sigmoid(delta / eps) n^T` and
//! `dv_t/dp = (v^T J - v_t n^T) / rho`:
//!
//! ```text
//! dr/dp = n dF_n/dp + F_n (I - n n^T) / rho + t dF_t/dp + F_t (J - t n^T) / rho,
//! dF_t/dp = mu tanh dF_n/dp + mu F_n sech^2 / v_eps dv_t/dp,
//! dr/dv = mu F_n sech^2(v_t / v_eps) / v_eps t t^T.
//! ```
//!
//! At the centre (`rho < 1e-300`) the direction is undefined and the smoothed radial field
//! is discontinuous; there the force is taken as zero (the symmetric limit: a centred shaft
//! stays centred) and `dr/dx = k sigmoid(-g / eps) I`, `dr/dv = 0`. For the usual
//! `g >> eps` both are zero to round-off anyway.

use super::definition::Definition;
use super::element::{check, distinct, Element, Tangent};
use crate::error::CoreError;
use serde::{Deserialize, Serialize};

/// Below this radius the shaft is taken as exactly centred.
const RHO_MIN: f64 = 1e-300;

/// `ln(1 + e^z)`, without overflow or cancellation.
fn softplus(z: f64) -> f64 {
    z.max(0.0) + (-z.abs()).exp().ln_1p()
}

/// `1 / (1 + e^-z)`, the derivative of [`softplus`].
fn sigmoid(z: f64) -> f64 {
    if z >= 0.0 {
        1.0 / (1.0 + (-z).exp())
    } else {
        let e = z.exp();
        e / (1.0 + e)
    }
}

/// Radial rub/impact element between the two lateral dofs of a shaft and a stator ring.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    dofs: [usize; 2],
    clearance: f64,
    stiffness: f64,
    friction: f64,
    smoothing: f64,
    velocity_smoothing: f64,
}

impl Contact {
    /// Contact on the dofs `(dof_x, dof_y)` with radial `clearance >= 0`, contact
    /// `stiffness > 0`, Coulomb `friction >= 0`, displacement `smoothing > 0` (a length) and
    /// `velocity_smoothing > 0` (a velocity). `dof_y == dof_x` is rejected (named `"dof_y"`).
    pub fn new(
        dof_x: usize,
        dof_y: usize,
        clearance: f64,
        stiffness: f64,
        friction: f64,
        smoothing: f64,
        velocity_smoothing: f64,
    ) -> Result<Self, CoreError> {
        distinct(dof_x, dof_y)?;
        check("clearance", clearance, false)?;
        check("stiffness", stiffness, true)?;
        check("friction", friction, false)?;
        check("smoothing", smoothing, true)?;
        check("velocity_smoothing", velocity_smoothing, true)?;
        Ok(Self {
            dofs: [dof_x, dof_y],
            clearance,
            stiffness,
            friction,
            smoothing,
            velocity_smoothing,
        })
    }

    /// Radial clearance `g`.
    pub fn clearance(&self) -> f64 {
        self.clearance
    }

    /// Contact stiffness `k`.
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// Coulomb friction coefficient `mu`.
    pub fn friction(&self) -> f64 {
        self.friction
    }

    /// Displacement smoothing `eps`.
    pub fn smoothing(&self) -> f64 {
        self.smoothing
    }

    /// Velocity smoothing `v_eps`.
    pub fn velocity_smoothing(&self) -> f64 {
        self.velocity_smoothing
    }

    /// The normal and friction force magnitudes `(F_n, F_t)` at position `p` and velocity
    /// `v` (both zero at the centre), e.g. to post-process contact forces.
    pub fn normal_and_friction(&self, p: [f64; 2], v: [f64; 2]) -> (f64, f64) {
        let rho = p[0].hypot(p[1]);
        if rho < RHO_MIN {
            return (0.0, 0.0);
        }
        let f_n =
            self.stiffness * self.smoothing * softplus((rho - self.clearance) / self.smoothing);
        let v_t = (p[0] * v[1] - p[1] * v[0]) / rho;
        let f_t = self.friction * f_n * (v_t / self.velocity_smoothing).tanh();
        (f_n, f_t)
    }
}

impl Element for Contact {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn eval(
        &self,
        x: &[f64],
        v: &[f64],
        _t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        debug_assert!(x.len() == 2 && v.len() == 2 && r.len() == 2);
        let (k, mu, eps, veps) = (
            self.stiffness,
            self.friction,
            self.smoothing,
            self.velocity_smoothing,
        );
        let rho = x[0].hypot(x[1]);
        if rho < RHO_MIN {
            if let Some(tg) = tangent {
                let s = k * sigmoid(-self.clearance / eps);
                tg.kx[0] += s;
                tg.kx[3] += s;
            }
            return Ok(());
        }
        let n = [x[0] / rho, x[1] / rho];
        let t = [-n[1], n[0]];
        let z = (rho - self.clearance) / eps;
        let f_n = k * eps * softplus(z);
        let v_t = t[0] * v[0] + t[1] * v[1];
        let (th, dth) = if mu > 0.0 {
            let th = (v_t / veps).tanh();
            (th, (1.0 - th * th) / veps)
        } else {
            (0.0, 0.0)
        };
        let f_t = mu * f_n * th;
        r[0] += f_n * n[0] + f_t * t[0];
        r[1] += f_n * n[1] + f_t * t[1];

        let Some(tg) = tangent else { return Ok(()) };
        let s = k * sigmoid(z);
        let dfn = [s * n[0], s * n[1]];
        // v^T J = (v_y, -v_x).
        let dvt = [(v[1] - v_t * n[0]) / rho, (-v[0] - v_t * n[1]) / rho];
        let g = mu * f_n * dth;
        let dft = [mu * th * dfn[0] + g * dvt[0], mu * th * dfn[1] + g * dvt[1]];
        const J: [[f64; 2]; 2] = [[0.0, -1.0], [1.0, 0.0]];
        for a in 0..2 {
            for b in 0..2 {
                let id = if a == b { 1.0 } else { 0.0 };
                tg.kx[2 * a + b] += n[a] * dfn[b]
                    + f_n * (id - n[a] * n[b]) / rho
                    + t[a] * dft[b]
                    + f_t * (J[a][b] - t[a] * n[b]) / rho;
                tg.cv[2 * a + b] += g * t[a] * t[b];
            }
        }
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        self.friction > 0.0
    }
}

/// `duhamel.elements.Contact`: the definition of a [`Contact`].
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactDef {
    pub dofs: (usize, usize),
    pub clearance: f64,
    pub stiffness: f64,
    #[serde(default)]
    pub friction: f64,
    #[serde(default)]
    pub smoothing: Option<f64>,
    #[serde(default)]
    pub velocity_smoothing: Option<f64>,
}

impl Definition for ContactDef {
    const NAME: &'static str = "Contact";
    const SIGNATURE: &'static str =
        "(dofs, *, clearance, stiffness, friction=0.0, smoothing=None, velocity_smoothing=None)";
    const DOC: &'static str = r#"Radial rub/impact of a shaft centre ``(x, y)`` in a stator of radial ``clearance``.

Normal force ``stiffness * (rho - clearance)`` beyond the clearance (``rho`` the radial
displacement), smoothed over ``smoothing`` (a length; None: ``1e-3 * clearance``) so that
Newton converges; Coulomb friction ``friction * F_n`` opposing the tangential (whirl)
velocity, smoothed with ``tanh(v_t / velocity_smoothing)`` (None: 1e-3 m/s).

Parameters
----------
dofs : pair of int or dof labels
    The shaft centre's dofs ``(x, y)``.
clearance : float
    Radial clearance, >= 0.
stiffness : float
    Contact stiffness, > 0.
friction : float, default 0.0
    Coulomb friction coefficient, >= 0.
smoothing, velocity_smoothing : float, optional
    The lengths of the smoothing of contact and friction.

Examples
--------
>>> import duhamel
>>> rub = duhamel.elements.Contact((0, 1), clearance=2e-4, stiffness=5e7, friction=0.2)
"#;
    const LEGACY: &'static [&'static str] = &[
        "dof_x",
        "dof_y",
        "clearance",
        "stiffness",
        "friction",
        "smoothing",
        "velocity_smoothing",
    ];
    type Runtime = Contact;

    fn build(&self) -> Result<Contact, CoreError> {
        let g = self.clearance;
        // at least the smallest normal number: a subnormal clearance must not give 0
        let smoothing = self.smoothing.unwrap_or(if g > 0.0 {
            (1e-3 * g).max(f64::MIN_POSITIVE)
        } else {
            1e-9
        });
        let velocity_smoothing = self.velocity_smoothing.unwrap_or(1e-3);
        let (x, y) = self.dofs;
        Contact::new(
            x,
            y,
            g,
            self.stiffness,
            self.friction,
            smoothing,
            velocity_smoothing,
        )
    }

    fn rename(old: &str) -> Option<(&'static str, Option<usize>)> {
        super::hysteretic::rename_axes(old)
    }

    fn passive(&self) -> bool {
        // friction at a spinning shaft's surface can drive whirl: passive only without it
        self.friction == 0.0
    }
}
