//! The extrema of an oscillator's response inside one step of a piecewise-linear load, for
//! the exact-peak spectra of [`super::exact`]: each quantity's derivative is a damped
//! sinusoid plus a constant ([`Wave`]); the zeros of its own derivative (closed form) cut the
//! step into pieces where it is monotone, each with at most one root, where the quantity is
//! concave or convex: its tangents at the ends bound its extremum ([`may_reach`]).

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
    /// `(cos, sin)` of `wd h` (`h` the record's step) where `wd h < pi` (see [`Wave::roots`]).
    turn: Option<(f64, f64)>,
}

impl Osc {
    /// The oscillator of `omega`, `zeta` on steps of `h`.
    pub(super) fn new(omega: f64, zeta: f64, h: f64) -> Self {
        let wd = omega * (1.0 - zeta * zeta).sqrt();
        let angle = wd * h;
        Osc {
            omega,
            zeta,
            k: omega * omega,
            c: 2.0 * zeta * omega,
            sigma: zeta * omega,
            wd,
            turn: (angle < std::f64::consts::PI * (1.0 - 1e-6)).then(|| {
                let (sn, cs) = angle.sin_cos();
                (cs, sn)
            }),
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
    /// `(cos, sin)` of `wd h` where `wd h < pi`, `h` the step ([`Osc`]'s).
    turn: Option<(f64, f64)>,
}

/// The quantity whose derivative a [`Wave`] is: `c0 + c1 s + exp(-sigma s) (p cos(wd s) + q
/// sin(wd s))` (the wave's `sigma`, `wd`), for the bound of [`Wave::roots`].
#[derive(Debug, Clone, Copy)]
struct Prim {
    c0: f64,
    c1: f64,
    p: f64,
    q: f64,
}

/// Whether the extremum of `f` at the root of its derivative `g` inside `[a, b]` may reach
/// `peak` in magnitude, from the values `fa`, `fb` and slopes `ga`, `gb` at the ends (`ga
/// gb < 0`) and `g` monotone on `[a, b]`: `f` is concave there (`g` falling) or convex, so it
/// lies on one side of its tangents at the ends, and the extremum between them and the end
/// values; `scale` bounds the terms of `fa`, `fb` (their rounding), a margin covers it.
fn may_reach(w: f64, (fa, fb): (f64, f64), (ga, gb): (f64, f64), scale: f64, peak: f64) -> bool {
    let t = ((fb - fa - gb * w) / (ga - gb)).clamp(0.0, w);
    let (l1, l2) = (ga.mul_add(t, fa), gb.mul_add(t - w, fb));
    let tangent = if ga > 0.0 { l1.min(l2) } else { l1.max(l2) };
    let bound = tangent.abs().max(fa.abs()).max(fb.abs());
    let margin = 1e-9 * peak + 1e-12 * (scale + fa.abs() + fb.abs() + (ga.abs() + gb.abs()) * w);
    // A NaN (an overflow, reported by the caller) keeps the piece.
    !matches!(
        (bound + margin).partial_cmp(&peak),
        Some(std::cmp::Ordering::Less)
    )
}

impl Wave {
    /// `g(s)` and, with the same transcendentals, `f(s)` of `f` (`f' = g`) and the size of
    /// `f`'s terms.
    fn eval_with(&self, f: &Prim, s: f64) -> (f64, f64, f64) {
        let (g, _, fs, scale) = self.eval_full(f, s);
        (g, fs, scale)
    }

    /// [`Wave::eval`] and, with the same transcendentals, `f(s)` of `f` (`f' = g`) and the
    /// size of `f`'s terms.
    fn eval_full(&self, f: &Prim, s: f64) -> (f64, f64, f64, f64) {
        let e = (-self.sigma * s).exp();
        let (sn, cs) = (self.wd * s).sin_cos();
        let g = e * (self.p * cs + self.q * sn) + self.k0;
        let d1 = -self.sigma * self.p + self.wd * self.q;
        let d2 = -self.sigma * self.q - self.wd * self.p;
        let fs = f.c1.mul_add(s, f.c0) + e * (f.p * cs + f.q * sn);
        let scale = f.c0.abs() + (f.c1 * s).abs() + e * (f.p.abs() + f.q.abs());
        (g, e * (d1 * cs + d2 * sn), fs, scale)
    }

    /// The roots in `(0, h)`, each in one piece where `g` is monotone, where the extremum
    /// of `f` (`f' = g`) there may reach `peak` ([`may_reach`]); `g0`, `gh` and `f0`, `fh`
    /// the values at the ends (known from the states there).
    ///
    /// Where `wd h < pi` (the wave's `turn`), `g'` (`d1 cos + d2 sin` times a positive
    /// factor) has at most one zero in the step, none where it has the same sign at both
    /// ends: then the step is one piece, with no arctangent. The sign counts only where it is
    /// clear (beyond `1e-8 (|d1| + |d2|)`, so the zero is at least `1e-8` of the angle
    /// outside the step, far beyond the arctangent's rounding): the same piece as the search
    /// through the arctangent, to the bit.
    fn roots(
        &self,
        h: f64,
        ((g0, gh), (f0, fh)): ((f64, f64), (f64, f64)),
        (f, peak): (&Prim, f64),
        out: &mut Vec<f64>,
    ) {
        out.clear();
        let d1 = -self.sigma * self.p + self.wd * self.q;
        let d2 = -self.sigma * self.q - self.wd * self.p;
        if let Some((ch, sh)) = self.turn {
            let (e0, e1) = (d1, d1.mul_add(ch, d2 * sh));
            let clear = 1e-8 * (d1.abs() + d2.abs());
            if e0.abs() > clear && e1.abs() > clear && (e0 > 0.0) == (e1 > 0.0) {
                if h > 0.0 && g0 * gh < 0.0 && may_reach(h, (f0, fh), (g0, gh), 0.0, peak) {
                    if let Some(s) = self.root((0.0, h), (g0, gh), (f, (f0, fh), (0.0, 0.0)), peak)
                    {
                        out.push(s);
                    }
                }
                return;
            }
        }
        // Zeros of g': d1 cos + d2 sin = 0 at wd s = phi + m pi, phi in (0, pi].
        let mut phi = (-d1).atan2(d2);
        let pi = std::f64::consts::PI;
        while phi <= 0.0 {
            phi += pi;
        }
        while phi > pi {
            phi -= pi;
        }
        let (mut a, mut ga, mut fa, mut ea) = (0.0, g0, f0, 0.0);
        let mut m = 0.0;
        loop {
            let b = ((phi + m * pi) / self.wd).min(h);
            let (gb, fb, eb) = if b >= h {
                (gh, fh, 0.0)
            } else {
                self.eval_with(f, b)
            };
            if b > a && ga * gb < 0.0 && may_reach(b - a, (fa, fb), (ga, gb), ea + eb, peak) {
                if let Some(s) = self.root((a, b), (ga, gb), (f, (fa, fb), (ea, eb)), peak) {
                    out.push(s);
                }
            }
            if b >= h {
                break;
            }
            (a, ga, fa, ea) = (b, gb, fb, eb);
            m += 1.0;
        }
    }

    /// The root of the monotone `g` on `[a, b]` (signs differ at the ends; `ga = g(a)`):
    /// Newton steps kept inside the bracket, bisection where they leave it. `None` once the
    /// bracket shows that the extremum of `f` there cannot reach `peak` ([`may_reach`] with
    /// `f`'s values `fs` and the size of their terms `es` at the bracket's ends).
    fn root(
        &self,
        (mut a, mut b): (f64, f64),
        (mut ga, mut gb): (f64, f64),
        (f, mut fs, mut es): (&Prim, (f64, f64), (f64, f64)),
        peak: f64,
    ) -> Option<f64> {
        let rising = ga < 0.0;
        // The secant point first (the wave is nearly linear on a short piece).
        let mut s = a + (b - a) * ga / (ga - gb);
        if !(s > a && s < b) {
            s = 0.5 * (a + b);
        }
        for _ in 0..100 {
            let (g, d, fv, ev) = self.eval_full(f, s);
            if g == 0.0 {
                return Some(s);
            }
            if (g < 0.0) == rising {
                (a, ga, fs.0, es.0) = (s, g, fv, ev);
            } else {
                (b, gb, fs.1, es.1) = (s, g, fv, ev);
            }
            if !may_reach(b - a, fs, (ga, gb), es.0 + es.1, peak) {
                return None;
            }
            let newton = s - g / d;
            let next = if newton > a && newton < b && d != 0.0 {
                newton
            } else {
                0.5 * (a + b)
            };
            if (next - s).abs() <= 1e-15 * b.abs().max(1e-300) || b - a <= 1e-15 * b {
                return Some(next);
            }
            s = next;
        }
        Some(s)
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
            turn: o.turn,
        };
        let wv = wave(pv, (a0 + o.sigma * pv) / o.wd, vp);
        let wa = wave(a0, (j0 + o.sigma * a0) / o.wd, 0.0);
        // d/ds (k x + c x') = k x' + c x''.
        let ws = wave(o.k * wv.p + o.c * wa.p, o.k * wv.q + o.c * wa.q, r);
        let (s0, s1) = (o.k.mul_add(x0, o.c * v0), o.k.mul_add(xn, o.c * vn));
        let ends = [
            ((v0, vn), (x0, xn)),
            ((a0, a1), (v0, vn)),
            (
                (o.k.mul_add(v0, o.c * a0), o.k.mul_add(vn, o.c * a1)),
                (s0, s1),
            ),
        ];
        let prim = |c0: f64, c1: f64, p: f64, q: f64| Prim { c0, c1, p, q };
        let sp = o.c.mul_add(vp, o.k * xp0);
        let prims = [
            prim(xp0, vp, cx, dx),
            prim(vp, 0.0, wv.p, wv.q),
            prim(
                sp,
                o.k * vp,
                o.k.mul_add(cx, o.c * wv.p),
                o.k.mul_add(dx, o.c * wv.q),
            ),
        ];
        // Short periods against the step: the value from the decomposition (the particular
        // part is not larger than the response there); long ones: the exact step matrices.
        let decomposed = o.omega * h >= 0.5;
        for (which, w) in [wv, wa, ws].iter().enumerate() {
            if !flags[which] {
                continue;
            }
            w.roots(
                h,
                ends[which],
                (&prims[which], peak[which]),
                &mut self.roots,
            );
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

#[cfg(test)]
mod tests {
    use super::*;

    /// On steps of damped sinusoids plus lines, the search with the tangent bound
    /// ([`may_reach`]) still finds every interior maximum of `|f|` that reaches the peak: against
    /// a peak just below the step's largest `|f|` (dense sampling), a root is kept where `|f|`
    /// reaches it; and the bound is tight enough to give up most steps against a peak 20 %
    /// above that.
    #[test]
    fn tangent_bound_keeps_the_extremum() {
        let (mut interior, mut given_up) = (0, 0);
        for (i, &(sigma, wd)) in [(0.1, 3.0), (2.0, 50.0), (0.0, 300.0), (5.0, 7.0)]
            .iter()
            .enumerate()
        {
            for j in 0..60 {
                let t = (i * 60 + j) as f64;
                let (p, q) = ((0.7 * t).sin(), (1.3 * t).cos() - 0.2);
                let (c0, c1) = (0.3 * (0.5 * t).sin(), 4.0 * (2.1 * t).cos());
                let f = Prim { c0, c1, p, q };
                // g = f' = c1 + exp(-sigma s) ((wd q - sigma p) cos + (-sigma q - wd p) sin).
                let w = Wave {
                    p: wd * q - sigma * p,
                    q: -sigma * q - wd * p,
                    k0: c1,
                    sigma,
                    wd,
                    turn: None,
                };
                let h = 0.01 + 0.02 * (j % 7) as f64;
                let (g0, f0, _) = w.eval_with(&f, 0.0);
                let (gh, fh, _) = w.eval_with(&f, h);
                let ends = ((g0, gh), (f0, fh));
                let n = 20_000;
                let top = (0..=n)
                    .map(|k| w.eval_with(&f, h * k as f64 / n as f64).1.abs())
                    .fold(0.0f64, f64::max);
                if top <= f0.abs().max(fh.abs()) * (1.0 + 1e-6) {
                    continue;
                }
                interior += 1;
                let mut roots = Vec::new();
                w.roots(h, ends, (&f, top * (1.0 - 1e-6)), &mut roots);
                let found = roots
                    .iter()
                    .map(|&s| w.eval_with(&f, s).1.abs())
                    .fold(0.0f64, f64::max);
                assert!(found >= top * (1.0 - 1e-6), "{i} {j}: {found} {top}");
                w.roots(h, ends, (&f, 1.2 * top), &mut roots);
                given_up += usize::from(roots.is_empty());
            }
        }
        assert!(
            interior > 40 && given_up > interior / 2,
            "{interior} {given_up}"
        );
    }

    /// Where `wd h < pi`, the step taken as one piece without the arctangent where `g'` has
    /// the same clear sign at its ends gives the roots of the search through the arctangent,
    /// to the bit, against any peak (here 0: every piece with a root is searched, and the
    /// peaks of the other test); and both find the roots at the interior extrema of `f`.
    #[test]
    fn one_piece_without_arctangent_is_the_same_search() {
        let (mut one_piece, mut compared, mut found) = (0, 0, 0);
        for (i, &(sigma, wd)) in [(0.1, 3.0), (2.0, 50.0), (0.0, 300.0), (15.0, 310.0)]
            .iter()
            .enumerate()
        {
            for j in 0..400 {
                let t = (i * 400 + j) as f64;
                let (p, q) = ((0.7 * t).sin(), (1.3 * t).cos() - 0.2);
                let (c0, c1) = (0.3 * (0.5 * t).sin(), 4.0 * (2.1 * t).cos());
                let f = Prim { c0, c1, p, q };
                let h = 0.001 + 0.0011 * (j % 11) as f64;
                let angle: f64 = wd * h;
                if angle >= std::f64::consts::PI * (1.0 - 1e-6) {
                    continue;
                }
                let (sn, cs) = angle.sin_cos();
                let wave = |turn| Wave {
                    p: wd * q - sigma * p,
                    q: -sigma * q - wd * p,
                    k0: c1,
                    sigma,
                    wd,
                    turn,
                };
                let (with, without) = (wave(Some((cs, sn))), wave(None));
                let (g0, f0, _) = without.eval_with(&f, 0.0);
                let (gh, fh, _) = without.eval_with(&f, h);
                let ends = ((g0, gh), (f0, fh));
                let d1 = -sigma * without.p + wd * without.q;
                let d2 = -sigma * without.q - wd * without.p;
                let e1 = d1 * cs + d2 * sn;
                one_piece += usize::from(d1 * e1 > 0.0);
                let top = f0.abs().max(fh.abs());
                for peak in [0.0, top, 1.001 * top, 0.999 * top] {
                    let (mut a, mut b) = (Vec::new(), Vec::new());
                    with.roots(h, ends, (&f, peak), &mut a);
                    without.roots(h, ends, (&f, peak), &mut b);
                    let bits = |r: &[f64]| r.iter().map(|s| s.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&a), bits(&b), "{i} {j} {peak}");
                    compared += 1;
                    found += a.len();
                    // Each root is a zero of g = f'.
                    for &s in &a {
                        let (g, _, scale) = without.eval_with(&f, s);
                        let size = without.p.abs() + without.q.abs() + c1.abs();
                        assert!(g.abs() <= 1e-9 * size, "{i} {j}: g({s}) = {g} ({scale})");
                    }
                }
            }
        }
        assert!(
            one_piece > 400 && compared > 4000 && found > 1000,
            "{one_piece} {compared} {found}"
        );
    }
}
