//! `duhamel.elements.Pinching4`: the element of OpenSees' [`Pinching4`] law, its
//! parameters named as OpenSees' (docs/materials.md), and the law's data: its parameters,
//! envelopes, internal variables, the state of a trial ([`Work`]) and the damaged envelope
//! it reads (OpenSees' `posEnvlpStress`, `negEnvlpStress` and their tangents). The law's
//! state determination is in `pinching4.rs`.

use serde::{Deserialize, Serialize};

use super::state::material_state;
use super::uniaxial::{initial_deformation_doc, uniaxial_methods, Uniaxial, UniaxialDefinition};
use crate::elements::definition::{Definition, Pair};
use crate::error::CoreError;

/// `duhamel.elements.Pinching4`: the definition of a [`Pinching4`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pinching4Def {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    #[serde(rename = "ePf1")]
    pub e_pf1: f64,
    #[serde(rename = "ePd1")]
    pub e_pd1: f64,
    #[serde(rename = "ePf2")]
    pub e_pf2: f64,
    #[serde(rename = "ePd2")]
    pub e_pd2: f64,
    #[serde(rename = "ePf3")]
    pub e_pf3: f64,
    #[serde(rename = "ePd3")]
    pub e_pd3: f64,
    #[serde(rename = "ePf4")]
    pub e_pf4: f64,
    #[serde(rename = "ePd4")]
    pub e_pd4: f64,
    #[serde(rename = "eNf1", default)]
    pub e_nf1: Option<f64>,
    #[serde(rename = "eNd1", default)]
    pub e_nd1: Option<f64>,
    #[serde(rename = "eNf2", default)]
    pub e_nf2: Option<f64>,
    #[serde(rename = "eNd2", default)]
    pub e_nd2: Option<f64>,
    #[serde(rename = "eNf3", default)]
    pub e_nf3: Option<f64>,
    #[serde(rename = "eNd3", default)]
    pub e_nd3: Option<f64>,
    #[serde(rename = "eNf4", default)]
    pub e_nf4: Option<f64>,
    #[serde(rename = "eNd4", default)]
    pub e_nd4: Option<f64>,
    #[serde(rename = "rDispP")]
    pub r_disp_p: f64,
    #[serde(rename = "rForceP")]
    pub r_force_p: f64,
    #[serde(rename = "uForceP")]
    pub u_force_p: f64,
    #[serde(rename = "rDispN", default)]
    pub r_disp_n: Option<f64>,
    #[serde(rename = "rForceN", default)]
    pub r_force_n: Option<f64>,
    #[serde(rename = "uForceN", default)]
    pub u_force_n: Option<f64>,
    #[serde(rename = "gK1")]
    pub g_k1: f64,
    #[serde(rename = "gK2")]
    pub g_k2: f64,
    #[serde(rename = "gK3")]
    pub g_k3: f64,
    #[serde(rename = "gK4")]
    pub g_k4: f64,
    #[serde(rename = "gKLim")]
    pub g_k_lim: f64,
    #[serde(rename = "gD1")]
    pub g_d1: f64,
    #[serde(rename = "gD2")]
    pub g_d2: f64,
    #[serde(rename = "gD3")]
    pub g_d3: f64,
    #[serde(rename = "gD4")]
    pub g_d4: f64,
    #[serde(rename = "gDLim")]
    pub g_d_lim: f64,
    #[serde(rename = "gF1")]
    pub g_f1: f64,
    #[serde(rename = "gF2")]
    pub g_f2: f64,
    #[serde(rename = "gF3")]
    pub g_f3: f64,
    #[serde(rename = "gF4")]
    pub g_f4: f64,
    #[serde(rename = "gFLim")]
    pub g_f_lim: f64,
    #[serde(rename = "gE")]
    pub g_e: f64,
    #[serde(rename = "dmgType", default = "energy")]
    pub dmg_type: String,
    #[serde(default)]
    pub initial_deformation: f64,
}

fn energy() -> String {
    "energy".into()
}

impl UniaxialDefinition for Pinching4Def {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = Pinching4;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<Pinching4, CoreError> {
        let pos = [
            (self.e_pf1, self.e_pd1),
            (self.e_pf2, self.e_pd2),
            (self.e_pf3, self.e_pd3),
            (self.e_pf4, self.e_pd4),
        ];
        let pinch_pos = [self.r_disp_p, self.r_force_p, self.u_force_p];
        let given = [
            self.e_nf1,
            self.e_nd1,
            self.e_nf2,
            self.e_nd2,
            self.e_nf3,
            self.e_nd3,
            self.e_nf4,
            self.e_nd4,
            self.r_disp_n,
            self.r_force_n,
            self.u_force_n,
        ];
        let (neg, pinch_neg) = match given.map(|v| v.unwrap_or(f64::NAN)) {
            _ if given.iter().all(Option::is_none) => (pos.map(|(f, d)| (-f, -d)), pinch_pos),
            [f1, d1, f2, d2, f3, d3, f4, d4, r, rf, uf] if given.iter().all(Option::is_some) => {
                ([(f1, d1), (f2, d2), (f3, d3), (f4, d4)], [r, rf, uf])
            }
            _ => {
                const NAMES: [&str; 11] = [
                    "eNf1", "eNd1", "eNf2", "eNd2", "eNf3", "eNd3", "eNf4", "eNd4", "rDispN",
                    "rForceN", "uForceN",
                ];
                let k = given.iter().position(Option::is_none).unwrap_or(0);
                return Err(CoreError::InvalidInput {
                    name: NAMES[k],
                    problem: "is missing: the negative side (`eNf1`...`eNd4`, `rDispN`, \
                              `rForceN`, `uForceN`) takes all eleven values or none (mirrored \
                              from the positive side)"
                        .into(),
                });
            }
        };
        let damage = match self.dmg_type.as_str() {
            "energy" => Pinching4Damage::Energy,
            "cycle" => Pinching4Damage::Cycle,
            other => {
                return Err(CoreError::InvalidInput {
                    name: "dmgType",
                    problem: format!("must be \"energy\" or \"cycle\", got {other:?}"),
                })
            }
        };
        Pinching4::new(Pinching4Params {
            pos,
            neg,
            pinch_pos,
            pinch_neg,
            gk: [self.g_k1, self.g_k2, self.g_k3, self.g_k4, self.g_k_lim],
            gd: [self.g_d1, self.g_d2, self.g_d3, self.g_d4, self.g_d_lim],
            gf: [self.g_f1, self.g_f2, self.g_f3, self.g_f4, self.g_f_lim],
            ge: self.g_e,
            damage,
        })
    }
}

impl Definition for Pinching4Def {
    const NAME: &'static str = "Pinching4";
    const SIGNATURE: &'static str =
        "(i, j=None, *, ePf1, ePd1, ePf2, ePd2, ePf3, ePd3, ePf4, ePd4, eNf1=None, \
        eNd1=None, eNf2=None, eNd2=None, eNf3=None, eNd3=None, eNf4=None, eNd4=None, \
        rDispP, rForceP, uForceP, rDispN=None, rForceN=None, uForceN=None, gK1, gK2, gK3, \
        gK4, gKLim, gD1, gD2, gD3, gD4, gDLim, gF1, gF2, gF3, gF4, gFLim, gE, \
        dmgType=\"energy\", initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"OpenSees' ``Pinching4`` material (Lowes, Mitra & Altoontash 2003) on the deformation
``u = x_i - x_j`` (``j=None``: to the ground): a four-point envelope per side, unload-reload
paths through a reloading point ``(rDisp u_max, rForce F(u_max))`` and an unloading force
``uForce``, and damage of the unloading stiffness (``gK``), the reloading target (``gD``)
and the strength (``gF``) growing with the energy dissipated (``dmgType="energy"``, capacity
``gE`` times the monotonic energy) or the cycles (``"cycle"``). OpenSees' state determination,
equal to it to the last bit (docs/materials.md). The negative side (``eNf1``...``uForceN``):
all eleven values or none (mirrored from the positive side, OpenSees' short form).
Linear part: the initial elastic slope.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
ePf1, ePd1, ..., ePf4, ePd4 : float
    Positive envelope points (force, deformation).
eNf1, eNd1, ..., eNf4, eNd4 : float, optional
    Negative envelope points (negative values).
rDispP, rForceP, uForceP : float
    Reloading deformation and force ratios, unloading force ratio (positive side).
rDispN, rForceN, uForceN : float, optional
    The same for the negative side.
gK1, gK2, gK3, gK4, gKLim : float
    Unloading stiffness damage.
gD1, gD2, gD3, gD4, gDLim : float
    Reloading deformation damage.
gF1, gF2, gF3, gF4, gFLim : float
    Strength damage.
gE : float
    Energy capacity, in monotonic envelope energies.
dmgType : {"energy", "cycle"}
    What the damage grows with.
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import duhamel
>>> joint = duhamel.elements.Pinching4(
...     0, ePf1=100.0, ePd1=0.005, ePf2=150.0, ePd2=0.015, ePf3=170.0, ePd3=0.03,
...     ePf4=40.0, ePd4=0.06, rDispP=0.5, rForceP=0.25, uForceP=0.05,
...     gK1=1.0, gK2=0.2, gK3=0.3, gK4=0.2, gKLim=0.9, gD1=0.5, gD2=0.5, gD3=2.0, gD4=2.0,
...     gDLim=0.5, gF1=1.0, gF2=0.0, gF3=1.0, gF4=1.0, gFLim=0.9, gE=10.0)
>>> round(float(duhamel.elements.drive(joint, [0.01]).force[0]), 9)
125.0
"#
    );
    type Runtime = Uniaxial<Pinching4>;
    uniaxial_methods!();
}

/// How the damage indices grow: with dissipated energy or with the number of cycles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pinching4Damage {
    Energy,
    Cycle,
}

/// The parameters of [`Pinching4`], in OpenSees' order and meaning.
#[derive(Clone, Debug, PartialEq)]
pub struct Pinching4Params {
    /// The four `(force, deformation)` envelope points of each side (negative side negative).
    pub pos: [(f64, f64); 4],
    pub neg: [(f64, f64); 4],
    /// Reloading deformation ratio, reloading force ratio and unloading force ratio:
    /// `(rDispP, rForceP, uForceP)` and `(rDispN, rForceN, uForceN)`.
    pub pinch_pos: [f64; 3],
    pub pinch_neg: [f64; 3],
    /// Unloading-stiffness damage `gK1..gK4`, `gKLim`.
    pub gk: [f64; 5],
    /// Reloading-deformation damage `gD1..gD4`, `gDLim`.
    pub gd: [f64; 5],
    /// Strength damage `gF1..gF4`, `gFLim`.
    pub gf: [f64; 5],
    /// Energy capacity factor `gE` (of the monotonic envelope's energy).
    pub ge: f64,
    pub damage: Pinching4Damage,
}

/// OpenSees' `Pinching4` uniaxial material.
#[derive(Clone, Debug)]
pub struct Pinching4 {
    pub(crate) p: Pinching4Params,
    /// The six-point envelopes (an initial tiny elastic point, the four given, a far one).
    pub(crate) pos_strain: [f64; 6],
    pub(crate) pos_stress: [f64; 6],
    pub(crate) neg_strain: [f64; 6],
    pub(crate) neg_stress: [f64; 6],
    pub(crate) k_elastic_pos: f64,
    pub(crate) k_elastic_neg: f64,
    pub(crate) energy_capacity: f64,
}

material_state! {
    /// OpenSees' committed members of `Pinching4Material`, the damage indices in use, and
    /// the deformation terms `(u_max/u_ult)^gamma_3` of the three damage indices with the
    /// `u_max` they are for (-1: none yet), kept so that a trial computes those powers only
    /// when the largest deformation moves.
    P4State {
        state, strain, stress, strain_rate, low_strain, low_stress, hgh_strain, hgh_stress,
        min_dmnd, max_dmnd, energy, gamma_k, gamma_d, gamma_f, n_cycle,
        gamma_k_used, gamma_f_used, powers_of, power_k, power_d, power_f,
    }
}

/// A trial: the committed variables, the trial ones and the damaged envelope in use.
pub(crate) struct Work<'a> {
    pub m: &'a Pinching4,
    pub c: &'a P4State,
    pub t: P4State,
    pub k_pos_d: f64,
    pub k_neg_d: f64,
    pub u_max_d: f64,
    pub u_min_d: f64,
    pub pos_d: [f64; 6],
    pub neg_d: [f64; 6],
}

impl Work<'_> {
    /// OpenSees' `posEnvlpStress` / `posEnvlpTangent` on the damaged envelope: `(f, k)`.
    pub(crate) fn pos_env(&self, u: f64) -> (f64, f64) {
        let (s, f) = (&self.m.pos_strain, &self.pos_d);
        let (mut k, mut out) = (0.0, 0.0);
        let mut i = 0;
        while k == 0.0 && i <= 4 {
            if u <= s[i + 1] {
                k = (f[i + 1] - f[i]) / (s[i + 1] - s[i]);
                out = f[i] + (u - s[i]) * k;
            }
            i += 1;
        }
        if k == 0.0 {
            k = (f[5] - f[4]) / (s[5] - s[4]);
            out = f[5] + k * (u - s[5]);
        }
        (out, k)
    }

    /// OpenSees' `negEnvlpStress` / `negEnvlpTangent` on the damaged envelope.
    pub(crate) fn neg_env(&self, u: f64) -> (f64, f64) {
        let (s, f) = (&self.m.neg_strain, &self.neg_d);
        let (mut k, mut out) = (0.0, 0.0);
        let mut i = 0;
        while k == 0.0 && i <= 4 {
            if u >= s[i + 1] {
                k = (f[i] - f[i + 1]) / (s[i] - s[i + 1]);
                out = f[i + 1] + (u - s[i + 1]) * k;
            }
            i += 1;
        }
        if k == 0.0 {
            k = (f[4] - f[5]) / (s[4] - s[5]);
            out = f[5] + k * (u - s[5]);
        }
        (out, k)
    }
}
