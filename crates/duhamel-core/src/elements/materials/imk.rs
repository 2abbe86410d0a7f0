//! `ModIMKPeakOriented`: the modified Ibarra-Medina-Krawinkler deterioration model with a
//! peak-oriented hysteresis (Ibarra, Medina & Krawinkler 2005; Lignos & Krawinkler 2011),
//! as OpenSees' `ModIMKPeakOriented` (Lignos; the `nFactor` stiffness amplification of
//! Ribeiro & Barbosa, after Ibarra & Krawinkler 2005, appendix B).
//!
//! The state determination follows OpenSees' `setTrialStrain` line for line, with its
//! `commitState` bookkeeping done here; where this implementation departs from OpenSees
//! (docs/materials.md, "ModIMKPeakOriented"):
//!
//! * the post-capping energy check reads `Enrgtot >= Enrgtd && Enrgtd != 0` where OpenSees
//!   writes `Enrgtd == 0` (a typo: with `lambda_c = 0`, "no post-capping deterioration",
//!   OpenSees instead scales the capping reference by `1 - D` at the first reversal);
//! * a negative energy ratio raised to a non-integer `c` (NaN in OpenSees, which then
//!   carries NaN in its state) is taken as 0; to an integer power it is kept, as OpenSees
//!   keeps it (a negative `beta` that stiffens or strengthens slightly).

use super::imk_envelope::Side;
use super::imk_params::{energy_ratio, ImkState, ModImkParams};
use super::imk_update::deteriorate;
use super::state::require;
use super::Material;
use crate::error::CoreError;

/// OpenSees' `ModIMKPeakOriented` uniaxial material.
#[derive(Clone, Debug)]
pub struct ModImkPeakOriented {
    pub(crate) p: ModImkParams,
}

impl ModImkPeakOriented {
    /// The material; an error names the first parameter out of its domain.
    pub fn new(p: ModImkParams) -> Result<Self, CoreError> {
        require(p.k0 > 0.0, "K0", p.k0, "> 0")?;
        for (name, v) in [("as_plus", p.as_plus), ("as_neg", p.as_neg)] {
            require((0.0..1.0).contains(&v), name, v, "in [0, 1)")?;
        }
        require(p.my_plus > 0.0, "My_plus", p.my_plus, "> 0")?;
        require(
            p.my_neg < 0.0,
            "My_neg",
            p.my_neg,
            "< 0 (a negative strength)",
        )?;
        for (name, v) in [
            ("lambda_s", p.lambda_s),
            ("lambda_c", p.lambda_c),
            ("lambda_a", p.lambda_a),
            ("lambda_k", p.lambda_k),
            ("c_s", p.c_s),
            ("c_c", p.c_c),
            ("c_a", p.c_a),
            ("c_k", p.c_k),
            ("theta_p_plus", p.theta_p_plus),
            ("theta_p_neg", p.theta_p_neg),
            ("n_factor", p.n_factor),
        ] {
            require(v >= 0.0, name, v, ">= 0")?;
        }
        for (name, v) in [
            ("theta_pc_plus", p.theta_pc_plus),
            ("theta_pc_neg", p.theta_pc_neg),
            ("theta_u_plus", p.theta_u_plus),
            ("theta_u_neg", p.theta_u_neg),
        ] {
            require(v > 0.0, name, v, "> 0")?;
        }
        for (name, v) in [
            ("res_plus", p.res_plus),
            ("res_neg", p.res_neg),
            ("D_plus", p.d_plus),
            ("D_neg", p.d_neg),
        ] {
            require((0.0..=1.0).contains(&v), name, v, "in [0, 1]")?;
        }
        Ok(Self { p })
    }

    /// The parameters.
    pub fn params(&self) -> &ModImkParams {
        &self.p
    }

    /// The spring's elastic stiffness `K0 (1 + n)`.
    fn ke(&self) -> f64 {
        self.p.k0 * (1.0 + self.p.n_factor)
    }

    /// OpenSees' first-step initialisation (`kon == 0`), for `deltaD`'s sign.
    fn first(&self, s: &mut ImkState, delta_d: f64) {
        let p = &self.p;
        let n = p.n_factor;
        s.ke = p.k0 * (1.0 + n);
        let ke = s.ke;
        s.alfa_neg = p.as_neg / (1.0 + n * (1.0 - p.as_neg));
        s.alfa_pos = p.as_plus / (1.0 + n * (1.0 - p.as_plus));
        s.ekhard_pos = ke * s.alfa_pos;
        s.ekhard_neg = ke * s.alfa_neg;
        s.enrgts = p.lambda_s * p.my_plus;
        s.enrgtk = 2.0 * p.lambda_k * p.my_plus;
        s.enrgta = p.lambda_a * p.my_plus;
        s.enrgtd = p.lambda_c * p.my_plus;
        s.enrgtot = 0.0;
        s.enrgc = 0.0;
        s.dmax = p.my_plus / ke;
        s.dmin = p.my_neg / ke;
        s.ek_p = ke;
        s.ekunload = ke;
        s.ekexcurs = ke;
        s.fy_pos = p.my_plus;
        s.fy_neg = p.my_neg;
        s.cp_pos = p.my_plus / ke + p.theta_p_plus;
        s.cp_neg = p.my_neg / ke - p.theta_p_neg;
        s.f_peak_pos = p.my_plus + s.ekhard_pos * p.theta_p_plus;
        s.f_peak_neg = p.my_neg + s.ekhard_neg * (-p.theta_p_neg);
        let csp = -s.f_peak_pos / (p.theta_pc_plus * p.k0);
        s.cap_slope_pos = csp / (1.0 + n * (1.0 - csp));
        let csn = s.f_peak_neg / (p.theta_pc_neg * p.k0);
        s.cap_slope_neg = csn / (1.0 + n * (1.0 - csn));
        s.f_cap_ref_pos = -s.cap_slope_pos * ke * (p.theta_p_plus + p.my_plus / ke) + s.f_peak_pos;
        s.f_cap_ref_neg = -s.cap_slope_neg * ke * (-p.theta_p_neg + p.my_neg / ke) + s.f_peak_neg;
        s.fmin = p.my_neg;
        s.fmax = p.my_plus;
        s.flagdeg = 0.0;
        s.flag_stop = 0.0;
        s.dlst_neg = p.my_neg / ke;
        s.dlst_pos = p.my_plus / ke;
        s.flst_neg = p.my_neg;
        s.flst_pos = p.my_plus;
        s.tangent = ke;
        s.ek = 0.0;
        s.sp = 0.0;
        s.fp = 0.0;
        s.sn = 0.0;
        s.unl = 1.0;
        s.rse = 0.0;
        s.prod_beta = 1.0;
        s.kon = if delta_d >= 0.0 { 1.0 } else { 2.0 };
    }

    /// The positive backbone with the current (deteriorated) parameters.
    pub(crate) fn pos_side(&self, s: &ImkState) -> Side {
        Side {
            fy: s.fy_pos,
            alpha: s.alfa_pos,
            alpha_cap: s.cap_slope_pos,
            cp: s.cp_pos,
            elstk: s.ke,
            fyield: self.p.my_plus,
            resfac: self.p.res_plus,
            frac: self.p.theta_u_plus,
        }
    }

    /// The negative backbone with the current (deteriorated) parameters.
    pub(crate) fn neg_side(&self, s: &ImkState) -> Side {
        Side {
            fy: s.fy_neg,
            alpha: s.alfa_neg,
            alpha_cap: s.cap_slope_neg,
            cp: s.cp_neg,
            elstk: s.ke,
            fyield: self.p.my_neg,
            resfac: self.p.res_neg,
            frac: -self.p.theta_u_neg,
        }
    }

    /// The unloading-stiffness deterioration at a reversal (OpenSees' `betak` update);
    /// `ekhard` is the hardening stiffness of the side being left.
    fn unloading_stiffness(&self, s: &mut ImkState, ekhard: f64) {
        let (n, ke) = (self.p.n_factor, s.ke);
        s.rse = 0.5 * s.fp * s.fp / s.ekunload;
        if self.p.lambda_k != 0.0 {
            let mut betak =
                energy_ratio(s.enrgc - s.rse, s.enrgtk - (s.enrgtot - s.rse), self.p.c_k);
            if s.enrgtot - s.rse >= s.enrgtk {
                betak = 1.0;
            }
            let kept = s.prod_beta * (1.0 - betak);
            s.ekunload = ke * (kept / (1.0 + n * (1.0 - kept)));
            s.prod_beta *= 1.0 - betak;
            if s.ekunload <= ekhard {
                s.flag_stop = 1.0;
            }
        }
    }

    /// OpenSees' `setTrialStrain` from the committed `s` to `strain`; returns `(f, ek)`.
    fn trial(&self, strain: f64, s: &mut ImkState) -> (f64, f64) {
        let mut d = strain;
        let delta_d = d - s.dp;
        s.flagdeg = 0.0;
        if delta_d.abs() < 1.0e-18 && strain != 0.0 && s.committed_once == 1.0 {
            return (s.fp, s.tangent);
        }
        if s.kon == 0.0 {
            self.first(s, delta_d);
        }
        let (mut f, mut ek) = (0.0, 0.0);
        if s.flag_stop == 0.0 {
            if delta_d >= 0.0 {
                if s.kon == 2.0 {
                    s.kon = 1.0;
                    s.unl = 0.0;
                    let rse = 0.5 * s.fp * s.fp / s.ekunload;
                    let a2 = s.enrgtk - (s.enrgtot - rse);
                    if a2 < 0.0 && s.enrgtk != 0.0 {
                        s.flag_stop = 1.0;
                    }
                    self.unloading_stiffness(s, s.ekhard_neg);
                    if s.fp < 0.0 {
                        let tst = s.dp - s.fp / s.ekunload;
                        let my_ke = self.p.my_plus / s.ke;
                        s.sn = if (s.dmax - my_ke).abs() >= 1.0e-10 && tst.abs() <= 1.0e-10 {
                            1.0e-9
                        } else {
                            s.dp - s.fp / s.ekunload
                        };
                    }
                    if (s.dmin - s.dp).abs() <= 1.0e-10 {
                        s.sp = s.sn + 1.0e-10;
                    }
                }
                (f, ek) = self.load_positive(s, &mut d, delta_d);
            } else {
                if s.kon == 1.0 {
                    s.kon = 2.0;
                    s.unl = 0.0;
                    self.unloading_stiffness(s, s.ekhard_pos);
                    if s.fp > 0.0 {
                        let tst = s.dp - s.fp / s.ekunload;
                        let my_ke = self.p.my_neg / s.ke;
                        s.sp = if (s.dmin - my_ke).abs() >= 1.0e-10 && tst.abs() <= 1.0e-10 {
                            1.0e-9
                        } else {
                            s.dp - s.fp / s.ekunload
                        };
                    }
                    if (s.dmax - s.dp).abs() <= 1.0e-10 {
                        s.sn = s.sp - 1.0e-10;
                    }
                }
                (f, ek) = self.load_negative(s, &mut d, delta_d);
            }
            let enrgi = 0.5 * (f + s.fp) * delta_d;
            s.enrgc += enrgi;
            s.enrgtot += enrgi;
            s.rse = 0.5 * f * f / s.ekunload;
            if f * s.fp < 0.0
                && ((s.fp > 0.0 && s.dmax > s.fy_pos / s.ke)
                    || (s.fp < 0.0 && s.dmin < s.fy_neg / s.ke))
            {
                s.flagdeg = 1.0;
            }
            if s.flagdeg == 1.0 {
                deteriorate(&self.p, s, delta_d);
            }
        }
        s.dp = d;
        s.fp = f;
        s.ek_p = ek;
        s.ek = ek;
        s.tangent = ek;
        (f, ek)
    }

    /// Loading towards positive deformations (OpenSees' `deltaD >= 0` branch).
    fn load_positive(&self, s: &mut ImkState, d: &mut f64, delta_d: f64) -> (f64, f64) {
        let (f, ek);
        if *d >= s.dmax {
            (f, ek) = self.pos_side(s).pos(d, &mut s.flag_stop);
            s.dmax = *d;
            s.fmax = f;
            s.dlst_pos = s.dmax + 1.0e-10;
            s.flst_pos = f;
        } else if s.sn.abs() > 1.0e-10 {
            let side = self.pos_side(s);
            let mut dmax = s.dmax;
            let (fmax, _) = side.pos(&mut dmax, &mut s.flag_stop);
            s.dmax = dmax;
            s.fmax = fmax;
            if *d <= s.sn {
                ek = s.ekunload;
                f = s.fp + ek * delta_d;
                if s.unl == 0.0 && (ek - s.ek_p).abs() > 1.0e-10 && s.dp != s.dmin {
                    s.dlst_neg = s.dp;
                    s.flst_neg = s.fp;
                }
            } else {
                let mut k = s.fmax / (s.dmax - s.sn);
                let mut f2 = k * (*d - s.sn);
                if s.dlst_pos > s.sn && s.dlst_pos < s.dmax {
                    let ekc = s.flst_pos / (s.dlst_pos - s.sn);
                    if ekc > k && s.flst_pos < s.fmax {
                        if *d < s.dlst_pos {
                            k = s.flst_pos / (s.dlst_pos - s.sn);
                            f2 = k * (*d - s.sn);
                        } else {
                            k = (s.fmax - s.flst_pos) / (s.dmax - s.dlst_pos);
                            f2 = s.flst_pos + k * (*d - s.dlst_pos);
                        }
                    }
                }
                let f1 = s.fp + s.ekunload * delta_d;
                f = if f1 < f2 { f1 } else { f2 };
                ek = if (f - f1).abs() < 1.0e-10 {
                    s.ekunload
                } else {
                    k
                };
            }
        } else if *d > 0.0 {
            (f, ek) = self.pos_side(s).pos(d, &mut s.flag_stop);
        } else {
            (f, ek) = self.neg_side(s).neg(d, &mut s.flag_stop);
        }
        (f, ek)
    }

    /// Loading towards negative deformations (OpenSees' `deltaD < 0` branch).
    fn load_negative(&self, s: &mut ImkState, d: &mut f64, delta_d: f64) -> (f64, f64) {
        let (f, ek);
        if *d <= s.dmin {
            (f, ek) = self.neg_side(s).neg(d, &mut s.flag_stop);
            s.dmin = *d;
            s.fmin = f;
            s.dlst_neg = s.dmin - 1.0e-10;
            s.flst_neg = f;
        } else if s.sp.abs() > 1.0e-10 {
            let side = self.neg_side(s);
            let mut dmin = s.dmin;
            let (fmin, _) = side.neg(&mut dmin, &mut s.flag_stop);
            s.dmin = dmin;
            s.fmin = fmin;
            if *d >= s.sp {
                ek = s.ekunload;
                f = s.fp + ek * delta_d;
                if s.unl == 0.0 && (ek - s.ek_p).abs() > 1.0e-10 && s.dp != s.dmax {
                    s.dlst_pos = s.dp;
                    s.flst_pos = s.fp;
                }
            } else {
                let mut k = s.fmin / (s.dmin - s.sp);
                let mut f2 = k * (*d - s.sp);
                if s.dlst_neg < s.sp && s.dlst_neg > s.dmin {
                    let ekc = s.flst_neg / (s.dlst_neg - s.sp);
                    if ekc > k && s.flst_neg > s.fmin {
                        if *d > s.dlst_neg {
                            k = s.flst_neg / (s.dlst_neg - s.sp);
                            f2 = k * (*d - s.sp);
                        } else {
                            k = (s.fmin - s.flst_neg) / (s.dmin - s.dlst_neg);
                            f2 = s.flst_neg + k * (*d - s.dlst_neg);
                        }
                    }
                }
                let f1 = s.fp + s.ekunload * delta_d;
                f = if f1 > f2 { f1 } else { f2 };
                ek = if (f - f1).abs() < 1.0e-10 {
                    s.ekunload
                } else {
                    k
                };
            }
        } else if *d > 0.0 {
            (f, ek) = self.pos_side(s).pos(d, &mut s.flag_stop);
        } else {
            (f, ek) = self.neg_side(s).neg(d, &mut s.flag_stop);
        }
        (f, ek)
    }
}

// Not `restarts_exactly`: along restart_tests.rs's growing cycles past the ultimate
// deformation one zero increment gave another force than the one committed.
impl Material for ModImkPeakOriented {
    fn state_len(&self) -> usize {
        ImkState::LEN
    }

    fn initial_state(&self, state: &mut [f64]) {
        let mut s = ImkState::default();
        self.first(&mut s, 0.0);
        s.kon = 0.0;
        s.ek_p = 0.0;
        s.tangent = self.ke();
        s.store(state);
    }

    fn response(
        &self,
        u: f64,
        _rate: f64,
        committed: &[f64],
        trial: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        let mut s = ImkState::load(committed);
        let (f, k) = self.trial(u, &mut s);
        s.committed_once = 1.0;
        s.store(trial);
        Ok((f, k))
    }

    fn initial_tangent(&self) -> f64 {
        self.ke()
    }

    fn stored_energy(&self, state: &[f64], _u: f64, force: f64) -> f64 {
        let k = ImkState::load(state).ekunload;
        if k > 0.0 {
            0.5 * force * force / k
        } else {
            0.0
        }
    }
}
