//! Two-node (or node-to-ground) springs and dampers.
//!
//! With `delta = x_i - x_j` (`x_j = 0` when `j` is `None`, i.e. to ground) the element force
//! `s` acts as `r_i = +s`, `r_j = -s` on the left-hand side: equal and opposite, restoring.
//!
//! * [`Spring`]: `s = k delta + k3 delta^3` (linear plus Duffing cubic; either sign).
//! * [`Damper`]: `s = c (v_i - v_j)`, `c >= 0`.

use super::element::{Element, Tangent};
use crate::error::CoreError;

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
    fn as_any(&self) -> Option<&dyn std::any::Any> {
        Some(self)
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
