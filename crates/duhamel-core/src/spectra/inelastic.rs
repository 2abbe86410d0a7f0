//! The bilinear oscillator under a record, exactly: on each branch of the hysteresis the
//! equation is linear, so every step is the exact transition of that branch, and the instants
//! of yielding and of unloading inside a step are located on the exact solution (safeguarded
//! Newton on the closed-form sub-step, derivative included). Constant-ductility spectra find,
//! per period, the largest yield strength whose peak ductility reaches the target.
//!
//! Model, per unit mass: `u'' + 2 zeta omega u' + f = -a_g`, `f = k (alpha u + (1 - alpha)
//! z)`, `k = omega^2`, with `z` the elastic-perfectly-plastic part: `z' = u'` while
//! `|z| < u_y` or unloading, `z' = 0` on yield (`|z| = u_y`, `z u' > 0`). Kinematic hardening
//! with post-yield stiffness `alpha k`; the yield force is `f_y = k u_y`.

use super::common::{check, map_tasks, Record, Step};
use super::elastic::elastic;
use crate::error::CoreError;
use crate::kernel::oscillator::Transfer;

/// Branch changes allowed in one step before the step is declared pathological.
const MAX_EVENTS: usize = 32;
/// Bracket width (fraction of the sub-step) at which an event time is taken as found.
const EVENT_TOL: f64 = 1e-14;

/// A bilinear oscillator: natural frequency `omega` (rad/s, of the elastic branch), damping
/// ratio `zeta` and post-yield stiffness ratio `alpha` (0 <= alpha < 1).
#[derive(Debug, Clone, Copy)]
pub struct BilinearOscillator {
    pub omega: f64,
    pub zeta: f64,
    pub alpha: f64,
}

/// State on a branch with constant force offset: `x'' + c x' + s x = q(t)`.
#[derive(Clone, Copy)]
struct Branch {
    stiffness: f64,
    c: f64,
}

impl Branch {
    /// State after `h` from `(x, v)` under `q` linear from `q0` to `q1`; the full-step matrices
    /// are used when given.
    fn advance(&self, full: Option<&Step>, h: f64, x: f64, v: f64, q: (f64, f64)) -> (f64, f64) {
        let s = match full {
            Some(s) => *s,
            None => Step::from_transfer(&Transfer::new(self.stiffness, self.c, h)),
        };
        s.apply(x, v, q.0, q.1)
    }
}

/// The time `tau` in `(0, h]` at which `g` (given with its derivative) changes sign, `g(0) =
/// g0` and `g(h)` having opposite signs: Newton steps kept inside a shrinking bracket. When
/// `g0 = 0` (the sub-step starts on the event, leaving it the other way first) the bracket
/// starts at the first of 16 equally spaced times where `g` has the sign opposite to
/// `g(h)`; None if there is none (the motion never left: the other branch holds).
fn event(g: impl Fn(f64) -> (f64, f64), h: f64, g0: f64) -> Option<f64> {
    let (mut value, mut slope) = g(h);
    let (mut lo, mut glo) = (0.0, g0);
    if g0 == 0.0 {
        let found = (1..16).map(|i| h * i as f64 / 16.0).find_map(|t| {
            let (gt, _) = g(t);
            (gt != 0.0 && (gt > 0.0) != (value > 0.0)).then_some((t, gt))
        });
        (lo, glo) = found?;
    }
    let (mut hi, mut tau) = (h, h);
    for _ in 0..200 {
        if (value > 0.0) == (glo > 0.0) {
            lo = tau;
        } else {
            hi = tau;
        }
        if hi - lo <= EVENT_TOL * h || value == 0.0 {
            break;
        }
        let newton = tau - value / slope;
        tau = if newton.is_finite() && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        (value, slope) = g(tau);
    }
    Some(hi.min(tau.max(lo)).max(f64::MIN_POSITIVE))
}

/// Peak `|u|` (at the samples) of the bilinear oscillator `o` with yield displacement `uy` under `-acc`.
pub fn peak_displacement(o: &BilinearOscillator, uy: f64, rec: Record) -> Result<f64, CoreError> {
    let k = o.omega * o.omega;
    let c = 2.0 * o.zeta * o.omega;
    let elastic = Branch { stiffness: k, c };
    let plastic = Branch {
        stiffness: o.alpha * k,
        c,
    };
    let full_el = Step::new(o.omega, o.zeta, rec.dt)?;
    let full_pl = Step::from_transfer(&Transfer::new(plastic.stiffness, c, rec.dt));
    let (mut u, mut v, mut z) = (0.0f64, 0.0f64, 0.0f64);
    let mut peak = 0.0f64;
    for (step, w) in rec.acc.windows(2).enumerate() {
        let (p0, p1) = (-w[0], -w[1]);
        let load = |s: f64| p0 * (1.0 - s) + p1 * s; // exact at both ends
        let mut s = 0.0; // fraction of the step done
        let mut events = 0;
        // the branch decided by a sub-step that found no event (None: by the state)
        let mut force: Option<bool> = None;
        while s < 1.0 {
            let h = (1.0 - s) * rec.dt;
            let dir = z.signum();
            let at_yield = z.abs() >= uy;
            let spring = k * (o.alpha * u + (1.0 - o.alpha) * z);
            let outward = v * dir > 0.0 || (v == 0.0 && (load(s) - spring) * dir > 0.0);
            if at_yield && force.unwrap_or(outward) {
                // plastic: stiffness alpha k, offset (1 - alpha) k z
                let off = (1.0 - o.alpha) * k * z;
                let q = |sf: f64| load(sf) - off;
                let full = (s == 0.0).then_some(&full_pl);
                let (u1, v1) = plastic.advance(full, h, u, v, (q(s), q(1.0)));
                if v1 * dir >= 0.0 {
                    (u, v, s) = (u1, v1, 1.0);
                } else {
                    let at = |tau: f64| {
                        let end = s + tau / rec.dt;
                        let (x, y) = plastic.advance(None, tau, u, v, (q(s), q(end)));
                        (y, q(end) - c * y - plastic.stiffness * x)
                    };
                    let Some(tau) = event(at, h, v) else {
                        force = Some(false); // never moved outward: elastic from here
                        events += 1;
                        continue;
                    };
                    let end = (s + tau / rec.dt).min(1.0);
                    let (x, _) = plastic.advance(None, tau, u, v, (q(s), q(end)));
                    (u, v, s) = (x, 0.0, end);
                    events += 1;
                    force = None;
                }
            } else {
                // elastic: stiffness k, offset (1 - alpha) k (z - u)
                let off = (1.0 - o.alpha) * k * (z - u);
                let q = |sf: f64| load(sf) - off;
                let full = (s == 0.0).then_some(&full_el);
                let (u1, v1) = elastic.advance(full, h, u, v, (q(s), q(1.0)));
                let z1 = z + (u1 - u);
                if z1.abs() <= uy {
                    (u, v, z, s) = (u1, v1, z1, 1.0);
                } else {
                    let side = z1.signum();
                    let target = u + (side * uy - z);
                    let at = |tau: f64| {
                        let end = s + tau / rec.dt;
                        let (x, y) = elastic.advance(None, tau, u, v, (q(s), q(end)));
                        (x - target, y)
                    };
                    let Some(tau) = event(at, h, u - target) else {
                        force = Some(true); // on yield and never moved inward: plastic
                        events += 1;
                        continue;
                    };
                    let end = (s + tau / rec.dt).min(1.0);
                    let (_, y) = elastic.advance(None, tau, u, v, (q(s), q(end)));
                    (u, v, z, s) = (target, y, side * uy, end);
                    events += 1;
                    force = None;
                }
            }
            if events > MAX_EVENTS {
                return Err(CoreError::InvalidInput {
                    name: "dt",
                    problem: format!(
                        "the bilinear oscillator (omega = {} rad/s, u_y = {uy:e}) changes \
                         branch more than {MAX_EVENTS} times in step {}: the record is too \
                         coarse for it",
                        o.omega,
                        step + 1
                    ),
                });
            }
        }
        peak = peak.max(u.abs()); // at the samples, as the elastic spectra
        if !(u.is_finite() && v.is_finite()) {
            return Err(CoreError::InvalidInput {
                name: "motions",
                problem: format!(
                    "the bilinear oscillator's response overflows at step {}",
                    step + 1
                ),
            });
        }
    }
    Ok(peak)
}

/// Per period: the yield displacement `u_y` whose peak ductility `max|u| / u_y` equals each
/// target, the largest such (strongest system) found by scanning the strength ratio
/// `eta = u_y / sd_elastic` down from 1 on a geometric grid (`grid` points per halving) and
/// bisecting the first bracket to `1e-10`. Layout `[ductility][period]`, values `u_y`; a
/// target not reached above `eta_min` gives an error.
pub fn ductility_spectrum(
    rec: Record,
    periods: &[f64],
    zeta: f64,
    alpha: f64,
    ductilities: &[f64],
    threads: Option<usize>,
) -> Result<Vec<f64>, CoreError> {
    check(&[rec], periods, &[zeta])?;
    if !(alpha.is_finite() && (0.0..1.0).contains(&alpha)) {
        return Err(CoreError::InvalidInput {
            name: "alpha",
            problem: format!("must be in [0, 1), got {alpha}"),
        });
    }
    if let Some(&m) = ductilities.iter().find(|m| !(m.is_finite() && **m >= 1.0)) {
        return Err(CoreError::InvalidInput {
            name: "ductility",
            problem: format!("must be finite and >= 1, got {m}"),
        });
    }
    if let Some(&t) = periods.iter().find(|t| **t == 0.0) {
        return Err(CoreError::InvalidInput {
            name: "periods",
            problem: format!("must be > 0 for inelastic spectra, got {t}"),
        });
    }
    let sd = elastic(&[rec], periods, &[zeta], Some(1))?.sd;
    let tasks: Vec<(usize, usize)> = (0..ductilities.len())
        .flat_map(|d| (0..periods.len()).map(move |p| (d, p)))
        .collect();
    let task = |&(d, p): &(usize, usize)| -> Result<f64, CoreError> {
        let o = BilinearOscillator {
            omega: 2.0 * std::f64::consts::PI / periods[p],
            zeta,
            alpha,
        };
        let target = ductilities[d];
        if target == 1.0 || sd[p] == 0.0 {
            return Ok(sd[p]);
        }
        let mu = |eta: f64| -> Result<f64, CoreError> {
            let uy = eta * sd[p];
            Ok(peak_displacement(&o, uy, rec)? / uy)
        };
        let ratio = 0.5f64.powf(1.0 / 16.0);
        let (mut hi, mut lo) = (1.0, ratio);
        while mu(lo)? < target {
            hi = lo;
            lo *= ratio;
            if lo < 1e-6 {
                return Err(CoreError::InvalidInput {
                    name: "ductility",
                    problem: format!(
                        "{target} is not reached at period {} s with a yield strength down to \
                         1e-6 of the elastic force",
                        periods[p]
                    ),
                });
            }
        }
        while hi - lo > 1e-10 * hi {
            let mid = 0.5 * (lo + hi);
            if mu(mid)? >= target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(lo * sd[p])
    };
    map_tasks(threads, &tasks, task)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record() -> Vec<f64> {
        (0..1500)
            .map(|k| {
                let t = 0.01 * k as f64;
                3.0 * (7.0 * t).sin() * (-0.2 * t).exp() + (2.3 * t).cos()
            })
            .collect()
    }

    /// Never yielding, the bilinear oscillator is the elastic one, step for step.
    #[test]
    fn elastic_when_strong() {
        let acc = record();
        let rec = Record {
            acc: &acc,
            dt: 0.01,
        };
        let o = BilinearOscillator {
            omega: 5.0,
            zeta: 0.05,
            alpha: 0.1,
        };
        let sd = elastic(
            &[rec],
            &[2.0 * std::f64::consts::PI / 5.0],
            &[0.05],
            Some(1),
        )
        .unwrap()
        .sd[0];
        assert_eq!(peak_displacement(&o, 1.0001 * sd, rec).unwrap(), sd);
    }

    /// `alpha = 1` is not allowed, but alpha -> 1 makes yielding irrelevant: the response
    /// approaches the elastic one continuously.
    #[test]
    fn hardening_to_elastic() {
        let acc = record();
        let rec = Record {
            acc: &acc,
            dt: 0.01,
        };
        let sd = elastic(&[rec], &[1.0], &[0.02], Some(1)).unwrap().sd[0];
        let o = BilinearOscillator {
            omega: 2.0 * std::f64::consts::PI,
            zeta: 0.02,
            alpha: 1.0 - 1e-9,
        };
        let p = peak_displacement(&o, 0.1 * sd, rec).unwrap();
        assert!((p - sd).abs() < 1e-7 * sd, "{p} vs {sd}");
    }

    #[test]
    fn ductility_reached() {
        let acc = record();
        let rec = Record {
            acc: &acc,
            dt: 0.01,
        };
        let periods = [0.3, 1.0];
        let uy = ductility_spectrum(rec, &periods, 0.05, 0.0, &[2.0, 4.0], Some(1)).unwrap();
        for (i, &y) in uy.iter().enumerate() {
            let o = BilinearOscillator {
                omega: 2.0 * std::f64::consts::PI / periods[i % 2],
                zeta: 0.05,
                alpha: 0.0,
            };
            let mu = peak_displacement(&o, y, rec).unwrap() / y;
            let target = [2.0, 4.0][i / 2];
            assert!(
                mu >= target && mu < target * (1.0 + 1e-3),
                "{mu} vs {target}"
            );
        }
    }
}
