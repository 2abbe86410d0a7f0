//! `Takeda`: a degrading, peak-oriented law on a multilinear backbone — the Takeda model
//! (Takeda, Sozen & Nielsen 1970, "Reinforced concrete response to simulated earthquakes",
//! J. Struct. Div. ASCE 96(ST12)) in the simplified form of Otani (1974; 1981, "Hysteresis
//! models of reinforced concrete for earthquake response analysis", J. Fac. Eng. Univ.
//! Tokyo 36(2)) with Emori & Schnobrich's unloading exponent, on the multilinear backbone of
//! the Takeda multilinear-plastic links of CSI's programs. OpenSees has no counterpart.
//!
//! Rules (deformation `u`, force `F`; the backbone of each side through the origin and its
//! points, the first point `(d_y, F_y)` being the yield point; `u_m` the largest deformation
//! reached on a side, `d_y` until it yields):
//! 1. within `[-d_y-, d_y+]` before any yield: elastic, `F = k0 u`;
//! 2. beyond the largest deformation reached on a side: on the backbone (`u_m` follows);
//! 3. unloading from a point with force on side `s`: a line of slope
//!    `k_u = k0 (d_y / u_m)^alpha` (`u_m` of side `s`) down to `F = 0`; reloading before
//!    `F = 0` runs back up the same line to its start and on along the branch it left;
//! 4. past `F = 0`: a line from the zero crossing towards the peak `(u_m, F(u_m))` of the
//!    other side (its yield point if it has not yielded), then on along its backbone; when
//!    that line would be steeper than the unloading stiffness `k_u` of that side (or the
//!    crossing is beyond the peak), a line of slope `k_u` from the crossing instead, until it
//!    meets the backbone beyond the peak (reloading is never stiffer than unloading, the
//!    rule of OpenSees' `Hysteretic`, which however jumps to the backbone at the peak's
//!    deformation);
//! 5. a reversal on a reloading line unloads as in 3 from the reversal point (Otani's
//!    inner-loop rule of the bilinear Takeda model).
//!
//! The tangent is the slope of the branch reached; a step follows the branches in order
//! from the committed state (a monotone path), so the result depends on the committed state
//! and the deformation only.

use serde::{Deserialize, Serialize};

use super::points::{check_points, Backbone};
use super::uniaxial::{initial_deformation_doc, uniaxial_methods, Uniaxial, UniaxialDefinition};
use super::Material;
use crate::elements::definition::{Definition, Pair};
use crate::error::CoreError;

/// `duhamel.elements.Takeda`: the definition of a [`Takeda`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TakedaDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub strain: Vec<f64>,
    pub stress: Vec<f64>,
    #[serde(default)]
    pub strain_neg: Option<Vec<f64>>,
    #[serde(default)]
    pub stress_neg: Option<Vec<f64>>,
    #[serde(default = "takeda_alpha")]
    pub alpha: f64,
    #[serde(default)]
    pub initial_deformation: f64,
}

fn takeda_alpha() -> f64 {
    0.4
}

impl UniaxialDefinition for TakedaDef {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = Takeda;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<Takeda, CoreError> {
        let negative = match (&self.strain_neg, &self.stress_neg) {
            (Some(e), Some(s)) => Some((e.as_slice(), s.as_slice())),
            (None, None) => None,
            (e, _) => {
                return Err(CoreError::InvalidInput {
                    name: if e.is_none() {
                        "strain_neg"
                    } else {
                        "stress_neg"
                    },
                    problem: "is missing: `strain_neg` and `stress_neg` go together (give \
                              both, or neither for a symmetric backbone)"
                        .into(),
                })
            }
        };
        Takeda::new(&self.strain, &self.stress, negative, self.alpha)
    }
}

impl Definition for TakedaDef {
    const NAME: &'static str = "Takeda";
    const SIGNATURE: &'static str =
        "(i, j=None, *, strain, stress, strain_neg=None, stress_neg=None, alpha=0.4, initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"Takeda's degrading, peak-oriented hysteresis on a multilinear backbone, on the
deformation ``u = x_i - x_j`` (``j=None``: to the ground): Takeda, Sozen & Nielsen (1970) in
Otani's simplified form with Emori & Schnobrich's unloading stiffness
``k0 (d_y / u_max)^alpha``, on the backbone of CSI's Takeda multilinear-plastic links.
Elastic before the first yield, on the backbone beyond the largest deformation reached,
unloading at the degraded stiffness to zero force, then towards the peak of the other side.
OpenSees has no counterpart (its ``Hysteretic`` without pinching or damage follows the same
rules up to the differences listed in docs/materials.md). Linear part: the first slope.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
strain, stress : sequence of float
    The positive backbone's points (positive, increasing strains, non-decreasing forces);
    the first is the yield point.
strain_neg, stress_neg : sequence of float, optional
    The negative backbone's points as magnitudes (default: symmetric).
alpha : float
    The unloading exponent, in [0, 1] (0: unloading at the initial stiffness).
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import duhamel
>>> column = duhamel.elements.Takeda(0, strain=[0.01, 0.05], stress=[1.0, 1.4], alpha=0.0)
>>> duhamel.elements.drive(column, [0.03, 0.018, -0.01]).force.round(12).tolist()
[1.2, 0.0, -1.0]
"#
    );
    type Runtime = Uniaxial<Takeda>;
    uniaxial_methods!();
}

/// The Takeda law (see the module documentation).
#[derive(Debug, Clone)]
pub struct Takeda {
    pos: Backbone,
    neg: Backbone,
    alpha: f64,
}

// state layout
const U: usize = 0;
const F: usize = 1;
const K: usize = 2;
const DPOS: usize = 3; // largest deformation reached, positive side (>= d_y+)
const DNEG: usize = 4; // most negative deformation reached (<= -d_y-)
const BRANCH: usize = 5;
// the unloading line
const UR: usize = 6;
const FR: usize = 7;
const KU: usize = 8;
const USIDE: usize = 9;
const OUTER: usize = 10; // 0: the branch the unloading left is the backbone; 1: the reloading line
                         // the reloading line (current, or the one the unloading left)
const U0: usize = 11;
const KL: usize = 12;
const UEND: usize = 13;
const RSIDE: usize = 14;
const LEN: usize = 15;

const VIRGIN: f64 = 0.0;
const BACKBONE: f64 = 1.0;
const UNLOAD: f64 = 2.0;
const RELOAD: f64 = 3.0;

impl Takeda {
    /// The backbone through `(strain[k], stress[k])` (positive side) and
    /// `(-strain_neg[k], -stress_neg[k])` (negative side, magnitudes; None: symmetric),
    /// each with positive strains and stresses, increasing strains and non-negative slopes;
    /// `alpha` in `[0, 1]` (Takeda: 0.4; 0: unloading at the initial stiffness). Errors name
    /// the parameter.
    pub fn new(
        strain: &[f64],
        stress: &[f64],
        negative: Option<(&[f64], &[f64])>,
        alpha: f64,
    ) -> Result<Self, CoreError> {
        let side = |names: (&'static str, &'static str), e: &[f64], s: &[f64]| {
            check_points(names, e, s, 1, true)?;
            let b = Backbone::new(e, s);
            if b.slopes().iter().any(|&k| k < 0.0) {
                return Err(CoreError::InvalidInput {
                    name: names.1,
                    problem: "must not decrease: the backbone's slopes must be >= 0".into(),
                });
            }
            Ok(b)
        };
        let pos = side(("strain", "stress"), strain, stress)?;
        let neg = match negative {
            Some((e, s)) => side(("strain_neg", "stress_neg"), e, s)?,
            None => pos.clone(),
        };
        if !(alpha.is_finite() && (0.0..=1.0).contains(&alpha)) {
            return Err(CoreError::InvalidInput {
                name: "alpha",
                problem: format!("must be in [0, 1], got {alpha}"),
            });
        }
        Ok(Self { pos, neg, alpha })
    }

    fn backbone(&self, side: f64) -> &Backbone {
        if side > 0.0 {
            &self.pos
        } else {
            &self.neg
        }
    }

    /// `(F, dF/du)` on the backbone of `side` at `u`.
    fn on_backbone(&self, side: f64, u: f64) -> (f64, f64) {
        let (f, k) = self.backbone(side).eval(side * u);
        (side * f, k)
    }

    /// The largest deformation (magnitude) reached on `side`.
    fn peak(s: &[f64], side: f64) -> f64 {
        if side > 0.0 {
            s[DPOS]
        } else {
            -s[DNEG]
        }
    }

    /// The unloading stiffness from a force on `side`.
    fn unloading(&self, s: &[f64], side: f64) -> f64 {
        let b = self.backbone(side);
        let (dy, _) = b.first();
        b.k0() * (dy / Self::peak(s, side)).powf(self.alpha)
    }

    /// Starts the reloading line from `(u0, 0)` towards `side`.
    fn reload(&self, s: &mut [f64], u0: f64, side: f64) {
        let b = self.backbone(side);
        let xp = Self::peak(s, side);
        let (fp, _) = b.eval(xp);
        let x0 = side * u0;
        let ku = self.unloading(s, side);
        let (k, xend) = if xp > x0 && fp / (xp - x0) <= ku {
            (fp / (xp - x0), xp)
        } else {
            (ku, b.meet(ku, x0, xp.max(x0)))
        };
        s[U0] = u0;
        s[KL] = k;
        s[UEND] = side * xend;
        s[RSIDE] = side;
        s[BRANCH] = RELOAD;
    }

    /// Outward on the backbone of `side` to `u`.
    fn load(&self, s: &mut [f64], side: f64, u: f64) -> (f64, f64) {
        s[BRANCH] = BACKBONE;
        if side > 0.0 {
            s[DPOS] = s[DPOS].max(u);
        } else {
            s[DNEG] = s[DNEG].min(u);
        }
        self.on_backbone(side, u)
    }
}

impl Material for Takeda {
    /// A zero increment leaves the committed variables and force as they are (checked in
    /// `restart_tests.rs`).
    fn restarts_exactly(&self) -> bool {
        true
    }

    fn state_len(&self) -> usize {
        LEN
    }

    fn initial_state(&self, s: &mut [f64]) {
        s.fill(0.0);
        s[K] = self.pos.k0();
        s[DPOS] = self.pos.first().0;
        s[DNEG] = -self.neg.first().0;
        s[BRANCH] = VIRGIN;
    }

    fn response(
        &self,
        u: f64,
        _rate: f64,
        c: &[f64],
        s: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        s.copy_from_slice(c);
        let du = u - c[U];
        if du == 0.0 {
            return Ok((c[F], c[K]));
        }
        let dir = du.signum();
        // the side of a backbone reached in this step (a committed one: its deformation's)
        let mut side = c[U].signum();
        let mut result = None;
        for _ in 0..8 {
            let branch = s[BRANCH];
            if branch == VIRGIN {
                let (dyp, dyn_) = (s[DPOS], -s[DNEG]);
                result = Some(if u > dyp {
                    self.load(s, 1.0, u)
                } else if u < -dyn_ {
                    self.load(s, -1.0, u)
                } else {
                    let k = if u >= 0.0 {
                        self.pos.k0()
                    } else {
                        self.neg.k0()
                    };
                    (k * u, k)
                });
            } else if branch == BACKBONE {
                if dir == side {
                    result = Some(self.load(s, side, u));
                } else {
                    // reversal at the committed point
                    s[UR] = c[U];
                    s[FR] = c[F];
                    s[KU] = self.unloading(s, side);
                    s[USIDE] = side;
                    s[OUTER] = 0.0;
                    s[BRANCH] = UNLOAD;
                    continue;
                }
            } else if branch == UNLOAD {
                let (us, ur, fr, ku) = (s[USIDE], s[UR], s[FR], s[KU]);
                let u0 = ur - fr / ku;
                if dir == us {
                    if us * u <= us * ur {
                        result = Some((fr + ku * (u - ur), ku));
                    } else if s[OUTER] == 0.0 {
                        side = us;
                        s[BRANCH] = BACKBONE;
                        continue;
                    } else {
                        s[BRANCH] = RELOAD;
                        continue;
                    }
                } else if us * u >= us * u0 {
                    result = Some((fr + ku * (u - ur), ku));
                } else {
                    self.reload(s, u0, -us);
                    continue;
                }
            } else {
                let (rs, u0, kl, uend) = (s[RSIDE], s[U0], s[KL], s[UEND]);
                if dir == rs {
                    if rs * u <= rs * uend {
                        result = Some((kl * (u - u0), kl));
                    } else {
                        side = rs;
                        s[BRANCH] = BACKBONE;
                        continue;
                    }
                } else {
                    // reversal on the reloading line, at the committed point
                    s[UR] = c[U];
                    s[FR] = c[F];
                    s[KU] = self.unloading(s, rs);
                    s[USIDE] = rs;
                    s[OUTER] = 1.0;
                    s[BRANCH] = UNLOAD;
                    continue;
                }
            }
            break;
        }
        let (f, k) = result.ok_or_else(|| CoreError::InvalidInput {
            name: "Takeda",
            problem: "the branch search did not end (a bug)".into(),
        })?;
        s[U] = u;
        s[F] = f;
        s[K] = k;
        Ok((f, k))
    }

    fn initial_tangent(&self) -> f64 {
        self.pos.k0()
    }

    fn tangent_bound(&self) -> Option<f64> {
        let all = self.pos.slopes().iter().chain(self.neg.slopes());
        Some(all.fold(0.0, |m: f64, &k| m.max(k)))
    }

    /// Unloading along the current unloading slope of the force's side.
    fn stored_energy(&self, state: &[f64], _u: f64, force: f64) -> f64 {
        if force == 0.0 {
            return 0.0;
        }
        0.5 * force * force / self.unloading(state, force.signum())
    }
}

#[cfg(test)]
#[path = "takeda_tests.rs"]
mod tests;
