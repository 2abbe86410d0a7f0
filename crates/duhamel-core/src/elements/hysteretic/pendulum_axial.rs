//! Friction pendulum with its vertical dof: the normal force from the model (OpenSees
//! `singleFPBearing` as the reference, `SingleFPSimple2d` and `SingleFPSimple3d`),
//! uniaxial on `(dof_x, dof_z)` or bidirectional on `(dof_x, dof_y, dof_z)`.
//!
//! On the horizontal displacement `u` (a scalar or a 2-vector) and the vertical
//! displacement `w` of the slider relative to the ground (`w > 0` up), the bearing carries
//! the compressive axial force `P = -k_v w` (`w < 0`; `k_v` the axial stiffness) and nothing
//! in tension (uplift: zero shear and zero axial force, the slider's plastic displacement
//! follows `u`). Compressed, the normal force on the concave surface is `N = P + V . u / R`
//! (the shear's component along the normal, as OpenSees writes it), the shear
//!
//! ```text
//! V = (N / R) u + f,    f = (k_i - N / R) (u - u_p),  |f| <= mu N,
//! ```
//!
//! with `k_i = mu_fast W / Y` the initial stiffness (`W` the nominal weight, `Y` the yield
//! displacement) and the plastic displacement `u_p` from the radial return mapping (a
//! circle in two directions). `N` is solved in closed form: sticking (`u_p` the committed
//! one), `N = (P + k_i (u - u_p) . u / R) / (1 - u . u_p / R^2)`,
//! `V = k_i (u - u_p) + N u_p / R`; sliding (`n` the direction of `u - u_p`),
//! `N = P / (1 - (u / R) . (u / R + mu n))`, `V = N (u / R + mu n)`,
//! `u_p = u - mu N n / (k_i - N / R)`.
//!
//! The friction coefficient (`law::Coefficient`): constant (OpenSees `Coulomb`),
//! velocity-dependent `mu = mu_fast - (mu_fast - mu_slow) exp(-rate s)` at the sliding
//! speed on the surface `s = sqrt(|u'|^2 + (u . u' / R)^2)` (`VelDependent`), and
//! optionally pressure-dependent, `mu_fast(N) = mu_fast - delta_mu tanh(alpha N / A)`
//! (`VelPressureDep`, `A` the contact area: the high-speed coefficient falls with the
//! contact pressure `N / A`); then `N` is found by Newton's method on the sliding
//! equation. Consistent tangents in `u`, `w` and the velocities; the vertical force on the
//! dof is `-P`. Internal variables: `[u_p,x, u_p,y]` (`u_p,y = 0` uniaxial).

mod law;

#[cfg(test)]
mod tests;

use super::common::{check, finite};
use crate::elements::element::{Element, PathState, Tangent};
use crate::error::CoreError;
use law::{Coefficient, Law, Response};

/// Friction pendulum to the ground on `(dof_x, dof_z)` or `(dof_x, dof_y, dof_z)`, its
/// normal force from the vertical dof.
#[derive(Debug, Clone, PartialEq)]
pub struct AxialFrictionPendulum {
    dofs: Vec<usize>,
    law: Law,
    /// The axial force `P0` carried at `x = 0` (None: none, `x = 0` unloaded).
    initial_axial: Option<f64>,
}

fn differ(dofs: &[usize]) -> Result<(), CoreError> {
    let names = ["dof_x", "dof_y", "dof_z"];
    let named: Vec<(&'static str, usize)> = if dofs.len() == 2 {
        vec![(names[0], dofs[0]), (names[2], dofs[1])]
    } else {
        names.iter().copied().zip(dofs.iter().copied()).collect()
    };
    for (k, &(name, dof)) in named.iter().enumerate() {
        if let Some(&(other, _)) = named[..k].iter().find(|(_, d)| *d == dof) {
            return Err(CoreError::InvalidInput {
                name,
                problem: format!("must differ from {other} (both are {dof})"),
            });
        }
    }
    Ok(())
}

impl AxialFrictionPendulum {
    /// Uniaxial bearing on the horizontal `dof_x` and vertical `dof_z` (distinct) with radius
    /// `radius > 0`, friction coefficient `mu >= 0`, nominal weight `weight > 0` and yield
    /// displacement `yield_displacement > 0` (initial stiffness `mu W / Y`), axial
    /// stiffness `vertical_stiffness > 0`.
    pub fn new(
        (dof_x, dof_z): (usize, usize),
        radius: f64,
        mu: f64,
        nominal: (f64, f64),
        vertical_stiffness: f64,
    ) -> Result<Self, CoreError> {
        Self::build(vec![dof_x, dof_z], radius, mu, nominal, vertical_stiffness)
    }

    /// Bidirectional bearing on the horizontal `(dof_x, dof_y)` and vertical `dof_z` (all
    /// distinct), the parameters as in [`Self::new`].
    pub fn bidirectional(
        (dof_x, dof_y, dof_z): (usize, usize, usize),
        radius: f64,
        mu: f64,
        nominal: (f64, f64),
        vertical_stiffness: f64,
    ) -> Result<Self, CoreError> {
        Self::build(
            vec![dof_x, dof_y, dof_z],
            radius,
            mu,
            nominal,
            vertical_stiffness,
        )
    }

    /// The bearing on `dofs`: `[dof_x, dof_z]` (uniaxial) or `[dof_x, dof_y, dof_z]`
    /// (bidirectional), the parameters as in [`Self::new`].
    pub fn on(
        dofs: &[usize],
        radius: f64,
        mu: f64,
        nominal: (f64, f64),
        vertical_stiffness: f64,
    ) -> Result<Self, CoreError> {
        if !(2..=3).contains(&dofs.len()) {
            return Err(CoreError::InvalidInput {
                name: "dofs",
                problem: format!(
                    "must be (dof_x, dof_z) or (dof_x, dof_y, dof_z), got {} dofs",
                    dofs.len()
                ),
            });
        }
        Self::build(dofs.to_vec(), radius, mu, nominal, vertical_stiffness)
    }

    fn build(
        dofs: Vec<usize>,
        radius: f64,
        mu: f64,
        (weight, yield_displacement): (f64, f64),
        vertical_stiffness: f64,
    ) -> Result<Self, CoreError> {
        differ(&dofs)?;
        check("radius", radius, true)?;
        check("mu", mu, false)?;
        check("weight", weight, true)?;
        check("yield_displacement", yield_displacement, true)?;
        check("vertical_stiffness", vertical_stiffness, true)?;
        let law = Law {
            radius,
            k_init: mu * weight / yield_displacement,
            kv: vertical_stiffness,
            friction: Coefficient {
                mu_fast: mu,
                velocity: None,
                pressure: None,
            },
        };
        Ok(Self {
            dofs,
            law,
            initial_axial: None,
        })
    }

    /// The same bearing carrying the compressive axial force `p0 >= 0` at `x = 0` (a loaded
    /// state whose loads are not in the model, e.g. an imported gravity state): its vertical
    /// displacement is `x_z - p0 / k_v` and its vertical force on the model the change from
    /// `p0`. Errors name `"initial_axial_force"`.
    pub fn with_axial_load(mut self, p0: f64) -> Result<Self, CoreError> {
        check("initial_axial_force", p0, false)?;
        self.initial_axial = Some(p0);
        Ok(self)
    }

    /// The same bearing with velocity-dependent friction from `mu_fast = mu` down to
    /// `mu_slow` (`0 <= mu_slow <= mu`) at rest, with `rate >= 0` (s/m; 0: constant `mu`).
    pub fn with_velocity(mut self, mu_slow: f64, rate: f64) -> Result<Self, CoreError> {
        check("mu_slow", mu_slow, false)?;
        check("rate", rate, false)?;
        let mu = self.law.friction.mu_fast;
        if mu_slow > mu {
            return Err(CoreError::InvalidInput {
                name: "mu_slow",
                problem: format!("must be <= mu (mu_fast) = {mu}, got {mu_slow}"),
            });
        }
        self.law.friction.velocity = (rate > 0.0).then_some((mu_slow, rate));
        Ok(self)
    }

    /// The same bearing with pressure-dependent friction (OpenSees `VelPressureDep`): the
    /// high-speed coefficient `mu - delta_mu tanh(alpha N / A)` with the contact area
    /// `area > 0`, `0 <= delta_mu < mu` and `alpha >= 0` (per unit pressure).
    pub fn with_pressure(
        mut self,
        area: f64,
        delta_mu: f64,
        alpha: f64,
    ) -> Result<Self, CoreError> {
        check("contact_area", area, true)?;
        check("delta_mu", delta_mu, false)?;
        check("pressure_alpha", alpha, false)?;
        let mu = self.law.friction.mu_fast;
        if delta_mu > 0.0 && delta_mu >= mu {
            return Err(CoreError::InvalidInput {
                name: "delta_mu",
                problem: format!("must be < mu (mu_fast) = {mu}, got {delta_mu}"),
            });
        }
        self.law.friction.pressure =
            (delta_mu > 0.0 && alpha > 0.0).then_some((area, delta_mu, alpha));
        Ok(self)
    }

    /// The same bearing with velocity-dependent friction (`velocity = (mu_slow, rate)`, see
    /// [`Self::with_velocity`]) and pressure-dependent friction (`pressure = (area,
    /// delta_mu, alpha)`, see [`Self::with_pressure`]) when given.
    pub fn with_friction(
        self,
        velocity: Option<(f64, f64)>,
        pressure: Option<(f64, f64, f64)>,
    ) -> Result<Self, CoreError> {
        let e = match velocity {
            Some((slow, rate)) => self.with_velocity(slow, rate)?,
            None => self,
        };
        match pressure {
            Some((area, delta, alpha)) => e.with_pressure(area, delta, alpha),
            None => Ok(e),
        }
    }

    /// The number of horizontal dofs (1 or 2).
    fn horizontal(&self) -> usize {
        self.dofs.len() - 1
    }

    /// The local `(u, w, v)` of the element's `x`, `v`.
    fn local(&self, x: &[f64], v: &[f64]) -> ([f64; 2], f64, [f64; 2]) {
        let (u, w, vel) = if self.horizontal() == 2 {
            ([x[0], x[1]], x[2], [v[0], v[1]])
        } else {
            ([x[0], 0.0], x[1], [v[0], 0.0])
        };
        match self.initial_axial {
            None => (u, w, vel),
            Some(p0) => (u, w - p0 / self.law.kv, vel),
        }
    }

    fn response(&self, x: &[f64], v: &[f64], up_c: [f64; 2]) -> Response {
        let (u, w, vel) = self.local(x, v);
        self.law.respond(u, w, vel, up_c)
    }

    fn add(
        &self,
        (x, v): (&[f64], &[f64]),
        up_c: [f64; 2],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<[f64; 2], CoreError> {
        let res = self.response(x, v, up_c);
        let (u, _, _) = self.local(x, v);
        // beyond the small-angle model (u of the order of R) the normal force has no solution
        let reach = u[0].hypot(u[1]);
        // false for a non-finite displacement as well
        let inside = reach < 0.5 * self.law.radius;
        if !inside {
            return Err(CoreError::OutOfDomain {
                time: t,
                step: 0,
                last_good_time: None,
                message: format!(
                    "FrictionPendulum with its vertical dof (dofs {:?}): the horizontal displacement \
                     |u| = {reach:.6e} m reached half the radius R = {:e} m, where the model \
                     (small angles, the normal force from the axial load) ends: the motion is \
                     beyond what this bearing model covers (check the bearing's displacement \
                     capacity and the excitation), or the step is too large",
                    self.dofs,
                    self.law.radius,
                ),
            });
        }
        let mut values = vec![res.axial];
        values.extend_from_slice(&res.shear);
        values.extend_from_slice(&res.plastic);
        values.extend_from_slice(&res.kx);
        values.extend_from_slice(&res.cv);
        finite(t, &values)?;
        let m = self.horizontal();
        // local index of the element's dofs: (x, z) -> (0, 2), (x, y, z) -> (0, 1, 2)
        let idx: &[usize] = if m == 2 { &[0, 1, 2] } else { &[0, 2] };
        let n = idx.len();
        for (ri, v) in r.iter_mut().zip(&res.shear[..m]) {
            *ri += v;
        }
        match self.initial_axial {
            None => r[m] -= res.axial,
            // the change from the axial force at x = 0: in compression -P + p0 = k_v x_z,
            // taken so (the small change without the cancellation of the large p0)
            Some(p0) => {
                r[m] += if res.axial > 0.0 {
                    self.law.kv * x[m]
                } else {
                    p0
                }
            }
        }
        if let Some(tg) = tangent {
            for (a, &i) in idx.iter().enumerate() {
                // the vertical row is -P
                let sign = if i == 2 { -1.0 } else { 1.0 };
                for (b, &j) in idx.iter().enumerate() {
                    tg.kx[a * n + b] += sign * res.kx[3 * i + j];
                    if j < 2 {
                        tg.cv[a * n + b] += sign * res.cv[3 * i + j];
                    }
                }
            }
        }
        Ok(res.plastic)
    }

    fn committed(&self, c: &[f64]) -> [f64; 2] {
        [c[0], c.get(1).copied().unwrap_or(0.0)]
    }
}

impl Element for AxialFrictionPendulum {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn eval(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        self.add((x, v), [0.0; 2], t, r, tangent).map(|_| ())
    }

    fn eval_path(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        history: PathState<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let plastic = self.add((x, v), self.committed(history.committed), t, r, tangent)?;
        let m = self.horizontal();
        history.trial.copy_from_slice(&plastic[..m]);
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        self.law.friction.velocity.is_some()
    }

    fn state_len(&self) -> usize {
        self.horizontal()
    }

    fn initial_state(&self, x: &[f64], v: &[f64], state: &mut [f64]) {
        // virgin at u = 0, loaded along the straight line to the initial state
        let plastic = self.response(x, v, [0.0; 2]).plastic;
        state.copy_from_slice(&plastic[..self.horizontal()]);
    }
}
