//! `Parallel`: materials side by side on the same deformation, the force the sum of theirs
//! (times optional factors), as OpenSees' `Parallel` material.

use serde::{Deserialize, Serialize};

use super::uniaxial::{
    initial_deformation_doc, part_law, uniaxial_methods, Uniaxial, UniaxialDefinition,
};
use super::Material;
use crate::elements::definition::{Definition, Pair};
use crate::elements::registry::Defined;
use crate::error::CoreError;

/// `duhamel.elements.Parallel`: the definition of a [`Parallel`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub materials: Vec<Defined>,
    #[serde(default)]
    pub factors: Option<Vec<f64>>,
    #[serde(default)]
    pub initial_deformation: f64,
}

impl UniaxialDefinition for ParallelDef {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = Parallel;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<Parallel, CoreError> {
        let parts = self
            .materials
            .iter()
            .enumerate()
            .map(|(k, m)| part_law(m, ("materials", Some(k)), self.pair(), "Parallel"))
            .collect::<Result<Vec<_>, _>>()?;
        Parallel::new(parts, self.factors.clone())
    }
}

impl Definition for ParallelDef {
    const NAME: &'static str = "Parallel";
    const SIGNATURE: &'static str =
        "(i, j=None, *, materials, factors=None, initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"Uniaxial materials side by side on the same deformation ``u = x_i - x_j``, as
OpenSees' ``uniaxialMaterial Parallel tag tag1 tag2 ... <-factors f1 f2 ...>``: the force
and tangent are the (weighted) sums of the parts'. Passive when every part is and every
factor is non-negative.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
materials : sequence of Element
    The parts (at least one): uniaxial material elements on the same ``i, j``.
factors : sequence of float, optional
    One factor per part (default: all 1).
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import duhamel
>>> E = duhamel.elements
>>> frame = E.ElasticMultiLinear(0, strain=[-1.0, 1.0], stress=[-50.0, 50.0])
>>> brace = E.MultiLinear(0, strain=[0.01, 0.05], stress=[1.0, 1.4])
>>> both = E.Parallel(0, materials=[frame, brace])
>>> E.drive(both, [0.005, 0.03]).force.round(12).tolist()
[0.75, 2.7]
"#
    );
    type Runtime = Uniaxial<Parallel>;
    uniaxial_methods!();
}

/// OpenSees' `uniaxialMaterial Parallel tag tag1 tag2 ... <-factors f1 f2 ...>`.
#[derive(Debug)]
pub struct Parallel {
    parts: Vec<Box<dyn Material>>,
    factors: Option<Vec<f64>>,
    /// Where each part's variables start in the state (and the end).
    offsets: Vec<usize>,
}

impl Parallel {
    /// `parts` (at least one) with `factors` (one finite number per part; None: all 1).
    /// Errors name `materials` or `factors`.
    pub fn new(
        parts: Vec<Box<dyn Material>>,
        factors: Option<Vec<f64>>,
    ) -> Result<Self, CoreError> {
        if parts.is_empty() {
            return Err(CoreError::InvalidInput {
                name: "materials",
                problem: "must hold at least one material".into(),
            });
        }
        if let Some(f) = &factors {
            if f.len() != parts.len() {
                return Err(CoreError::LengthMismatch {
                    name: "factors",
                    got: f.len(),
                    expected: parts.len(),
                });
            }
            if let Some(v) = f.iter().find(|v| !v.is_finite()) {
                return Err(CoreError::InvalidInput {
                    name: "factors",
                    problem: format!("must be finite, got {v}"),
                });
            }
        }
        let offsets = offsets(&parts);
        Ok(Self {
            parts,
            factors,
            offsets,
        })
    }

    fn factor(&self, i: usize) -> f64 {
        self.factors.as_ref().map_or(1.0, |f| f[i])
    }

    fn range(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i]..self.offsets[i + 1]
    }
}

/// The start of each part's variables in a composite's state, after `head` of its own,
/// and the end.
pub(crate) fn offsets_after(head: usize, parts: &[Box<dyn Material>]) -> Vec<usize> {
    let mut out = vec![head];
    for p in parts {
        out.push(out[out.len() - 1] + p.state_len());
    }
    out
}

fn offsets(parts: &[Box<dyn Material>]) -> Vec<usize> {
    offsets_after(0, parts)
}

impl Material for Parallel {
    /// The same sums of the parts' forces.
    fn restarts_exactly(&self) -> bool {
        self.parts.iter().all(|p| p.restarts_exactly())
    }

    fn state_len(&self) -> usize {
        self.offsets[self.parts.len()]
    }

    fn initial_state(&self, s: &mut [f64]) {
        for (i, p) in self.parts.iter().enumerate() {
            p.initial_state(&mut s[self.range(i)]);
        }
    }

    fn response(
        &self,
        u: f64,
        rate: f64,
        c: &[f64],
        t: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        let (mut f, mut k) = (0.0, 0.0);
        for (i, p) in self.parts.iter().enumerate() {
            let r = self.range(i);
            let (fi, ki) = p.response(u, rate, &c[r.clone()], &mut t[r])?;
            match &self.factors {
                None => {
                    f += fi;
                    k += ki;
                }
                Some(w) => {
                    f += w[i] * fi;
                    k += w[i] * ki;
                }
            }
        }
        Ok((f, k))
    }

    fn initial_tangent(&self) -> f64 {
        (0..self.parts.len())
            .map(|i| self.factor(i) * self.parts[i].initial_tangent())
            .sum()
    }

    fn uses_rate(&self) -> bool {
        self.parts.iter().any(|p| p.uses_rate())
    }

    fn tangent_bound(&self) -> Option<f64> {
        let mut sum = 0.0;
        for (i, p) in self.parts.iter().enumerate() {
            sum += self.factor(i).abs() * p.tangent_bound()?;
        }
        Some(sum)
    }

    fn passive(&self) -> bool {
        (0..self.parts.len()).all(|i| self.factor(i) >= 0.0 && self.parts[i].passive())
    }

    /// The parts' stored energies, each at its own force (re-evaluated at `u` from its
    /// committed variables).
    fn stored_energy(&self, s: &[f64], u: f64, _force: f64) -> f64 {
        let mut scratch = vec![0.0; s.len()];
        let mut total = 0.0;
        for (i, p) in self.parts.iter().enumerate() {
            let r = self.range(i);
            let fi = match p.response(u, 0.0, &s[r.clone()], &mut scratch[r.clone()]) {
                Ok((fi, _)) => fi,
                Err(_) => return f64::NAN,
            };
            total += self.factor(i) * p.stored_energy(&s[r], u, fi);
        }
        total
    }
}

#[cfg(test)]
#[path = "parallel_tests.rs"]
mod tests;
