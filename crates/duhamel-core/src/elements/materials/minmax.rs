//! `MinMax`: a material that fails — force 0 from then on — once its deformation reaches
//! `min` or `max`, as OpenSees' `MinMax` wrapper. The trial at or beyond a limit has force
//! 0 and, as OpenSees, the tangent `1e-8` of the inner material's initial tangent (a
//! failed spring keeps a matrix regular); a commit there makes the failure permanent. Until
//! then the inner material answers.

use serde::{Deserialize, Serialize};

use super::uniaxial::{
    initial_deformation_doc, part_law, uniaxial_methods, Uniaxial, UniaxialDefinition,
};
use super::Material;
use crate::elements::definition::{Definition, Pair};
use crate::elements::registry::Defined;
use crate::error::CoreError;

/// `duhamel.elements.MinMax`: the definition of a [`MinMax`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MinMaxDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub material: Box<Defined>,
    #[serde(default = "lowest")]
    pub min: f64,
    #[serde(default = "highest")]
    pub max: f64,
    #[serde(default)]
    pub initial_deformation: f64,
}

fn lowest() -> f64 {
    -1.0e16
}
fn highest() -> f64 {
    1.0e16
}

impl UniaxialDefinition for MinMaxDef {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = MinMax;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<MinMax, CoreError> {
        let inner = part_law(&self.material, ("material", None), self.pair(), "MinMax")?;
        MinMax::new(inner, self.min, self.max)
    }
}

impl Definition for MinMaxDef {
    const NAME: &'static str = "MinMax";
    const SIGNATURE: &'static str =
        "(i, j=None, *, material, min=-1e16, max=1e16, initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"A uniaxial material that fails beyond a deformation, as OpenSees'
``uniaxialMaterial MinMax tag otherTag -min min -max max``: `material` answers until a trial
deformation ``u = x_i - x_j`` reaches `min` or `max`; there the force is 0 (and the tangent,
as OpenSees', ``1e-8`` of the material's initial tangent, which keeps a stiffness matrix
regular), and a step committed there makes the failure permanent. A hinge that loses its
strength for good, for collapse.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
material : Element
    The material: a uniaxial material element on the same ``i, j`` (``Steel02``,
    ``ModIMKPeakOriented``, ... or another wrapper).
min, max : float
    The deformations at which it fails, ``min < max``.
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import duhamel
>>> steel = duhamel.elements.Steel02(0, fy=1.0, E=100.0, b=0.02)
>>> fuse = duhamel.elements.MinMax(0, material=steel, max=0.03)
>>> duhamel.elements.drive(fuse, [0.0, 0.02, 0.03, 0.0]).force.tolist()[2:]
[0.0, 0.0]
"#
    );
    type Runtime = Uniaxial<MinMax>;
    uniaxial_methods!();
}

/// OpenSees' `uniaxialMaterial MinMax tag otherTag -min min -max max`.
#[derive(Debug)]
pub struct MinMax {
    inner: Box<dyn Material>,
    min: f64,
    max: f64,
}

/// OpenSees' tangent of a failed MinMax, relative to the inner initial tangent.
const FAILED_TANGENT: f64 = 1.0e-8;

impl MinMax {
    /// `inner` failing at `u <= min` or `u >= max` (OpenSees' defaults: `-1e16`, `1e16`).
    /// Errors name `min` or `max`.
    pub fn new(inner: Box<dyn Material>, min: f64, max: f64) -> Result<Self, CoreError> {
        if min.is_nan() || max.is_nan() || min >= max {
            let (name, value) = if min.is_nan() {
                ("min", min)
            } else {
                ("max", max)
            };
            return Err(CoreError::InvalidInput {
                name,
                problem: format!(
                    "must be a number with min < max, got min = {min}, max = {max} ({value})"
                ),
            });
        }
        Ok(Self { inner, min, max })
    }

    fn failed_tangent(&self) -> f64 {
        FAILED_TANGENT * self.inner.initial_tangent()
    }
}

impl Material for MinMax {
    /// Failed, the force is 0; else the inner law's.
    fn restarts_exactly(&self) -> bool {
        self.inner.restarts_exactly()
    }

    fn state_len(&self) -> usize {
        1 + self.inner.state_len()
    }

    fn initial_state(&self, s: &mut [f64]) {
        s[0] = 0.0;
        self.inner.initial_state(&mut s[1..]);
    }

    fn response(
        &self,
        u: f64,
        rate: f64,
        c: &[f64],
        t: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        if c[0] != 0.0 || u >= self.max || u <= self.min {
            // failed (committed, or in this trial): the inner material keeps its committed
            // state
            t.copy_from_slice(c);
            t[0] = 1.0;
            return Ok((0.0, self.failed_tangent()));
        }
        t[0] = 0.0;
        self.inner.response(u, rate, &c[1..], &mut t[1..])
    }

    fn initial_tangent(&self) -> f64 {
        self.inner.initial_tangent()
    }

    fn uses_rate(&self) -> bool {
        self.inner.uses_rate()
    }

    fn tangent_bound(&self) -> Option<f64> {
        self.inner
            .tangent_bound()
            .map(|b| b.max(self.failed_tangent().abs()))
    }

    fn passive(&self) -> bool {
        self.inner.passive()
    }

    /// A failed material stores nothing (its force is 0).
    fn stored_energy(&self, s: &[f64], u: f64, force: f64) -> f64 {
        if s[0] != 0.0 {
            0.0
        } else {
            self.inner.stored_energy(&s[1..], u, force)
        }
    }
}

#[cfg(test)]
#[path = "minmax_tests.rs"]
mod tests;
