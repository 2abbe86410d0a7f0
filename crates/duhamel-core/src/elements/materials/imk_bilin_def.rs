//! `duhamel.elements.IMKBilin`: the element of the [`ImkBilin`] hinge law, its parameters
//! named as OpenSees' (docs/materials.md).

use serde::{Deserialize, Serialize};

use super::imk_bilin::{ImkBilin, ImkBilinParams};
use super::uniaxial::{initial_deformation_doc, uniaxial_methods, Uniaxial, UniaxialDefinition};
use crate::elements::definition::{Definition, Pair};
use crate::error::CoreError;

/// `duhamel.elements.IMKBilin`: the definition of a [`ImkBilin`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImkBilinDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    #[serde(rename = "Ke")]
    pub ke: f64,
    pub theta_p_plus: f64,
    pub theta_pc_plus: f64,
    pub theta_u_plus: f64,
    #[serde(rename = "My_plus")]
    pub my_plus: f64,
    #[serde(rename = "Mmax_My_plus")]
    pub mmax_my_plus: f64,
    pub res_plus: f64,
    pub theta_p_neg: f64,
    pub theta_pc_neg: f64,
    pub theta_u_neg: f64,
    #[serde(rename = "My_neg")]
    pub my_neg: f64,
    #[serde(rename = "Mmax_My_neg")]
    pub mmax_my_neg: f64,
    pub res_neg: f64,
    pub lambda_s: f64,
    pub lambda_c: f64,
    pub lambda_k: f64,
    pub c_s: f64,
    pub c_c: f64,
    pub c_k: f64,
    #[serde(rename = "D_plus")]
    pub d_plus: f64,
    #[serde(rename = "D_neg")]
    pub d_neg: f64,
    #[serde(default)]
    pub initial_deformation: f64,
}

impl UniaxialDefinition for ImkBilinDef {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = ImkBilin;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<ImkBilin, CoreError> {
        let p = ImkBilinParams {
            ke: self.ke,
            theta_p_plus: self.theta_p_plus,
            theta_pc_plus: self.theta_pc_plus,
            theta_u_plus: self.theta_u_plus,
            my_plus: self.my_plus,
            mmax_my_plus: self.mmax_my_plus,
            res_plus: self.res_plus,
            theta_p_neg: self.theta_p_neg,
            theta_pc_neg: self.theta_pc_neg,
            theta_u_neg: self.theta_u_neg,
            my_neg: self.my_neg,
            mmax_my_neg: self.mmax_my_neg,
            res_neg: self.res_neg,
            lambda_s: self.lambda_s,
            lambda_c: self.lambda_c,
            lambda_k: self.lambda_k,
            c_s: self.c_s,
            c_c: self.c_c,
            c_k: self.c_k,
            d_plus: self.d_plus,
            d_neg: self.d_neg,
        };
        ImkBilin::new(p)
    }
}

impl Definition for ImkBilinDef {
    const NAME: &'static str = "IMKBilin";
    const SIGNATURE: &'static str =
        "(i, j=None, *, Ke, theta_p_plus, theta_pc_plus, theta_u_plus, My_plus, \
        Mmax_My_plus, res_plus, theta_p_neg, theta_pc_neg, theta_u_neg, My_neg, \
        Mmax_My_neg, res_neg, lambda_s, lambda_c, lambda_k, c_s, c_c, c_k, D_plus, \
        D_neg, initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"The modified Ibarra-Medina-Krawinkler deterioration model with a bilinear hysteresis,
on the deformation ``u = x_i - x_j`` (``j=None``: to the ground; a rotation for a hinge), as
OpenSees' ``uniaxialMaterial IMKBilin`` (Lignos & Krawinkler 2011; Lignos et al. 2019; the
successor of OpenSees' ``Bilin``): elastic to ``My``, hardening to ``Mmax`` at the capping
point, post-capping softening to the residual, strength lost past the ultimate deformation;
kinematic (bilinear) unloading and reloading; cyclic deterioration of strength,
post-capping strength and unloading stiffness by the hysteretic energy. OpenSees' state
determination, with the exact tangent (OpenSees reports the step's secant) and the
documented departures of docs/materials.md. Linear part: ``Ke``.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
Ke : float
    Elastic stiffness, > 0.
theta_p_plus, theta_pc_plus, theta_u_plus : float
    Pre-capping plastic, post-capping and ultimate deformations, positive side.
My_plus, Mmax_My_plus, res_plus : float
    Yield strength, capping-to-yield strength ratio and residual ratio, positive side.
theta_p_neg, theta_pc_neg, theta_u_neg, My_neg, Mmax_My_neg, res_neg : float
    The same, negative side (deformations and strength in either sign: their magnitudes).
lambda_s, lambda_c, lambda_k : float
    Cyclic deterioration capacities (strength, post-capping strength, unloading
    stiffness), >= 0 (0: none).
c_s, c_c, c_k : float
    Their rates (exponents).
D_plus, D_neg : float
    Rates of cyclic deterioration in each direction.
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import duhamel
>>> hinge = duhamel.elements.IMKBilin(
...     0, Ke=1e4, theta_p_plus=0.03, theta_pc_plus=0.1, theta_u_plus=0.2, My_plus=100.0,
...     Mmax_My_plus=1.1, res_plus=0.4, theta_p_neg=0.03, theta_pc_neg=0.1, theta_u_neg=0.2,
...     My_neg=100.0, Mmax_My_neg=1.1, res_neg=0.4, lambda_s=2.0, lambda_c=2.0,
...     lambda_k=2.0, c_s=1.0, c_c=1.0, c_k=1.0, D_plus=1.0, D_neg=1.0)
>>> f = duhamel.elements.drive(hinge, [0.005, 0.04]).force
>>> float(f[0]), round(float(f[1]), 9)   # elastic, then capping at 0.01 + 0.03
(50.0, 110.0)
"#
    );
    type Runtime = Uniaxial<ImkBilin>;
    uniaxial_methods!();
}
