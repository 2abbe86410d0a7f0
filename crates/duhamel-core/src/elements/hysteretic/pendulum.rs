//! The friction pendulum bearing as a model defines it: on its horizontal dofs
//! ([`FrictionPendulum`]) or with its vertical dof ([`AxialFrictionPendulum`]), one class.

use serde::{Deserialize, Serialize};

use super::common::check;
use super::friction::{FrictionPendulum, DEFAULT_YIELD_DISPLACEMENT};
use super::pendulum_axial::AxialFrictionPendulum;
use super::rubber::rename_axes;
use crate::elements::definition::Definition;
use crate::error::CoreError;

/// `duhamel.elements.FrictionPendulum`: the definition of a [`FrictionPendulum`], or of an
/// [`AxialFrictionPendulum`] with its vertical dof.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionPendulumDef {
    pub dofs: Vec<Option<usize>>,
    pub radius: f64,
    pub mu: f64,
    pub weight: f64,
    #[serde(default = "default_yield")]
    pub yield_displacement: f64,
    #[serde(default)]
    pub mu_slow: Option<f64>,
    #[serde(default)]
    pub rate: f64,
    #[serde(default)]
    pub vertical_stiffness: Option<f64>,
    #[serde(default)]
    pub contact_area: Option<f64>,
    #[serde(default)]
    pub delta_mu: f64,
    #[serde(default)]
    pub pressure_alpha: f64,
    #[serde(default)]
    pub initial_axial_force: Option<f64>,
}

fn default_yield() -> f64 {
    DEFAULT_YIELD_DISPLACEMENT
}

crate::element_variants! {
    /// A friction pendulum on its horizontal dofs, or with its vertical dof.
    pub enum PendulumElement {
        Flat(FrictionPendulum),
        Axial(AxialFrictionPendulum),
    }
}

impl FrictionPendulumDef {
    /// `(dof_x, dof_y, dof_z)`, checked.
    fn axes(&self) -> Result<(usize, Option<usize>, Option<usize>), CoreError> {
        let bad = |problem: String| CoreError::InvalidInput {
            name: "dofs",
            problem,
        };
        let get = |k: usize| self.dofs.get(k).copied().flatten();
        let x = get(0).ok_or_else(|| bad("must start with the dof x (not None)".into()))?;
        if self.dofs.len() > 3 {
            return Err(bad(format!(
                "must be x, (x, y), (x, None, z) or (x, y, z), got {} entries",
                self.dofs.len()
            )));
        }
        Ok((x, get(1), get(2)))
    }

    fn local(&self) -> Vec<usize> {
        self.dofs.iter().flatten().copied().collect()
    }

    fn vertical_checks(&self, vertical: bool) -> Result<(), CoreError> {
        let bad = |name: &'static str, problem: &str| CoreError::InvalidInput {
            name,
            problem: problem.into(),
        };
        if vertical && self.vertical_stiffness.is_none() {
            return Err(bad(
                "vertical_stiffness",
                "is required with the vertical dof (dofs=(x, y, z) or (x, None, z))",
            ));
        }
        if !vertical && self.vertical_stiffness.is_some() {
            return Err(bad(
                "vertical_stiffness",
                "needs the vertical dof: dofs=(x, y, z) or (x, None, z)",
            ));
        }
        if self.contact_area.is_none() && (self.delta_mu != 0.0 || self.pressure_alpha != 0.0) {
            return Err(bad("delta_mu", "and `pressure_alpha` need `contact_area`"));
        }
        if self.initial_axial_force.is_some() && !vertical {
            return Err(bad(
                "initial_axial_force",
                "needs the vertical dof: dofs=(x, y, z) or (x, None, z)",
            ));
        }
        if self.contact_area.is_some() && !vertical {
            return Err(bad(
                "contact_area",
                "(pressure-dependent friction) needs the vertical dof: dofs=(x, y, z) or (x, None, z)",
            ));
        }
        Ok(())
    }
}

impl Definition for FrictionPendulumDef {
    const NAME: &'static str = "FrictionPendulum";
    const SIGNATURE: &'static str = "(dofs, *, radius, mu, weight, yield_displacement=0.00025, \
        mu_slow=None, rate=0.0, vertical_stiffness=None, contact_area=None, delta_mu=0.0, \
        pressure_alpha=0.0, initial_axial_force=None)";
    const DOC: &'static str = r#"Single friction pendulum isolator, bidirectional (coupled) on two horizontal dofs
``dofs=(x, y)`` or uniaxial on one (``dofs=x``: a plane model): restoring force
``(weight / radius) u`` plus friction bounded by ``|f| <= mu weight`` (a circle in two
directions), with a pre-sliding (elastic) stiffness ``mu weight / yield_displacement`` and a
radial return mapping. The isolated period is ``2 pi sqrt(radius / g)``.

Velocity-dependent friction (OpenSees' ``VelDependent`` model): with `mu_slow` and
``rate > 0``, ``mu(s) = mu - (mu - mu_slow) exp(-rate s)`` at the sliding speed ``s`` (`mu`
is then the high-speed coefficient ``mu_fast``; the pre-sliding stiffness stays
``mu weight / yield_displacement``). Units: `yield_displacement` defaults to 2.5e-4 (m).

With a vertical dof (``dofs=(x, y, z)``, or ``(x, None, z)`` uniaxial; upward, to the
ground) and the bearing's axial stiffness `vertical_stiffness` ``k_v``, the normal force
comes from the model (OpenSees ``singleFPBearing``, 2-D and 3-D): the bearing carries
``P = -k_v u_z`` in compression and nothing in tension (uplift: zero shear, zero axial
force); the shear is ``V = (N / R) u + f`` with the normal force ``N = P + V . u / R``,
friction ``|f| <= mu N`` (a circle in two directions) and the pre-sliding stiffness
``k_i - N / R`` (``k_i = mu weight / yield_displacement``, `weight` the nominal load: it sets
only this stiffness). The weight itself is a load on the vertical dof (start from the static
state, e.g. ``x0`` with ``u_z = -W / k_v``). There the sliding speed of `mu_slow`/`rate` is
the speed on the surface, ``sqrt(|u'|^2 + (u . u' / R)^2)`` (as OpenSees), and friction may
also depend on the contact pressure ``N / A`` (OpenSees ``VelPressureDep``): with
`contact_area` ``A``, `delta_mu` and `pressure_alpha`, the high-speed coefficient is
``mu - delta_mu tanh(pressure_alpha N / A)``. A model whose ``x = 0`` is the loaded state
(an imported gravity state, :func:`duhamel.opensees.from_opensees`) gives the axial force
there as `initial_axial_force` ``P0``: the vertical displacement is then measured from where
the bearing carries ``P0`` and its vertical force on the model is the change from ``P0``
(the weight is no load of the model then).

Parameters
----------
dofs : int, dof label, or tuple of them
    ``x``, ``(x, y)``, ``(x, None, z)`` or ``(x, y, z)``: the bearing's horizontal dofs and
    its vertical dof (to the ground).
radius : float
    Radius of curvature, > 0.
mu : float
    Friction coefficient (the high-speed one with `mu_slow`), >= 0.
weight : float
    The vertical load (with a vertical dof: the nominal load), > 0.
yield_displacement : float, default 2.5e-4
    Displacement where sliding starts, > 0.
mu_slow, rate : float, optional
    Velocity-dependent friction: the coefficient at rest and the rate (s/m).
vertical_stiffness : float, optional
    Axial stiffness, with the vertical dof.
contact_area, delta_mu, pressure_alpha : float, optional
    Pressure-dependent friction, with the vertical dof.
initial_axial_force : float, optional
    The compressive axial force at ``x = 0``, with the vertical dof.

Examples
--------
>>> import duhamel
>>> fps = duhamel.elements.FrictionPendulum((0, 1), radius=2.0, mu=0.05, weight=5e6)
>>> fps.yield_displacement
0.00025
>>> plane = duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.06, mu_slow=0.03,
...                                           rate=20.0, weight=5e6)
>>> plane.dofs
(0,)
>>> spatial = duhamel.elements.FrictionPendulum((0, 1, 2), radius=2.0, mu=0.06,
...     mu_slow=0.03, rate=20.0, weight=5e6, vertical_stiffness=5e9)
"#;
    const LEGACY: &'static [&'static str] = &[
        "dof_x",
        "dof_y",
        "radius",
        "mu",
        "weight",
        "yield_displacement",
        "mu_slow",
        "rate",
        "dof_z",
        "vertical_stiffness",
        "contact_area",
        "delta_mu",
        "pressure_alpha",
    ];
    const LEGACY_DEFAULTS: &'static [(&'static str, &'static str)] =
        &[("radius", "1.0"), ("mu", "0.05"), ("weight", "1.0")];
    type Runtime = PendulumElement;

    fn build(&self) -> Result<PendulumElement, CoreError> {
        let (x, y, z) = self.axes()?;
        self.vertical_checks(z.is_some())?;
        let nominal = (self.weight, self.yield_displacement);
        if z.is_some() {
            let kv = self.vertical_stiffness.unwrap_or(f64::NAN);
            let velocity = match self.mu_slow {
                Some(slow) if self.rate > 0.0 => Some((slow, self.rate)),
                _ => None,
            };
            let pressure = self
                .contact_area
                .map(|a| (a, self.delta_mu, self.pressure_alpha));
            let e = AxialFrictionPendulum::on(&self.local(), self.radius, self.mu, nominal, kv)?;
            let e = match self.initial_axial_force {
                Some(p0) => e.with_axial_load(p0)?,
                None => e,
            };
            return Ok(PendulumElement::Axial(e.with_friction(velocity, pressure)?));
        }
        let e = match y {
            Some(y) => FrictionPendulum::new(x, y, self.radius, self.mu, nominal.0, nominal.1)?,
            None => FrictionPendulum::uniaxial(x, self.radius, self.mu, nominal.0, nominal.1)?,
        };
        check("rate", self.rate, false)?;
        Ok(PendulumElement::Flat(match self.mu_slow {
            Some(slow) => e.with_velocity(slow, self.rate)?,
            None => e,
        }))
    }

    fn rename(old: &str) -> Option<(&'static str, Option<usize>)> {
        rename_axes(old)
    }

    fn passive(&self) -> bool {
        true
    }

    fn linear_stiffness(&self) -> Option<Vec<f64>> {
        // the pendulum's gravity stiffness W / R in each direction (friction stays); with the
        // vertical dof, W / R and the axial stiffness
        let n = self.local().len();
        let kp = self.weight / self.radius;
        let vertical = self.dofs.get(2).copied().flatten().is_some();
        Some(
            (0..n * n)
                .map(|k| match (k % (n + 1) == 0, vertical && k == n * n - 1) {
                    (true, true) => self.vertical_stiffness.unwrap_or(0.0),
                    (true, false) => kp,
                    _ => 0.0,
                })
                .collect(),
        )
    }

    fn stored_energy(&self, u: &[f64], f: &[f64]) -> f64 {
        if self.dofs.get(2).copied().flatten().is_some() {
            // the axial spring's energy and the pendulum's N u^2 / (2 R) at the current axial
            // force (approximate: the coupled model has no separable potential)
            // the last local force is the vertical one (-P, or its change from P0)
            let axial = self.initial_axial_force.unwrap_or(0.0) - f[f.len() - 1];
            let kv = self.vertical_stiffness.unwrap_or(f64::INFINITY);
            return axial * axial / (2.0 * kv) + axial * (u[0] * u[0]) / (2.0 * self.radius);
        }
        let kr = self.weight / self.radius;
        let elastic: f64 = 0.5 * kr * u.iter().map(|u| u * u).sum::<f64>();
        let friction: f64 = u
            .iter()
            .zip(f)
            .map(|(u, f)| (f - kr * u) * (f - kr * u))
            .sum();
        let ki = self.mu * self.weight / self.yield_displacement;
        elastic
            + if self.mu > 0.0 {
                friction / (2.0 * ki)
            } else {
                0.0
            }
    }
}
