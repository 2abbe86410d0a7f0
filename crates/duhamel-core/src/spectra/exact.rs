//! Exact peaks of elastic response spectra: the largest `|x|`, `|x'|` and `|2 zeta omega x' +
//! omega^2 x|` of each oscillator over the whole piecewise-linear record, between the samples
//! too, not only at them.
//!
//! Inside a step under the linear load `p0 + r s`, every one of the three quantities `f` has
//! a derivative of the form `g(s) = exp(-sigma s) (P cos(wd s) + Q sin(wd s)) + K` (`wd` the
//! damped frequency): `x' `, `x''` and `omega^2 x' + 2 zeta omega x''`. An interior extremum
//! of `f` is a root of `g`; the zeros of `g'` (closed form) split the step into pieces on which
//! `g` is monotone, each with at most one root, found by a safeguarded Newton iteration; `f`
//! there is then evaluated with the oscillator's exact step matrices over the fraction of the
//! step. On such a piece `f` is concave or convex, so its tangents at the piece's (or the
//! bracket's) ends bound the extremum: a piece or bracket whose bound stays below the peak is
//! given up, with no more evaluations (the roots searched, and so the peaks, are those of a
//! search to the end). The sampled response and its peaks come first; an interior value counts only if it
//! exceeds those, the largest of the record, so a step is searched only when a bound says it
//! may: a cheap gate `|f| <= max(|f0|, |f1|) + h^2/8 max|f''|` (`|f''|` bounded by the
//! amplitude of `x''`, a damped sinusoid under a linear load, times 1, `omega` or `omega^2 +
//! 2 zeta omega^2`), then the free part's amplitude. The sampled recurrence and a blockwise
//! form of the gate against the peaks so far share one pass over the record, no state
//! stored ([`super::gate`]): the gate's arithmetic does not feed the recurrence's chain,
//! so it runs in that chain's latency. Only the blocks it keeps are gone over again.
//! Underdamped oscillators (`zeta < 1`) only.

use super::common::{check, map_tasks, Record, Step};
use super::elastic::{Peaks, LANES};
use super::gate::{block_jumps, first_pass, larger, Candidate, Lanes, BLOCK};
use super::inside::{Osc, Search};
use crate::error::CoreError;

/// The lanes' transition matrices, entry by entry.
fn transpose_a(steps: &[Step; LANES]) -> [[[f64; LANES]; 2]; 2] {
    let mut a = [[[0.0; LANES]; 2]; 2];
    for (r, row) in a.iter_mut().enumerate() {
        for (q, cell) in row.iter_mut().enumerate() {
            for (l, s) in steps.iter().enumerate() {
                cell[l] = s.a[r][q];
            }
        }
    }
    a
}

/// The lanes' load vectors: `(b0 x, b0 v, b1 x, b1 v)`.
#[allow(clippy::type_complexity)]
fn transpose_b(steps: &[Step; LANES]) -> ([f64; LANES], [f64; LANES], [f64; LANES], [f64; LANES]) {
    let mut b = ([0.0; LANES], [0.0; LANES], [0.0; LANES], [0.0; LANES]);
    for (l, s) in steps.iter().enumerate() {
        b.0[l] = s.b0[0];
        b.1[l] = s.b0[1];
        b.2[l] = s.b1[0];
        b.3[l] = s.b1[1];
    }
    b
}

/// Per lane, the constants of the bounds.
#[derive(Clone, Copy, Default)]
struct Bound {
    k: f64,
    c: f64,
    sigma: f64,
    inv_wd: f64,
    inv_k: f64,
    /// `|f''|` against the amplitude of `x''`: `omega` for `x'`, `omega^2 + c omega` for
    /// `k x + c x'`.
    f1: f64,
    f2: f64,
}

impl Bound {
    fn new(o: &Osc) -> Self {
        let inv = |y: f64| if y > 0.0 { 1.0 / y } else { 0.0 };
        Bound {
            k: o.k,
            c: o.c,
            sigma: o.sigma,
            inv_wd: inv(o.wd),
            inv_k: inv(o.k),
            f1: o.omega,
            f2: o.k + o.c * o.omega,
        }
    }

    /// Whether `x`, `x'`, `k x + c x'` may exceed their peaks `pk` inside the step from
    /// `(x0, v0)` to `(xn, vn)` under `p0 + r s`: two bounds of each, the smaller counts —
    /// the ends' values plus `h^2/8` (`h2`: its square, with a margin) times the bound of the
    /// second derivative (tight for long periods), and the particular part's (linear) ends
    /// plus the amplitude of the free, damped sinusoidal part (tight for short periods).
    /// Branch-free (`&`, `|`), so the lanes' loop vectorises.
    #[inline(always)]
    fn flags(
        &self,
        (h, h2): (f64, f64),
        (x0, v0): (f64, f64),
        (xn, vn): (f64, f64),
        (p0, r): (f64, f64),
        pk: [f64; 3],
    ) -> [bool; 3] {
        let (k, c, sigma, iw, ik) = (self.k, self.c, self.sigma, self.inv_wd, self.inv_k);
        let s0 = k.mul_add(x0, c * v0);
        let s1 = k.mul_add(xn, c * vn);
        let a0 = p0 - c * v0 - k * x0;
        let q = (r - c * a0 - k * v0 + sigma * a0) * iw;
        let amp2 = a0.mul_add(a0, q * q) * h2;
        let vp = r * ik;
        let xp0 = (p0 - c * vp) * ik;
        let xp1 = xp0 + vp * h;
        let cx = x0 - xp0;
        let dx = (v0 - vp + sigma * cx) * iw;
        let pv = v0 - vp;
        let qv = (a0 + sigma * pv) * iw;
        let (ps, qs) = (k.mul_add(cx, c * pv), k.mul_add(dx, c * qv));
        let sp = c * vp;
        let over = |top: f64, peak: f64, f: f64| {
            let gap = peak - top;
            (gap <= 0.0) | (amp2 * f * f > gap * gap)
        };
        // The margin covers the rounding of the decomposition.
        let free = |top: f64, peak: f64, r2: f64| {
            let gap = peak * (1.0 - 1e-9) - top;
            (gap <= 0.0) | (r2 > gap * gap)
        };
        let big = |a: f64, b: f64| larger(a.abs(), b.abs());
        [
            over(big(x0, xn), pk[0], 1.0) & free(big(xp0, xp1), pk[0], cx.mul_add(cx, dx * dx)),
            over(big(v0, vn), pk[1], self.f1) & free(vp.abs(), pk[1], pv.mul_add(pv, qv * qv)),
            over(big(s0, s1), pk[2], self.f2)
                & free(
                    big(k * xp0 + sp, k * xp1 + sp),
                    pk[2],
                    ps.mul_add(ps, qs * qs),
                ),
        ]
    }
}

/// Exact peaks `[sd, sv, sa]` of the lanes `o` (`None`: a padding lane, at rest) over
/// `acc` (`jumps`: its [`block_jumps`]), and whether the final states are finite.
///
/// One pass over the record runs the sampled spectra's recurrence with its peaks and gates
/// blocks of steps against the record's sampled peaks ([`first_pass`]; so a block
/// it lets go has no step that could exceed the final ones). The steps of a block it keeps
/// are gated again, all lanes and steps at once, against the peaks at the block's start
/// ([`Lanes::block_steps`], branch-free); then, in time order, each step that passes in
/// some lane is scored against the peaks raised by the searches so far and searched in the
/// lanes whose bounds may exceed them. The gate is monotone in the peaks and passed by every
/// step whose score is `>= 0`: the steps, order and peaks of a pass over every step with the
/// states kept.
fn run(
    (acc, jumps): (&[f64], &[[f64; 3]]),
    h: f64,
    o: &[Option<Osc>; LANES],
    steps: &[Step; LANES],
) -> ([[f64; 3]; LANES], bool) {
    let mut bound = [Bound::default(); LANES];
    for (b, ol) in bound.iter_mut().zip(o) {
        if let Some(ol) = ol {
            *b = Bound::new(ol);
        }
    }
    // The bounds' constants lane by lane (structure of arrays: the loop vectorises).
    let lane = |f: fn(&Bound) -> f64| -> [f64; LANES] {
        let mut out = [0.0; LANES];
        for (y, b) in out.iter_mut().zip(&bound) {
            *y = f(b);
        }
        out
    };
    let (b0x, b0v, b1x, b1v) = transpose_b(steps);
    let h2 = (h * h / 8.0 * (1.0 + 1e-9)).powi(2);
    let lanes = Lanes {
        a: transpose_a(steps),
        b: [b0x, b0v, b1x, b1v],
        k: lane(|b| b.k),
        c: lane(|b| b.c),
        sigma: lane(|b| b.sigma),
        iw: lane(|b| b.inv_wd),
        ik: lane(|b| b.inv_k),
        f1: lane(|b| b.f1),
        f2: lane(|b| b.f2),
        // A padding lane's factors are 0: infinite inverses, its gaps (infinite peaks) infinite.
        i1: lane(|b| 1.0 / b.f1),
        i2: lane(|b| 1.0 / b.f2),
        h2,
    };
    // Padding lanes (at rest) never need a search: an infinite peak (reset below).
    let mut pk = [[0.0f64; LANES]; 3];
    for (l, ol) in o.iter().enumerate() {
        if ol.is_none() {
            for q in &mut pk {
                q[l] = f64::INFINITY;
            }
        }
    }
    let (cands, x, v) = first_pass((acc, jumps), h, &lanes, &mut pk);
    let mut search = Search::new();
    let (mut xs, mut vs) = ([[0.0; LANES]; BLOCK + 1], [[0.0; LANES]; BLOCK + 1]);
    for Candidate { n: start, x, v } in &cands {
        let samples = &acc[*start..acc.len().min(start + BLOCK + 1)];
        let bits = lanes.block_steps((x, v), (samples, h), &pk, (&mut xs, &mut vs));
        // The steps some lane keeps, in time order; every lane scored at once (the lanes'
        // loop vectorises), then searched where its score is `>= 0` (so where it keeps it).
        let mut steps = bits.iter().fold(0, |a, b| a | b);
        while steps != 0 {
            let i = steps.trailing_zeros() as usize;
            steps &= steps - 1;
            let (p0, p1) = (-samples[i], -samples[i + 1]);
            let r = (p1 - p0) / h;
            let mut score = [0.0; LANES];
            for (l, s) in score.iter_mut().enumerate() {
                let ends = ((xs[i][l], vs[i][l]), (xs[i + 1][l], vs[i + 1][l]));
                *s = lanes.score(l, h, ends, (p0, r), [pk[0][l], pk[1][l], pk[2][l]]);
            }
            for (l, ol) in o.iter().enumerate() {
                if let (Some(ol), true) = (ol, score[l] >= 0.0) {
                    let ends = ((xs[i][l], vs[i][l]), (xs[i + 1][l], vs[i + 1][l]));
                    let mut peak = [pk[0][l], pk[1][l], pk[2][l]];
                    let f = bound[l].flags((h, h2), ends.0, ends.1, (p0, r), peak);
                    search.step(ol, h, ends, (p0, p1), f, &mut peak);
                    [pk[0][l], pk[1][l], pk[2][l]] = peak;
                }
            }
        }
    }
    let mut peak = [[0.0; 3]; LANES];
    for (l, p) in peak.iter_mut().enumerate() {
        if o[l].is_some() {
            *p = [pk[0][l], pk[1][l], pk[2][l]];
        }
    }
    let finite = x
        .iter()
        .chain(&v)
        .chain(peak.iter().flatten())
        .all(|y| y.is_finite());
    (peak, finite)
}

/// Elastic spectra with exact peaks (see the module docstring); the arguments, layout and
/// errors of [`super::elastic::elastic`], and an error for a damping ratio `>= 1`.
pub fn elastic_exact(
    records: &[Record],
    periods: &[f64],
    dampings: &[f64],
    threads: Option<usize>,
) -> Result<Peaks, CoreError> {
    check(records, periods, dampings)?;
    if let Some(&z) = dampings.iter().find(|z| **z >= 1.0) {
        return Err(CoreError::InvalidInput {
            name: "damping",
            problem: format!("must be < 1 for exact peaks (underdamped oscillators), got {z}"),
        });
    }
    let (nr, nd, np) = (records.len(), dampings.len(), periods.len());
    let chunks = np.div_ceil(LANES);
    let jumps: Vec<Vec<[f64; 3]>> = records.iter().map(|r| block_jumps(r.acc)).collect();
    let tasks: Vec<(usize, usize, usize)> = (0..nr)
        .flat_map(|r| (0..nd).flat_map(move |d| (0..chunks).map(move |c| (r, d, c))))
        .collect();
    let task = |&(r, d, c): &(usize, usize, usize)| -> Result<Vec<[f64; 3]>, CoreError> {
        let rec = records[r];
        let zeta = dampings[d];
        let span = &periods[c * LANES..np.min((c + 1) * LANES)];
        let mut osc = [None; LANES];
        let mut steps = [Step::default(); LANES];
        for (l, &t) in span.iter().enumerate() {
            if t > 0.0 {
                let omega = 2.0 * std::f64::consts::PI / t;
                steps[l] = Step::new(omega, zeta, rec.dt)?;
                osc[l] = Some(Osc::new(omega, zeta, rec.dt));
            }
        }
        let (peak, finite) = run((rec.acc, &jumps[r]), rec.dt, &osc, &steps);
        if !finite {
            return Err(CoreError::InvalidInput {
                name: "motions",
                problem: format!(
                    "record {r}: the oscillator response overflows (damping {zeta}, periods \
                     {span:?}); check the record's units and values"
                ),
            });
        }
        let pga = rec.acc.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        Ok(span
            .iter()
            .enumerate()
            .map(|(l, &t)| if t > 0.0 { peak[l] } else { [0.0, 0.0, pga] })
            .collect())
    };
    let results = map_tasks(threads, &tasks, task)?;
    let mut out = Peaks {
        sd: Vec::with_capacity(nr * nd * np),
        sv: Vec::with_capacity(nr * nd * np),
        sa: Vec::with_capacity(nr * nd * np),
    };
    for chunk in results.iter().flatten() {
        out.sd.push(chunk[0]);
        out.sv.push(chunk[1]);
        out.sa.push(chunk[2]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Undamped oscillator under a constant acceleration `-g0` from rest: `x = -(g0 /
    /// omega^2)(1 - cos omega t)`, whose peak `2 g0 / omega^2` falls between samples.
    #[test]
    fn constant_record_peak_between_samples() {
        let acc = vec![1.5; 301];
        let rec = [Record {
            acc: &acc,
            dt: 0.01,
        }];
        let periods = [0.0, 0.0137, 0.05, 0.33, 1.1];
        let p = elastic_exact(&rec, &periods, &[0.0], Some(1)).unwrap();
        for (i, &t) in periods.iter().enumerate().skip(1) {
            let w = 2.0 * std::f64::consts::PI / t;
            let sd = 2.0 * 1.5 / (w * w);
            assert!(
                (p.sd[i] - sd).abs() <= 1e-12 * sd,
                "T = {t}: {} vs {sd}",
                p.sd[i]
            );
            // |x'| peaks at 1.5 / omega, |omega^2 x| at 2 * 1.5.
            assert!((p.sv[i] - 1.5 / w).abs() <= 1e-12 * 1.5 / w, "T = {t}");
            assert!((p.sa[i] - 3.0).abs() <= 1e-12 * 3.0, "T = {t}");
        }
        assert_eq!((p.sd[0], p.sv[0], p.sa[0]), (0.0, 0.0, 1.5));
        let e = elastic_exact(&rec, &periods, &[1.0], Some(1)).unwrap_err();
        assert!(e.to_string().contains("damping"), "{e}");
    }
}
