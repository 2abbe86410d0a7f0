//! `Pinching4`: a four-point (quadrilinear) envelope, trilinear unload-reload paths with
//! pinching, and damage of unloading stiffness, reloading deformation and strength from
//! displacement history and dissipated energy (or cycles) — Lowes, Mitra & Altoontash
//! (2003), as OpenSees' `Pinching4Material`, whose state determination this follows line for
//! line, its `commitState` done here (docs/materials.md, "Pinching4").
//!
//! OpenSees keeps the damaged envelope, unloading stiffnesses and "used" damage indices in
//! members that are set in `commitState` from the trial ones and not reverted; they are
//! internal variables here. The committed deformation rate of a step whose increment is
//! below 1e-12 is 0 (OpenSees' `TstrainRate` after its last revert).

use super::pinching4_def::{P4State, Pinching4, Pinching4Params, Work};
use super::pinching4_paths::{path3, path4, piecewise};
use super::state::require;
use super::Material;
use crate::error::CoreError;

impl Pinching4 {
    /// The material; an error names the first parameter out of its domain.
    pub fn new(p: Pinching4Params) -> Result<Self, CoreError> {
        const PN: [&str; 4] = ["ePd1", "ePd2", "ePd3", "ePd4"];
        const NN: [&str; 4] = ["eNd1", "eNd2", "eNd3", "eNd4"];
        const PF: [&str; 4] = ["ePf1", "ePf2", "ePf3", "ePf4"];
        const NF: [&str; 4] = ["eNf1", "eNf2", "eNf3", "eNf4"];
        let mut prev = (0.0, 0.0);
        for k in 0..4 {
            require(true, PF[k], p.pos[k].0, "a force")?;
            require(true, NF[k], p.neg[k].0, "a force")?;
            let msg = "beyond the previous point (deformations increase away from 0)";
            require(p.pos[k].1 > prev.0, PN[k], p.pos[k].1, msg)?;
            require(p.neg[k].1 < prev.1, NN[k], p.neg[k].1, msg)?;
            prev = (p.pos[k].1, p.neg[k].1);
        }
        require(p.pos[0].0 > 0.0, "ePf1", p.pos[0].0, "> 0")?;
        require(p.neg[0].0 < 0.0, "eNf1", p.neg[0].0, "< 0")?;
        let names = [
            ["rDispP", "rForceP", "uForceP"],
            ["rDispN", "rForceN", "uForceN"],
        ];
        for (vals, names) in [(p.pinch_pos, names[0]), (p.pinch_neg, names[1])] {
            for (v, name) in vals.into_iter().zip(names) {
                require(true, name, v, "a ratio")?;
            }
        }
        let gnames = [
            ["gK1", "gK2", "gK3", "gK4", "gKLim"],
            ["gD1", "gD2", "gD3", "gD4", "gDLim"],
            ["gF1", "gF2", "gF3", "gF4", "gFLim"],
        ];
        for (vals, names) in [(p.gk, gnames[0]), (p.gd, gnames[1]), (p.gf, gnames[2])] {
            for (v, name) in vals.into_iter().zip(names) {
                require(v >= 0.0, name, v, ">= 0")?;
            }
        }
        require(p.ge >= 0.0, "gE", p.ge, ">= 0")?;
        Ok(Self::envelope(p))
    }

    /// OpenSees' `SetEnvelope`.
    fn envelope(p: Pinching4Params) -> Self {
        let [(f1p, d1p), _, (f3p, d3p), (f4p, d4p)] = p.pos;
        let [(f1n, d1n), _, (f3n, d3n), (f4n, d4n)] = p.neg;
        let k_pos = f1p / d1p;
        let k_neg = f1n / d1n;
        let k = if k_pos > k_neg { k_pos } else { k_neg };
        let u = if d1p > -d1n { 1e-4 * d1p } else { -1e-4 * d1n };
        let mut pos_strain = [u, 0.0, 0.0, 0.0, 0.0, 0.0];
        let mut pos_stress = [u * k, 0.0, 0.0, 0.0, 0.0, 0.0];
        let mut neg_strain = [-u, 0.0, 0.0, 0.0, 0.0, 0.0];
        let mut neg_stress = [-u * k, 0.0, 0.0, 0.0, 0.0, 0.0];
        for i in 0..4 {
            (pos_stress[i + 1], pos_strain[i + 1]) = p.pos[i];
            (neg_stress[i + 1], neg_strain[i + 1]) = p.neg[i];
        }
        let k1 = (f4p - f3p) / (d4p - d3p);
        let k2 = (f4n - f3n) / (d4n - d3n);
        pos_strain[5] = 1e6 * d4p;
        pos_stress[5] = if k1 > 0.0 {
            f4p + k1 * (pos_strain[5] - d4p)
        } else {
            f4p * 1.1
        };
        neg_strain[5] = 1e6 * d4n;
        neg_stress[5] = if k2 > 0.0 {
            f4n + k2 * (neg_strain[5] - d4n)
        } else {
            f4n * 1.1
        };
        let k_elastic_pos = pos_stress[1] / pos_strain[1];
        let k_elastic_neg = neg_stress[1] / neg_strain[1];
        let energy = |strain: &[f64; 6], stress: &[f64; 6]| {
            let mut e = 0.5 * strain[0] * stress[0];
            for j in 0..4 {
                e += 0.5 * (stress[j] + stress[j + 1]) * (strain[j + 1] - strain[j]);
            }
            e
        };
        let ep = energy(&pos_strain, &pos_stress);
        let en = energy(&neg_strain, &neg_stress);
        let max_energy = if ep > en { ep } else { en };
        Self {
            energy_capacity: p.ge * max_energy,
            p,
            pos_strain,
            pos_stress,
            neg_strain,
            neg_stress,
            k_elastic_pos,
            k_elastic_neg,
        }
    }

    /// The parameters.
    pub fn params(&self) -> &Pinching4Params {
        &self.p
    }
}

impl Work<'_> {
    fn damage_neg(&mut self) {
        self.t.gamma_f_used = self.c.gamma_f;
        for i in 0..6 {
            self.neg_d[i] = self.m.neg_stress[i] * (1.0 - self.t.gamma_f_used);
        }
    }

    fn damage_pos(&mut self) {
        self.t.gamma_f_used = self.c.gamma_f;
        for i in 0..6 {
            self.pos_d[i] = self.m.pos_stress[i] * (1.0 - self.t.gamma_f_used);
        }
    }

    fn set_bounds(&mut self, low: (f64, f64), hgh: (f64, f64)) {
        (self.t.low_strain, self.t.low_stress) = low;
        (self.t.hgh_strain, self.t.hgh_stress) = hgh;
    }

    /// OpenSees' `getstate`: the branch (0 initial, 1/2 positive/negative envelope, 3/4
    /// unload-reload towards negative/positive) and its end points.
    fn get_state(&mut self, u: f64, du: f64) {
        let m = self.m;
        let (ps, pf, ns, nf) = (&m.pos_strain, &m.pos_stress, &m.neg_strain, &m.neg_stress);
        let cid = du * self.c.strain_rate <= 0.0;
        let mut new_state = None;
        let t = &self.t;
        if !(u < t.low_strain || u > t.hgh_strain || cid) {
            return;
        }
        let (cs, cf) = (self.c.strain, self.c.stress);
        match self.t.state as i32 {
            0 => {
                if u > self.t.hgh_strain {
                    new_state = Some(1.0);
                    self.set_bounds((ps[0], pf[0]), (ps[5], pf[5]));
                } else if u < self.t.low_strain {
                    new_state = Some(2.0);
                    self.set_bounds((ns[5], nf[5]), (ns[0], nf[0]));
                }
            }
            1 if du < 0.0 => {
                if cs > self.t.max_dmnd {
                    self.t.max_dmnd = u - du;
                }
                if self.t.max_dmnd < self.u_max_d {
                    self.t.max_dmnd = self.u_max_d;
                }
                self.damage_neg();
                if u < self.u_min_d {
                    new_state = Some(2.0);
                    self.set_bounds((ns[5], nf[5]), (ns[0], nf[0]));
                } else {
                    new_state = Some(3.0);
                    let low = (self.u_min_d, self.neg_env(self.u_min_d).0);
                    self.set_bounds(low, (cs, cf));
                }
                self.t.gamma_k_used = self.c.gamma_k;
                self.k_pos_d = m.k_elastic_pos * (1.0 - self.t.gamma_k_used);
            }
            2 if du > 0.0 => {
                if cs < self.t.min_dmnd {
                    self.t.min_dmnd = cs;
                }
                if self.t.min_dmnd > self.u_min_d {
                    self.t.min_dmnd = self.u_min_d;
                }
                self.damage_pos();
                if u > self.u_max_d {
                    new_state = Some(1.0);
                    self.set_bounds((ps[0], pf[0]), (ps[5], pf[5]));
                } else {
                    new_state = Some(4.0);
                    let hgh = (self.u_max_d, self.pos_env(self.u_max_d).0);
                    self.set_bounds((cs, cf), hgh);
                }
                self.t.gamma_k_used = self.c.gamma_k;
                self.k_neg_d = m.k_elastic_neg * (1.0 - self.t.gamma_k_used);
            }
            3 => {
                if u < self.t.low_strain {
                    new_state = Some(2.0);
                    let (l, h) = ((ns[5], self.neg_d[5]), (ns[0], self.neg_d[0]));
                    self.set_bounds(l, h);
                } else if u > self.u_max_d && du > 0.0 {
                    new_state = Some(1.0);
                    self.set_bounds((ps[0], pf[0]), (ps[5], pf[5]));
                } else if du > 0.0 {
                    new_state = Some(4.0);
                    self.damage_pos();
                    let hgh = (self.u_max_d, self.pos_env(self.u_max_d).0);
                    self.set_bounds((cs, cf), hgh);
                    self.t.gamma_k_used = self.c.gamma_k;
                    self.k_neg_d = m.k_elastic_neg * (1.0 - self.t.gamma_k_used);
                }
            }
            4 => {
                if u > self.t.hgh_strain {
                    new_state = Some(1.0);
                    let (l, h) = ((ps[0], self.pos_d[0]), (ps[5], self.pos_d[5]));
                    self.set_bounds(l, h);
                } else if u < self.u_min_d && du < 0.0 {
                    new_state = Some(2.0);
                    let (l, h) = ((ns[5], self.neg_d[5]), (ns[0], self.neg_d[0]));
                    self.set_bounds(l, h);
                } else if du < 0.0 {
                    new_state = Some(3.0);
                    self.damage_neg();
                    let low = (self.u_min_d, self.neg_env(self.u_min_d).0);
                    self.set_bounds(low, (cs, cf));
                    self.t.gamma_k_used = self.c.gamma_k;
                    self.k_pos_d = m.k_elastic_pos * (1.0 - self.t.gamma_k_used);
                }
            }
            _ => {}
        }
        if let Some(s) = new_state {
            self.t.state = s;
        }
    }

    /// OpenSees' `setTrialStrain` followed by its `commitState`: `(F, dF/du)`.
    fn trial(&mut self, strain: f64) -> (f64, f64) {
        let m = self.m;
        self.t.strain = strain;
        let mut dstrain = strain - self.c.strain;
        if dstrain < 1e-12 && dstrain > -1e-12 {
            dstrain = 0.0;
        }
        self.get_state(strain, dstrain);
        let (stress, tangent) = match self.t.state as i32 {
            0 => {
                let k = m.pos_stress[0] / m.pos_strain[0];
                (k * strain, k)
            }
            1 => self.pos_env(strain),
            2 => self.neg_env(strain),
            3 => {
                let k = if self.t.hgh_strain < 0.0 {
                    self.k_neg_d
                } else {
                    self.k_pos_d
                };
                let (s, f) = path3(self, k);
                piecewise(&s, &f, strain)
            }
            _ => {
                let k = if self.t.low_strain < 0.0 {
                    self.k_neg_d
                } else {
                    self.k_pos_d
                };
                let (s, f) = path4(self, k);
                piecewise(&s, &f, strain)
            }
        };
        self.t.stress = stress;
        let denergy = 0.5 * (stress + self.c.stress) * dstrain;
        let elastic = if strain > 0.0 {
            0.5 * stress / self.k_pos_d * stress
        } else {
            0.5 * stress / self.k_neg_d * stress
        };
        self.t.energy = self.c.energy + denergy;
        self.update_damage(strain, dstrain, elastic);
        // commitState
        self.t.strain_rate = if dstrain.abs() > 1e-12 { dstrain } else { 0.0 };
        (stress, tangent)
    }
}

// Not `restarts_exactly`: a zero increment can take another branch than the increment that
// committed the state (found on an SDOF under a record: 5.5e-6 of the force once in 4,000
// steps), so the integrators evaluate the start of each step again.
impl Material for Pinching4 {
    fn state_len(&self) -> usize {
        P4State::LEN
    }

    fn initial_state(&self, state: &mut [f64]) {
        let s = P4State {
            low_strain: self.neg_strain[0],
            low_stress: self.neg_stress[0],
            hgh_strain: self.pos_strain[0],
            hgh_stress: self.pos_stress[0],
            min_dmnd: self.neg_strain[1],
            max_dmnd: self.pos_strain[1],
            powers_of: -1.0,
            ..P4State::default()
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
        let c = P4State::load(committed);
        let mut w = Work {
            m: self,
            c: &c,
            t: c,
            k_pos_d: self.k_elastic_pos * (1.0 - c.gamma_k_used),
            k_neg_d: self.k_elastic_neg * (1.0 - c.gamma_k_used),
            u_max_d: c.max_dmnd * (1.0 + c.gamma_d),
            u_min_d: c.min_dmnd * (1.0 + c.gamma_d),
            pos_d: self.pos_stress.map(|f| f * (1.0 - c.gamma_f_used)),
            neg_d: self.neg_stress.map(|f| f * (1.0 - c.gamma_f_used)),
        };
        let out = w.trial(u);
        w.t.store(trial);
        Ok(out)
    }

    fn initial_tangent(&self) -> f64 {
        self.pos_stress[0] / self.pos_strain[0]
    }

    fn stored_energy(&self, state: &[f64], _u: f64, force: f64) -> f64 {
        let s = P4State::load(state);
        let k = if force > 0.0 {
            self.k_elastic_pos
        } else {
            self.k_elastic_neg
        } * (1.0 - s.gamma_k_used);
        if k > 0.0 {
            0.5 * force * force / k
        } else {
            0.0
        }
    }
}
