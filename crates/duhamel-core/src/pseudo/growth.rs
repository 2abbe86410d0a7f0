//! The growth guard: a run whose response takes far more energy than anything supplied it
//! stops, instead of returning a finite explosion.
//!
//! In modal coordinates (unit modal masses) the background's energy is
//! `E = 1/2 sum (v_m^2 + k_m q_m^2)` and, exactly, `dE/dt = v . p + v . Q - v . C v` with
//! `p` the external modal load and `Q` the pseudo-force. For passive elements (springs,
//! gaps, hysteretic and viscous devices: they store or dissipate what they receive, so the
//! total energy `E + S` grows by `v . p` at most) and dissipative or gyroscopic couplings,
//! `d(E + S)/dt <= |v| |p| <= sqrt(2 (E + S)) |p|`, so
//!
//! ```text
//! sqrt(E(t)) <= sqrt(E(0) + S(0)) + int_0^t |p| dt / sqrt(2)
//! ```
//!
//! a bound that does not grow with the response itself (its worst case is a resonance,
//! growing linearly). Over a step the load is the step's quadratic `p0 + (p1 - p0) s +
//! 4 s (1 - s) p2` (`s` in [0, 1]), whose integral of `|p|` is at most
//! `dt (max(|p0|, |p1|) + 2/3 |p2|)`: the bound holds for any step, however long. A
//! pseudo-force step beyond its stability limit breaks it by orders of magnitude (the
//! step's quadrature creates energy) while the state stays finite for a long time. The
//! guard checks, after every step, `E(t) <= limit * B(t)^2` with `B` the right-hand side,
//! `S(0)` estimated by the static energy `sum Q_m(0)^2 / k_m` of the initial pseudo-force.
//! The default limit (100: ten times the amplitude) leaves room for what the bound does not
//! count (the energy of element stiffness moved into the background, a discretisation's own
//! error). It is the caller's to run the guard only on passive models (`Plan.passive` on the
//! Python side): a model that gains energy by itself (a softening spring past its peak, a
//! parametric resonance, cross-coupled stiffness, a self-excited whirl) can exceed it
//! rightly.

use super::force::PseudoForce;
use crate::error::CoreError;
use crate::problem::ModalProblem;

/// The guard of one run (see the module's documentation).
#[derive(Debug, Clone)]
pub struct GrowthGuard {
    limit: f64,
    /// The background's modal stiffness, negative entries counted as 0.
    k: Vec<f64>,
    /// `E(0) + S(0)`, and its square root.
    start: f64,
    root: f64,
    /// `int |p| dt / sqrt(2)` so far.
    amplitude: f64,
}

impl GrowthGuard {
    /// The guard of a run from `(q0, v0)` with the background's modal stiffness `k` and the
    /// pseudo-force `force0` at the start; None when `limit` is not a finite number above 1
    /// (the guard off) or when the initial pseudo-force loads a mode without stiffness (its
    /// static energy is unbounded: nothing to compare with).
    pub fn new(limit: f64, k: &[f64], (q0, v0): (&[f64], &[f64]), force0: &[f64]) -> Option<Self> {
        // Coordinates without mass (`k = +inf`, a massless dof's) hold no kinetic energy:
        // the bound is not derived for them, the guard is off.
        if !(limit.is_finite() && limit > 1.0) || k.iter().any(|x| x.is_infinite()) {
            return None;
        }
        let k: Vec<f64> = k.iter().map(|&x| x.max(0.0)).collect();
        let mut held = 0.0;
        for (&km, &f) in k.iter().zip(force0) {
            if f != 0.0 {
                if km <= 0.0 {
                    return None;
                }
                held += f * f / km;
            }
        }
        let mut guard = GrowthGuard {
            limit,
            k,
            start: 0.0,
            root: 0.0,
            amplitude: 0.0,
        };
        guard.start = guard.energy(q0, v0) + held;
        guard.root = guard.start.sqrt();
        guard.start.is_finite().then_some(guard)
    }

    /// The guard of a run continued from a run before (its [`GrowthGuard::state`]): the
    /// bound counts from the first run's start. None when the state is not two finite,
    /// non-negative numbers or `limit` turns the guard off.
    pub fn resume(limit: f64, k: &[f64], state: &[f64]) -> Option<Self> {
        if !(limit.is_finite() && limit > 1.0) || k.iter().any(|x| x.is_infinite()) {
            return None;
        }
        let &[start, amplitude] = state else {
            return None;
        };
        if !(start.is_finite() && start >= 0.0 && amplitude.is_finite() && amplitude >= 0.0) {
            return None;
        }
        Some(GrowthGuard {
            limit,
            k: k.iter().map(|&x| x.max(0.0)).collect(),
            start,
            root: start.sqrt(),
            amplitude,
        })
    }

    /// What a continued run needs: `[E(0) + S(0), int |p| dt / sqrt(2)]`.
    pub fn state(&self) -> Vec<f64> {
        vec![self.start, self.amplitude]
    }

    /// The background's energy at `(q, v)`.
    pub fn energy(&self, q: &[f64], v: &[f64]) -> f64 {
        let mut e = 0.0;
        for ((&km, &x), &y) in self.k.iter().zip(q).zip(v) {
            e += y * y + km * x * x;
        }
        0.5 * e
    }

    /// [`GrowthGuard::energy`] in four partial sums (one chain of additions over the modes
    /// was most of the guard's cost per step): what the check after each step compares,
    /// equal to it up to rounding.
    fn energy_check(&self, q: &[f64], v: &[f64]) -> f64 {
        let n = self.k.len().min(q.len()).min(v.len());
        let (k, q, v) = (&self.k[..n], &q[..n], &v[..n]);
        let mut acc = [0.0; 4];
        let (ck, cq, cv) = (k.chunks_exact(4), q.chunks_exact(4), v.chunks_exact(4));
        let mut tail = 0.0;
        for ((&km, &x), &y) in ck
            .remainder()
            .iter()
            .zip(cq.remainder())
            .zip(cv.remainder())
        {
            tail += y * y + km * x * x;
        }
        for ((km, x), y) in ck.zip(cq).zip(cv) {
            for j in 0..4 {
                acc[j] += y[j] * y[j] + km[j] * x[j] * x[j];
            }
        }
        0.5 * ((acc[0] + acc[2]) + (acc[1] + acc[3]) + tail)
    }

    /// Checks the end `(q1, v1)` of a step of length `dt` whose modal load is `p0` at the
    /// start, `p1` at the end and `p2` the coefficient of its bubble `4 s (1 - s)`. The
    /// error's message says how much energy the response holds against the bound and what
    /// to do.
    pub fn step(
        &mut self,
        dt: f64,
        (q1, v1): (&[f64], &[f64]),
        (p0, p1, p2): (&[f64], &[f64], &[f64]),
    ) -> Result<(), CoreError> {
        let (s0, s1, s2) = squares3([p0, p1, p2]);
        let held = self.energy_check(q1, v1);
        self.check(dt, (s0, s1, s2), held)
    }

    /// [`GrowthGuard::step`] with the step's load given as its basis `(p0, Dp, p2)`: the
    /// end value `p1 = p0 + Dp` formed where its sum reads it (not stored), one mode on
    /// scalars (the generic sums' loops were most of the guard's cost for one mode). The
    /// same numbers: one term summed from zero is that term.
    #[inline]
    pub fn step_basis(
        &mut self,
        dt: f64,
        (q1, v1): (&[f64], &[f64]),
        [p0, dp, p2]: [&[f64]; 3],
    ) -> Result<(), CoreError> {
        let single = (p0, dp, p2, q1, v1, &self.k[..]);
        let (squares, held) = if let ([a], [b], [c], [x], [y], [km]) = single {
            let p1 = a + b;
            ((a * a, p1 * p1, c * c), 0.5 * (y * y + km * x * x))
        } else {
            self.squares_held([p0, dp, p2], (q1, v1))
        };
        self.check(dt, squares, held)
    }

    /// [`squares_basis`] and [`GrowthGuard::energy_check`], out of line (the scalar path of
    /// [`GrowthGuard::step_basis`] is inlined into the route's loop).
    #[inline(never)]
    fn squares_held(&self, p: [&[f64]; 3], (q1, v1): (&[f64], &[f64])) -> ((f64, f64, f64), f64) {
        (squares_basis(p), self.energy_check(q1, v1))
    }

    /// The check of a step of length `dt` whose load's squared norms are `(s0, s1, s2)`
    /// (start, end, bubble) and whose end holds the energy `held`.
    #[inline(always)]
    fn check(
        &mut self,
        dt: f64,
        (s0, s1, s2): (f64, f64, f64),
        held: f64,
    ) -> Result<(), CoreError> {
        // sqrt is monotonic and correctly rounded: the larger root is the larger's root
        let mut load = s0.max(s1).sqrt();
        // the bubble's root only when it has one (a load linear over the step has none),
        // behind a call the compiler cannot turn into a select (it computed both roots at
        // every step otherwise); `+ 2/3 * 0` left out is the same sum (the root is >= +0)
        if s2 != 0.0 {
            load += bubble(s2);
        }
        self.amplitude += dt * load * std::f64::consts::FRAC_1_SQRT_2;
        let bound = self.root + self.amplitude;
        let supply = bound * bound;
        if held <= self.limit * supply || !held.is_finite() {
            return Ok(());
        }
        Err(growth_error(held, self.limit, supply))
    }
}

/// The error of a response holding `held` against `limit` times the `supply` (cold: out of
/// the step's inlined check).
#[cold]
#[inline(never)]
fn growth_error(held: f64, limit: f64, supply: f64) -> CoreError {
    CoreError::Growth {
        message: format!(
            "the response grew without bound: its modal energy {held:.4e} exceeds \
             {limit} times the most the initial state and the loads can give this \
             passive model ({supply:.4e}): the step is unstable for it (an element or \
             coupling far stiffer than the modes it loads: reduce `dt` or raise \
             `subdivisions`); pass `growth_limit=None` to see the growth",
        ),
        time: 0.0,
        step: 0,
        last_good_time: None,
    }
}

/// `2/3 sqrt(s2)`: the bound's share of the load's bubble, out of line (see
/// [`GrowthGuard::step`]).
#[inline(never)]
fn bubble(s2: f64) -> f64 {
    2.0 / 3.0 * s2.sqrt()
}

/// [`squares3`] of `(p0, p0 + dp, p2)`, the middle row formed in the pass (as the route
/// formed it: `p0 + dp` entry by entry): the same numbers.
fn squares_basis(p: [&[f64]; 3]) -> (f64, f64, f64) {
    let n = p[0].len().min(p[1].len()).min(p[2].len());
    let (a, d, c) = (&p[0][..n], &p[1][..n], &p[2][..n]);
    let mut acc = [[0.0; 4]; 3];
    let full = n - n % 4;
    for j in (0..full).step_by(4) {
        for k in 0..4 {
            let b = a[j + k] + d[j + k];
            acc[0][k] += a[j + k] * a[j + k];
            acc[1][k] += b * b;
            acc[2][k] += c[j + k] * c[j + k];
        }
    }
    let row = |j: usize, which: usize| match which {
        0 => a[j],
        1 => a[j] + d[j],
        _ => c[j],
    };
    let mut out = [0.0; 3];
    for (which, (o, acc)) in out.iter_mut().zip(acc.iter()).enumerate() {
        let tail: f64 = (full..n).map(|j| row(j, which) * row(j, which)).sum();
        *o = (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail;
    }
    (out[0], out[1], out[2])
}

/// `(p_0 . p_0, p_1 . p_1, p_2 . p_2)` in one pass, each summed as [`crate::dense::dot`]
/// sums it (four partial sums, then the tail): the same numbers.
fn squares3(p: [&[f64]; 3]) -> (f64, f64, f64) {
    let n = p[0].len().min(p[1].len()).min(p[2].len());
    let (a, b, c) = (&p[0][..n], &p[1][..n], &p[2][..n]);
    let mut acc = [[0.0; 4]; 3];
    let full = n - n % 4;
    let chunks = a
        .chunks_exact(4)
        .zip(b.chunks_exact(4))
        .zip(c.chunks_exact(4));
    for ((ac, bc), cc) in chunks {
        for k in 0..4 {
            acc[0][k] += ac[k] * ac[k];
            acc[1][k] += bc[k] * bc[k];
            acc[2][k] += cc[k] * cc[k];
        }
    }
    let mut out = [0.0; 3];
    for (o, (acc, v)) in out.iter_mut().zip(acc.iter().zip([a, b, c])) {
        let tail: f64 = (full..n).map(|j| v[j] * v[j]).sum();
        *o = (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail;
    }
    (out[0], out[1], out[2])
}

/// The run's growth guard (None when `limit` is infinite or nothing bounds the start), from
/// the pseudo-force at the initial state. A pseudo-force that cannot be evaluated there
/// leaves the run unguarded: the run's first step reports that failure in its place.
pub(super) fn growth_guard(
    pf: &mut PseudoForce,
    base: &ModalProblem,
    limit: f64,
    continued: Option<&[f64]>,
) -> Option<GrowthGuard> {
    if !limit.is_finite() {
        return None;
    }
    if let Some(state) = continued {
        return GrowthGuard::resume(limit, base.k, state);
    }
    let n = base.n_modes();
    let mut force0 = vec![0.0; n];
    pf.at_state(base.q0, base.v0, base.time(0), &vec![0.0; n], &mut force0)
        .ok()?;
    GrowthGuard::new(limit, base.k, (base.q0, base.v0), &force0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn off_for_bad_limits_and_unbounded_static_energy() {
        let k = [4.0, 0.0];
        let z = [0.0, 0.0];
        assert!(GrowthGuard::new(f64::INFINITY, &k, (&z, &z), &z).is_none());
        assert!(GrowthGuard::new(0.5, &k, (&z, &z), &z).is_none());
        assert!(GrowthGuard::new(1e6, &k, (&z, &z), &[0.0, 1.0]).is_none());
        assert!(GrowthGuard::new(1e6, &k, (&z, &z), &[1.0, 0.0]).is_some());
        assert!(GrowthGuard::resume(1e6, &k, &[1.0]).is_none());
        assert!(GrowthGuard::resume(1e6, &k, &[1.0, -1.0]).is_none());
        assert!(GrowthGuard::resume(1e6, &k, &[1.0, 2.0]).is_some());
    }

    #[test]
    fn a_resonance_passes_and_an_explosion_stops() {
        // a unit oscillator driven at resonance by p = cos t from rest: x = t sin(t) / 2
        // grows linearly; its energy stays below the bound (limit 1: the bound itself)
        let k = [1.0];
        let mut g = GrowthGuard::new(1.0 + 1e-9, &k, (&[0.0], &[0.0]), &[0.0]).unwrap();
        let dt = 1e-3;
        let (mut q, mut v) = (0.0_f64, 0.0_f64);
        for n in 1..=20_000 {
            let (t0, t) = ((n - 1) as f64 * dt, n as f64 * dt);
            (q, v) = (0.5 * t * t.sin(), 0.5 * (t.sin() + t * t.cos()));
            g.step(dt, (&[q], &[v]), (&[t0.cos()], &[t.cos()], &[0.0]))
                .unwrap();
        }
        assert!(q.is_finite());
        // the same state scaled by 10: 100 times the energy, beyond the bound
        let t: f64 = 20.0;
        let err = g
            .step(
                dt,
                (&[10.0 * q], &[10.0 * v]),
                (&[t.cos()], &[t.cos()], &[0.0]),
            )
            .unwrap_err();
        assert!(matches!(err, CoreError::Growth { .. }));
        assert!(err.to_string().contains("growth_limit"));
    }

    /// The guard on the step's load basis is the guard on its end values, bit for bit
    /// (amplitude and decision), for one mode (its scalar path) and for several.
    #[test]
    fn the_basis_step_is_the_end_value_step() {
        for n in [1, 2, 5, 9] {
            let k: Vec<f64> = (0..n).map(|m| 1.0 + 3.7 * m as f64).collect();
            let zero = vec![0.0; n];
            let start = vec![1e-3; n];
            let mut a = GrowthGuard::new(50.0, &k, (&start, &zero), &zero).unwrap();
            let mut b = a.clone();
            for step in 0..500 {
                let x = step as f64 * 0.37;
                let row = |c: f64| -> Vec<f64> {
                    (0..n).map(|m| (c * x + m as f64).sin() * 1e-2).collect()
                };
                let (p0, dp, p2) = (row(1.0), row(2.3), row(0.7));
                let p2 = if step % 3 == 0 { zero.clone() } else { p2 };
                let p1: Vec<f64> = p0.iter().zip(&dp).map(|(a, b)| a + b).collect();
                // a state that grows: both guards stop at the same step
                let q: Vec<f64> = row(0.3).iter().map(|v| v * (step as f64).powi(2)).collect();
                let v = row(1.9);
                let ra = a.step(1e-2, (&q, &v), (&p0, &p1, &p2));
                let rb = b.step_basis(1e-2, (&q, &v), [&p0, &dp, &p2]);
                assert_eq!(ra.is_ok(), rb.is_ok(), "n = {n}, step {step}");
                assert_eq!(a.state()[1].to_bits(), b.state()[1].to_bits());
                if ra.is_err() {
                    break;
                }
            }
        }
    }

    #[test]
    fn a_long_step_counts_its_load_inside() {
        // a load zero at both ends of one long step, all in its bubble: still counted
        let mut g = GrowthGuard::new(2.0, &[1.0], (&[0.0], &[0.0]), &[0.0]).unwrap();
        // int |p| = 2/3 * 3 * 10 = 20, bound^2 = 200: energy 288 passes the limit 2
        assert!(g
            .step(10.0, (&[0.0], &[24.0]), (&[0.0], &[0.0], &[3.0]))
            .is_ok());
    }
}
