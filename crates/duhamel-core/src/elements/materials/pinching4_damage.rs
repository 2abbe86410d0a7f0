//! The damage indices of [`Pinching4`](super::pinching4::Pinching4) (Lowes, Mitra &
//! Altoontash 2003, eq. for `delta_k`, `delta_d`, `delta_f`): `gamma_1 (u_max/u_ult)^gamma_3 +
//! gamma_2 (E/E_capacity)^gamma_4` (or the number of cycles in place of the energy ratio),
//! capped by `gamma_lim` and, for the unloading stiffness, by the secant to the largest
//! deformation — OpenSees' `updateDmg`, line for line.

use super::pinching4_def::{Pinching4Damage, Work};

impl Work<'_> {
    /// OpenSees' `updateDmg`: the trial damage indices.
    pub(crate) fn update_damage(&mut self, strain: f64, dstrain: f64, elastic_energy: f64) {
        let m = self.m;
        let t = &self.t;
        let umax_abs = if t.max_dmnd > -t.min_dmnd {
            t.max_dmnd
        } else {
            -t.min_dmnd
        };
        let uult_abs = if m.pos_strain[4] > -m.neg_strain[4] {
            m.pos_strain[4]
        } else {
            -m.neg_strain[4]
        };
        self.t.n_cycle = self.c.n_cycle + dstrain.abs() / (4.0 * umax_abs);
        let inside = strain < uult_abs && strain > -uult_abs;
        if !inside {
            return;
        }
        let kmin_p = self.pos_env(self.t.max_dmnd).0 / self.t.max_dmnd;
        let kmin_n = self.neg_env(self.t.min_dmnd).0 / self.t.min_dmnd;
        let (rp, rn) = (kmin_p / m.k_elastic_pos, kmin_n / m.k_elastic_neg);
        let (gk, gd, gf) = (&m.p.gk, &m.p.gd, &m.p.gf);
        if self.t.energy < m.energy_capacity {
            // the deformation terms: the committed ones while u_max stays (bit for bit)
            if umax_abs.to_bits() != self.t.powers_of.to_bits() {
                let ratio = umax_abs / uult_abs;
                self.t.powers_of = umax_abs;
                self.t.power_k = ratio.powf(gk[2]);
                self.t.power_d = ratio.powf(gd[2]);
                self.t.power_f = ratio.powf(gf[2]);
            }
            let mut g_k = gk[0] * self.t.power_k;
            let mut g_d = gd[0] * self.t.power_d;
            let mut g_f = gf[0] * self.t.power_f;
            let measure = match m.p.damage {
                Pinching4Damage::Energy if self.t.energy > elastic_energy => {
                    Some((self.t.energy - elastic_energy) / m.energy_capacity)
                }
                Pinching4Damage::Cycle => Some(self.t.n_cycle),
                Pinching4Damage::Energy => None,
            };
            if let Some(x) = measure {
                g_k += gk[1] * x.powf(gk[3]);
                g_d += gd[1] * x.powf(gd[3]);
                g_f += gf[1] * x.powf(gf[3]);
            }
            let kmin = if rp > rn { rp } else { rn };
            let lim_env = if 0.0 > 1.0 - kmin { 0.0 } else { 1.0 - kmin };
            let k1 = if g_k < gk[4] { g_k } else { gk[4] };
            self.t.gamma_k = if k1 < lim_env { k1 } else { lim_env };
            self.t.gamma_d = if g_d < gd[4] { g_d } else { gd[4] };
            self.t.gamma_f = if g_f < gf[4] { g_f } else { gf[4] };
        } else {
            let kmin = if rp >= rn { rp } else { rn };
            let lim_env = if 0.0 > 1.0 - kmin { 0.0 } else { 1.0 - kmin };
            self.t.gamma_k = if gk[4] < lim_env { gk[4] } else { lim_env };
            self.t.gamma_d = gd[4];
            self.t.gamma_f = gf[4];
        }
    }
}
