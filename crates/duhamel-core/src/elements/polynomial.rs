//! A polynomial restoring force at one degree of freedom, `r = sum_i c_i x^i`.
//!
//! The Duffing hardening/softening spring `r = k3 x^3` is [`Polynomial::cubic`]. The force is
//! evaluated by Horner's scheme together with its derivative `dr/dx`.

use serde::{Deserialize, Serialize};

use super::definition::Definition;
use super::element::{Element, Tangent};
use crate::error::CoreError;

/// `duhamel.elements.Polynomial`: the definition of a [`Polynomial`].
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolynomialDef {
    pub i: usize,
    pub coefficients: Vec<f64>,
}

/// Renames the single dof of the previous release (`dof`).
fn rename_dof(old: &str) -> Option<(&'static str, Option<usize>)> {
    (old == "dof").then_some(("i", None))
}

impl Definition for PolynomialDef {
    const NAME: &'static str = "Polynomial";
    const SIGNATURE: &'static str = "(i, *, coefficients)";
    const DOC: &'static str = r#"``r = sum_k coefficients[k] x_i^k`` at one degree of freedom.

Parameters
----------
i : int or dof label
    The dof.
coefficients : sequence of float
    ``c_0, c_1, ...`` (``c_0`` a constant force).

Examples
--------
>>> import duhamel
>>> softening = duhamel.elements.Polynomial(0, coefficients=[0.0, 0.0, 0.0, -0.5])
"#;
    const LEGACY: &'static [&'static str] = &["dof", "coefficients"];
    type Runtime = Polynomial;

    fn build(&self) -> Result<Polynomial, CoreError> {
        Polynomial::new(self.i, self.coefficients.clone())
    }

    fn rename(old: &str) -> Option<(&'static str, Option<usize>)> {
        rename_dof(old)
    }

    fn passive(&self) -> bool {
        // a potential bounded below: odd powers with non-negative coefficients only
        let c = &self.coefficients;
        c.iter().step_by(2).all(|&v| v == 0.0) && c.iter().skip(1).step_by(2).all(|&v| v >= 0.0)
    }

    fn tangent_bound(&self) -> Option<(f64, f64)> {
        let c = &self.coefficients;
        (c.len() > 1 && c[2..].iter().all(|&v| v == 0.0)).then(|| (c[1].abs(), 0.0))
    }

    fn linear_stiffness(&self) -> Option<Vec<f64>> {
        let k = self.coefficients.get(1).copied().unwrap_or(0.0);
        (k > 0.0).then(|| vec![k])
    }

    fn without_linear(&self) -> Option<Self> {
        let mut coefficients = self.coefficients.clone();
        if let Some(c1) = coefficients.get_mut(1) {
            *c1 = 0.0;
        }
        Some(PolynomialDef {
            i: self.i,
            coefficients,
        })
    }

    fn linear(&self) -> Result<(Vec<f64>, Vec<f64>), String> {
        let c = &self.coefficients;
        if c.iter().skip(2).any(|&v| v != 0.0) {
            return Err("is nonlinear (a coefficient of degree >= 2 is non-zero)".into());
        }
        if c.first().is_some_and(|&v| v != 0.0) {
            return Err(
                "applies a constant force (coefficient of degree 0), which is not linear".into(),
            );
        }
        Ok((vec![c.get(1).copied().unwrap_or(0.0)], vec![0.0]))
    }
}

/// `duhamel.elements.Cubic`: the Duffing spring, a [`Polynomial`] `k3 x^3`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CubicDef {
    pub i: usize,
    pub k3: f64,
}

impl Definition for CubicDef {
    const NAME: &'static str = "Cubic";
    const SIGNATURE: &'static str = "(i, *, k3)";
    const DOC: &'static str = r#"Duffing spring to ground, ``r = k3 x_i^3`` (``k3 < 0`` softens).

Parameters
----------
i : int or dof label
    The dof.
k3 : float
    Cubic stiffness.

Examples
--------
>>> import numpy as np, duhamel
>>> duffing = duhamel.System(np.eye(1), np.eye(1)).add(duhamel.elements.Cubic(0, k3=4.0))
"#;
    const LEGACY: &'static [&'static str] = &["dof", "k3"];
    type Runtime = Polynomial;

    fn build(&self) -> Result<Polynomial, CoreError> {
        Polynomial::cubic(self.i, self.k3)
    }

    fn rename(old: &str) -> Option<(&'static str, Option<usize>)> {
        rename_dof(old)
    }

    fn passive(&self) -> bool {
        self.k3 >= 0.0
    }

    fn linear(&self) -> Result<(Vec<f64>, Vec<f64>), String> {
        if self.k3 != 0.0 {
            return Err("is nonlinear (k3 != 0)".into());
        }
        Ok((vec![0.0], vec![0.0]))
    }
}

/// Restoring force `r = c_0 + c_1 x + c_2 x^2 + ...` at one dof (`c_0` is a constant force).
///
/// Trailing zero coefficients are trimmed at construction, so [`Element::polynomial_degree`]
/// is the true degree (`0` for an empty or all-zero list, which is the zero force).
#[derive(Debug, Clone, PartialEq)]
pub struct Polynomial {
    dofs: [usize; 1],
    coefficients: Vec<f64>,
}

impl Polynomial {
    /// `r = sum_i coefficients[i] * x^i` at `dof`. Coefficients must be finite (any sign).
    pub fn new(dof: usize, coefficients: Vec<f64>) -> Result<Self, CoreError> {
        Self::build(dof, coefficients, "coefficients")
    }

    /// The Duffing spring `r = k3 x^3` at `dof`; `k3 < 0` is a softening spring.
    pub fn cubic(dof: usize, k3: f64) -> Result<Self, CoreError> {
        Self::build(dof, vec![0.0, 0.0, 0.0, k3], "k3")
    }

    fn build(
        dof: usize,
        mut coefficients: Vec<f64>,
        name: &'static str,
    ) -> Result<Self, CoreError> {
        if let Some((i, c)) = coefficients
            .iter()
            .enumerate()
            .find(|(_, c)| !c.is_finite())
        {
            return Err(CoreError::InvalidInput {
                name,
                problem: format!("must be finite (entry {i} is {c})"),
            });
        }
        while coefficients.last() == Some(&0.0) {
            coefficients.pop();
        }
        Ok(Self {
            dofs: [dof],
            coefficients,
        })
    }

    /// The degree of freedom the force acts on.
    pub fn dof(&self) -> usize {
        self.dofs[0]
    }

    /// The coefficients `c_0, c_1, ...` with trailing zeros trimmed.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// The force and its derivative `(r(x), dr/dx(x))` by Horner's scheme.
    pub fn force_and_slope(&self, x: f64) -> (f64, f64) {
        let mut r = 0.0;
        let mut dr = 0.0;
        for &c in self.coefficients.iter().rev() {
            dr = dr * x + r;
            r = r * x + c;
        }
        (r, dr)
    }
}

impl Element for Polynomial {
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
        debug_assert!(x.len() == 1 && r.len() == 1);
        let (f, df) = self.force_and_slope(x[0]);
        r[0] += f;
        if let Some(tg) = tangent {
            tg.kx[0] += df;
        }
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        Some(self.coefficients.len().saturating_sub(1) as u32)
    }

    fn modal_cubic(&self, phi: &[f64]) -> Option<super::element::ModalCubic> {
        // phi * sum c_k (phi q)^k
        if self.coefficients.len() > 4 {
            return None;
        }
        let mut a = [[0.0; 4]; 4];
        let mut p = phi[0];
        for (k, c) in self.coefficients.iter().enumerate() {
            a[k][0] = c * p;
            p *= phi[0];
        }
        Some(a)
    }

    fn uses_velocity(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn horner_matches_direct_sum() {
        let p = Polynomial::new(0, vec![1.5, -2.0, 0.5, 3.0, 0.0, 0.0]).unwrap();
        assert_eq!(p.coefficients().len(), 4);
        let x = 0.7_f64;
        let (f, df) = p.force_and_slope(x);
        assert!((f - (1.5 - 2.0 * x + 0.5 * x * x + 3.0 * x.powi(3))).abs() < 1e-14);
        assert!((df - (-2.0 + x + 9.0 * x * x)).abs() < 1e-14);
    }
}
