//! The triple friction pendulum as a model defines it (its engine element is
//! [`TripleFrictionPendulum`]).

use serde::{Deserialize, Serialize};

use super::rubber::{horizontal, rename_axes};
use super::triple::TripleFrictionPendulum;
use crate::elements::definition::Definition;
use crate::error::CoreError;

/// `duhamel.elements.TripleFrictionPendulum`: the definition of a [`TripleFrictionPendulum`].
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TripleFrictionPendulumDef {
    pub dofs: Vec<Option<usize>>,
    pub mu: [f64; 3],
    pub radius: [f64; 3],
    pub displacement_capacity: [f64; 3],
    pub weight: f64,
    #[serde(default = "default_yield")]
    pub yield_displacement: f64,
    #[serde(default)]
    pub vertical_stiffness: Option<f64>,
    #[serde(default)]
    pub min_axial_force: f64,
    #[serde(default)]
    pub initial_axial_force: Option<f64>,
}

fn default_yield() -> f64 {
    super::friction::DEFAULT_YIELD_DISPLACEMENT
}

impl TripleFrictionPendulumDef {
    /// The horizontal dofs, the vertical one and the rotations (`dofs=(x, y, z)`,
    /// `(x, None, z)`, or with the rotations `(x, y, z, rx, ry, rz)`).
    #[allow(clippy::type_complexity)]
    fn split(&self) -> Result<(&[Option<usize>], Option<usize>, [Option<usize>; 3]), CoreError> {
        let d = &self.dofs;
        let get = |k: usize| d.get(k).copied().flatten();
        match d.len() {
            0..=2 => Ok((d, None, [None; 3])),
            3..=6 => Ok((&d[..2], get(2), [get(3), get(4), get(5)])),
            _ => Err(CoreError::InvalidInput {
                name: "dofs",
                problem: format!(
                    "must be x, (x, y), (x, y, z) or (x, y, z, rx, ry, rz) (None where a dof is \
                     absent), got {} entries",
                    d.len()
                ),
            }),
        }
    }
}

impl TripleFrictionPendulumDef {
    /// The number of horizontal dofs and whether the vertical dof is present.
    fn layout(&self) -> (usize, bool) {
        match self.split() {
            Ok((plane, z, _)) => (plane.iter().flatten().count(), z.is_some()),
            Err(_) => (self.dofs.iter().flatten().count(), false),
        }
    }
}

impl Definition for TripleFrictionPendulumDef {
    const NAME: &'static str = "TripleFrictionPendulum";
    const SIGNATURE: &'static str =
        "(dofs, *, mu, radius, displacement_capacity, weight, yield_displacement=0.00025, \
        vertical_stiffness=None, min_axial_force=0.0, initial_axial_force=None)";
    const DOC: &'static str = r#"Triple friction pendulum isolator, bidirectional (coupled) on two horizontal dofs
``dofs=(x, y)`` or uniaxial on one (``dofs=x``: a plane model), to the ground, under a
constant vertical load `weight` ``W``.

The series model of OpenSees' ``TripleFrictionPendulum`` element (Dao, Ryan, Sato & Sasaki
2013, after Fenz & Constantinou 2008): `mu` ``= (mu1, mu2, mu3)`` the friction coefficients
of the two inner surfaces (equal) and of the two outer ones, ordered
``mu1 <= mu2 <= mu3``; `radius` ``= (L1, L2, L3)`` their effective radii (radius of
curvature minus the height of the pivot, ``L1 < L2, L3``); `displacement_capacity`
``= (d1, d2, d3)`` the actual displacement capacity of each surface (OpenSees' ``d1, d2,
d3``; the bearing's is ``2 d1 + d2 + d3 + L1 d3 / L3 - L1 d2 / L2``). Sliding starts at
``mu1 W`` after the elastic displacement `yield_displacement` (OpenSees' ``uy``; 2.5e-4, in
metres, by default). Under increasing displacement the force passes Fenz & Constantinou's
five regimes: stiffness ``W / (2 L1)`` from ``mu1 W``, ``W / (L1 + L2)`` from ``mu2 W``,
``W / (L2 + L3)`` from ``mu3 W``, ``W / (L1 + L3)`` from ``W (mu2 + d2 / L2)`` (surface 2 on
its stop) and ``W / (2 L1)`` from ``W (mu3 + d3 / L3)`` (surface 3 on its stop), then the
stiff stop of the inner slider. Constant (Coulomb) friction (docs/structural.md).

With a vertical dof (``dofs=(x, y, z)``, or ``(x, None, z)`` uniaxial; ``z`` up, to the
ground) and the axial stiffness `vertical_stiffness` ``k_v``, the vertical load is the
bearing's axial force, as in OpenSees' element: the compression ``N = -k_v u_z``, and in
tension (uplift) OpenSees' ``MinFv``, `min_axial_force` (0 by default); the shear is ``N``
times the normalised force above (which changes with the overturning and vertical
motion), the vertical force on the dof ``-N``, the tangent the exact one (coupled through
``N``). `weight` is then the nominal load (it sets only the linear stiffness taken out by
``Semianalytic(linear_parts="background")``); the weight itself is a load on the vertical
dof (start from the static state, ``u_z = -W / k_v``). A model whose ``x = 0`` is the loaded
state (an imported gravity state, :func:`duhamel.opensees.from_opensees`) gives the axial
force there as `initial_axial_force` ``P0``: ``u_z`` is measured from where the bearing
carries ``P0`` and its vertical force on the model is the change ``P0 - N``. OpenSees'
P-Delta moments of the element on its top node's rotations (``N u_y / 2``, ``-N u_x / 2``,
``N (f_x u_y - f_y u_x) / 2`` with ``N f`` the shear) act on the rotations given after the
vertical dof, ``dofs=(x, y, z, rx, ry, rz)`` (None where absent).

Parameters
----------
dofs : int, dof label, or tuple of them
    ``x``, ``(x, y)``, ``(x, None, z)`` or ``(x, y, z)``: the bearing top's horizontal dofs
    and its vertical dof (to the ground); then optionally its rotations ``rx, ry, rz``.
mu, radius, displacement_capacity : three floats
    ``(mu1, mu2, mu3)``, ``(L1, L2, L3)``, ``(d1, d2, d3)``.
weight : float
    The vertical load, > 0.
yield_displacement : float, default 2.5e-4
    Displacement where sliding starts, > 0.
vertical_stiffness : float, optional
    Axial stiffness ``k_v`` > 0, with (and required by) the vertical dof.
min_axial_force : float, default 0
    The normal force in uplift (OpenSees' ``MinFv``), >= 0, with the vertical dof.
initial_axial_force : float, optional
    The compressive axial force at ``x = 0``, > 0, with the vertical dof.

Examples
--------
>>> import numpy as np, duhamel
>>> tfp = duhamel.elements.TripleFrictionPendulum(
...     0, mu=(0.02, 0.06, 0.10), radius=(0.3, 2.0, 2.0),
...     displacement_capacity=(0.05, 0.3, 0.3), weight=1e6)
>>> s = duhamel.System(1e6 / 9.81 * np.eye(1), np.zeros((1, 1))).add(tfp)
>>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=2.0, dt=0.01, v0=[0.5])
>>> bool(abs(sol.elements[0].force).max() > 0.02e6)
True
>>> spatial = duhamel.elements.TripleFrictionPendulum(
...     (0, 1, 2), mu=(0.02, 0.06, 0.10), radius=(0.3, 2.0, 2.0),
...     displacement_capacity=(0.05, 0.3, 0.3), weight=1e6, vertical_stiffness=1e9)
>>> spatial.dofs
(0, 1, 2)
"#;
    const LEGACY: &'static [&'static str] = &["dof_x", "dof_y"];
    const LEGACY_DEFAULTS: &'static [(&'static str, &'static str)] = &[
        ("mu", "[0.02, 0.06, 0.1]"),
        ("radius", "[0.3, 2.0, 2.0]"),
        ("displacement_capacity", "[0.05, 0.3, 0.3]"),
        ("weight", "1.0"),
    ];
    type Runtime = TripleFrictionPendulum;

    fn build(&self) -> Result<TripleFrictionPendulum, CoreError> {
        let (d, w, uy) = (
            self.displacement_capacity,
            self.weight,
            self.yield_displacement,
        );
        let (plane, z, rotations) = self.split()?;
        let e = match horizontal(plane)? {
            (x, Some(y)) => TripleFrictionPendulum::new(x, y, self.mu, self.radius, d, w, uy),
            (x, None) => TripleFrictionPendulum::uniaxial(x, self.mu, self.radius, d, w, uy),
        }?;
        let bad = |name: &'static str| CoreError::InvalidInput {
            name,
            problem: "needs the vertical dof: dofs=(x, y, z) or (x, None, z)".into(),
        };
        match (z, self.vertical_stiffness) {
            (Some(z), Some(kv)) => {
                e.with_vertical(z, kv, self.min_axial_force, self.initial_axial_force)
            }
            (Some(_), None) => Err(CoreError::InvalidInput {
                name: "vertical_stiffness",
                problem: "is required with the vertical dof (dofs=(x, y, z) or (x, None, z))"
                    .into(),
            }),
            (None, Some(_)) => Err(bad("vertical_stiffness")),
            (None, None) if self.initial_axial_force.is_some() => Err(bad("initial_axial_force")),
            (None, None) if self.min_axial_force != 0.0 => Err(bad("min_axial_force")),
            (None, None) => Ok(e),
        }?
        .with_rotations(rotations)
    }

    fn rename(old: &str) -> Option<(&'static str, Option<usize>)> {
        rename_axes(old)
    }

    fn passive(&self) -> bool {
        // the P-Delta moments on the rotations are not a potential's
        self.dofs.len() <= 3
    }

    fn linear_stiffness(&self) -> Option<Vec<f64>> {
        // the softest sliding stiffness W / (L2 + L3) (regime III) in each direction: the
        // remainder's tangent stays positive semidefinite in every regime
        // (with the vertical dof: the nominal weight's, and the axial stiffness)
        let n = self.dofs.iter().flatten().count();
        let (m, z) = self.layout();
        let k = self.weight / (self.radius[1] + self.radius[2]);
        let mut out = vec![0.0; n * n];
        for i in 0..m {
            out[i * (n + 1)] = k;
        }
        if let (true, Some(kv)) = (z, self.vertical_stiffness) {
            out[m * (n + 1)] = kv;
        }
        Some(out)
    }

    fn stored_energy(&self, _u: &[f64], f: &[f64]) -> f64 {
        // the vertical spring's (the sliding surfaces store none of their own here): the
        // work of its force on the model, from x = 0
        match (self.layout(), self.vertical_stiffness) {
            ((m, true), Some(kv)) => f[m] * f[m] / (2.0 * kv),
            _ => 0.0,
        }
    }
}
