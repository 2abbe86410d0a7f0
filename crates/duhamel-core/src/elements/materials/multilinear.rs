//! `MultiLinear`: OpenSees' multilinear kinematic-hardening law (symmetric backbone through
//! `(e_k, s_k)`, `k = 1..n`, and the mirror points), operation for operation.
//!
//! The law keeps, per segment `k`, its current negative and positive ends `(e-, s-)`,
//! `(e+, s+)`; segment 0 is the elastic range. Loading beyond the elastic range onto
//! segment `m` drags the ends of segments `0..m` with the point reached (the elastic range
//! and the inner segments keep their widths, `2 (e_k - e_(k-1))`, behind it) and shifts
//! the opposite ends of the outer ones (OpenSees' `commitState`, here done in `response`).
//! The tangent is the slope of the segment the deformation lies on.
//!
//! One deliberate difference: OpenSees repeats the update of the ends when a state is
//! committed twice at the same deformation (its trial keeps the last segment index when
//! the strain did not change), which moves the elastic range to the wrong side — after a
//! positive yield, the next unloading is then on the negative yield branch. Here a
//! deformation equal to the committed one to round-off (`f64::EPSILON` relative) keeps the
//! committed state, as a single commit does (docs/materials.md).

use serde::{Deserialize, Serialize};

use super::points::check_points;
use super::uniaxial::{initial_deformation_doc, uniaxial_methods, Uniaxial, UniaxialDefinition};
use super::Material;
use crate::elements::definition::{Definition, Pair};
use crate::error::CoreError;

/// `duhamel.elements.MultiLinear`: the definition of a [`MultiLinear`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MultiLinearDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub strain: Vec<f64>,
    pub stress: Vec<f64>,
    #[serde(default)]
    pub initial_deformation: f64,
}

impl UniaxialDefinition for MultiLinearDef {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = MultiLinear;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<MultiLinear, CoreError> {
        MultiLinear::new(&self.strain, &self.stress)
    }
}

impl Definition for MultiLinearDef {
    const NAME: &'static str = "MultiLinear";
    const SIGNATURE: &'static str = "(i, j=None, *, strain, stress, initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"Multilinear kinematic hardening on the deformation ``u = x_i - x_j`` (``j=None``: to
the ground), as OpenSees' ``uniaxialMaterial MultiLinear tag e1 s1 e2 s2 ...``: a symmetric
backbone through the points ``(strain[k], stress[k])`` and their mirror images (extended past
the last point with the last slope); loading past the elastic range drags the inner segments
with it (Masing's rule: after a reversal the branch is the backbone scaled by 2). The
tangent is the slope of the segment reached. One deliberate difference from OpenSees (a
deformation committed twice, docs/materials.md). Linear part: the first slope.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
strain, stress : sequence of float
    At least two points, strains positive and increasing, stresses positive.
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import duhamel
>>> link = duhamel.elements.MultiLinear(0, strain=[0.01, 0.05], stress=[1.0, 1.4])
>>> duhamel.elements.drive(link, [0.03, 0.0]).force.round(12).tolist()  # 1.2 - 2 B(0.015)
[1.2, -0.9]
"#
    );
    type Runtime = Uniaxial<MultiLinear>;
    uniaxial_methods!();
}

/// OpenSees' `uniaxialMaterial MultiLinear tag e1 s1 e2 s2 ...`.
#[derive(Debug, Clone)]
pub struct MultiLinear {
    /// Per segment: its slope and its half width `e_k - e_(k-1)` (OpenSees' `data(k, 4..6)`).
    slope: Vec<f64>,
    dist: Vec<f64>,
    strain: Vec<f64>,
    stress: Vec<f64>,
}

// state: committed strain, stress, tangent, then per segment (neg strain, pos strain,
// neg stress, pos stress)
const HEAD: usize = 3;
const NEG_E: usize = 0;
const POS_E: usize = 1;
const NEG_S: usize = 2;
const POS_S: usize = 3;

impl MultiLinear {
    /// The backbone through the points `(strain[k], stress[k])`: at least two, strains
    /// positive and increasing, stresses positive. Errors name `strain` or `stress`.
    pub fn new(strain: &[f64], stress: &[f64]) -> Result<Self, CoreError> {
        check_points(("strain", "stress"), strain, stress, 2, true)?;
        let n = strain.len();
        let mut slope = vec![stress[0] / strain[0]];
        let mut dist = vec![strain[0]];
        for k in 1..n {
            slope.push((stress[k] - stress[k - 1]) / (strain[k] - strain[k - 1]));
            dist.push(strain[k] - strain[k - 1]);
        }
        Ok(Self {
            slope,
            dist,
            strain: strain.to_vec(),
            stress: stress.to_vec(),
        })
    }

    fn n(&self) -> usize {
        self.slope.len()
    }
}

/// The segment `k`'s entry `col` in the state `d` (after the three head entries).
#[inline]
fn at(k: usize, col: usize) -> usize {
    HEAD + 4 * k + col
}

impl Material for MultiLinear {
    /// A zero increment leaves the committed variables and force as they are (checked in
    /// `restart_tests.rs`).
    fn restarts_exactly(&self) -> bool {
        true
    }

    fn state_len(&self) -> usize {
        HEAD + 4 * self.n()
    }

    fn initial_state(&self, s: &mut [f64]) {
        s[0] = 0.0;
        s[1] = 0.0;
        s[2] = self.slope[0];
        for k in 0..self.n() {
            s[at(k, NEG_E)] = -self.strain[k];
            s[at(k, POS_E)] = self.strain[k];
            s[at(k, NEG_S)] = -self.stress[k];
            s[at(k, POS_S)] = self.stress[k];
        }
    }

    fn response(
        &self,
        u: f64,
        _rate: f64,
        c: &[f64],
        t: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        t.copy_from_slice(c);
        // the same deformation to round-off (relative: a frame starts from rest with
        // deformations far below f64::EPSILON, which an absolute test would freeze)
        if (c[0] - u).abs() <= f64::EPSILON * c[0].abs().max(u.abs()) {
            return Ok((c[1], c[2]));
        }
        let n = self.n();
        let d = |k: usize, col: usize| c[at(k, col)];
        let (slope, stress);
        let mut seg = 0;
        if u >= d(0, NEG_E) && u <= d(0, POS_E) {
            // from the elastic range's centre (the origin before any yield): the force's
            // round-off scales with the force near rest, not with the yield force
            let centre_e = 0.5 * (d(0, NEG_E) + d(0, POS_E));
            let centre_s = 0.5 * (d(0, NEG_S) + d(0, POS_S));
            stress = centre_s + (u - centre_e) * self.slope[0];
            slope = self.slope[0];
        } else if u < d(0, NEG_E) {
            seg = 1;
            while seg < n && u < d(seg, NEG_E) {
                seg += 1;
            }
            if seg == n {
                seg = n - 1;
            }
            stress = d(seg, NEG_S) + (u - d(seg, NEG_E)) * self.slope[seg];
            slope = self.slope[seg];
        } else {
            seg = 1;
            while seg < n && u > d(seg, POS_E) {
                seg += 1;
            }
            if seg == n {
                seg = n - 1;
            }
            stress = d(seg, POS_S) + (u - d(seg, POS_E)) * self.slope[seg];
            slope = self.slope[seg];
        }
        t[0] = u;
        t[1] = stress;
        t[2] = slope;
        if seg != 0 {
            self.drag(t, seg, u, stress);
        }
        Ok((stress, slope))
    }

    fn initial_tangent(&self) -> f64 {
        self.slope[0]
    }

    fn tangent_bound(&self) -> Option<f64> {
        Some(self.slope.iter().fold(0.0_f64, |m, s| m.max(s.abs())))
    }

    fn passive(&self) -> bool {
        self.slope.iter().all(|&s| s >= 0.0)
    }
}

impl MultiLinear {
    /// OpenSees' `commitState` after yielding onto segment `seg` at `(u, stress)`: moves the
    /// ends in `t` (which holds the committed ones).
    fn drag(&self, t: &mut [f64], seg: usize, u: f64, stress: f64) {
        let n = self.n();
        let (k, dist) = (&self.slope, &self.dist);
        let i = |k: usize, col: usize| at(k, col);
        if u > t[i(0, POS_E)] {
            t[i(0, POS_E)] = u;
            t[i(0, POS_S)] = stress;
            t[i(0, NEG_E)] = u - 2.0 * dist[0];
            t[i(0, NEG_S)] = stress - 2.0 * dist[0] * k[0];
            for j in 1..seg {
                t[i(j, POS_E)] = u;
                t[i(j, POS_S)] = stress;
                t[i(j, NEG_E)] = t[i(j - 1, NEG_E)] - 2.0 * dist[j];
                t[i(j, NEG_S)] = t[i(j - 1, NEG_S)] - 2.0 * dist[j] * k[j];
            }
            for j in seg..n {
                t[i(j, NEG_E)] =
                    t[i(j - 1, NEG_E)] - 2.0 * dist[j] + t[i(j, POS_E)] - t[i(j - 1, POS_E)];
                t[i(j, NEG_S)] = t[i(j - 1, NEG_S)] + (t[i(j, NEG_E)] - t[i(j - 1, NEG_E)]) * k[j];
            }
        } else {
            t[i(0, NEG_E)] = u;
            t[i(0, NEG_S)] = stress;
            t[i(0, POS_E)] = u + 2.0 * dist[0];
            t[i(0, POS_S)] = stress + 2.0 * dist[0] * k[0];
            for j in 1..seg {
                t[i(j, NEG_E)] = u;
                t[i(j, NEG_S)] = stress;
                t[i(j, POS_E)] = t[i(j - 1, POS_E)] + 2.0 * dist[j];
                t[i(j, POS_S)] = t[i(j - 1, POS_S)] + 2.0 * dist[j] * k[j];
            }
            for j in seg..n {
                t[i(j, POS_E)] =
                    t[i(j - 1, POS_E)] + 2.0 * dist[j] + t[i(j, NEG_E)] - t[i(j - 1, NEG_E)];
                t[i(j, POS_S)] = t[i(j - 1, POS_S)] + (t[i(j, POS_E)] - t[i(j - 1, POS_E)]) * k[j];
            }
        }
    }
}

#[cfg(test)]
#[path = "multilinear_tests.rs"]
mod tests;
