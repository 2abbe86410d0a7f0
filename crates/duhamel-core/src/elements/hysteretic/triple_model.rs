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
}

fn default_yield() -> f64 {
    super::friction::DEFAULT_YIELD_DISPLACEMENT
}

impl Definition for TripleFrictionPendulumDef {
    const NAME: &'static str = "TripleFrictionPendulum";
    const SIGNATURE: &'static str =
        "(dofs, *, mu, radius, displacement_capacity, weight, yield_displacement=0.00025)";
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
stiff stop of the inner slider. Constant (Coulomb) friction, no uplift, no change of ``W``
with the overturning (docs/structural.md).

Parameters
----------
dofs : int, dof label or pair of them
    The horizontal dofs ``(x, y)`` of the bearing's top (to the ground), or one dof.
mu, radius, displacement_capacity : three floats
    ``(mu1, mu2, mu3)``, ``(L1, L2, L3)``, ``(d1, d2, d3)``.
weight : float
    The vertical load, > 0.
yield_displacement : float, default 2.5e-4
    Displacement where sliding starts, > 0.

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
        match horizontal(&self.dofs)? {
            (x, Some(y)) => TripleFrictionPendulum::new(x, y, self.mu, self.radius, d, w, uy),
            (x, None) => TripleFrictionPendulum::uniaxial(x, self.mu, self.radius, d, w, uy),
        }
    }

    fn rename(old: &str) -> Option<(&'static str, Option<usize>)> {
        rename_axes(old)
    }

    fn passive(&self) -> bool {
        true
    }

    fn linear_stiffness(&self) -> Option<Vec<f64>> {
        // the softest sliding stiffness W / (L2 + L3) (regime III) in each direction: the
        // remainder's tangent stays positive semidefinite in every regime
        let n = self.dofs.iter().flatten().count();
        let k = self.weight / (self.radius[1] + self.radius[2]);
        Some(
            (0..n * n)
                .map(|i| if i % (n + 1) == 0 { k } else { 0.0 })
                .collect(),
        )
    }
}
