//! `IMKBilin`: the modified Ibarra-Medina-Krawinkler deterioration model with a bilinear
//! hysteresis (Lignos & Krawinkler 2011; Lignos, Hartloper, Elkady, Deierlein & Hamburger
//! 2019), as OpenSees' `IMKBilin` (Elkady & Kolani, 2022), whose state determination this
//! follows line for line. Departures (docs/materials.md, "IMKBilin"):
//!
//! * the tangent is the exact derivative of the force at fixed committed variables (the
//!   branch slope, 0 on a flat branch and after failure); OpenSees reports the secant
//!   `(F - F_committed) / dU` of the step, 1e-6 where that is zero;
//! * a reference energy exhausted before the half cycle (`E_t - sum E_j <= 0` with
//!   `Lambda > 0`) fails the material (`beta = 1`, as Ibarra et al. 2005 and OpenSees'
//!   `ModIMKPeakOriented` do), where OpenSees' `IMKBilin` takes the negative ratio to a
//!   power (0 after its clamp for `c = 1`, NaN for a non-integer `c`).

use super::imk_bilin_backbone::{bilin_update, Backbone};
use super::state::{flag, material_state, require};
use super::Material;
use crate::error::CoreError;

/// The parameters of [`ImkBilin`], in OpenSees' order; negative-side deformations and
/// strength may be given with either sign (OpenSees takes their magnitudes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImkBilinParams {
    /// Elastic stiffness.
    pub ke: f64,
    /// Pre-capping plastic, post-capping and ultimate deformations, positive side.
    pub theta_p_plus: f64,
    pub theta_pc_plus: f64,
    pub theta_u_plus: f64,
    /// Effective yield strength, positive side.
    pub my_plus: f64,
    /// Capping (maximum) strength and residual strength as ratios of `my_plus`.
    pub mmax_my_plus: f64,
    pub res_plus: f64,
    /// The same for the negative side.
    pub theta_p_neg: f64,
    pub theta_pc_neg: f64,
    pub theta_u_neg: f64,
    pub my_neg: f64,
    pub mmax_my_neg: f64,
    pub res_neg: f64,
    /// Reference energies `Lambda My_plus` for strength, post-capping and unloading-stiffness
    /// deterioration (0: none).
    pub lambda_s: f64,
    pub lambda_c: f64,
    pub lambda_k: f64,
    /// Their exponents.
    pub c_s: f64,
    pub c_c: f64,
    pub c_k: f64,
    /// Rates of cyclic deterioration in each direction.
    pub d_plus: f64,
    pub d_neg: f64,
}

/// OpenSees' `IMKBilin` uniaxial material.
#[derive(Clone, Debug)]
pub struct ImkBilin {
    pub(crate) p: ImkBilinParams,
    /// The initial backbones (OpenSees' `*_0` values), both sides.
    pub(crate) init: [Backbone; 2],
    /// Reference energies `(S, C, K)`.
    pub(crate) eng_ref: [f64; 3],
}

material_state! {
    /// OpenSees' committed members of `IMKBilin`, and the last tangent.
    BilinState {
        pos_uy, pos_fy, pos_ucap, pos_fcap, pos_fres, pos_kp, pos_kpc,
        neg_uy, neg_fy, neg_ucap, neg_fcap, neg_fres, neg_kp, neg_kpc,
        ui, fi, kunload, eng_acml, eng_dspt,
        /// 0 elastic, 1 yielded, 2 residual reached, 3/4 strength lost on the positive /
        /// negative side, 5 on both (OpenSees' `Failure_State`).
        failure_state,
        on_backbone,
        /// The tangent returned with the committed force.
        kt,
    }
}

impl ImkBilin {
    /// The material; an error names the first parameter out of its domain.
    pub fn new(mut p: ImkBilinParams) -> Result<Self, CoreError> {
        p.theta_p_neg = p.theta_p_neg.abs();
        p.theta_pc_neg = p.theta_pc_neg.abs();
        p.theta_u_neg = p.theta_u_neg.abs();
        p.my_neg = p.my_neg.abs();
        require(p.ke > 0.0, "Ke", p.ke, "> 0")?;
        for (name, v) in [
            ("theta_p_plus", p.theta_p_plus),
            ("theta_pc_plus", p.theta_pc_plus),
            ("theta_u_plus", p.theta_u_plus),
            ("My_plus", p.my_plus),
            ("Mmax_My_plus", p.mmax_my_plus),
            ("theta_p_neg", p.theta_p_neg),
            ("theta_pc_neg", p.theta_pc_neg),
            ("theta_u_neg", p.theta_u_neg),
            ("My_neg", p.my_neg),
            ("Mmax_My_neg", p.mmax_my_neg),
        ] {
            require(v > 0.0, name, v, "nonzero (a magnitude > 0)")?;
        }
        for (name, v) in [
            ("lambda_s", p.lambda_s),
            ("lambda_c", p.lambda_c),
            ("lambda_k", p.lambda_k),
            ("c_s", p.c_s),
            ("c_c", p.c_c),
            ("c_k", p.c_k),
        ] {
            require(v >= 0.0, name, v, ">= 0")?;
        }
        for (name, v) in [
            ("res_plus", p.res_plus),
            ("res_neg", p.res_neg),
            ("D_plus", p.d_plus),
            ("D_neg", p.d_neg),
        ] {
            require((0.0..=1.0).contains(&v), name, v, "in [0, 1]")?;
        }
        let side = |up: f64, upc: f64, fy: f64, fcap_fy: f64, fres_fy: f64, sign: f64| {
            let uy = fy / p.ke;
            let fcap = fcap_fy * fy;
            Backbone {
                uy: sign * uy,
                fy: sign * fy,
                ucap: sign * (uy + up),
                fcap: sign * fcap,
                fres: sign * fy * fres_fy,
                kp: (fcap - fy) / up,
                kpc: -(fcap / upc),
            }
        };
        let init = [
            side(
                p.theta_p_plus,
                p.theta_pc_plus,
                p.my_plus,
                p.mmax_my_plus,
                p.res_plus,
                1.0,
            ),
            side(
                p.theta_p_neg,
                p.theta_pc_neg,
                p.my_neg,
                p.mmax_my_neg,
                p.res_neg,
                -1.0,
            ),
        ];
        let eng_ref = [
            p.lambda_s * p.my_plus,
            p.lambda_c * p.my_plus,
            p.lambda_k * p.my_plus,
        ];
        Ok(Self { p, init, eng_ref })
    }

    /// The parameters (negative-side magnitudes positive).
    pub fn params(&self) -> &ImkBilinParams {
        &self.p
    }

    /// OpenSees' `setTrialStrain` from the committed `s`: `(F, exact dF/dU)`.
    fn trial(&self, u: f64, s: &mut BilinState) -> (f64, f64) {
        let (ui_1, fi_1) = (s.ui, s.fi);
        s.ui = u;
        let du = u - ui_1;
        if s.failure_state == 5.0 {
            s.fi = 0.0;
            s.kt = 0.0;
            return (0.0, 0.0);
        }
        if du == 0.0 {
            s.fi = fi_1;
            return (s.fi, s.kt);
        }
        let ke = self.p.ke;
        let mut on_backbone = s.on_backbone == 1.0;
        let mut fail_k = false;
        let (mut fail_s, mut fail_c) = (false, false);
        if (on_backbone && fi_1 * du < 0.0) || (on_backbone && fi_1 == 0.0 && ui_1 * du <= 0.0) {
            on_backbone = false;
            let elastic = 0.5 * (fi_1 / s.kunload) * fi_1;
            let epj_k = s.eng_acml - elastic;
            let ei_k = s.eng_acml - s.eng_dspt - elastic;
            let (beta_k, fk) = beta(ei_k, self.eng_ref[2], epj_k, self.p.c_k);
            fail_k = fk;
            s.kunload *= 1.0 - beta_k;
            if s.failure_state > 1.0 {
                s.kunload = 0.5 * ke;
            }
        }
        let mut fi = fi_1 + s.kunload * du;
        let mut kt = s.kunload;
        if !on_backbone && fi_1 * fi <= 0.0 && s.failure_state > 0.0 {
            let ei = (s.eng_acml - s.eng_dspt).max(0.0);
            let (beta_s, fs) = beta(ei, self.eng_ref[0], s.eng_acml, self.p.c_s);
            let (beta_c, fc) = beta(ei, self.eng_ref[1], s.eng_acml, self.p.c_c);
            fail_s = fs;
            fail_c = fc;
            s.eng_dspt = s.eng_acml;
            let side = usize::from(du <= 0.0);
            let dmg = if du > 0.0 {
                self.p.d_plus
            } else {
                self.p.d_neg
            };
            let b = bilin_update(
                self.backbones(s)[side],
                self.init[side],
                (ke, s.kunload, dmg),
                du > 0.0,
                (beta_s, beta_c),
                (ui_1, fi_1),
            );
            set_backbone(s, side, &b);
        }
        let b = self.backbones(s);
        if du > 0.0 {
            let (mut fb, mut kb) = b[0].force(u, true);
            if fb < b[0].fres || s.failure_state == 4.0 {
                (fb, kb) = (b[0].fres, 0.0);
            }
            if s.failure_state == 3.0 {
                (fb, kb) = (0.0, 0.0);
            }
            if fi > fb {
                (fi, kt) = (fb, kb);
                on_backbone = true;
            }
        } else {
            let (mut fb, mut kb) = b[1].force(u, false);
            if fb > b[1].fres || s.failure_state == 3.0 {
                (fb, kb) = (b[1].fres, 0.0);
            }
            if s.failure_state == 4.0 {
                (fb, kb) = (0.0, 0.0);
            }
            if fi < fb {
                (fi, kt) = (fb, kb);
                on_backbone = true;
            }
        }
        let res_p = b[0].residual_reached(u, fi, true);
        let res_n = b[1].residual_reached(u, fi, false);
        let fail_dp = du > 0.0 && u >= self.p.theta_u_plus;
        let fail_dn = du < 0.0 && u <= -self.p.theta_u_neg;
        let fail_rp = du > 0.0 && on_backbone && fi <= 0.0;
        let fail_rn = du < 0.0 && on_backbone && fi >= 0.0;
        let fs = s.failure_state;
        if fail_s || fail_c || fail_k {
            (fi, kt) = (0.0, 0.0);
            s.failure_state = 5.0;
        } else if fail_dp || fail_rp {
            (fi, kt) = (0.0, 0.0);
            s.failure_state = if fs == 4.0 { 5.0 } else { 3.0 };
        } else if fail_dn || fail_rn {
            (fi, kt) = (0.0, 0.0);
            s.failure_state = if fs == 3.0 { 5.0 } else { 4.0 };
        } else if fs < 2.0 && (res_p || res_n) {
            s.failure_state = 2.0;
        } else if fs == 0.0 && on_backbone {
            s.failure_state = 1.0;
        }
        s.eng_acml += 0.5 * (fi + fi_1) * du;
        s.fi = fi;
        s.kt = kt;
        s.on_backbone = flag(on_backbone);
        (fi, kt)
    }

    /// The current backbones `[positive, negative]` from the state.
    pub(crate) fn backbones(&self, s: &BilinState) -> [Backbone; 2] {
        [
            Backbone {
                uy: s.pos_uy,
                fy: s.pos_fy,
                ucap: s.pos_ucap,
                fcap: s.pos_fcap,
                fres: s.pos_fres,
                kp: s.pos_kp,
                kpc: s.pos_kpc,
            },
            Backbone {
                uy: s.neg_uy,
                fy: s.neg_fy,
                ucap: s.neg_ucap,
                fcap: s.neg_fcap,
                fres: s.neg_fres,
                kp: s.neg_kp,
                kpc: s.neg_kpc,
            },
        ]
    }
}

/// Stores the side `side` (0 positive, 1 negative) of the backbone in the state.
fn set_backbone(s: &mut BilinState, side: usize, b: &Backbone) {
    if side == 0 {
        (s.pos_uy, s.pos_fy, s.pos_ucap, s.pos_fcap) = (b.uy, b.fy, b.ucap, b.fcap);
        (s.pos_fres, s.pos_kp, s.pos_kpc) = (b.fres, b.kp, b.kpc);
    } else {
        (s.neg_uy, s.neg_fy, s.neg_ucap, s.neg_fcap) = (b.uy, b.fy, b.ucap, b.fcap);
        (s.neg_fres, s.neg_kp, s.neg_kpc) = (b.fres, b.kp, b.kpc);
    }
}

/// The deterioration parameter `(E_i / (E_ref - E_acc))^c`, clamped to [0, 1], and whether
/// it exceeded 1 (failure), as OpenSees computes it; departures: `E_ref = 0` (Lambda = 0)
/// means no deterioration, an exhausted capacity (`E_ref - E_acc <= 0`) fails, and a NaN (a
/// negative ratio to a non-integer power) is taken as 0.
pub(crate) fn beta(ei: f64, e_ref: f64, e_acc: f64, c: f64) -> (f64, bool) {
    if e_ref == 0.0 {
        return (0.0, false);
    }
    let left = e_ref - e_acc;
    if left <= 0.0 {
        return (1.0, true);
    }
    let b = (ei / left).powf(c);
    if b.is_nan() {
        return (0.0, false);
    }
    (b.clamp(0.0, 1.0), b > 1.0)
}

// Not `restarts_exactly` (not shown to hold: ModIMKPeakOriented's zero increment can change
// its force past the ultimate deformation, and this law shares its bookkeeping).
impl Material for ImkBilin {
    fn state_len(&self) -> usize {
        BilinState::LEN
    }

    fn initial_state(&self, state: &mut [f64]) {
        let [p, n] = self.init;
        let s = BilinState {
            pos_uy: p.uy,
            pos_fy: p.fy,
            pos_ucap: p.ucap,
            pos_fcap: p.fcap,
            pos_fres: p.fres,
            pos_kp: p.kp,
            pos_kpc: p.kpc,
            neg_uy: n.uy,
            neg_fy: n.fy,
            neg_ucap: n.ucap,
            neg_fcap: n.fcap,
            neg_fres: n.fres,
            neg_kp: n.kp,
            neg_kpc: n.kpc,
            kunload: self.p.ke,
            kt: self.p.ke,
            ..BilinState::default()
        };
        s.store(state);
    }

    fn response(
        &self,
        u: f64,
        _rate: f64,
        committed: &[f64],
        trial: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        let mut s = BilinState::load(committed);
        let out = self.trial(u, &mut s);
        s.store(trial);
        Ok(out)
    }

    fn initial_tangent(&self) -> f64 {
        self.p.ke
    }

    fn tangent_bound(&self) -> Option<f64> {
        // every branch is the unloading stiffness (<= Ke; Ke/2 after a residual) or a
        // backbone slope, and the backbone slopes only shrink from their initial values
        // (hardening by 1 - beta_s D or capped, post-capping by the lost strength)
        let mut k = self.p.ke;
        for b in &self.init {
            k = k.max(b.kp.abs()).max(b.kpc.abs());
        }
        Some(k)
    }

    fn stored_energy(&self, state: &[f64], _u: f64, force: f64) -> f64 {
        let k = BilinState::load(state).kunload;
        if k > 0.0 {
            0.5 * force * force / k
        } else {
            0.0
        }
    }
}
