//! Uniaxial friction pendulum with its vertical dof: the normal force from the model
//! (OpenSees `singleFPBearing` in 2-D, `SingleFPSimple2d`, as the reference).
//!
//! On the horizontal displacement `u` and the vertical displacement `w` of the slider
//! relative to the ground (`w > 0` up), the bearing carries the compressive axial force
//! `P = -k_v w` (`w < 0`; `k_v` the axial stiffness) and nothing in tension (uplift: zero
//! shear and zero axial force, the slider's plastic displacement follows `u`). Compressed,
//! the normal force on the concave surface is `N = P + V u / R` (the shear's component
//! along the normal, as OpenSees writes it), the shear
//!
//! ```text
//! V = (N / R) u + f,    f = (k_i - N / R) (u - u_p),  |f| <= mu N,
//! ```
//!
//! with `k_i = mu W / Y` the initial stiffness (`W` the nominal weight, `Y` the yield
//! displacement) and the plastic displacement `u_p` from the return mapping. `N` is solved
//! in closed form: sticking (`u_p` the committed one),
//! `N = (P + k_i (u - u_p) u / R) / (1 - u u_p / R^2)`, `V = k_i (u - u_p) + N u_p / R`;
//! sliding (`s` the sign of `u - u_p`), `N = P / (1 - (u / R)(u / R + mu s))`,
//! `V = N (u / R + mu s)`, `u_p = u - mu N s / (k_i - N / R)`. Consistent tangents in `u`
//! and `w`; the vertical force on the dof is `-P`. Constant friction coefficient. Internal
//! variable: `[u_p]`.

use super::common::{check, finite};
use crate::elements::element::{distinct, Element, PathState, Tangent};
use crate::error::CoreError;

/// Uniaxial friction pendulum on `(dof_x, dof_z)` to the ground, its normal force from
/// the vertical dof.
#[derive(Debug, Clone, PartialEq)]
pub struct AxialFrictionPendulum {
    dofs: Vec<usize>,
    radius: f64,
    mu: f64,
    k_init: f64,
    kv: f64,
}

/// The shear `V`, axial force `P`, trial plastic displacement and the tangents
/// `(dV/du, dV/dw, dP/dw)`.
struct Response {
    shear: f64,
    axial: f64,
    plastic: f64,
    dv: [f64; 2],
    dp: f64,
}

impl AxialFrictionPendulum {
    /// Bearing on the horizontal `dof_x` and vertical `dof_z` (distinct) with radius
    /// `radius > 0`, friction coefficient `mu >= 0`, nominal weight `weight > 0` and yield
    /// displacement `yield_displacement > 0` (initial stiffness `mu W / Y`), axial
    /// stiffness `vertical_stiffness > 0`.
    pub fn new(
        (dof_x, dof_z): (usize, usize),
        radius: f64,
        mu: f64,
        (weight, yield_displacement): (f64, f64),
        vertical_stiffness: f64,
    ) -> Result<Self, CoreError> {
        distinct(dof_x, dof_z).map_err(|_| CoreError::InvalidInput {
            name: "dof_z",
            problem: format!("must differ from dof_x (both are {dof_x})"),
        })?;
        check("radius", radius, true)?;
        check("mu", mu, false)?;
        check("weight", weight, true)?;
        check("yield_displacement", yield_displacement, true)?;
        check("vertical_stiffness", vertical_stiffness, true)?;
        Ok(Self {
            dofs: vec![dof_x, dof_z],
            radius,
            mu,
            k_init: mu * weight / yield_displacement,
            kv: vertical_stiffness,
        })
    }

    fn response(&self, u: f64, w: f64, up_c: f64) -> Response {
        let (r, mu, ki, kv) = (self.radius, self.mu, self.k_init, self.kv);
        if w >= 0.0 {
            // no compression: no shear; lifted off, the slider goes with the top
            let plastic = if w > 0.0 { u } else { up_c };
            return Response {
                shear: 0.0,
                axial: 0.0,
                plastic,
                dv: [0.0; 2],
                dp: 0.0,
            };
        }
        let p = -kv * w;
        let d = u - up_c;
        // sticking
        let den = 1.0 - u * up_c / (r * r);
        let num = p + ki * d * u / r;
        let n = num / den;
        if mu > 0.0 && ((ki - n / r) * d).abs() <= mu * n || mu == 0.0 && d == 0.0 {
            let dn_du = (ki * (d + u) / r * den + num * up_c / (r * r)) / (den * den);
            let dn_dw = -kv / den;
            return Response {
                shear: ki * d + n * up_c / r,
                axial: p,
                plastic: up_c,
                dv: [ki + up_c / r * dn_du, up_c / r * dn_dw],
                dp: -kv,
            };
        }
        // sliding
        let s = if d >= 0.0 { 1.0 } else { -1.0 };
        let a = u / r + mu * s;
        let den = 1.0 - u / r * a;
        let n = p / den;
        let dden_du = -2.0 * u / (r * r) - mu * s / r;
        let dn_du = -p * dden_du / (den * den);
        let dn_dw = -kv / den;
        Response {
            shear: n * a,
            axial: p,
            plastic: u - mu * n * s / (ki - n / r),
            dv: [dn_du * a + n / r, dn_dw * a],
            dp: -kv,
        }
    }

    fn add(
        &self,
        x: &[f64],
        up_c: f64,
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<f64, CoreError> {
        let res = self.response(x[0], x[1], up_c);
        // beyond the small-angle model (u of the order of R) the normal force has no solution
        let valid = x[0].abs() < 0.5 * self.radius;
        let values = [
            res.shear,
            res.axial,
            res.plastic,
            res.dv[0],
            res.dv[1],
            if valid { 0.0 } else { f64::NAN },
        ];
        finite(t, &values)?;
        r[0] += res.shear;
        r[1] -= res.axial;
        if let Some(tg) = tangent {
            tg.kx[0] += res.dv[0];
            tg.kx[1] += res.dv[1];
            tg.kx[3] -= res.dp;
        }
        Ok(res.plastic)
    }
}

impl Element for AxialFrictionPendulum {
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
        self.add(x, 0.0, t, r, tangent).map(|_| ())
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
        history.trial[0] = self.add(x, history.committed[0], t, r, tangent)?;
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        false
    }

    fn state_len(&self) -> usize {
        1
    }

    fn initial_state(&self, x: &[f64], _v: &[f64], state: &mut [f64]) {
        // virgin at u = 0, loaded along the straight line to the initial state
        state[0] = self.response(x[0], x[1], 0.0).plastic;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(e: &AxialFrictionPendulum, x: [f64; 2], up: f64) -> ([f64; 2], [f64; 4], f64) {
        let (mut r, mut kx, mut cv) = ([0.0; 2], [0.0; 4], [0.0; 4]);
        let mut trial = [0.0];
        let history = PathState {
            committed: &[up],
            trial: &mut trial,
        };
        let tangent = Tangent {
            kx: &mut kx,
            cv: &mut cv,
        };
        e.eval_path(&x, &[0.0; 2], 0.0, history, &mut r, Some(tangent))
            .unwrap();
        (r, kx, trial[0])
    }

    #[test]
    fn normal_force_balances_and_tangent_is_consistent() {
        let e = AxialFrictionPendulum::new((0, 1), 2.0, 0.05, (1e3, 1e-3), 1e5).unwrap();
        for (x, up) in [
            ([0.3, -0.01], 0.0),
            ([0.3, -0.01], 0.2995),
            ([-0.2, -0.012], 0.1),
        ] {
            let (r, k, trial) = eval(&e, x, up);
            let p = -1e5 * x[1];
            assert!((r[1] + p).abs() < 1e-9);
            // N = P + V u / R and, sliding, |V - N u / R| = mu N
            let n = p + r[0] * x[0] / 2.0;
            let f = r[0] - n * x[0] / 2.0;
            assert!(f.abs() <= 0.05 * n * (1.0 + 1e-12));
            if trial != up {
                assert!((f.abs() - 0.05 * n).abs() < 1e-9 * n);
            }
            for j in 0..2 {
                let h = 1e-7;
                let (mut xp, mut xm) = (x, x);
                xp[j] += h;
                xm[j] -= h;
                let (rp, _, _) = eval(&e, xp, up);
                let (rm, _, _) = eval(&e, xm, up);
                for i in 0..2 {
                    let fd = (rp[i] - rm[i]) / (2.0 * h);
                    let an = k[2 * i + j];
                    assert!(
                        (an - fd).abs() <= 1e-5 * (1.0 + an.abs()),
                        "{i}{j}: {an} {fd}"
                    );
                }
            }
        }
        // uplift: nothing carried, the slider follows
        let (r, k, trial) = eval(&e, [0.1, 0.001], 0.0);
        assert_eq!((r, k, trial), ([0.0; 2], [0.0; 4], 0.1));
    }
}
