//! The cyclic deterioration of [`ModImkPeakOriented`](super::imk::ModImkPeakOriented) at the
//! end of a half cycle (the force changed sign after a yield): basic strength and hardening
//! (`beta_s`), post-capping strength (`beta_c`), accelerated reloading (`beta_a`), each
//! `beta_i = (E_i / (E_t - sum_j E_j))^c` (Ibarra, Medina & Krawinkler 2005, eq. 4), applied
//! to the side being loaded as `(1 - beta D)` — OpenSees' `flagdeg == 1` block.

use super::imk_envelope::Side;
use super::imk_params::{energy_ratio, ImkState, ModImkParams};

/// The three deterioration parameters `(beta_s, beta_a, beta_c)` of the half cycle just
/// closed, as OpenSees computes them (the first capacity exceeded takes the whole step).
fn betas(p: &ModImkParams, s: &ImkState) -> (f64, f64, f64) {
    let (mut bs, mut ba, mut bc) = (0.0, 0.0, 0.0);
    if s.enrgtot >= s.enrgts && s.enrgts != 0.0 {
        bs = 1.0;
    } else if s.enrgtot >= s.enrgta && s.enrgta != 0.0 {
        ba = 1.0;
    } else if s.enrgtot >= s.enrgtd && s.enrgtd != 0.0 {
        // OpenSees: `Enrgtd == 0.0` (a typo; see the module documentation of `imk`)
        bc = 1.0;
    } else {
        let beta = |lambda: f64, et: f64, c: f64| {
            if lambda != 0.0 {
                let b = energy_ratio(s.enrgc, et - s.enrgtot, c);
                if b.abs() >= 1.0 {
                    1.0
                } else {
                    b
                }
            } else {
                0.0
            }
        };
        bs = beta(p.lambda_s, s.enrgts, p.c_s);
        ba = beta(p.lambda_a, s.enrgta, p.c_a);
        bc = beta(p.lambda_c, s.enrgtd, p.c_c);
    }
    (bs, ba, bc)
}

/// A ratio `r` of the spring (amplified by `n`) back to the member's: `r (1+n) / (1+n r)`.
fn member(r: f64, n: f64) -> f64 {
    r * (1.0 + n) / (1.0 + n * r)
}

/// Deteriorates the side that the half cycle loaded (`delta_d < 0`: negative).
pub(crate) fn deteriorate(p: &ModImkParams, s: &mut ImkState, delta_d: f64) {
    let (n, k0, ke) = (p.n_factor, p.k0, s.ke);
    let (bs, ba, bc) = betas(p, s);
    s.ekexcurs = s.ekunload;
    s.enrgc = 0.0;
    if delta_d < 0.0 {
        s.fy_neg *= 1.0 - bs * p.d_neg;
        let alfa = member(s.alfa_neg, n) * (1.0 - bs * p.d_neg);
        s.alfa_neg = alfa / (1.0 + n * (1.0 - alfa));
        s.f_cap_ref_neg *= 1.0 - bc * p.d_neg;
        let (am, cm) = (member(s.alfa_neg, n), member(s.cap_slope_neg, n));
        let d1 = s.f_cap_ref_neg / (k0 - cm * k0);
        let d2 = (s.f_cap_ref_neg + am * k0 * s.fy_neg / k0 - s.fy_neg) / (am * k0 - cm * k0);
        let cp_orig = if d1 < d2 { d1 } else { d2 };
        if ke > k0 {
            s.dmin += s.fmin / k0;
            s.dmin *= 1.0 + ba;
            let side = Side {
                fy: s.fy_neg,
                alpha: am,
                alpha_cap: cm,
                cp: cp_orig,
                elstk: k0,
                fyield: p.my_neg,
                resfac: p.res_neg,
                frac: -p.theta_u_neg,
            };
            let mut dmin = s.dmin;
            let (f_orig, _) = side.neg(&mut dmin, &mut s.flag_stop);
            s.dmin = dmin - f_orig / k0;
        } else {
            s.dmin *= 1.0 + ba;
        }
        let dy = s.fy_neg / ke;
        s.ekhard_neg = s.alfa_neg * ke;
        let d1 = s.f_cap_ref_neg / (ke - s.cap_slope_neg * ke);
        let d2 = (s.f_cap_ref_neg + s.ekhard_neg * dy - s.fy_neg)
            / (s.ekhard_neg - s.cap_slope_neg * ke);
        s.cp_neg = if d1 < d2 { d1 } else { d2 };
    } else {
        s.fy_pos *= 1.0 - bs * p.d_plus;
        let alfa = member(s.alfa_pos, n) * (1.0 - bs * p.d_plus);
        s.alfa_pos = alfa / (1.0 + n * (1.0 - alfa));
        s.f_cap_ref_pos *= 1.0 - bc * p.d_plus;
        let (am, cm) = (member(s.alfa_pos, n), member(s.cap_slope_pos, n));
        let d1 = s.f_cap_ref_pos / (k0 - cm * k0);
        let d2 = (s.f_cap_ref_pos + am * k0 * s.fy_pos / k0 - s.fy_pos) / (am * k0 - cm * k0);
        let cp_orig = if d1 > d2 { d1 } else { d2 };
        if ke > k0 {
            s.dmax += s.fmax / k0;
            s.dmax *= 1.0 + ba;
            let side = Side {
                fy: s.fy_pos,
                alpha: am,
                alpha_cap: cm,
                cp: cp_orig,
                elstk: k0,
                fyield: p.my_plus,
                resfac: p.res_plus,
                frac: p.theta_u_plus,
            };
            let mut dmax = s.dmax;
            let (f_orig, _) = side.pos(&mut dmax, &mut s.flag_stop);
            s.dmax = dmax - f_orig / k0;
        } else {
            s.dmax *= 1.0 + ba;
        }
        let dy = s.fy_pos / ke;
        s.ekhard_pos = s.alfa_pos * ke;
        let d1 = s.f_cap_ref_pos / (ke - s.cap_slope_pos * ke);
        let d2 = (s.f_cap_ref_pos + s.ekhard_pos * dy - s.fy_pos)
            / (s.ekhard_pos - s.cap_slope_pos * ke);
        s.cp_pos = if d1 > d2 { d1 } else { d2 };
    }
}
