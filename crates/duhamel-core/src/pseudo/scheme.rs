//! How the state is approximated inside a step (the paper's schemes a, b, c, eq. 20) and how
//! the pseudo-force along it is integrated against `A(dt - tau)` (the quadratures).

use crate::kernel::oscillator::Transfer;

/// The approximation of `x(tau)`, `x'(tau)` inside the step (NOTES.md section 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scheme {
    /// `x' = (v0 + v1)/2` constant, `x = x0 + tau (v0 + v1)/2`.
    A,
    /// `x` linear from `x0` to `x1`, `x' = (x1 - x0)/dt` (unconditionally stable).
    B,
    /// `x` the parabola through `x0` with slope `v0` and `x1`;
    /// `x' = v0 + 2 (tau/dt) (x1 - x0 - v0 dt)/dt`.
    C,
    /// `x` the cubic Hermite interpolant of `(x0, v0)` and `(x1, v1)`, `x'` its derivative:
    /// interpolation error `O(dt^4)` in `x` (and `O(dt^3)` in `x'`, odd about the middle of
    /// the step). With the parabolic quadrature (nodes 0, 1/2, 1) the step is of order 4
    /// (slopes measured in tests/integrators/test_fourth_order.py) and its amplification on
    /// `x'' + omega^2 x = -alpha omega^2 x` (the whole force a pseudo-force) has spectral
    /// radius at most 1 as far as measured (`alpha` up to 1e4, `omega_c dt` up to the
    /// stiffness watch's 2); the Python side pairs it with no other quadrature.
    H,
}

/// How the pseudo-force along the interpolant is integrated over the step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quadrature {
    /// Linear in time between its values at the start and the end of the step.
    Trapezoid,
    /// The parabola through its values at the start, middle and end (the paper's `B`).
    Parabolic,
    /// The cubic through four equally spaced values: exact for forces that are polynomials
    /// of degree <= 3 along a linear interpolant (schemes a and b), with Duhamel moments up
    /// to `s^3`.
    Exact,
}

impl Quadrature {
    /// Nodes `s = tau/dt` and the monomial coefficients of their Lagrange polynomials.
    fn rule(self) -> (&'static [f64], &'static [[f64; 4]]) {
        match self {
            Quadrature::Trapezoid => (&[0.0, 1.0], &[[1.0, -1.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]]),
            Quadrature::Parabolic => (
                &[0.0, 0.5, 1.0],
                &[
                    [1.0, -3.0, 2.0, 0.0],
                    [0.0, 4.0, -4.0, 0.0],
                    [0.0, -1.0, 2.0, 0.0],
                ],
            ),
            Quadrature::Exact => (
                &[0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0],
                &[
                    [1.0, -5.5, 9.0, -4.5],
                    [0.0, 9.0, -22.5, 13.5],
                    [0.0, -4.5, 18.0, -13.5],
                    [0.0, 1.0, -4.5, 4.5],
                ],
            ),
        }
    }
}

/// One quadrature node: where it lies and how the interpolated state depends on the end
/// state `(q1, v1)` there.
#[derive(Debug, Clone, Copy)]
pub struct Node {
    /// `s = tau/dt`.
    pub s: f64,
    /// `dq(s)/dq1, dq(s)/dv1, dv(s)/dq1, dv(s)/dv1`.
    pub d: [f64; 4],
}

impl Scheme {
    /// The state `(q, v)` at `s` for one mode.
    #[inline]
    pub fn state(self, s: f64, dt: f64, q0: f64, v0: f64, q1: f64, v1: f64) -> (f64, f64) {
        match self {
            Scheme::A => {
                let vm = 0.5 * (v0 + v1);
                (q0 + s * dt * vm, vm)
            }
            Scheme::B => (q0 + s * (q1 - q0), (q1 - q0) / dt),
            Scheme::C => {
                let e = q1 - q0 - v0 * dt;
                (q0 + s * dt * v0 + s * s * e, v0 + 2.0 * s * e / dt)
            }
            Scheme::H => {
                let ([h00, h10, h01, h11], [d00, d10, d01, d11]) = hermite(s);
                (
                    h00 * q0 + dt * (h10 * v0 + h11 * v1) + h01 * q1,
                    (d00 * q0 + d01 * q1) / dt + d10 * v0 + d11 * v1,
                )
            }
        }
    }

    /// Derivatives of the state at `s` with respect to `(q1, v1)`.
    fn derivatives(self, s: f64, dt: f64) -> [f64; 4] {
        match self {
            Scheme::A => [0.0, 0.5 * s * dt, 0.0, 0.5],
            Scheme::B => [s, 0.0, 1.0 / dt, 0.0],
            Scheme::C => [s * s, 0.0, 2.0 * s / dt, 0.0],
            Scheme::H => {
                let ([_, _, h01, h11], [_, _, d01, d11]) = hermite(s);
                [h01, dt * h11, d01 / dt, d11]
            }
        }
    }
}

/// The cubic Hermite basis at `s` (`h00, h10, h01, h11`: the value of `x0`, `dt v0`, `x1`,
/// `dt v1`) and its derivatives in `s`.
#[inline(always)]
fn hermite(s: f64) -> ([f64; 4], [f64; 4]) {
    let s2 = s * s;
    let s3 = s2 * s;
    (
        [
            2.0 * s3 - 3.0 * s2 + 1.0,
            s3 - 2.0 * s2 + s,
            3.0 * s2 - 2.0 * s3,
            s3 - s2,
        ],
        [
            6.0 * (s2 - s),
            3.0 * s2 - 4.0 * s + 1.0,
            6.0 * (s - s2),
            3.0 * s2 - 2.0 * s,
        ],
    )
}

/// Nodes and per-mode weights: the end state gains `wx[i][m] Q_i[m]` and `wv[i][m] Q_i[m]`
/// from the pseudo-force value `Q_i` at node `i`.
pub struct Rule {
    /// The nodes.
    pub nodes: Vec<Node>,
    /// Displacement weights per node and mode.
    pub wx: Vec<Vec<f64>>,
    /// Velocity weights per node and mode.
    pub wv: Vec<Vec<f64>>,
}

impl Rule {
    /// The rule for a scheme and quadrature, with the exact moments of each mode.
    pub fn new(scheme: Scheme, quadrature: Quadrature, dt: f64, transfers: &[Transfer]) -> Self {
        let (nodes, lagrange) = quadrature.rule();
        let weight = |row: usize, l: &[f64; 4]| -> Vec<f64> {
            transfers
                .iter()
                .map(|tr| (0..4).map(|k| l[k] * tr.m[row][k]).sum())
                .collect()
        };
        Rule {
            nodes: nodes
                .iter()
                .map(|&s| Node {
                    s,
                    d: scheme.derivatives(s, dt),
                })
                .collect(),
            wx: lagrange.iter().map(|l| weight(0, l)).collect(),
            wv: lagrange.iter().map(|l| weight(1, l)).collect(),
        }
    }
}

/// Which part of the end state the pseudo-force depends on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Unknown {
    Q1,
    V1,
    Both,
}

/// The start of a step and its linear (load-only) prediction.
pub struct StepInput<'s> {
    pub t: f64,
    pub q0: &'s [f64],
    pub v0: &'s [f64],
    /// End state of the linear step (background and external loads only).
    pub q_lin: &'s [f64],
    pub v_lin: &'s [f64],
    /// Modal external load basis `(p0, Dp, DDp)` over the step.
    pub pb: [&'s [f64]; 3],
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lagrange_rules_reproduce_their_nodes() {
        for q in [
            Quadrature::Trapezoid,
            Quadrature::Parabolic,
            Quadrature::Exact,
        ] {
            let (nodes, l) = q.rule();
            for (i, li) in l.iter().enumerate() {
                for (j, &s) in nodes.iter().enumerate() {
                    let v = li[0] + li[1] * s + li[2] * s * s + li[3] * s * s * s;
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((v - want).abs() < 1e-14, "{q:?} {i} {j}");
                }
            }
        }
    }

    #[test]
    fn schemes_match_their_end_conditions() {
        let (dt, q0, v0, q1, v1) = (0.3, 1.0, -2.0, 0.7, 0.5);
        for sch in [Scheme::A, Scheme::B, Scheme::C] {
            let (q, _) = sch.state(0.0, dt, q0, v0, q1, v1);
            assert!((q - q0).abs() < 1e-15);
        }
        assert!((Scheme::B.state(1.0, dt, q0, v0, q1, v1).0 - q1).abs() < 1e-15);
        let (q, v) = Scheme::H.state(1.0, dt, q0, v0, q1, v1);
        assert!((q - q1).abs() < 1e-15 && (v - v1).abs() < 1e-14);
        let (q, v) = Scheme::H.state(0.0, dt, q0, v0, q1, v1);
        assert!((q - q0).abs() < 1e-15 && (v - v0).abs() < 1e-14);
        // the derivatives are those of the state, which is linear in (q1, v1)
        for s in [0.25, 0.5, 0.8] {
            let d = Scheme::H.derivatives(s, dt);
            let base = Scheme::H.state(s, dt, q0, v0, q1, v1);
            let dq = Scheme::H.state(s, dt, q0, v0, q1 + 1.0, v1);
            let dv = Scheme::H.state(s, dt, q0, v0, q1, v1 + 1.0);
            let got = [dq.0 - base.0, dv.0 - base.0, dq.1 - base.1, dv.1 - base.1];
            for (g, w) in got.iter().zip(d) {
                assert!((g - w).abs() < 1e-12, "{s} {got:?} {d:?}");
            }
        }
        // a cubic in time is reproduced exactly: x = 1 + t - t^2 + 2 t^3
        let x = |t: f64| 1.0 + t - t * t + 2.0 * t * t * t;
        let xd = |t: f64| 1.0 - 2.0 * t + 6.0 * t * t;
        for s in [0.1, 0.5, 0.9] {
            let (q, v) = Scheme::H.state(s, dt, x(0.0), xd(0.0), x(dt), xd(dt));
            assert!((q - x(s * dt)).abs() < 1e-14 && (v - xd(s * dt)).abs() < 1e-13);
        }
        let (q, v) = Scheme::C.state(1.0, dt, q0, v0, q1, v1);
        assert!((q - q1).abs() < 1e-15);
        assert!((Scheme::C.state(0.0, dt, q0, v0, q1, v1).1 - v0).abs() < 1e-15);
        assert!(v.is_finite());
    }
}
