//! The parameters and internal variables of
//! [`ModImkPeakOriented`](super::imk::ModImkPeakOriented), and its deterioration exponent.

use super::state::material_state;

/// The parameters of [`ModImkPeakOriented`](super::imk::ModImkPeakOriented), in OpenSees' order and meaning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModImkParams {
    /// Elastic stiffness `K0` (of the member; the spring's is `K0 (1 + n_factor)`).
    pub k0: f64,
    /// Strain-hardening ratios (positive, negative loading).
    pub as_plus: f64,
    pub as_neg: f64,
    /// Effective yield strengths: `My_plus > 0`, `My_neg < 0`.
    pub my_plus: f64,
    pub my_neg: f64,
    /// Cyclic deterioration parameters `Lambda` (reference energy `Lambda My_plus`; 0: none)
    /// for basic strength, post-capping strength, accelerated reloading and unloading
    /// stiffness (`Lamda_S`, `Lamda_C`, `Lamda_A`, `Lamda_K`).
    pub lambda_s: f64,
    pub lambda_c: f64,
    pub lambda_a: f64,
    pub lambda_k: f64,
    /// Rates of cyclic deterioration (exponents `c_S`, `c_C`, `c_A`, `c_K`).
    pub c_s: f64,
    pub c_c: f64,
    pub c_a: f64,
    pub c_k: f64,
    /// Pre-capping plastic deformations (positive numbers, both directions).
    pub theta_p_plus: f64,
    pub theta_p_neg: f64,
    /// Post-capping deformations to zero strength (positive numbers).
    pub theta_pc_plus: f64,
    pub theta_pc_neg: f64,
    /// Residual strength ratios (of `My`).
    pub res_plus: f64,
    pub res_neg: f64,
    /// Ultimate deformations (positive numbers): the force drops to zero there.
    pub theta_u_plus: f64,
    pub theta_u_neg: f64,
    /// Rates of cyclic deterioration in each direction (`D_Plus`, `D_Neg`).
    pub d_plus: f64,
    pub d_neg: f64,
    /// Stiffness amplification `n` of the spring (0: none).
    pub n_factor: f64,
}

material_state! {
    /// OpenSees' committed members of `ModIMKPeakOriented` (names as there).
    ImkState {
        dp, fp, ek, unl, kon, flag_stop, dmax, dmin, fmax, fmin, fy_pos, fy_neg,
        dlst_pos, dlst_neg, flst_pos, flst_neg, sn, sp, enrgc, enrgtot, enrgts, enrgtd,
        enrgtk, enrgta, f_peak_pos, f_peak_neg, cap_slope_pos, cap_slope_neg,
        f_cap_ref_pos, f_cap_ref_neg, ekunload, cp_neg, cp_pos, ekhard_pos, ekhard_neg,
        ekexcurs, ek_p, flagdeg, rse, ke, alfa_neg, alfa_pos, prod_beta, tangent,
        /// 1 once a state has been committed (OpenSees' `commitCalledOnce`).
        committed_once,
    }
}

/// `(num / den)^c` for a deterioration parameter, as OpenSees computes it (a negative ratio
/// to an integer power keeps its sign), except that a NaN — a negative ratio to a
/// non-integer power, where OpenSees' state turns to NaN — is taken as 0.
pub(crate) fn energy_ratio(num: f64, den: f64, c: f64) -> f64 {
    let b = (num / den).powf(c);
    if b.is_nan() {
        0.0
    } else {
        b
    }
}
