//! `duhamel.elements.ModIMKPeakOriented`: the element of the [`ModImkPeakOriented`] hinge law,
//! its parameters named as OpenSees' (docs/materials.md).

use serde::{Deserialize, Serialize};

use super::imk::ModImkPeakOriented;
use super::imk_params::ModImkParams;
use super::uniaxial::{initial_deformation_doc, uniaxial_methods, Uniaxial, UniaxialDefinition};
use crate::elements::definition::{Definition, Pair};
use crate::error::CoreError;

/// `duhamel.elements.ModIMKPeakOriented`: the definition of a [`ModImkPeakOriented`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModImkPeakOrientedDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    #[serde(rename = "K0")]
    pub k0: f64,
    pub as_plus: f64,
    pub as_neg: f64,
    #[serde(rename = "My_plus")]
    pub my_plus: f64,
    #[serde(rename = "My_neg")]
    pub my_neg: f64,
    pub lambda_s: f64,
    pub lambda_c: f64,
    pub lambda_a: f64,
    pub lambda_k: f64,
    pub c_s: f64,
    pub c_c: f64,
    pub c_a: f64,
    pub c_k: f64,
    pub theta_p_plus: f64,
    pub theta_p_neg: f64,
    pub theta_pc_plus: f64,
    pub theta_pc_neg: f64,
    pub res_plus: f64,
    pub res_neg: f64,
    pub theta_u_plus: f64,
    pub theta_u_neg: f64,
    #[serde(rename = "D_plus")]
    pub d_plus: f64,
    #[serde(rename = "D_neg")]
    pub d_neg: f64,
    #[serde(default)]
    pub n_factor: f64,
    #[serde(default)]
    pub initial_deformation: f64,
}

impl UniaxialDefinition for ModImkPeakOrientedDef {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = ModImkPeakOriented;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<ModImkPeakOriented, CoreError> {
        let p = ModImkParams {
            k0: self.k0,
            as_plus: self.as_plus,
            as_neg: self.as_neg,
            my_plus: self.my_plus,
            my_neg: self.my_neg,
            lambda_s: self.lambda_s,
            lambda_c: self.lambda_c,
            lambda_a: self.lambda_a,
            lambda_k: self.lambda_k,
            c_s: self.c_s,
            c_c: self.c_c,
            c_a: self.c_a,
            c_k: self.c_k,
            theta_p_plus: self.theta_p_plus,
            theta_p_neg: self.theta_p_neg,
            theta_pc_plus: self.theta_pc_plus,
            theta_pc_neg: self.theta_pc_neg,
            res_plus: self.res_plus,
            res_neg: self.res_neg,
            theta_u_plus: self.theta_u_plus,
            theta_u_neg: self.theta_u_neg,
            d_plus: self.d_plus,
            d_neg: self.d_neg,
            n_factor: self.n_factor,
        };
        ModImkPeakOriented::new(p)
    }
}

impl Definition for ModImkPeakOrientedDef {
    const NAME: &'static str = "ModIMKPeakOriented";
    const SIGNATURE: &'static str =
        "(i, j=None, *, K0, as_plus, as_neg, My_plus, My_neg, lambda_s, lambda_c, \
        lambda_a, lambda_k, c_s, c_c, c_a, c_k, theta_p_plus, theta_p_neg, theta_pc_plus, \
        theta_pc_neg, res_plus, res_neg, theta_u_plus, theta_u_neg, D_plus, D_neg, \
        n_factor=0.0, initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"The modified Ibarra-Medina-Krawinkler deterioration model with a peak-oriented
hysteresis, on the deformation ``u = x_i - x_j`` (``j=None``: to the ground; a rotation for a
hinge), as OpenSees' ``uniaxialMaterial ModIMKPeakOriented`` (Ibarra, Medina & Krawinkler
2005; Lignos & Krawinkler 2011): elastic to ``My``, hardening to the capping point,
post-capping softening to the residual strength, zero force past the ultimate deformation;
peak-oriented reloading; cyclic deterioration of strength, post-capping strength, reloading
target and unloading stiffness by the hysteretic energy (``lambda`` times ``My_plus``, rates
``c``). Exactly OpenSees' state determination except two documented departures (a zero
``lambda_c`` means none; a negative half-cycle energy to a non-integer power is taken as no
deterioration): docs/materials.md. The tangent is the branch slope (exact). Linear part: the
spring's elastic stiffness ``K0 (1 + n_factor)``.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
K0 : float
    Elastic stiffness (of the member), > 0.
as_plus, as_neg : float
    Strain-hardening ratios, in [0, 1).
My_plus, My_neg : float
    Effective yield strengths, ``My_plus > 0``, ``My_neg < 0``.
lambda_s, lambda_c, lambda_a, lambda_k : float
    Cyclic deterioration capacities (strength, post-capping strength, accelerated
    reloading, unloading stiffness), >= 0 (0: none).
c_s, c_c, c_a, c_k : float
    Their rates (exponents), >= 0.
theta_p_plus, theta_p_neg : float
    Pre-capping plastic deformations, >= 0.
theta_pc_plus, theta_pc_neg : float
    Post-capping deformations to zero strength, > 0.
res_plus, res_neg : float
    Residual strengths (of ``My``).
theta_u_plus, theta_u_neg : float
    Ultimate deformations (positive): the force drops to zero there for good.
D_plus, D_neg : float
    Rates of cyclic deterioration in each direction.
n_factor : float
    Stiffness amplification ``n`` of the spring (0: none).
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import duhamel
>>> hinge = duhamel.elements.ModIMKPeakOriented(
...     0, K0=1e4, as_plus=0.03, as_neg=0.03, My_plus=100.0, My_neg=-100.0,
...     lambda_s=2.0, lambda_c=2.0, lambda_a=2.0, lambda_k=2.0, c_s=1.0, c_c=1.0, c_a=1.0,
...     c_k=1.0, theta_p_plus=0.03, theta_p_neg=0.03, theta_pc_plus=0.1, theta_pc_neg=0.1,
...     res_plus=0.4, res_neg=0.4, theta_u_plus=0.2, theta_u_neg=0.2, D_plus=1.0, D_neg=1.0)
>>> f = duhamel.elements.drive(hinge, [0.005, 0.1, 0.25, 0.0]).force
>>> float(f[0]), bool(abs(f[2:]).max() < 1e-6)
(50.0, True)
"#
    );
    type Runtime = Uniaxial<ModImkPeakOriented>;
    uniaxial_methods!();
}
