//! The extrema of an oscillator's response inside one step of a piecewise-linear load, for
//! the exact-peak spectra of [`super::exact`]: each quantity's derivative is a damped
//! sinusoid plus a constant ([`Wave`]); the zeros of its own derivative (closed form) cut the
//! step into pieces where it is monotone, each with at most one root.

use super::common::Step;
use crate::kernel::oscillator::Transfer;

/// One oscillator's constants.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Osc {
    pub(super) omega: f64,
    pub(super) zeta: f64,
    /// `omega^2`, `2 zeta omega`, `zeta omega`, the damped frequency.
    pub(super) k: f64,
    pub(super) c: f64,
    pub(super) sigma: f64,
    pub(super) wd: f64,
}

impl Osc {
    pub(super) fn new(omega: f64, zeta: f64) -> Self {
        Osc {
            omega,
            zeta,
            k: omega * omega,
            c: 2.0 * zeta * omega,
            sigma: zeta * omega,
            wd: omega * (1.0 - zeta * zeta).sqrt(),
        }
    }
}

/// `exp(-sigma s) (p cos(wd s) + q sin(wd s)) + k0` and its derivative.
#[derive(Debug, Clone, Copy)]
struct Wave {
    p: f64,
    q: f64,
    k0: f64,
    sigma: f64,
    wd: f64,
}

impl Wave {
    fn eval(&self, s: f64) -> (f64, f64) {
        let e = (-self.sigma * s).exp();
        let (sn, cs) = (self.wd * s).sin_cos();
        let g = e * (self.p * cs + self.q * sn) + self.k0;
        let d1 = -self.sigma * self.p + self.wd * self.q;
        let d2 = -self.sigma * self.q - self.wd * self.p;
        (g, e * (d1 * cs + d2 * sn))
    }

    /// The roots in `(0, h)`, each in one piece where `g` is monotone; `g0`, `gh` the
    /// values at the ends (known from the states there).
    fn roots(&self, h: f64, (g0, gh): (f64, f64), out: &mut Vec<f64>) {
        out.clear();
        let d1 = -self.sigma * self.p + self.wd * self.q;
        let d2 = -self.sigma * self.q - self.wd * self.p;
        // Zeros of g': d1 cos + d2 sin = 0 at wd s = phi + m pi, phi in (0, pi].
        let mut phi = (-d1).atan2(d2);
        let pi = std::f64::consts::PI;
        while phi <= 0.0 {
            phi += pi;
        }
        while phi > pi {
            phi -= pi;
        }
        let mut a = 0.0;
        let mut ga = g0;
        let mut m = 0.0;
        loop {
            let b = ((phi + m * pi) / self.wd).min(h);
            let gb = if b >= h { gh } else { self.eval(b).0 };
            if b > a && ga * gb < 0.0 {
                out.push(self.root(a, b, ga, gb));
            }
            if b >= h {
                break;
            }
            a = b;
            ga = gb;
            m += 1.0;
        }
    }

    /// The root of the monotone `g` on `[a, b]` (signs differ at the ends; `ga = g(a)`):
    /// Newton steps kept inside the bracket, bisection where they leave it.
    fn root(&self, mut a: f64, mut b: f64, ga: f64, gb: f64) -> f64 {
        let rising = ga < 0.0;
        // The secant point first (the wave is nearly linear on a short piece).
        let mut s = a + (b - a) * ga / (ga - gb);
        if !(s > a && s < b) {
            s = 0.5 * (a + b);
        }
        for _ in 0..100 {
            let (g, d) = self.eval(s);
            if g == 0.0 {
                return s;
            }
            if (g < 0.0) == rising {
                a = s;
            } else {
                b = s;
            }
            let newton = s - g / d;
            let next = if newton > a && newton < b && d != 0.0 {
                newton
            } else {
                0.5 * (a + b)
            };
            if (next - s).abs() <= 1e-15 * b.abs().max(1e-300) || b - a <= 1e-15 * b {
                return next;
            }
            s = next;
        }
        s
    }
}

/// Per lane, what a step needs for its exact search.
pub(super) struct Search {
    roots: Vec<f64>,
}

impl Search {
    pub(super) fn new() -> Self {
        Search { roots: Vec::new() }
    }

    /// Updates `peak` (`[sd, sv, sa]`) with the interior extrema of the step of length `h`
    /// from `(x0, v0)` under `p0 -> p1` whose bounds (`flags`) say they may exceed it.
    pub(super) fn step(
        &mut self,
        o: &Osc,
        h: f64,
        ((x0, v0), (xn, vn)): ((f64, f64), (f64, f64)),
        (p0, p1): (f64, f64),
        flags: [bool; 3],
        peak: &mut [f64; 3],
    ) {
        let r = (p1 - p0) / h;
        let a0 = p0 - o.c * v0 - o.k * x0;
        let a1 = p1 - o.c * vn - o.k * xn;
        let j0 = r - o.c * a0 - o.k * v0;
        // x = xp + free part (Cx, Dx); x' = Wv, x'' = Wa (no constant: the load's second
        // derivative vanishes).
        let vp = r / o.k;
        let xp0 = (p0 - o.c * vp) / o.k;
        let pv = v0 - vp;
        let cx = x0 - xp0;
        let dx = (pv + o.sigma * cx) / o.wd;
        let wave = |p: f64, q: f64, k0: f64| Wave {
            p,
            q,
            k0,
            sigma: o.sigma,
            wd: o.wd,
        };
        let wv = wave(pv, (a0 + o.sigma * pv) / o.wd, vp);
        let wa = wave(a0, (j0 + o.sigma * a0) / o.wd, 0.0);
        // d/ds (k x + c x') = k x' + c x''.
        let ws = wave(o.k * wv.p + o.c * wa.p, o.k * wv.q + o.c * wa.q, r);
        let ends = [
            (v0, vn),
            (a0, a1),
            (o.k.mul_add(v0, o.c * a0), o.k.mul_add(vn, o.c * a1)),
        ];
        // Short periods against the step: the value from the decomposition (the particular
        // part is not larger than the response there); long ones: the exact step matrices.
        let decomposed = o.omega * h >= 0.5;
        for (which, w) in [wv, wa, ws].iter().enumerate() {
            if !flags[which] {
                continue;
            }
            w.roots(h, ends[which], &mut self.roots);
            for &s in &self.roots {
                let (x, v) = if decomposed {
                    let e = (-o.sigma * s).exp();
                    let (sn, cs) = (o.wd * s).sin_cos();
                    (
                        xp0 + vp * s + e * (cx * cs + dx * sn),
                        vp + e * (wv.p * cs + wv.q * sn),
                    )
                } else {
                    let st = Step::from_transfer(&Transfer::from_omega_zeta(o.omega, o.zeta, s));
                    st.apply(x0, v0, p0, p0 + r * s)
                };
                let f = match which {
                    0 => x,
                    1 => v,
                    _ => o.k.mul_add(x, o.c * v),
                };
                peak[which] = peak[which].max(f.abs());
            }
        }
    }
}
