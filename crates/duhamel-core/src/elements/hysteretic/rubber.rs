//! Lead-rubber (elastomeric) bearing: coupled bidirectional Bouc-Wen hysteresis.
//!
//! On the horizontal deformation `u = (x, y)` (or `x` alone: uniaxial) of the bearing, with
//! initial stiffness `k`, yield force `fy` and post-yield stiffness ratio `alpha` (as
//! [`super::bilinear::Bilinear`]: characteristic strength `Qd = (1 - alpha) fy`, yield displacement
//! `uy = fy / k`), the restoring force is
//!
//! ```text
//! r = alpha k u + (1 - alpha) fy z,
//! uy dz = [I - |z|^(eta - 2) (gamma + beta sgn(z . du)) z z^T] du,
//! ```
//!
//! the biaxial Bouc-Wen law of Park, Wen and Ang (1986) as OpenSees'
//! `ElastomericBearingBoucWen` writes it (`A = 1`, no nonlinear hardening): the
//! hysteretic vector `z` stays within the unit circle (`|z| = 1` on yielding when
//! `beta + gamma = 1`) and the two directions interact. From the committed `(u_c, z_c)` the
//! increment to `u` is integrated along the straight path by the trapezoidal rule (second
//! order in the increment; OpenSees uses backward Euler, first order) in `m` equal substeps
//! (`|du| / m <= uy / 4`), each solved by Newton; the tangent `dr/du` is the exact derivative
//! of that discrete update (chained through the substeps). Internal variables:
//! `[u_c_x, u_c_y, z_x, z_y]`. Virgin (`z = 0`) at `u = 0`; an initial displacement is
//! reached along a straight line.

use super::common::{check, check_alpha, finite};
use crate::elements::definition::Definition;
use crate::elements::element::distinct;
use crate::elements::element::{Element, PathState, Tangent};
use crate::error::CoreError;
use serde::{Deserialize, Serialize};

/// Coupled Bouc-Wen bearing on `(dof_x, dof_y)` or on `dof_x` alone.
#[derive(Debug, Clone, PartialEq)]
pub struct LeadRubberBearing {
    dofs: Vec<usize>,
    k: f64,
    fy: f64,
    alpha: f64,
    eta: f64,
    beta: f64,
    gamma: f64,
}

/// Row-major 2 x 2 helpers.
fn solve2(a: [f64; 4], b: [f64; 2]) -> Option<[f64; 2]> {
    let det = a[0] * a[3] - a[1] * a[2];
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some([
        (a[3] * b[0] - a[1] * b[1]) / det,
        (a[0] * b[1] - a[2] * b[0]) / det,
    ])
}

fn mul2(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] + a[1] * b[2],
        a[0] * b[1] + a[1] * b[3],
        a[2] * b[0] + a[3] * b[2],
        a[2] * b[1] + a[3] * b[3],
    ]
}

fn inv2(a: [f64; 4]) -> Option<[f64; 4]> {
    let det = a[0] * a[3] - a[1] * a[2];
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some([a[3] / det, -a[1] / det, -a[2] / det, a[0] / det])
}

impl LeadRubberBearing {
    /// Bearing on `(dof_x, dof_y)` (`dof_y` None: uniaxial on `dof_x`) with initial
    /// stiffness `k > 0`, yield force `fy > 0`, post-yield ratio `alpha <= 1`, yield
    /// exponent `eta >= 1` and loop shape `beta > 0`, `gamma > -beta`.
    pub fn new(
        dof_x: usize,
        dof_y: Option<usize>,
        (k, fy, alpha): (f64, f64, f64),
        (eta, beta, gamma): (f64, f64, f64),
    ) -> Result<Self, CoreError> {
        if let Some(y) = dof_y {
            distinct(dof_x, y)?;
        }
        check("k", k, true)?;
        check("fy", fy, true)?;
        check_alpha(alpha)?;
        if !(eta.is_finite() && eta >= 1.0) {
            return Err(CoreError::InvalidInput {
                name: "eta",
                problem: format!("must be finite and >= 1, got {eta}"),
            });
        }
        check("beta", beta, true)?;
        if !(gamma.is_finite() && gamma > -beta) {
            return Err(CoreError::InvalidInput {
                name: "gamma",
                problem: format!("must be finite and > -beta = {}, got {gamma}", -beta),
            });
        }
        let dofs = match dof_y {
            Some(y) => vec![dof_x, y],
            None => vec![dof_x],
        };
        Ok(Self {
            dofs,
            k,
            fy,
            alpha,
            eta,
            beta,
            gamma,
        })
    }

    fn uy(&self) -> f64 {
        self.fy / self.k
    }

    /// `G(z, d) = |z|^(eta-2) (gamma + beta sgn(z.d)) (z.d)` and its gradients in `z`, `d`.
    fn g(&self, z: [f64; 2], d: [f64; 2]) -> (f64, [f64; 2], [f64; 2]) {
        let nz = z[0].hypot(z[1]);
        if nz == 0.0 {
            return (0.0, [0.0; 2], [0.0; 2]);
        }
        let s = z[0] * d[0] + z[1] * d[1];
        let c = self.gamma
            + self.beta
                * if s > 0.0 {
                    1.0
                } else if s < 0.0 {
                    -1.0
                } else {
                    0.0
                };
        let p = nz.powf(self.eta - 2.0);
        let q = (self.eta - 2.0) * nz.powf(self.eta - 4.0) * s;
        let dz = [c * (q * z[0] + p * d[0]), c * (q * z[1] + p * d[1])];
        let dd = [c * p * z[0], c * p * z[1]];
        (c * p * s, dz, dd)
    }

    /// `T(z, d) = z G(z, d)` and its Jacobians in `z` and `d` (row-major 2 x 2).
    fn t(&self, z: [f64; 2], d: [f64; 2]) -> ([f64; 2], [f64; 4], [f64; 4]) {
        let (g, gz, gd) = self.g(z, d);
        let tz = [
            g + z[0] * gz[0],
            z[0] * gz[1],
            z[1] * gz[0],
            g + z[1] * gz[1],
        ];
        let td = [z[0] * gd[0], z[0] * gd[1], z[1] * gd[0], z[1] * gd[1]];
        ([z[0] * g, z[1] * g], tz, td)
    }

    /// One trapezoidal substep `d` from `z0`, `F = z1 - z0 - (d - (T(z0) + T(z1)) / 2) / uy`:
    /// the new `z1` with `dF/dz1`, `dF/dz0` and `dF/dd`.
    #[allow(clippy::type_complexity)]
    fn substep(
        &self,
        z0: [f64; 2],
        d: [f64; 2],
    ) -> Option<([f64; 2], [f64; 4], [f64; 4], [f64; 4])> {
        let uy = self.uy();
        let (t0, t0z, t0d) = self.t(z0, d);
        let system = |z: [f64; 2]| {
            let (t1, t1z, t1d) = self.t(z, d);
            let f = [
                z[0] - z0[0] - (d[0] - 0.5 * (t0[0] + t1[0])) / uy,
                z[1] - z0[1] - (d[1] - 0.5 * (t0[1] + t1[1])) / uy,
            ];
            let j1 = [
                1.0 + 0.5 * t1z[0] / uy,
                0.5 * t1z[1] / uy,
                0.5 * t1z[2] / uy,
                1.0 + 0.5 * t1z[3] / uy,
            ];
            let jd = [
                -(1.0 - 0.5 * (t0d[0] + t1d[0])) / uy,
                0.5 * (t0d[1] + t1d[1]) / uy,
                0.5 * (t0d[2] + t1d[2]) / uy,
                -(1.0 - 0.5 * (t0d[3] + t1d[3])) / uy,
            ];
            (f, j1, jd)
        };
        let j0 = [
            -1.0 + 0.5 * t0z[0] / uy,
            0.5 * t0z[1] / uy,
            0.5 * t0z[2] / uy,
            -1.0 + 0.5 * t0z[3] / uy,
        ];
        // Newton from the explicit (Euler) predictor
        let mut z = [z0[0] + (d[0] - t0[0]) / uy, z0[1] + (d[1] - t0[1]) / uy];
        for _ in 0..60 {
            let (f, j1, _) = system(z);
            let step = solve2(j1, f)?;
            z = [z[0] - step[0], z[1] - step[1]];
            if step[0].hypot(step[1]) <= 1e-14 * (1.0 + z[0].hypot(z[1])) {
                let (_, j1, jd) = system(z);
                return Some((z, j1, j0, jd));
            }
        }
        None
    }

    /// `z` at `u` from the committed `(u_c, z_c)` and `dz/du` (row-major 2 x 2).
    pub fn evolve(
        &self,
        u_c: [f64; 2],
        z_c: [f64; 2],
        u: [f64; 2],
    ) -> Option<([f64; 2], [f64; 4])> {
        let du = [u[0] - u_c[0], u[1] - u_c[1]];
        let m = ((du[0].hypot(du[1]) / (0.25 * self.uy())).ceil() as usize).clamp(1, 100_000);
        let d = [du[0] / m as f64, du[1] / m as f64];
        let mut z = z_c;
        let mut dzdu = [0.0; 4];
        for _ in 0..m {
            let (z1, j1, j0, jd) = self.substep(z, d)?;
            // F(z1, z0, d) = 0: dz1/du = -J1^-1 (J0 dz0/du + jd / m)
            let inv = inv2(j1)?;
            let chained = mul2(j0, dzdu);
            let rhs = [
                -(chained[0] + jd[0] / m as f64),
                -(chained[1] + jd[1] / m as f64),
                -(chained[2] + jd[2] / m as f64),
                -(chained[3] + jd[3] / m as f64),
            ];
            dzdu = mul2(inv, rhs);
            z = z1;
        }
        Some((z, dzdu))
    }

    fn plane(&self, x: &[f64]) -> [f64; 2] {
        [x[0], if self.dofs.len() == 2 { x[1] } else { 0.0 }]
    }

    fn add(
        &self,
        u: [f64; 2],
        evolved: Option<([f64; 2], [f64; 4])>,
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<[f64; 2], CoreError> {
        let Some((z, dzdu)) = evolved else {
            return Err(CoreError::NonFinite {
                time: t,
                step: 0,
                last_good_time: None,
            });
        };
        let (ka, q) = (self.alpha * self.k, (1.0 - self.alpha) * self.fy);
        let force = [ka * u[0] + q * z[0], ka * u[1] + q * z[1]];
        finite(t, &force)?;
        finite(t, &dzdu)?;
        let n = self.dofs.len();
        for i in 0..n {
            r[i] += force[i];
        }
        if let Some(tg) = tangent {
            for i in 0..n {
                for j in 0..n {
                    tg.kx[i * n + j] += q * dzdu[2 * i + j];
                }
                tg.kx[i * n + i] += ka;
            }
        }
        Ok(z)
    }
}

impl Element for LeadRubberBearing {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn eval(
        &self,
        x: &[f64],
        _v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let u = self.plane(x);
        self.add(u, self.evolve([0.0; 2], [0.0; 2], u), t, r, tangent)?;
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        false
    }

    fn state_len(&self) -> usize {
        4
    }

    fn initial_state(&self, x: &[f64], _v: &[f64], state: &mut [f64]) {
        let u = self.plane(x);
        let z = self.evolve([0.0; 2], [0.0; 2], u).map_or([0.0; 2], |e| e.0);
        state.copy_from_slice(&[u[0], u[1], z[0], z[1]]);
    }

    fn eval_path(
        &self,
        x: &[f64],
        _v: &[f64],
        t: f64,
        history: PathState<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let c = history.committed;
        let u = self.plane(x);
        let z = self.add(u, self.evolve([c[0], c[1]], [c[2], c[3]], u), t, r, tangent)?;
        history.trial.copy_from_slice(&[u[0], u[1], z[0], z[1]]);
        Ok(())
    }
}

/// `duhamel.elements.LeadRubberBearing`: the definition of a [`LeadRubberBearing`].
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LeadRubberBearingDef {
    pub dofs: Vec<Option<usize>>,
    pub k: f64,
    pub fy: f64,
    pub alpha: f64,
    #[serde(default = "one")]
    pub eta: f64,
    #[serde(default = "half")]
    pub beta: f64,
    #[serde(default = "half")]
    pub gamma: f64,
}

fn one() -> f64 {
    1.0
}

fn half() -> f64 {
    0.5
}

/// The horizontal dofs of the previous release (`dof_x`, `dof_y`) as entries of `dofs`.
pub(crate) fn rename_axes(old: &str) -> Option<(&'static str, Option<usize>)> {
    match old {
        "dof_x" => Some(("dofs", Some(0))),
        "dof_y" => Some(("dofs", Some(1))),
        "dof_z" => Some(("dofs", Some(2))),
        _ => None,
    }
}

/// `dofs` as one dof (uniaxial: `(x,)` or `(x, None)`) or two (bidirectional):
/// `(dof_x, dof_y)`.
pub(crate) fn horizontal(dofs: &[Option<usize>]) -> Result<(usize, Option<usize>), CoreError> {
    match *dofs {
        [Some(x)] | [Some(x), None] => Ok((x, None)),
        [Some(x), Some(y)] => Ok((x, Some(y))),
        _ => Err(CoreError::InvalidInput {
            name: "dofs",
            problem: format!(
                "must be one dof (uniaxial: x or (x, None)) or two (x, y), got {dofs:?}"
            ),
        }),
    }
}

impl Definition for LeadRubberBearingDef {
    const NAME: &'static str = "LeadRubberBearing";
    const SIGNATURE: &'static str = "(dofs, *, k, fy, alpha, eta=1.0, beta=0.5, gamma=0.5)";
    const DOC: &'static str = r#"Lead-rubber (elastomeric) bearing with coupled bidirectional Bouc-Wen hysteresis (OpenSees
``ElastomericBearingBoucWen`` without nonlinear hardening), on two horizontal dofs
``dofs=(x, y)`` or uniaxial on one (``dofs=x``): ``r = alpha k u + (1 - alpha) fy z`` with
``(fy / k) dz = [I - |z|^(eta - 2) (gamma + beta sgn(z . du)) z z^T] du``. The parameters
are those of :class:`Bilinear`: initial stiffness `k`, yield force `fy` (characteristic
strength ``Qd = (1 - alpha) fy``), post-yield stiffness ratio `alpha`; `eta` sharpens the
yielding (1: smooth). The increment of a step is integrated by the trapezoidal rule (second
order) in substeps of at most a quarter of the yield displacement, with the exact tangent of
that update (docs/structural.md).

Parameters
----------
dofs : int, dof label or pair of them
    The horizontal dofs ``(x, y)`` of the bearing's top (to the ground), or one dof.
k : float
    Initial stiffness, > 0.
fy : float
    Yield force, > 0.
alpha : float
    Post-yield stiffness ratio, <= 1.
eta : float, default 1.0
    Yield exponent, >= 1.
beta, gamma : float, default 0.5
    Loop shape: ``beta > 0``, ``gamma > -beta``.

Examples
--------
>>> import duhamel
>>> lrb = duhamel.elements.LeadRubberBearing((0, 1), k=2e7, fy=2e5, alpha=0.1)
>>> lrb.eta, lrb.beta, lrb.gamma
(1.0, 0.5, 0.5)
"#;
    const LEGACY: &'static [&'static str] =
        &["dof_x", "dof_y", "k", "fy", "alpha", "eta", "beta", "gamma"];
    const LEGACY_DEFAULTS: &'static [(&'static str, &'static str)] =
        &[("k", "1.0"), ("fy", "1.0"), ("alpha", "0.0")];
    type Runtime = LeadRubberBearing;

    fn build(&self) -> Result<LeadRubberBearing, CoreError> {
        let (x, y) = horizontal(&self.dofs)?;
        LeadRubberBearing::new(
            x,
            y,
            (self.k, self.fy, self.alpha),
            (self.eta, self.beta, self.gamma),
        )
    }

    fn rename(old: &str) -> Option<(&'static str, Option<usize>)> {
        rename_axes(old)
    }

    fn passive(&self) -> bool {
        // the coupled Bouc-Wen loop dissipates for beta >= |gamma|, as the uniaxial one
        self.alpha >= 0.0 && self.beta >= self.gamma.abs()
    }

    fn linear_stiffness(&self) -> Option<Vec<f64>> {
        let n = self.dofs.iter().flatten().count(); // the initial stiffness, each direction
        Some(
            (0..n * n)
                .map(|k| if k % (n + 1) == 0 { self.k } else { 0.0 })
                .collect(),
        )
    }

    fn stored_energy(&self, u: &[f64], f: &[f64]) -> f64 {
        let (ak, soft) = (self.alpha * self.k, (1.0 - self.alpha) * self.k);
        let hyst: f64 = u
            .iter()
            .zip(f)
            .map(|(u, f)| (f - ak * u) * (f - ak * u))
            .sum();
        let elastic = 0.5 * ak * u.iter().map(|u| u * u).sum::<f64>();
        elastic + if soft > 0.0 { hyst / (2.0 * soft) } else { 0.0 }
    }
}

#[cfg(test)]
#[path = "rubber_tests.rs"]
mod tests;
