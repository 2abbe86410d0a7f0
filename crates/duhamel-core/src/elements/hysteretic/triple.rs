//! Triple friction pendulum isolator (bidirectional, coupled; or uniaxial): the series model
//! of its four sliding surfaces, as OpenSees' `TripleFrictionPendulum` element writes it
//! (Dao, Ryan, Sato & Sasaki 2013, "Predicting the displacement of triple pendulum
//! bearings in a full-scale shaking experiment using a three-dimensional element",
//! Earthquake Engng Struct. Dyn. 42; after Fenz & Constantinou 2008, "Spherical sliding
//! isolation bearings with adaptive behavior: theory", Earthquake Engng Struct. Dyn. 37, and
//! "Modeling triple friction pendulum bearings for response-history analysis", Earthquake
//! Spectra 24).
//!
//! Effective radii `L1` (the two inner surfaces), `L2`, `L3` (the outer ones), friction
//! coefficients `mu1 <= mu2 <= mu3` and displacement capacities `d1, d2, d3` of the
//! surfaces. Three elements in series carry the same force `F = W f` (`f` normalised by the
//! vertical load `W`) and add up to the bearing's displacement `u = d_1 + d_2 + d_3`; each
//! is a bidirectional elastoplastic element with linear kinematic hardening in parallel
//! with a circular gap (the displacement restrainer):
//!
//! ```text
//! element   yield  sliding stiffness   gap (restrainer)
//! inner     mu1    1 / (2 L1)          2 (d1 + d3 L1 / L3)
//! outer 2   mu2    1 / (L2 - L1)       d2 (1 - L1 / L2)
//! outer 3   mu3    1 / (L3 - L1)       d3 (1 - L1 / L3)
//! ```
//!
//! with the elastic stiffness `E = 3 mu1 / uy` in every element (the bearing's pre-sliding
//! stiffness is `mu1 W / uy`), the hardening `H = E Ep / (E - Ep)` that makes the sliding
//! stiffness `Ep`, and the gap stiffness `E` beyond the gap. This gives Fenz & Constantinou's
//! regimes: I sliding on the inner surfaces from `F = mu1 W` (stiffness `W / (2 L1)`),
//! II on surface 2 from `mu2 W` (`W / (L1 + L2)`), III on both outer ones from `mu3 W`
//! (`W / (L2 + L3)`), IV surface 2 at its stop from `F = W (mu2 + d2 / L2)` (`W / (L1 + L3)`)
//! and V surface 3 at its stop from `F = W (mu3 + d3 / L3)` (`W / (2 L1)`), up to the
//! stiffening when the inner slider reaches its own.
//!
//! Each element's return mapping is backward Euler from the committed plastic displacement
//! (radial return, OpenSees' `BidirectionalPlastic`): for a given total displacement the
//! trial state is unique, the series equations (equal forces, displacements adding up to
//! `u`) are the stationarity conditions of a convex potential and are solved by Newton's
//! method with a line search on it, to round-off. The tangent is the exact one: the inverse
//! of the sum of the elements' compliances (the series model is [`super::triple_series`]).
//! Coulomb friction. Internal variables: `[d_1, d_2, d_3, ep_1, ep_2, ep_3]` (each 2
//! entries; `y` entries 0 for a uniaxial bearing). **Initial state:** virgin at `u = 0`,
//! loaded along the straight line to the initial displacement.
//!
//! **The vertical load:** constant (`W`), or with the vertical dof `z` (up, to the ground)
//! the axial force of OpenSees' element: its vertical spring `k_v` carries the compression
//! `N = -k_v w` (`w` the vertical displacement, `< 0` compressed), and in tension (uplift,
//! `k_v w >= 0`) the bearing carries OpenSees' `MinFv` (`N_min`, >= 0) as its normal force.
//! The shear is `N f(u)`, the vertical force on the dof `-N` (with an initial axial force
//! `P0` at `x = 0`, `w` is measured from where the spring carries `P0` and the force is the
//! change `P0 - N`); the tangent couples `u` and `w` through `N` (`f dN/dw`).
//!
//! **P-Delta moments:** OpenSees' element puts `N u_y / 2`, `-N u_x / 2` and
//! `N (f_x u_y - f_y u_x) / 2` on its nodes' rotations `(rx, ry, rz)` (not in its tangent);
//! with the top node's rotations given ([`TripleFrictionPendulum::with_rotations`]) they
//! act there, with their exact tangent.

use super::common::{check, finite};
use super::triple_segment::{Segment, V2};
use super::triple_series::{Solved, Surfaces};
use crate::elements::element::distinct;
use crate::elements::element::{Element, PathState, Tangent};
use crate::error::CoreError;

/// The vertical dof's spring: axial stiffness, the normal force in uplift, and the axial
/// force at `x = 0` (None: `x = 0` unloaded).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Vertical {
    kv: f64,
    min_axial: f64,
    initial_axial: Option<f64>,
}

/// Triple friction pendulum bearing on `(dof_x, dof_y)`, or on `dof_x` alone, with an
/// optional vertical dof last.
#[derive(Debug, Clone, PartialEq)]
pub struct TripleFrictionPendulum {
    dofs: Vec<usize>,
    mu: [f64; 3],
    radius: [f64; 3],
    capacity: [f64; 3],
    weight: f64,
    yield_displacement: f64,
    series: Surfaces,
    vertical: Option<Vertical>,
    /// The local indices of the top node's rotations `(rx, ry, rz)` that carry OpenSees'
    /// P-Delta moments.
    rotations: [Option<usize>; 3],
}
impl TripleFrictionPendulum {
    /// Bearing on the distinct dofs `(dof_x, dof_y)` with friction coefficients
    /// `mu = (mu1, mu2, mu3)`, `0 < mu1 <= mu2 <= mu3`, effective radii
    /// `radius = (L1, L2, L3)`, `0 < L1 < L2, L3`, displacement capacities
    /// `capacity = (d1, d2, d3) > 0`, vertical load `weight > 0` and the displacement
    /// `yield_displacement` where sliding starts (`> 0`, small enough that each element's
    /// elastic stiffness exceeds its sliding stiffness).
    pub fn new(
        dof_x: usize,
        dof_y: usize,
        mu: [f64; 3],
        radius: [f64; 3],
        capacity: [f64; 3],
        weight: f64,
        yield_displacement: f64,
    ) -> Result<Self, CoreError> {
        distinct(dof_x, dof_y)?;
        let bad = |name: &'static str, problem: String| CoreError::InvalidInput { name, problem };
        for (name, values) in [
            ("mu", mu),
            ("radius", radius),
            ("displacement_capacity", capacity),
        ] {
            if !values.iter().all(|v| v.is_finite() && *v > 0.0) {
                return Err(bad(
                    name,
                    format!("must be > 0 (three finite values), got {values:?}"),
                ));
            }
        }
        if !(mu[0] <= mu[1] && mu[1] <= mu[2]) {
            return Err(bad(
                "mu",
                format!("must be ordered mu1 <= mu2 <= mu3 (inner surfaces first), got {mu:?}"),
            ));
        }
        let [l1, l2, l3] = radius;
        if !(l2 > l1 && l3 > l1) {
            return Err(bad(
                "radius",
                format!("the inner radius L1 must be below L2 and L3, got {radius:?}"),
            ));
        }
        check("weight", weight, true)?;
        check("yield_displacement", yield_displacement, true)?;
        let e = 3.0 * mu[0] / yield_displacement;
        let slopes = [1.0 / (2.0 * l1), 1.0 / (l2 - l1), 1.0 / (l3 - l1)];
        let softest = slopes.iter().copied().fold(0.0, f64::max);
        if e <= softest {
            return Err(bad(
                "yield_displacement",
                format!(
                    "must be below 3 mu1 / max(1 / (2 L1), 1 / (L2 - L1), 1 / (L3 - L1)) = {} \
                     (the elastic stiffness of each sliding element must exceed its sliding \
                     stiffness), got {yield_displacement}",
                    3.0 * mu[0] / softest
                ),
            ));
        }
        let [d1, d2, d3] = capacity;
        let gaps = [
            2.0 * (l1 / l3 * d3 + d1),
            d2 * (1.0 - l1 / l2),
            d3 * (1.0 - l1 / l3),
        ];
        let segment = |i: usize| Segment {
            fy: mu[i],
            e,
            h: e * slopes[i] / (e - slopes[i]),
            gap: gaps[i],
        };
        Ok(Self {
            dofs: vec![dof_x, dof_y],
            mu,
            radius,
            capacity,
            weight,
            yield_displacement,
            series: Surfaces {
                segments: [segment(0), segment(1), segment(2)],
            },
            vertical: None,
            rotations: [None; 3],
        })
    }

    /// Uniaxial bearing on `dof_x` (a plane model), the parameters as in [`Self::new`].
    pub fn uniaxial(
        dof_x: usize,
        mu: [f64; 3],
        radius: [f64; 3],
        capacity: [f64; 3],
        weight: f64,
        yield_displacement: f64,
    ) -> Result<Self, CoreError> {
        let mut e = Self::new(
            dof_x,
            dof_x + 1,
            mu,
            radius,
            capacity,
            weight,
            yield_displacement,
        )?;
        e.dofs = vec![dof_x];
        Ok(e)
    }

    /// Friction coefficients `(mu1, mu2, mu3)`.
    pub fn mu(&self) -> [f64; 3] {
        self.mu
    }

    /// Effective radii `(L1, L2, L3)`.
    pub fn radius(&self) -> [f64; 3] {
        self.radius
    }

    /// Displacement capacities `(d1, d2, d3)`.
    pub fn displacement_capacity(&self) -> [f64; 3] {
        self.capacity
    }

    /// Vertical load `W`.
    pub fn weight(&self) -> f64 {
        self.weight
    }

    /// Displacement where sliding starts, `uy`.
    pub fn yield_displacement(&self) -> f64 {
        self.yield_displacement
    }

    /// The same bearing with its vertical dof `dof_z` (distinct from the horizontal ones)
    /// and axial stiffness `kv > 0`: the normal force is the compression `-kv w`, `min_axial`
    /// (>= 0, OpenSees' `MinFv`) in tension; `initial_axial` (> 0) the axial force at `x = 0`
    /// when `x = 0` is the loaded state (None: unloaded).
    pub fn with_vertical(
        mut self,
        dof_z: usize,
        kv: f64,
        min_axial: f64,
        initial_axial: Option<f64>,
    ) -> Result<Self, CoreError> {
        self.distinct_from_mine(dof_z)?;
        check("vertical_stiffness", kv, true)?;
        check("min_axial_force", min_axial, false)?;
        if let Some(p0) = initial_axial {
            check("initial_axial_force", p0, true)?;
        }
        self.dofs.push(dof_z);
        self.vertical = Some(Vertical {
            kv,
            min_axial,
            initial_axial,
        });
        Ok(self)
    }

    /// The same bearing with the rotations `(rx, ry, rz)` of its top node (each optional,
    /// distinct from its other dofs) carrying OpenSees' P-Delta moments of the element on
    /// that node: `N u_y / 2`, `-N u_x / 2` and `N (f_x u_y - f_y u_x) / 2` (`N f` the
    /// shear).
    pub fn with_rotations(mut self, rotations: [Option<usize>; 3]) -> Result<Self, CoreError> {
        for (k, dof) in rotations.iter().enumerate() {
            if let Some(dof) = *dof {
                self.distinct_from_mine(dof)?;
                self.rotations[k] = Some(self.dofs.len());
                self.dofs.push(dof);
            }
        }
        Ok(self)
    }

    /// `dof` checked against the bearing's dofs so far (the error names `dofs`).
    fn distinct_from_mine(&self, dof: usize) -> Result<(), CoreError> {
        if self.dofs.contains(&dof) {
            return Err(CoreError::InvalidInput {
                name: "dofs",
                problem: format!(
                    "must be distinct: {dof} is already one of the bearing's dofs {:?}",
                    self.dofs
                ),
            });
        }
        Ok(())
    }

    /// The number of horizontal dofs (1 or 2).
    fn horizontal(&self) -> usize {
        let rotations = self.rotations.iter().flatten().count();
        self.dofs.len() - usize::from(self.vertical.is_some()) - rotations
    }

    /// Adds the P-Delta moments on the rotations and their tangent (`n` local dofs).
    fn moments(&self, solved: &Solved, x: &[f64], r: &mut [f64], tangent: Option<&mut [f64]>) {
        let (big_n, dn, _) = self.normal(x);
        let [ux, uy] = self.plane(x);
        let (f, k) = (solved.f, solved.k);
        let m = self.horizontal();
        let n = self.dofs.len();
        let z = self.vertical.map(|_| m);
        // rows: the moment, d/du_x, d/du_y, its factor of dN/dw
        let rows = [
            (big_n * uy / 2.0, [0.0, big_n / 2.0], uy / 2.0),
            (-big_n * ux / 2.0, [-big_n / 2.0, 0.0], -ux / 2.0),
            (
                big_n * (f[0] * uy - f[1] * ux) / 2.0,
                [
                    big_n * (k[0] * uy - k[2] * ux - f[1]) / 2.0,
                    big_n * (k[1] * uy - k[3] * ux + f[0]) / 2.0,
                ],
                (f[0] * uy - f[1] * ux) / 2.0,
            ),
        ];
        let mut kx = tangent;
        for (slot, (moment, du, dw)) in self.rotations.iter().zip(rows) {
            let Some(a) = *slot else { continue };
            r[a] += moment;
            if let Some(kx) = kx.as_deref_mut() {
                for (j, d) in du.iter().enumerate().take(m) {
                    kx[a * n + j] += d;
                }
                if let Some(z) = z {
                    kx[a * n + z] += dn * dw;
                }
            }
        }
    }

    /// The local `(x, y)` of `x` (`y = 0` for a uniaxial bearing).
    fn plane(&self, x: &[f64]) -> V2 {
        [x[0], if self.horizontal() == 2 { x[1] } else { 0.0 }]
    }

    /// The normal force `N`, `dN/dw` and the vertical force on the dof at `x`.
    fn normal(&self, x: &[f64]) -> (f64, f64, f64) {
        let Some(v) = self.vertical else {
            return (self.weight, 0.0, 0.0);
        };
        let w = x[self.horizontal()];
        let p0 = v.initial_axial.unwrap_or(0.0);
        // OpenSees: the vertical material's force kv (w - w0), uplift when it is >= 0
        let spring = v.kv * w - p0;
        if spring < 0.0 {
            // -N + P0 = kv w, taken so (without the cancellation of the large P0)
            (-spring, -v.kv, v.kv * w)
        } else {
            (v.min_axial, 0.0, p0 - v.min_axial)
        }
    }

    fn add(
        &self,
        solved: &Solved,
        x: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let (w, dw, vertical) = self.normal(x);
        let force = [w * solved.f[0], w * solved.f[1], vertical];
        finite(t, &force)?;
        finite(t, &solved.k)?;
        let m = self.horizontal();
        let n = self.dofs.len();
        for i in 0..m {
            r[i] += force[i];
        }
        if self.vertical.is_some() {
            r[m] += vertical;
        }
        let any_rotation = self.rotations.iter().any(Option::is_some);
        if let Some(tg) = tangent {
            if any_rotation {
                self.moments(solved, x, r, Some(&mut *tg.kx));
            }
            for i in 0..m {
                for j in 0..m {
                    tg.kx[i * n + j] += w * solved.k[2 * i + j];
                }
                if self.vertical.is_some() {
                    tg.kx[i * n + m] += dw * solved.f[i];
                }
            }
            if self.vertical.is_some() {
                tg.kx[m * n + m] -= dw;
            }
        } else if any_rotation {
            self.moments(solved, x, r, None);
        }
        Ok(())
    }
}

impl Element for TripleFrictionPendulum {
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
        let solved = self.series.solve(&[0.0; 12], self.plane(x), t)?;
        self.add(&solved, x, t, r, tangent)
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        false
    }

    fn state_len(&self) -> usize {
        12
    }

    fn initial_state(&self, x: &[f64], _v: &[f64], state: &mut [f64]) {
        // a state the model cannot solve (non-finite x) starts virgin; the run then fails
        // at its first evaluation with the error
        let solved = self.series.solve(&[0.0; 12], self.plane(x), 0.0);
        state.copy_from_slice(&solved.map(|s| s.state).unwrap_or([0.0; 12]));
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
        let solved = self.series.solve(history.committed, self.plane(x), t)?;
        self.add(&solved, x, t, r, tangent)?;
        history.trial.copy_from_slice(&solved.state);
        Ok(())
    }
}

#[cfg(test)]
#[path = "triple_tests.rs"]
mod tests;
