//! `Hysteretic`: a bilinear or trilinear envelope with pinching of force and deformation,
//! damage from ductility and dissipated energy, and unloading stiffness degraded with
//! ductility — OpenSees' `HystereticMaterial` (written by M. H. Scott), whose state
//! determination this follows line for line, `commitState` included (docs/materials.md,
//! "Hysteretic").
//!
//! Flat branches report OpenSees' `1e-9 E` tangents (the force there is constant).

use std::cmp::Ordering;

use super::state::{material_state, require};
use super::Material;
use crate::error::CoreError;

/// OpenSees' `POS_INF_STRAIN`.
const INF_STRAIN: f64 = 1.0e16;

/// The parameters of [`Hysteretic`]: envelope points `(force, deformation)`, 2 or 3 per side
/// (negative side: negative values), pinching factors, damage factors and the unloading
/// degradation exponent, in OpenSees' order and meaning.
#[derive(Clone, Debug, PartialEq)]
pub struct HystereticParams {
    pub pos: Vec<(f64, f64)>,
    pub neg: Vec<(f64, f64)>,
    /// Pinching factor for deformation, `pinchX`.
    pub pinch_x: f64,
    /// Pinching factor for force, `pinchY`.
    pub pinch_y: f64,
    /// Damage due to ductility, `damage1`.
    pub damage1: f64,
    /// Damage due to energy, `damage2`.
    pub damage2: f64,
    /// Unloading stiffness degradation exponent, `beta` (unloading stiffness `E mu^-beta`).
    pub beta: f64,
}

/// One side of the envelope: points and slopes as OpenSees stores them.
#[derive(Clone, Copy, Debug)]
struct Envelope {
    /// `(moment, rotation)` of the three points (2-point input: the middle one halfway).
    m: [f64; 3],
    r: [f64; 3],
    e: [f64; 3],
}

/// OpenSees' `Hysteretic` uniaxial material.
#[derive(Clone, Debug)]
pub struct Hysteretic {
    p: HystereticParams,
    pos: Envelope,
    neg: Envelope,
    eup: f64,
    eun: f64,
    energy_a: f64,
}

material_state! {
    /// OpenSees' committed members of `HystereticMaterial`, its last tangent, and the
    /// unloading-stiffness factors `(kp, kn)` of its peaks `rot_max`, `rot_min`
    /// ([`Hysteretic::degradation`], kept so that a call computes its two powers only when a
    /// peak moves).
    HystState {
        rot_max, rot_min, rot_pu, rot_nu, energy_d, load_indicator, stress, strain, tangent,
        kp, kn,
    }
}

const NAMES: [[(&str, &str); 3]; 2] = [
    [("s1p", "e1p"), ("s2p", "e2p"), ("s3p", "e3p")],
    [("s1n", "e1n"), ("s2n", "e2n"), ("s3n", "e3n")],
];

/// The envelope of one side from 2 or 3 points (`sign` +1 or -1), checked as OpenSees does
/// (deformations strictly monotonic away from zero), and its share of OpenSees' `energyA`.
fn envelope(points: &[(f64, f64)], sign: f64, side: usize) -> Result<(Envelope, f64), CoreError> {
    let names = &NAMES[side];
    if !(points.len() == 2 || points.len() == 3) {
        return Err(CoreError::InvalidInput {
            name: if side == 0 { "pos" } else { "neg" },
            problem: format!(
                "must have 2 or 3 (force, deformation) points, got {}",
                points.len()
            ),
        });
    }
    let dirn = if sign > 0.0 { "> 0" } else { "< 0" };
    require(points[0].0 * sign > 0.0, names[0].0, points[0].0, dirn)?;
    let mut prev = 0.0;
    for (k, &(m, r)) in points.iter().enumerate() {
        let name = names[k];
        require(true, name.0, m, "a force value")?;
        let problem = if k == 0 {
            dirn.to_string()
        } else {
            format!("beyond the previous point's deformation {prev}")
        };
        require((r - prev) * sign > 0.0, name.1, r, &problem)?;
        prev = r;
    }
    let (m, r, energy) = if points.len() == 3 {
        let [(m1, r1), (m2, r2), (m3, r3)] = [points[0], points[1], points[2]];
        let energy = r1 * m1 + (r2 - r1) * (m2 + m1) + (r3 - r2) * (m3 + m2);
        ([m1, m2, m3], [r1, r2, r3], energy)
    } else {
        let [(m1, r1), (m3, r3)] = [points[0], points[1]];
        let energy = r1 * m1 + (r3 - r1) * (m3 + m1);
        ([m1, 0.5 * (m1 + m3), m3], [r1, 0.5 * (r1 + r3), r3], energy)
    };
    let e = [
        m[0] / r[0],
        (m[1] - m[0]) / (r[1] - r[0]),
        (m[2] - m[1]) / (r[2] - r[1]),
    ];
    Ok((Envelope { m, r, e }, energy))
}

impl Envelope {
    /// OpenSees' `posEnvlpStress` (`sign` +1) / `negEnvlpStress` (-1).
    fn stress(&self, u: f64, sign: f64) -> f64 {
        let x = u * sign;
        let [r1, r2, r3] = self.r.map(|r| r * sign);
        if x <= 0.0 {
            0.0
        } else if x <= r1 {
            self.e[0] * u
        } else if x <= r2 {
            self.m[0] + self.e[1] * (u - self.r[0])
        } else if x <= r3 || self.e[2] > 0.0 {
            self.m[1] + self.e[2] * (u - self.r[1])
        } else {
            self.m[2]
        }
    }

    /// OpenSees' `posEnvlpTangent` / `negEnvlpTangent`.
    fn tangent(&self, u: f64, sign: f64) -> f64 {
        let x = u * sign;
        let [r1, r2, r3] = self.r.map(|r| r * sign);
        if x < 0.0 {
            self.e[0] * 1.0e-9
        } else if x <= r1 {
            self.e[0]
        } else if x <= r2 {
            self.e[1]
        } else if x <= r3 || self.e[2] > 0.0 {
            self.e[2]
        } else {
            self.e[0] * 1.0e-9
        }
    }

    /// OpenSees' `posEnvlpRotlim` / `negEnvlpRotlim`: where a softening envelope reaches
    /// zero force (signed infinity when it does not).
    fn rotlim(&self, u: f64, sign: f64) -> f64 {
        let x = u * sign;
        let [r1, r2, _] = self.r.map(|r| r * sign);
        let inf = sign * INF_STRAIN;
        if x <= r1 {
            return inf;
        }
        let mut limit = inf;
        if x > r1 && x <= r2 && self.e[1] < 0.0 {
            limit = self.r[0] - self.m[0] / self.e[1];
        }
        if x > r2 && self.e[2] < 0.0 {
            limit = self.r[1] - self.m[1] / self.e[2];
        }
        if limit == inf || self.stress(limit, sign) * sign > 0.0 {
            inf
        } else {
            limit
        }
    }
}

impl Hysteretic {
    /// The material; an error names the first parameter out of its domain.
    pub fn new(p: HystereticParams) -> Result<Self, CoreError> {
        let (pos, ep) = envelope(&p.pos, 1.0, 0)?;
        let (neg, en) = envelope(&p.neg, -1.0, 1)?;
        for (name, v) in [("pinch_x", p.pinch_x), ("pinch_y", p.pinch_y)] {
            require((0.0..=1.0).contains(&v), name, v, "in [0, 1]")?;
        }
        for (name, v) in [
            ("damage1", p.damage1),
            ("damage2", p.damage2),
            ("beta", p.beta),
        ] {
            require(v >= 0.0, name, v, ">= 0")?;
        }
        let eup = pos.e.iter().copied().fold(pos.e[0], f64::max);
        let eun = neg.e.iter().copied().fold(neg.e[0], f64::max);
        Ok(Self {
            p,
            pos,
            neg,
            eup,
            eun,
            energy_a: 0.5 * (ep + en),
        })
    }

    /// The parameters.
    pub fn params(&self) -> &HystereticParams {
        &self.p
    }

    /// The unloading-stiffness factors `(kp, kn)` after the committed peaks.
    fn degradation(&self, s: &HystState) -> (f64, f64) {
        let f = |x: f64| {
            let k = x.powf(self.p.beta);
            if k < 1.0 {
                1.0
            } else {
                1.0 / k
            }
        };
        (f(s.rot_max / self.pos.r[0]), f(s.rot_min / self.neg.r[0]))
    }

    /// OpenSees' `positiveIncrement` (`sign` +1) and `negativeIncrement` (-1), written once
    /// for both directions: `c` committed, `t` trial.
    fn increment(&self, c: &HystState, t: &mut HystState, d_strain: f64, sign: f64) {
        let (kp, kn) = (c.kp, c.kn);
        // "this" side is the one being loaded, "other" the one being left
        let (this, other) = if sign > 0.0 {
            (&self.pos, &self.neg)
        } else {
            (&self.neg, &self.pos)
        };
        let (e_this, e_other) = if sign > 0.0 {
            (self.eup, self.eun)
        } else {
            (self.eun, self.eup)
        };
        let (k_this, k_other) = if sign > 0.0 { (kp, kn) } else { (kn, kp) };
        let (ind_this, ind_other) = if sign > 0.0 { (1.0, 2.0) } else { (2.0, 1.0) };
        let c_peak_other = if sign > 0.0 { c.rot_min } else { c.rot_max };
        let c_peak_this = if sign > 0.0 { c.rot_max } else { c.rot_min };
        let mut peak = if sign > 0.0 { t.rot_max } else { t.rot_min };
        let mut rel_other = if sign > 0.0 { t.rot_nu } else { t.rot_pu };
        if t.load_indicator == ind_other {
            t.load_indicator = ind_this;
            if c.stress * sign <= 0.0 {
                rel_other = c.strain - c.stress / (e_other * k_other);
                let energy = c.energy_d - 0.5 * c.stress / (e_other * k_other) * c.stress;
                let mut damfc = 0.0;
                if c_peak_other * sign < other.r[0] * sign {
                    damfc = self.p.damage2 * energy / self.energy_a;
                    damfc += self.p.damage1 * (c_peak_other - other.r[0]) / other.r[0];
                }
                peak = c_peak_this * (1.0 + damfc);
            }
        }
        t.load_indicator = ind_this;
        if peak * sign > INF_STRAIN {
            peak = sign * INF_STRAIN;
        }
        // OpenSees: `(TrotMax > rot1p) ? TrotMax : rot1p` (a NaN peak becomes rot1p)
        let beyond = (peak * sign).partial_cmp(&(this.r[0] * sign)) == Some(Ordering::Greater);
        if !beyond {
            peak = this.r[0];
        }
        let maxmom = this.stress(peak, sign);
        let rotlim = other.rotlim(c_peak_other, -sign);
        let rotrel = if rotlim * sign > rel_other * sign {
            rotlim
        } else {
            rel_other
        };
        let (px, py) = (self.p.pinch_x, self.p.pinch_y);
        let rotmp2 = peak - (1.0 - py) * maxmom / (e_this * k_this);
        let rotch = rotrel + (rotmp2 - rotrel) * px;
        let x = t.strain;
        let (stress, tangent);
        if x * sign < rel_other * sign {
            let k = e_other * k_other;
            let f = c.stress + k * d_strain;
            if f * sign >= 0.0 {
                (stress, tangent) = (0.0, e_other * 1.0e-9);
            } else {
                (stress, tangent) = (f, k);
            }
        } else if x * sign < rotch * sign {
            if x * sign <= rotrel * sign {
                (stress, tangent) = (0.0, e_this * 1.0e-9);
            } else {
                let k = maxmom * py / (rotch - rotrel);
                let f1 = c.stress + e_this * k_this * d_strain;
                let f2 = (x - rotrel) * k;
                (stress, tangent) = if f1 * sign < f2 * sign {
                    (f1, e_this * k_this)
                } else {
                    (f2, k)
                };
            }
        } else {
            let k = (1.0 - py) * maxmom / (peak - rotch);
            let f1 = c.stress + e_this * k_this * d_strain;
            let f2 = py * maxmom + (x - rotch) * k;
            (stress, tangent) = if f1 * sign < f2 * sign {
                (f1, e_this * k_this)
            } else {
                (f2, k)
            };
        }
        if sign > 0.0 {
            (t.rot_max, t.rot_nu) = (peak, rel_other);
        } else {
            (t.rot_min, t.rot_pu) = (peak, rel_other);
        }
        (t.stress, t.tangent) = (stress, tangent);
    }

    /// OpenSees' `setTrialStrain` from the committed `c`, into `t` (a copy of `c`).
    fn trial(&self, strain: f64, c: &HystState, t: &mut HystState) {
        if c.load_indicator == 0.0 && strain == 0.0 {
            return;
        }
        t.strain = strain;
        let d_strain = strain - c.strain;
        if d_strain.abs() < f64::EPSILON {
            return;
        }
        if t.load_indicator == 0.0 {
            t.load_indicator = if d_strain < 0.0 { 2.0 } else { 1.0 };
        }
        if strain >= c.rot_max {
            t.rot_max = strain;
            t.tangent = self.pos.tangent(strain, 1.0);
            t.stress = self.pos.stress(strain, 1.0);
            t.load_indicator = 1.0;
        } else if strain <= c.rot_min {
            t.rot_min = strain;
            t.tangent = self.neg.tangent(strain, -1.0);
            t.stress = self.neg.stress(strain, -1.0);
            t.load_indicator = 2.0;
        } else if d_strain < 0.0 {
            self.increment(c, t, d_strain, -1.0);
        } else if d_strain > 0.0 {
            self.increment(c, t, d_strain, 1.0);
        }
        t.energy_d = c.energy_d + 0.5 * (c.stress + t.stress) * d_strain;
    }
}

impl Material for Hysteretic {
    /// A zero increment leaves the committed variables and force as they are (checked in
    /// `restart_tests.rs`).
    fn restarts_exactly(&self) -> bool {
        true
    }

    fn state_len(&self) -> usize {
        HystState::LEN
    }

    fn initial_state(&self, state: &mut [f64]) {
        let mut s = HystState {
            tangent: self.pos.e[0],
            ..HystState::default()
        };
        (s.kp, s.kn) = self.degradation(&s);
        s.store(state);
    }

    fn response(
        &self,
        u: f64,
        _rate: f64,
        committed: &[f64],
        trial: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        let c = HystState::load(committed);
        let mut t = c;
        self.trial(u, &c, &mut t);
        if t.rot_max.to_bits() != c.rot_max.to_bits() || t.rot_min.to_bits() != c.rot_min.to_bits()
        {
            (t.kp, t.kn) = self.degradation(&t);
        }
        t.store(trial);
        Ok((t.stress, t.tangent))
    }

    fn initial_tangent(&self) -> f64 {
        self.pos.e[0]
    }

    fn stored_energy(&self, state: &[f64], _u: f64, force: f64) -> f64 {
        let s = HystState::load(state);
        let (kp, kn) = (s.kp, s.kn);
        let k = if force > 0.0 {
            self.eup * kp
        } else {
            self.eun * kn
        };
        if k > 0.0 {
            0.5 * force * force / k
        } else {
            0.0
        }
    }
}
