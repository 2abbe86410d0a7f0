//! The backbone of [`ImkBilin`](super::imk_bilin::ImkBilin) and its update at a new
//! excursion: yield strength and hardening scaled by `1 - beta_s D`, the post-capping line
//! moved towards the origin by `1 - beta_c D`, the capping point their intersection, the
//! hardening slope capped so that the branch from the last reversal does not pass below the
//! residual — OpenSees' `IMKBilin` "UPDATE BACKBONE CURVE" block.

/// One side of the backbone (signed values on the negative side; `kp > 0`, `kpc <= 0` on both).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Backbone {
    pub uy: f64,
    pub fy: f64,
    pub ucap: f64,
    pub fcap: f64,
    pub fres: f64,
    pub kp: f64,
    pub kpc: f64,
}

impl Backbone {
    /// The hardening or post-capping line at `u` and its slope (before the residual clamp).
    pub(crate) fn force(&self, u: f64, positive: bool) -> (f64, f64) {
        let hardening = if positive {
            u < self.ucap
        } else {
            self.ucap < u
        };
        let k = if hardening { self.kp } else { self.kpc };
        (self.fcap + (u - self.ucap) * k, k)
    }

    /// Whether `(u, f)` is on or past the residual branch (OpenSees' `ResP` / `ResN`).
    pub(crate) fn residual_reached(&self, u: f64, f: f64, positive: bool) -> bool {
        if self.kpc == 0.0 {
            return f == self.fres;
        }
        let ures = (self.fres - self.fcap + self.kpc * self.ucap) / self.kpc;
        if positive {
            u >= ures
        } else {
            u <= ures
        }
    }
}

/// The side `b` deteriorated with `(beta_s, beta_c)` at rate `dmg` (`init` its initial
/// values, `ke` the elastic stiffness, `kunload` the unloading stiffness, the last reversal
/// at `(ui_1, fi_1)`; `positive`: the positive side).
pub(crate) fn bilin_update(
    side: Backbone,
    init: Backbone,
    (ke, kunload, dmg): (f64, f64, f64),
    positive: bool,
    (beta_s, beta_c): (f64, f64),
    (ui_1, fi_1): (f64, f64),
) -> Backbone {
    let mut b = side;
    let mut fcap_proj = b.fcap - b.kpc * b.ucap;
    b.fy *= 1.0 - beta_s * dmg;
    b.kp *= 1.0 - beta_s * dmg;
    fcap_proj *= 1.0 - beta_c * dmg;
    b.uy = b.fy / ke;
    let below = if positive {
        b.fy < b.fres
    } else {
        b.fy > b.fres
    };
    b.kpc = if below {
        0.0
    } else {
        init.kpc * (b.fy - b.fres) / (init.fy - b.fres)
    };
    let fy_proj = b.fy - b.kp * b.uy;
    b.ucap = if b.kp <= b.kpc {
        0.0
    } else {
        (fcap_proj - fy_proj) / (b.kp - b.kpc)
    };
    b.fcap = fy_proj + b.kp * b.ucap;
    let candidate = (b.fcap - b.fres) / (b.ucap - ui_1 - (b.fres - fi_1) / kunload);
    let cap_below = if positive {
        b.fcap < b.fres
    } else {
        b.fcap > b.fres
    };
    if cap_below {
        b.fy = b.fres;
        b.fcap = b.fres;
        b.kp = 0.0;
        b.kpc = 0.0;
        b.uy = b.fy / ke;
        b.ucap = 0.0;
    } else if candidate > 0.0 && b.kp > candidate {
        b.kp = candidate;
    }
    b
}
