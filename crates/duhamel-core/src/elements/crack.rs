//! A breathing transverse crack at a shaft node (Gasch 1976/1993; Mayes & Davies 1984): the
//! shaft's stiffness loss in the frame turning with the rotor, switched on and off as the
//! crack opens and closes.
//!
//! In the rotating frame `(xi, eta)` at the rotor angle `phi = theta(t) + phase` (`xi` normal
//! to the crack front, `xi = x cos(phi) + y sin(phi)`, `eta = -x sin(phi) + y cos(phi)`), the
//! open crack lowers the stiffness by `dk_xi` along `xi` and `dk_eta` along `eta`. The
//! element is that loss, a restoring force of the opposite sign added to the uncracked
//! shaft's stiffness (carried by the background):
//!
//! ```text
//! r = -f R(phi) diag(dk_xi, dk_eta) R(phi)^T (x, y),
//! ```
//!
//! with the breathing function `f`: `Switching` (Gasch) `f = 1` while `xi > 0` (the crack
//! opens under tension), else 0; `Cosine` (Mayes & Davies) `f = (1 + cos(phi)) / 2`, the
//! crack fully open at `phi = 0` (under a dominant static deflection along `+x`... the
//! caller's phase says where), closed at `phi = pi`. The cosine crack is linear in the state
//! with time-periodic coefficients; the switching one piecewise linear.

use super::definition::Definition;
use super::element::{check, distinct, Element, Tangent};
use crate::error::CoreError;
use crate::speed::SpeedLaw;
use serde::{Deserialize, Serialize};

/// How the crack opens and closes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Breathing {
    /// Open while `xi > 0` (Gasch's hinge model).
    Switching,
    /// `f = (1 + cos(phi)) / 2` (Mayes & Davies).
    Cosine,
}

/// A breathing crack on the two lateral dofs of a shaft node.
#[derive(Debug, Clone, PartialEq)]
pub struct BreathingCrack {
    dofs: [usize; 2],
    dk_xi: f64,
    dk_eta: f64,
    breathing: Breathing,
    phase: f64,
    law: SpeedLaw,
}

impl BreathingCrack {
    /// The crack on `(dof_x, dof_y)`, stiffness losses `dk_xi`, `dk_eta` (`>= 0`, not both
    /// 0) when open, its `breathing`, at the rotor angle `law.theta(t) + phase`.
    pub fn new(
        dof_x: usize,
        dof_y: usize,
        dk_xi: f64,
        dk_eta: f64,
        breathing: Breathing,
        phase: f64,
        law: SpeedLaw,
    ) -> Result<Self, CoreError> {
        distinct(dof_x, dof_y)?;
        check("dk_xi", dk_xi, false)?;
        check("dk_eta", dk_eta, false)?;
        if !phase.is_finite() {
            return Err(CoreError::InvalidInput {
                name: "phase",
                problem: format!("must be finite, got {phase}"),
            });
        }
        law.validate()?;
        Ok(Self {
            dofs: [dof_x, dof_y],
            dk_xi,
            dk_eta,
            breathing,
            phase,
            law,
        })
    }

    /// The crack's stiffness loss matrix at `(x, y)`, time `t`: `f R diag R^T` (row-major).
    pub fn loss(&self, x: &[f64], t: f64) -> [f64; 4] {
        let phi = self.law.theta(t) + self.phase;
        let (s, c) = phi.sin_cos();
        let f = match self.breathing {
            Breathing::Cosine => 0.5 * (1.0 + c),
            Breathing::Switching => {
                if x[0] * c + x[1] * s > 0.0 {
                    1.0
                } else {
                    0.0
                }
            }
        };
        let (a, b) = (f * self.dk_xi, f * self.dk_eta);
        let off = (a - b) * s * c;
        [a * c * c + b * s * s, off, off, a * s * s + b * c * c]
    }
}

impl Element for BreathingCrack {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn eval(
        &self,
        x: &[f64],
        _v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let k = self.loss(x, t);
        r[0] -= k[0] * x[0] + k[1] * x[1];
        r[1] -= k[2] * x[0] + k[3] * x[1];
        if let Some(tg) = tangent {
            for (d, kk) in tg.kx.iter_mut().zip(k) {
                *d -= kk;
            }
        }
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        false
    }
}

/// `duhamel.rotor.BreathingCrack`: the definition of a [`BreathingCrack`].
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BreathingCrackDef {
    pub dofs: (usize, usize),
    pub dk_xi: f64,
    #[serde(default)]
    pub dk_eta: f64,
    #[serde(default = "cosine")]
    pub breathing: Breathing,
    #[serde(default = "at_rest")]
    pub speed: SpeedLaw,
    #[serde(default)]
    pub phase: f64,
}

fn cosine() -> Breathing {
    Breathing::Cosine
}

fn at_rest() -> SpeedLaw {
    SpeedLaw::Constant(0.0)
}

impl Definition for BreathingCrackDef {
    const NAME: &'static str = "BreathingCrack";
    const SIGNATURE: &'static str =
        "(dofs, *, dk_xi, dk_eta=0.0, breathing='cosine', speed=0.0, phase=0.0)";
    const DOC: &'static str = r#"A breathing transverse crack on the lateral dofs ``dofs=(x, y)`` of a shaft node: the open
crack's stiffness losses `dk_xi` (across the crack front) and `dk_eta` (along it), N/m, in the
frame turning at `speed` (rad/s, or a :mod:`duhamel.speed` law), `phase` the angle (rad) of
the crack's ``xi`` axis from ``x`` at ``t = 0``, and `breathing` ``"switching"`` (Gasch: open
while the node's displacement has a positive ``xi`` component) or ``"cosine"`` (Mayes &
Davies: ``f = (1 + cos(phi)) / 2``, fully open when ``xi`` points along ``+x``... at
``phi = 0``). The uncracked shaft stays in the model's stiffness; the element is the loss, a
restoring force ``-f R diag(dk_xi, dk_eta) R^T x``.

Parameters
----------
dofs : pair of int or dof labels
    The node's lateral dofs ``(x, y)``.
dk_xi, dk_eta : float
    The open crack's stiffness losses, >= 0.
breathing : {"cosine", "switching"}
    How the crack opens and closes.
speed : float or speed law
    The rotor's speed (rad/s) or a :mod:`duhamel.speed` law.
phase : float
    The angle of the crack's axis at ``t = 0`` (rad).

Examples
--------
>>> from duhamel.rotor import BreathingCrack
>>> crack = BreathingCrack((0, 1), dk_xi=2e4, breathing="cosine", speed=100.0)
>>> r, K, C = crack.evaluate([1e-3, 0.0], t=0.0)  # fully open, xi along x
>>> K.tolist()
[[-20000.0, 0.0], [0.0, 0.0]]
"#;
    const LEGACY: &'static [&'static str] = &[
        "dof_x",
        "dof_y",
        "dk_xi",
        "dk_eta",
        "breathing",
        "speed",
        "phase",
    ];
    type Runtime = BreathingCrack;

    fn build(&self) -> Result<BreathingCrack, CoreError> {
        let (x, y) = self.dofs;
        BreathingCrack::new(
            x,
            y,
            self.dk_xi,
            self.dk_eta,
            self.breathing,
            self.phase,
            self.speed,
        )
    }

    fn rename(old: &str) -> Option<(&'static str, Option<usize>)> {
        super::hysteretic::rename_axes(old)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_and_closed_states_in_the_rotating_frame() {
        let phase = 0.7;
        let crack = |b| BreathingCrack::new(0, 1, 3.0, 1.0, b, phase, SpeedLaw::Constant(0.0));
        let (s, c) = phase.sin_cos();
        // displacement along +xi: open, loss 3 along xi
        let mut r = [0.0; 2];
        crack(Breathing::Switching)
            .unwrap()
            .eval(&[c, s], &[0.0; 2], 0.0, &mut r, None)
            .unwrap();
        assert!((r[0] + 3.0 * c).abs() < 1e-14 && (r[1] + 3.0 * s).abs() < 1e-14);
        // along -xi: closed
        let mut r = [0.0; 2];
        crack(Breathing::Switching)
            .unwrap()
            .eval(&[-c, -s], &[0.0; 2], 0.0, &mut r, None)
            .unwrap();
        assert_eq!(r, [0.0, 0.0]);
        // cosine at phi = phase: open by f = (1 + cos(phase)) / 2; along eta: loss f * 1
        let f = 0.5 * (1.0 + c);
        let mut r = [0.0; 2];
        crack(Breathing::Cosine)
            .unwrap()
            .eval(&[-s, c], &[0.0; 2], 0.0, &mut r, None)
            .unwrap();
        assert!((r[0] - f * s).abs() < 1e-14 && (r[1] + f * c).abs() < 1e-14);
        assert!(crack(Breathing::Cosine).is_ok());
        assert!(BreathingCrack::new(
            0,
            0,
            1.0,
            0.0,
            Breathing::Cosine,
            0.0,
            SpeedLaw::Constant(0.0)
        )
        .is_err());
        assert!(BreathingCrack::new(
            0,
            1,
            -1.0,
            0.0,
            Breathing::Cosine,
            0.0,
            SpeedLaw::Constant(0.0)
        )
        .is_err());
    }
}
