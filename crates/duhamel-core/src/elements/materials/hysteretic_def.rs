//! `duhamel.elements.Hysteretic`: the element of OpenSees' [`Hysteretic`] law, its
//! parameters named as OpenSees' (docs/materials.md).

use serde::{Deserialize, Serialize};

use super::hysteretic::{Hysteretic, HystereticParams};
use super::uniaxial::{initial_deformation_doc, uniaxial_methods, Uniaxial, UniaxialDefinition};
use crate::elements::definition::{Definition, Pair};
use crate::error::CoreError;

/// `duhamel.elements.Hysteretic`: the definition of a [`Hysteretic`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HystereticDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub s1p: f64,
    pub e1p: f64,
    pub s2p: f64,
    pub e2p: f64,
    #[serde(default)]
    pub s3p: Option<f64>,
    #[serde(default)]
    pub e3p: Option<f64>,
    pub s1n: f64,
    pub e1n: f64,
    pub s2n: f64,
    pub e2n: f64,
    #[serde(default)]
    pub s3n: Option<f64>,
    #[serde(default)]
    pub e3n: Option<f64>,
    pub pinch_x: f64,
    pub pinch_y: f64,
    pub damage1: f64,
    pub damage2: f64,
    #[serde(default)]
    pub beta: f64,
    #[serde(default)]
    pub initial_deformation: f64,
}

impl UniaxialDefinition for HystereticDef {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = Hysteretic;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<Hysteretic, CoreError> {
        let side = |names: [(&'static str, &'static str); 3],
                    pts: [(f64, f64); 2],
                    third: (Option<f64>, Option<f64>)| {
            let mut out = pts.to_vec();
            match third {
                (Some(s), Some(e)) => out.push((s, e)),
                (None, None) => {}
                (s, _) => {
                    let (ns, ne) = names[2];
                    return Err(CoreError::InvalidInput {
                        name: if s.is_none() { ns } else { ne },
                        problem: format!(
                            "is missing: `{ns}` and `{ne}` go together (give both or neither)"
                        ),
                    });
                }
            }
            Ok(out)
        };
        let pos = side(
            [("s1p", "e1p"), ("s2p", "e2p"), ("s3p", "e3p")],
            [(self.s1p, self.e1p), (self.s2p, self.e2p)],
            (self.s3p, self.e3p),
        )?;
        let neg = side(
            [("s1n", "e1n"), ("s2n", "e2n"), ("s3n", "e3n")],
            [(self.s1n, self.e1n), (self.s2n, self.e2n)],
            (self.s3n, self.e3n),
        )?;
        Hysteretic::new(HystereticParams {
            pos,
            neg,
            pinch_x: self.pinch_x,
            pinch_y: self.pinch_y,
            damage1: self.damage1,
            damage2: self.damage2,
            beta: self.beta,
        })
    }
}

impl Definition for HystereticDef {
    const NAME: &'static str = "Hysteretic";
    const SIGNATURE: &'static str =
        "(i, j=None, *, s1p, e1p, s2p, e2p, s3p=None, e3p=None, s1n, e1n, s2n, e2n, \
        s3n=None, e3n=None, pinch_x, pinch_y, damage1, damage2, beta=0.0, initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"OpenSees' ``Hysteretic`` material on the deformation ``u = x_i - x_j`` (``j=None``: to
the ground): a bilinear or trilinear envelope through ``(e1p, s1p), (e2p, s2p), (e3p, s3p)``
and ``(e1n, s1n), ...`` (negative side negative), pinching of deformation ``pinch_x`` and
force ``pinch_y`` on reloading, damage from ductility ``damage1`` and energy ``damage2``
(the reloading target grows), unloading stiffness degraded as ``mu^-beta``. OpenSees' state
determination, equal to it to the last bit (docs/materials.md). With two points per side
the middle one is put halfway, as OpenSees does. Linear part: ``s1p / e1p``.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
s1p, e1p, s2p, e2p, s3p, e3p : float
    Positive envelope points (force, deformation); the third is optional.
s1n, e1n, s2n, e2n, s3n, e3n : float
    Negative envelope points (negative values); the third is optional.
pinch_x, pinch_y : float
    Pinching factors for deformation and force (OpenSees' ``pinchX``, ``pinchY``).
damage1, damage2 : float
    Damage due to ductility and to energy.
beta : float
    Unloading stiffness degradation exponent.
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import duhamel
>>> wall = duhamel.elements.Hysteretic(
...     0, s1p=100.0, e1p=0.01, s2p=130.0, e2p=0.04, s1n=-100.0, e1n=-0.01, s2n=-130.0,
...     e2n=-0.04, pinch_x=0.8, pinch_y=0.2, damage1=0.0, damage2=0.0)
>>> duhamel.elements.drive(wall, [0.005, 0.025]).force.tolist()
[50.0, 115.0]
"#
    );
    type Runtime = Uniaxial<Hysteretic>;
    uniaxial_methods!();
}
