//! `ElasticMultiLinear`: a nonlinear elastic law, piecewise linear through given
//! `(strain, stress)` points (both sides of the origin, extended beyond the end points with
//! the end slopes), as OpenSees' `ElasticMultiLinear` without its viscous term `eta`.
//! Loading and unloading follow the same curve: no internal variables, no dissipation.

use serde::{Deserialize, Serialize};

use super::points::check_points;
use super::uniaxial::{initial_deformation_doc, uniaxial_methods, Uniaxial, UniaxialDefinition};
use super::Material;
use crate::elements::definition::{Definition, Pair};
use crate::error::CoreError;

/// `duhamel.elements.ElasticMultiLinear`: the definition of an [`ElasticMultiLinear`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElasticMultiLinearDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub strain: Vec<f64>,
    pub stress: Vec<f64>,
    #[serde(default)]
    pub initial_deformation: f64,
}

impl UniaxialDefinition for ElasticMultiLinearDef {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = ElasticMultiLinear;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<ElasticMultiLinear, CoreError> {
        ElasticMultiLinear::new(&self.strain, &self.stress)
    }
}

impl Definition for ElasticMultiLinearDef {
    const NAME: &'static str = "ElasticMultiLinear";
    const SIGNATURE: &'static str = "(i, j=None, *, strain, stress, initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"Nonlinear elastic spring on the deformation ``u = x_i - x_j`` (``j=None``: to the
ground), piecewise linear through the points ``(strain[k], stress[k])`` (both sides of the
origin, extended past the end points with the end slopes), as OpenSees' ``uniaxialMaterial
ElasticMultiLinear tag -strain ... -stress ...`` without its viscous term ``eta``. Loading and
unloading follow the same curve: no internal variables, no dissipation; the stored energy is
the potential ``int_0^u F``. Linear part: the slope at ``u = 0`` (when positive).

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
strain, stress : sequence of float
    At least two points, strains strictly increasing.
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import duhamel
>>> gap = duhamel.elements.ElasticMultiLinear(0, strain=[-1.0, 0.0, 0.01, 1.0],
...                                           stress=[0.0, 0.0, 0.0, 99.0])
>>> duhamel.elements.drive(gap, [-0.5, 0.005, 0.11]).force.tolist()
[0.0, 0.0, 10.0]
"#
    );
    type Runtime = Uniaxial<ElasticMultiLinear>;
    uniaxial_methods!();
}

/// OpenSees' `uniaxialMaterial ElasticMultiLinear tag -strain ... -stress ...`.
#[derive(Debug, Clone)]
pub struct ElasticMultiLinear {
    strain: Vec<f64>,
    stress: Vec<f64>,
    /// `int_(strain[0])^(strain[k]) F`.
    work: Vec<f64>,
    /// `int_(strain[0])^0 F`.
    work0: f64,
    k0: f64,
}

impl ElasticMultiLinear {
    /// The curve through `(strain[k], stress[k])`: at least two points, strains strictly
    /// increasing. Errors name `strain` or `stress`.
    pub fn new(strain: &[f64], stress: &[f64]) -> Result<Self, CoreError> {
        check_points(("strain", "stress"), strain, stress, 2, false)?;
        let mut m = Self {
            strain: strain.to_vec(),
            stress: stress.to_vec(),
            work: vec![0.0; strain.len()],
            work0: 0.0,
            k0: 0.0,
        };
        m.k0 = m.eval(0.0).1;
        for k in 1..strain.len() {
            m.work[k] =
                m.work[k - 1] + 0.5 * (stress[k] + stress[k - 1]) * (strain[k] - strain[k - 1]);
        }
        m.work0 = m.integral_from_first(0.0);
        Ok(m)
    }

    /// The interval `[strain[i], strain[i + 1]]` holding `u` (the first or last beyond
    /// the end points), as OpenSees' search when the strain increases.
    fn interval(&self, u: f64) -> usize {
        let n = self.strain.len();
        self.strain[1..n - 1]
            .iter()
            .position(|&e| u < e)
            .unwrap_or(n - 2)
    }

    /// `(F(u), F'(u))`.
    fn eval(&self, u: f64) -> (f64, f64) {
        let i = self.interval(u);
        let (e1, e2) = (self.strain[i], self.strain[i + 1]);
        let (s1, s2) = (self.stress[i], self.stress[i + 1]);
        let k = (s2 - s1) / (e2 - e1);
        // from the nearer point: the force's round-off then scales with the force near a
        // point of zero force (not with the neighbouring point's), down to deformations far
        // below f64::EPSILON (a frame starting from rest)
        let (e, s) = if (u - e1).abs() <= (e2 - u).abs() {
            (e1, s1)
        } else {
            (e2, s2)
        };
        let mut f = s + k * (u - e);
        if f.abs() < 2.0 * f64::EPSILON * s.abs() {
            f = 0.0; // round-off of a zero crossing inside a segment
        }
        (f, k)
    }

    /// `int_(strain[0])^u F` (the trapezoid is exact on a linear piece).
    fn integral_from_first(&self, u: f64) -> f64 {
        let i = self.interval(u);
        let (e1, s1) = (self.strain[i], self.stress[i]);
        let k = (self.stress[i + 1] - s1) / (self.strain[i + 1] - e1);
        self.work[i] + (s1 + 0.5 * k * (u - e1)) * (u - e1)
    }

    /// The potential `W(u) = int_0^u F`.
    fn potential(&self, u: f64) -> f64 {
        self.integral_from_first(u) - self.work0
    }
}

impl Material for ElasticMultiLinear {
    /// A zero increment leaves the committed variables and force as they are (checked in
    /// `restart_tests.rs`).
    fn restarts_exactly(&self) -> bool {
        true
    }

    fn state_len(&self) -> usize {
        0
    }

    fn initial_state(&self, _state: &mut [f64]) {}

    fn response(
        &self,
        u: f64,
        _rate: f64,
        _committed: &[f64],
        _trial: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        Ok(self.eval(u))
    }

    fn initial_tangent(&self) -> f64 {
        self.k0
    }

    fn tangent_bound(&self) -> Option<f64> {
        Some(
            self.strain
                .windows(2)
                .zip(self.stress.windows(2))
                .map(|(e, s)| ((s[1] - s[0]) / (e[1] - e[0])).abs())
                .fold(0.0, f64::max),
        )
    }

    /// `F(u) u >= 0` everywhere: the potential is bounded below by its value 0 at rest.
    fn passive(&self) -> bool {
        let n = self.strain.len();
        let end_slopes = [
            self.eval(self.strain[0] - 1.0).1,
            self.eval(self.strain[n - 1] + 1.0).1,
        ];
        self.eval(0.0).0 == 0.0
            && end_slopes.iter().all(|&k| k >= 0.0)
            && self
                .strain
                .iter()
                .zip(&self.stress)
                .all(|(&e, &s)| e * s >= 0.0)
    }

    /// The potential `int_0^u F` (path-independent).
    fn stored_energy(&self, _state: &[f64], u: f64, _force: f64) -> f64 {
        self.potential(u)
    }
}

#[cfg(test)]
#[path = "elastic_multilinear_tests.rs"]
mod tests;
