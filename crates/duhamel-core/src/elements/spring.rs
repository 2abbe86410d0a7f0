//! Two-node (or node-to-ground) springs and dampers.
//!
//! With `delta = x_i - x_j` (`x_j = 0` when `j` is `None`, i.e. to ground) the element force
//! `s` acts as `r_i = +s`, `r_j = -s` on the left-hand side: equal and opposite, restoring.
//!
//! * [`Spring`]: `s = k delta + k3 delta^3` (linear plus Duffing cubic; either sign).
//! * [`Damper`]: `s = c (v_i - v_j)`, `c >= 0`.

use serde::{Deserialize, Serialize};

use super::definition::{along, deformation, pair_matrix, Definition, Pair};
use super::element::{Element, Tangent};
use crate::error::CoreError;

/// `duhamel.elements.Spring`: the definition of a [`Spring`].
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub k: f64,
    #[serde(default)]
    pub k3: f64,
}

impl Definition for SpringDef {
    const NAME: &'static str = "Spring";
    const SIGNATURE: &'static str = "(i, j=None, *, k, k3=0.0)";
    const DOC: &'static str = r#"Spring ``s = k d + k3 d^3`` on the deformation ``d = x_i - x_j`` (``j=None``: to the
ground); negative `k` (negative-stiffness springs) and negative `k3` (softening) are allowed.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
k : float
    Linear stiffness.
k3 : float, default 0.0
    Cubic stiffness.

Examples
--------
>>> import duhamel
>>> link = duhamel.elements.Spring(3, 4, k=0.0, k3=2e9)
"#;
    const LEGACY: &'static [&'static str] = &["i", "j", "k", "k3"];
    const LEGACY_DEFAULTS: &'static [(&'static str, &'static str)] = &[("k", "0.0")];
    type Runtime = Spring;

    fn build(&self) -> Result<Spring, CoreError> {
        Spring::new(self.i, self.j, self.k, self.k3)
    }

    fn directions(&self) -> Option<Vec<Pair>> {
        along(self.i, self.j)
    }

    fn passive(&self) -> bool {
        self.k >= 0.0 && self.k3 >= 0.0
    }

    fn tangent_bound(&self) -> Option<(f64, f64)> {
        (self.k3 == 0.0).then_some((self.k.abs(), 0.0))
    }

    fn linear_stiffness(&self) -> Option<Vec<f64>> {
        (self.k > 0.0).then(|| pair_matrix(self.j, self.k))
    }

    fn without_linear(&self) -> Option<Self> {
        Some(SpringDef {
            k: 0.0,
            ..self.clone()
        })
    }

    fn stored_energy(&self, u: &[f64], _f: &[f64]) -> f64 {
        let d = deformation(u);
        0.5 * self.k * d * d + 0.25 * self.k3 * d.powi(4)
    }

    fn linear(&self) -> Result<(Vec<f64>, Vec<f64>), String> {
        if self.k3 != 0.0 {
            return Err("is nonlinear (k3 != 0)".into());
        }
        Ok((pair_matrix(self.j, self.k), pair_matrix(self.j, 0.0)))
    }
}

/// `duhamel.elements.Damper`: the definition of a [`Damper`].
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DamperDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub c: f64,
}

impl Definition for DamperDef {
    const NAME: &'static str = "Damper";
    const SIGNATURE: &'static str = "(i, j=None, *, c)";
    const DOC: &'static str = r#"Linear viscous damper ``c (v_i - v_j)`` (``j=None``: to the ground).

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
c : float
    Damping coefficient, >= 0.

Examples
--------
>>> import duhamel
>>> dashpot = duhamel.elements.Damper(0, c=0.2)
"#;
    const LEGACY: &'static [&'static str] = &["i", "j", "c"];
    const LEGACY_DEFAULTS: &'static [(&'static str, &'static str)] = &[("c", "0.0")];
    type Runtime = Damper;

    fn build(&self) -> Result<Damper, CoreError> {
        Damper::new(self.i, self.j, self.c)
    }

    fn directions(&self) -> Option<Vec<Pair>> {
        along(self.i, self.j)
    }

    fn passive(&self) -> bool {
        self.c >= 0.0
    }

    fn tangent_bound(&self) -> Option<(f64, f64)> {
        Some((0.0, self.c.abs()))
    }

    fn linear(&self) -> Result<(Vec<f64>, Vec<f64>), String> {
        Ok((pair_matrix(self.j, 0.0), pair_matrix(self.j, self.c)))
    }
}

fn check_finite(name: &'static str, value: f64) -> Result<(), CoreError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(CoreError::InvalidInput {
            name,
            problem: format!("must be finite, got {value}"),
        })
    }
}

fn local_dofs(i: usize, j: Option<usize>) -> Result<Vec<usize>, CoreError> {
    match j {
        None => Ok(vec![i]),
        Some(j) if j == i => Err(CoreError::InvalidInput {
            name: "j",
            problem: format!("must differ from i (both are {i}); use j=None to connect to ground"),
        }),
        Some(j) => Ok(vec![i, j]),
    }
}

/// Scatters the element force `s` and its scalar derivative `ds` (with respect to the
/// relative coordinate) into `r` and the `n x n` tangent `m` (`n = 1` or `2`).
fn scatter(n: usize, s: f64, ds: f64, r: &mut [f64], m: Option<&mut [f64]>) {
    r[0] += s;
    if n == 2 {
        r[1] -= s;
    }
    if let Some(m) = m {
        if n == 1 {
            m[0] += ds;
        } else {
            m[0] += ds;
            m[1] -= ds;
            m[2] -= ds;
            m[3] += ds;
        }
    }
}

/// Spring `s = k delta + k3 delta^3` between dofs `i` and `j` (or `i` and ground).
///
/// Negative `k` (negative-stiffness springs) and negative `k3` (softening) are allowed.
#[derive(Debug, Clone, PartialEq)]
pub struct Spring {
    dofs: Vec<usize>,
    k: f64,
    k3: f64,
}

impl Spring {
    /// Spring from dof `i` to dof `j` (`None`: to ground) with linear stiffness `k` and cubic
    /// stiffness `k3`. Errors: non-finite `k`/`k3`, `j == Some(i)` (named `"j"`).
    pub fn new(i: usize, j: Option<usize>, k: f64, k3: f64) -> Result<Self, CoreError> {
        check_finite("k", k)?;
        check_finite("k3", k3)?;
        Ok(Self {
            dofs: local_dofs(i, j)?,
            k,
            k3,
        })
    }

    /// Linear stiffness.
    pub fn k(&self) -> f64 {
        self.k
    }

    /// Cubic stiffness.
    pub fn k3(&self) -> f64 {
        self.k3
    }

    /// Element force `s(delta)` and stiffness `ds/ddelta`.
    pub fn force_and_stiffness(&self, delta: f64) -> (f64, f64) {
        let d2 = delta * delta;
        (delta * (self.k + self.k3 * d2), self.k + 3.0 * self.k3 * d2)
    }
}

impl Element for Spring {
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
        _t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let n = self.dofs.len();
        debug_assert!(x.len() == n && r.len() == n);
        let delta = if n == 2 { x[0] - x[1] } else { x[0] };
        let (s, ds) = self.force_and_stiffness(delta);
        scatter(n, s, ds, r, tangent.map(|t| t.kx));
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        Some(if self.k3 != 0.0 { 3 } else { 1 })
    }

    fn modal_cubic(&self, phi: &[f64]) -> Option<super::element::ModalCubic> {
        // d = dphi q: dphi (k d + k3 d^3)
        let d = super::element::relative(phi);
        let mut a = [[0.0; 4]; 4];
        a[1][0] = self.k * d * d;
        a[3][0] = self.k3 * d * d * d * d;
        Some(a)
    }

    fn uses_velocity(&self) -> bool {
        false
    }
}

/// Linear viscous damper `s = c (v_i - v_j)` between dofs `i` and `j` (or `i` and ground).
#[derive(Debug, Clone, PartialEq)]
pub struct Damper {
    dofs: Vec<usize>,
    c: f64,
}

impl Damper {
    /// Damper from dof `i` to dof `j` (`None`: to ground) with coefficient `c >= 0`.
    /// Errors: non-finite or negative `c`, `j == Some(i)` (named `"j"`).
    pub fn new(i: usize, j: Option<usize>, c: f64) -> Result<Self, CoreError> {
        check_finite("c", c)?;
        if c < 0.0 {
            return Err(CoreError::InvalidInput {
                name: "c",
                problem: format!("must be >= 0, got {c}"),
            });
        }
        Ok(Self {
            dofs: local_dofs(i, j)?,
            c,
        })
    }

    /// Damping coefficient.
    pub fn c(&self) -> f64 {
        self.c
    }
}

impl Element for Damper {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn eval(
        &self,
        _x: &[f64],
        v: &[f64],
        _t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let n = self.dofs.len();
        debug_assert!(v.len() == n && r.len() == n);
        let dv = if n == 2 { v[0] - v[1] } else { v[0] };
        scatter(n, self.c * dv, self.c, r, tangent.map(|t| t.cv));
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        Some(1)
    }

    fn modal_cubic(&self, phi: &[f64]) -> Option<super::element::ModalCubic> {
        let d = super::element::relative(phi);
        let mut a = [[0.0; 4]; 4];
        a[0][1] = self.c * d * d;
        Some(a)
    }

    fn uses_velocity(&self) -> bool {
        true
    }
}
