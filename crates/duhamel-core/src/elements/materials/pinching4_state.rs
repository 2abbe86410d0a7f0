//! The data of [`Pinching4`]: its parameters, envelopes, internal variables, the state of a
//! trial ([`Work`]) and the damaged envelope it reads (OpenSees' `posEnvlpStress`,
//! `negEnvlpStress` and their tangents).

use super::state::material_state;

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
