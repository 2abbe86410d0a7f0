//! Compression-only gap (pounding) element.
//!
//! With the deformation `u = x_i - x_j` (`x_i` when grounded), initial opening `gap >= 0`
//! and contact stiffness `k`, the element force (`r_i = +F`, `r_j = -F`) is
//!
//! ```text
//! F = k (u + gap)   when u < -gap   (closed),      F = 0   otherwise (open).
//! ```
//!
//! Sign convention: node `i` lies on the positive side of node `j` (or of a stop at
//! `-gap` when grounded); the gap closes when `i` moves towards `j` by `gap`, and the contact
//! then pushes them apart (`F < 0` on `i`, i.e. towards `+x`, and `-F > 0` on `j`). For the
//! opposite arrangement swap `i` and `j`. This matches OpenSees' compression gap
//! (`ElasticPPGap` / `ENT` with a negative gap).
//!
//! Stateless, path-independent; the force has a kink at contact: the tangent is `k` when
//! closed and 0 when open (at exactly `u = -gap`: 0). No impact damping.

use serde::{Deserialize, Serialize};

use super::common::{check, finite, local_dofs, relative, scatter};
use crate::elements::definition::{along, Definition, Pair};
use crate::elements::element::{Element, Tangent};
use crate::error::CoreError;

/// `duhamel.elements.Gap`: the definition of a [`Gap`].
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GapDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub gap: f64,
    pub k: f64,
}

impl Definition for GapDef {
    const NAME: &'static str = "Gap";
    const SIGNATURE: &'static str = "(i, j=None, *, gap, k)";
    const DOC: &'static str = r#"Compression-only contact (pounding, a stop): ``F = k (u + gap)`` once the deformation
``u = x_i - x_j`` closes the opening, ``u < -gap``, else 0 (node `i` on the positive side of
`j`, or of a fixed stop at ``-gap`` when ``j=None``).

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: a fixed stop).
gap : float
    Initial opening, >= 0.
k : float
    Contact stiffness, > 0.

Examples
--------
>>> import duhamel
>>> moat = duhamel.elements.Gap(0, None, gap=0.3, k=1e9)
"#;
    const LEGACY: &'static [&'static str] = &["i", "j", "gap", "k"];
    const LEGACY_DEFAULTS: &'static [(&'static str, &'static str)] =
        &[("gap", "0.0"), ("k", "1.0")];
    type Runtime = Gap;

    fn build(&self) -> Result<Gap, CoreError> {
        Gap::new(self.i, self.j, self.gap, self.k)
    }

    fn directions(&self) -> Option<Vec<Pair>> {
        along(self.i, self.j)
    }

    fn passive(&self) -> bool {
        true
    }

    fn tangent_bound(&self) -> Option<(f64, f64)> {
        Some((self.k, 0.0)) // closed: k, open: 0
    }
}

/// Compression-only contact between dofs `i` and `j` (or `i` and a stop).
#[derive(Debug, Clone, PartialEq)]
pub struct Gap {
    dofs: Vec<usize>,
    gap: f64,
    k: f64,
}

impl Gap {
    /// Gap from dof `i` to dof `j` (`None`: to a fixed stop) with opening `gap >= 0` and
    /// contact stiffness `k > 0`. Errors name the parameter (`"j"` when `j == Some(i)`).
    pub fn new(i: usize, j: Option<usize>, gap: f64, k: f64) -> Result<Self, CoreError> {
        check("gap", gap, false)?;
        check("k", k, true)?;
        Ok(Self {
            dofs: local_dofs(i, j)?,
            gap,
            k,
        })
    }

    /// Initial opening.
    pub fn gap(&self) -> f64 {
        self.gap
    }

    /// Contact stiffness.
    pub fn k(&self) -> f64 {
        self.k
    }

    /// The force and its derivative `(F, dF/du)` at deformation `u`.
    pub fn force(&self, u: f64) -> (f64, f64) {
        if u < -self.gap {
            (self.k * (u + self.gap), self.k)
        } else {
            (0.0, 0.0)
        }
    }
}

impl Element for Gap {
    fn path_reads(&self) -> Option<(bool, bool)> {
        Some((false, false))
    }

    fn restarts_exactly(&self) -> bool {
        true
    }

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
        let u = relative(x);
        finite(t, &[u])?;
        let (f, df) = self.force(u);
        scatter(f, df, r, tangent.map(|tg| tg.kx));
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closes_at_minus_gap() {
        let g = Gap::new(0, None, 0.5, 10.0).unwrap();
        assert_eq!(g.force(1.0), (0.0, 0.0));
        assert_eq!(g.force(-0.5), (0.0, 0.0));
        assert_eq!(g.force(-0.75), (-2.5, 10.0));
        let touching = Gap::new(0, None, 0.0, 10.0).unwrap();
        assert_eq!(touching.force(-0.1), (-1.0, 10.0));
    }
}
