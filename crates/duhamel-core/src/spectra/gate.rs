//! The bounds that decide which steps of an exact-peak spectrum ([`super::exact`]) are
//! searched between the samples: one pass over the record with the sampled recurrence, its
//! peaks and a cheap gate per block of steps ([`first_pass`]), then, for the blocks that
//! pass, the gate and the score of each step ([`Lanes::gate`], [`Lanes::score`]).

use super::elastic::LANES;

/// `max(m, y)` without `f64::max`'s NaN rule (a NaN is caught by the final check).
#[inline(always)]
pub(super) fn larger(m: f64, y: f64) -> f64 {
    if y > m {
        y
    } else {
        m
    }
}

/// `min(m, y)` as a select (see [`larger`]).
#[inline(always)]
pub(super) fn smaller(m: f64, y: f64) -> f64 {
    if y < m {
        y
    } else {
        m
    }
}

/// The lanes' constants: the step (structure of arrays) and the bounds'.
pub(super) struct Lanes {
    pub(super) a: [[[f64; LANES]; 2]; 2],
    /// `(b0 x, b0 v, b1 x, b1 v)`.
    pub(super) b: [[f64; LANES]; 4],
    pub(super) k: [f64; LANES],
    pub(super) c: [f64; LANES],
    pub(super) sigma: [f64; LANES],
    pub(super) iw: [f64; LANES],
    pub(super) ik: [f64; LANES],
    pub(super) f1: [f64; LANES],
    pub(super) f2: [f64; LANES],
    /// `1 / f1`, `1 / f2` (a padding lane's: infinite).
    pub(super) i1: [f64; LANES],
    pub(super) i2: [f64; LANES],
    /// `(h^2 / 8)^2`, with a margin.
    pub(super) h2: f64,
}

impl Lanes {
    /// The lanes' state after the step from `(x, v)` under `p0 -> p1`: the sampled spectra's
    /// expression, so both passes over a step (and the sampled spectra) agree to the bit.
    #[inline(always)]
    pub(super) fn advance(
        &self,
        x: &[f64; LANES],
        v: &[f64; LANES],
        p0: f64,
        p1: f64,
    ) -> [[f64; LANES]; 2] {
        let [[a00, a01], [a10, a11]] = &self.a;
        let [b0x, b0v, b1x, b1v] = &self.b;
        let (mut xn, mut vn) = ([0.0; LANES], [0.0; LANES]);
        for l in 0..LANES {
            let (x0, v0) = (x[l], v[l]);
            xn[l] = a00[l].mul_add(x0, a01[l].mul_add(v0, b0x[l].mul_add(p0, b1x[l] * p1)));
            vn[l] = a10[l].mul_add(x0, a11[l].mul_add(v0, b0v[l].mul_add(p0, b1v[l] * p1)));
        }
        [xn, vn]
    }

    /// For lane `l`, a number `>= 0` where a quantity may exceed its peak in the step from
    /// `(x0, v0)` to `(xn, vn)` under `p0 + r s`: the smaller excess of its two bounds
    /// (`exact::Bound::flags`), the largest over the quantities. Selects and arithmetic only.
    #[inline(always)]
    pub(super) fn score(
        &self,
        l: usize,
        h: f64,
        ((x0, v0), (xn, vn)): ((f64, f64), (f64, f64)),
        (p0, r): (f64, f64),
        [px, pv, pa]: [f64; 3],
    ) -> f64 {
        let (kl, cl, sl, iwl, ikl) = (self.k[l], self.c[l], self.sigma[l], self.iw[l], self.ik[l]);
        let s0 = kl.mul_add(x0, cl * v0);
        let s1 = kl.mul_add(xn, cl * vn);
        let a0 = p0 - cl * v0 - kl * x0;
        let q = (r - cl * a0 - kl * v0 + sl * a0) * iwl;
        let amp2 = a0.mul_add(a0, q * q) * self.h2;
        let vp = r * ikl;
        let xp0 = (p0 - cl * vp) * ikl;
        let xp1 = xp0 + vp * h;
        let cx = x0 - xp0;
        let dx = (v0 - vp + sl * cx) * iwl;
        let pvl = v0 - vp;
        let qv = (a0 + sl * pvl) * iwl;
        let (ps, qs) = (kl.mul_add(cx, cl * pvl), kl.mul_add(dx, cl * qv));
        let sp = cl * vp;
        let excess = |gap: f64, r2: f64| r2 - gap * gap.abs();
        let big = |a: f64, b: f64| larger(a.abs(), b.abs());
        let ex = smaller(
            excess(px - big(x0, xn), amp2),
            excess(px * (1.0 - 1e-9) - big(xp0, xp1), cx.mul_add(cx, dx * dx)),
        );
        let ev = smaller(
            excess(pv - big(v0, vn), amp2 * self.f1[l] * self.f1[l]),
            excess(pv * (1.0 - 1e-9) - vp.abs(), pvl.mul_add(pvl, qv * qv)),
        );
        let es = smaller(
            excess(pa - big(s0, s1), amp2 * self.f2[l] * self.f2[l]),
            excess(
                pa * (1.0 - 1e-9) - big(kl * xp0 + sp, kl * xp1 + sp),
                ps.mul_add(ps, qs * qs),
            ),
        );
        larger(ex, larger(ev, es))
    }

    /// The gate of lane `l` in the step from `(x0, v0)` to `(xn, vn)` under `p0 + r s`
    /// against the peaks `pk` (`s0`, `s1`: `k x + c x'` at the ends): whether a quantity's
    /// ends plus `h^2/8` times the bound of its second derivative reach its peak, the first of
    /// the two bounds of [`Lanes::score`] in the same arithmetic, so a step whose score is
    /// `>= 0` passes. Monotone in the peaks: a step that fails against some fails against
    /// larger ones.
    #[inline(always)]
    fn gate(
        &self,
        l: usize,
        [(x0, v0, s0), (xn, vn, s1)]: [(f64, f64, f64); 2],
        (p0, r): (f64, f64),
        [px, pv, pa]: [f64; 3],
    ) -> bool {
        let (kl, cl, sl, iwl) = (self.k[l], self.c[l], self.sigma[l], self.iw[l]);
        let a0 = p0 - cl * v0 - kl * x0;
        let q = (r - cl * a0 - kl * v0 + sl * a0) * iwl;
        let amp2 = a0.mul_add(a0, q * q) * self.h2;
        let excess = |gap: f64, r2: f64| r2 - gap * gap.abs();
        let big = |a: f64, b: f64| larger(a.abs(), b.abs());
        let g = larger(
            excess(px - big(x0, xn), amp2),
            larger(
                excess(pv - big(v0, vn), amp2 * self.f1[l] * self.f1[l]),
                excess(pa - big(s0, s1), amp2 * self.f2[l] * self.f2[l]),
            ),
        );
        g >= 0.0
    }

    /// The steps of a kept block (from the states `x`, `v` at its start; `acc` its samples)
    /// that pass [`Lanes::gate`] against the peaks `pk`: per lane a bit per step. Fills the
    /// states at the block's points (`xs[i]`, `vs[i]`, `i <= BLOCK`). The recurrence first,
    /// then the gates, step by step independent (no branch: a loop at the machine's
    /// throughput).
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    pub(super) fn block_steps(
        &self,
        (x, v): (&[f64; LANES], &[f64; LANES]),
        (acc, h): (&[f64], f64),
        pk: &[[f64; LANES]; 3],
        (xs, vs): (
            &mut [[f64; LANES]; BLOCK + 1],
            &mut [[f64; LANES]; BLOCK + 1],
        ),
    ) -> [u64; LANES] {
        let steps = acc.len() - 1;
        let (mut x, mut v) = (*x, *v);
        (xs[0], vs[0]) = (x, v);
        for i in 0..steps {
            [x, v] = self.advance(&x, &v, -acc[i], -acc[i + 1]);
            (xs[i + 1], vs[i + 1]) = (x, v);
        }
        let (k, c) = (&self.k, &self.c);
        let mut bits = [0u64; LANES];
        for i in 0..steps {
            let (p0, p1) = (-acc[i], -acc[i + 1]);
            let r = (p1 - p0) / h;
            let (x0s, v0s, xns, vns) = (&xs[i], &vs[i], &xs[i + 1], &vs[i + 1]);
            for l in 0..LANES {
                let (x0, v0, xn, vn) = (x0s[l], v0s[l], xns[l], vns[l]);
                let s0 = k[l].mul_add(x0, c[l] * v0);
                let s1 = k[l].mul_add(xn, c[l] * vn);
                let p = [pk[0][l], pk[1][l], pk[2][l]];
                let hit = self.gate(l, [(x0, v0, s0), (xn, vn, s1)], (p0, r), p);
                bits[l] |= if hit { 1u64 << i } else { 0 };
            }
        }
        bits
    }
}

/// A block of steps that passed the first pass's gate: its first step and the lanes' states
/// at its start (the states after are recomputed with [`Lanes::advance`], to the bit).
pub(super) struct Candidate {
    pub(super) n: usize,
    pub(super) x: [f64; LANES],
    pub(super) v: [f64; LANES],
}

/// Steps per block of the first pass's gate (at most 64: a lane's steps of a block are the
/// bits of a `u64` in [`Lanes::block_steps`]). Longer blocks cost the pass less per step,
/// and the second pass less than before for their steps (white noise, core alone: 32 steps
/// 3.29 ms, 64 steps 3.17).
pub(super) const BLOCK: usize = 64;

/// One block's record from the pass: the lanes' states at its start, the largest `|x|`,
/// `|x'|`, and the largest and smallest `k x + c x'` (its ends included).
#[derive(Clone, Copy)]
struct Block {
    x: [f64; LANES],
    v: [f64; LANES],
    m: [[f64; LANES]; 4],
}

/// Per block of [`BLOCK`] steps of `acc`, the largest `|r|` (times `h`) of its steps and
/// the largest and smallest load `p = -acc` at its points: the record's alone, so computed
/// once for all its periods.
pub(super) fn block_jumps(acc: &[f64]) -> Vec<[f64; 3]> {
    let steps = acc.len().saturating_sub(1);
    (0..steps)
        .step_by(BLOCK)
        .map(|start| {
            let block = &acc[start..acc.len().min(start + BLOCK + 1)];
            let jump = block
                .windows(2)
                .fold(0.0, |m, w| larger(m, (w[0] - w[1]).abs()));
            let top = block.iter().fold(f64::NEG_INFINITY, |m, &a| larger(m, -a));
            let bottom = block.iter().fold(f64::INFINITY, |m, &a| smaller(m, -a));
            [jump, top, bottom]
        })
        .collect()
}

thread_local! {
    /// The blocks of the pass, kept from one call to the next on a thread (no fresh pages).
    static BLOCKS: std::cell::RefCell<Vec<Block>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The one pass over the record: the sampled spectra's recurrence and peaks `pk` (raised in
/// place), and the blocks of [`BLOCK`] steps that pass a cheap gate against the record's
/// sampled peaks; returns those (their first step and the states there) and the final states.
///
/// The gate is [`Lanes::gate`] over a block: the largest ends of the block's steps and a
/// bound of their amplitudes of `x''` (from bounds of its terms: with `s = k x + c x'`,
/// `|x''| = |p - s|` at a step's start is at most the larger of `max p - min s` and
/// `max s - min p` over the block, to the bit as rounding is monotone), the quantities' gaps
/// to their peaks over the bounds' factors, with a margin for the rearrangement's rounding,
/// so it lets go only blocks none of whose steps [`Lanes::gate`] would keep. The pass itself
/// keeps per block only the states at its start and the maxima (a few maxima per step beside
/// the recurrence, whose chain of fused multiply-adds sets the pace; every coefficient is a
/// local array and each loop over the lanes has a constant trip count, so the state stays in
/// registers); the gate runs over the blocks after it, against the final peaks (the
/// tightest: the second pass gates its steps against those, raised by its searches).
#[allow(clippy::type_complexity)]
pub(super) fn first_pass(
    (acc, jumps): (&[f64], &[[f64; 3]]),
    h: f64,
    o: &Lanes,
    pk: &mut [[f64; LANES]; 3],
) -> (Vec<Candidate>, [f64; LANES], [f64; LANES]) {
    BLOCKS.with(|b| {
        let mut blocks = b.borrow_mut();
        let (x, v) = record_blocks(acc, o, &mut blocks);
        (gate_blocks(&blocks, jumps, h, o, pk), x, v)
    })
}

/// The pass over the record (see [`first_pass`]): the blocks' records, and the final states.
fn record_blocks(acc: &[f64], o: &Lanes, blocks: &mut Vec<Block>) -> ([f64; LANES], [f64; LANES]) {
    let [[a00, a01], [a10, a11]] = o.a;
    let [b0x, b0v, b1x, b1v] = o.b;
    let (k, c) = (o.k, o.c);
    let steps = acc.len() - 1;
    let empty = Block {
        x: [0.0; LANES],
        v: [0.0; LANES],
        m: [[0.0; LANES]; 4],
    };
    // Every block is written below: no need to clear the buffer.
    blocks.resize(steps.div_ceil(BLOCK), empty);
    // The lanes' x, x', k x + c x'.
    let mut st = [[0.0f64; LANES]; 3];
    // One step of every lane: the recurrence, then the block's largest |x|, |x'| and the
    // largest and smallest k x + c x' (whose largest magnitude is the sampled peak), in `m`.
    // |x''| at the steps' starts is bounded from those and the block's loads (`block_jumps`);
    // the other term of the squared amplitude of x'', |x''' + sigma x''| / wd = |r - sigma
    // x'' - k x'| / wd, from the largest |r| (the same for every lane), |x''| and |x'|: no
    // arithmetic per lane and step beyond the sampled loop's (which takes |k x + c x'|).
    let step = |p0: f64, p1: f64, [x, v, s]: &mut [[f64; LANES]; 3], m: &mut [[f64; LANES]; 4]| {
        for l in 0..LANES {
            let (x0, v0) = (x[l], v[l]);
            let xn = a00[l].mul_add(x0, a01[l].mul_add(v0, b0x[l].mul_add(p0, b1x[l] * p1)));
            let vn = a10[l].mul_add(x0, a11[l].mul_add(v0, b0v[l].mul_add(p0, b1v[l] * p1)));
            let sn = k[l].mul_add(xn, c[l] * vn);
            m[0][l] = larger(m[0][l], xn.abs());
            m[1][l] = larger(m[1][l], vn.abs());
            m[2][l] = larger(m[2][l], sn);
            m[3][l] = smaller(m[3][l], sn);
            (x[l], v[l], s[l]) = (xn, vn, sn);
        }
    };
    for (start, rec) in (0..steps).step_by(BLOCK).zip(blocks.iter_mut()) {
        let [xs, vs, ss] = st;
        let mut m = [[0.0; LANES]; 4];
        for l in 0..LANES {
            (m[0][l], m[1][l], m[2][l], m[3][l]) = (xs[l].abs(), vs[l].abs(), ss[l], ss[l]);
        }
        if start + BLOCK <= steps {
            // A whole block: a constant trip count, so the compiler unrolls it.
            let block = &acc[start..start + BLOCK + 1];
            for i in 0..BLOCK {
                step(-block[i], -block[i + 1], &mut st, &mut m);
            }
        } else {
            for pair in acc[start..].windows(2) {
                step(-pair[0], -pair[1], &mut st, &mut m);
            }
        }
        *rec = Block { x: xs, v: vs, m };
    }
    (st[0], st[1])
}

/// The sampled peaks `pk` raised by the blocks' maxima, and the blocks that pass the gate
/// against them (see [`first_pass`]).
fn gate_blocks(
    blocks: &[Block],
    jumps: &[[f64; 3]],
    h: f64,
    o: &Lanes,
    [px, pv, pa]: &mut [[f64; LANES]; 3],
) -> Vec<Candidate> {
    for b in blocks {
        for l in 0..LANES {
            px[l] = larger(px[l], b.m[0][l]);
            pv[l] = larger(pv[l], b.m[1][l]);
            pa[l] = larger(pa[l], larger(b.m[2][l], -b.m[3][l]));
        }
    }
    let (k, sigma, iw, i1, i2) = (o.k, o.sigma, o.iw, o.i1, o.i2);
    let wide = o.h2 * (1.0 + 1e-6);
    let inv_h = 1.0 / h;
    let mut cands = Vec::new();
    for (j, (b, &[jump, top, bottom])) in blocks.iter().zip(jumps).enumerate() {
        let [mx, mv, smax, smin] = b.m;
        let (mut ms, mut ma) = ([0.0; LANES], [0.0; LANES]);
        for l in 0..LANES {
            ms[l] = larger(smax[l], -smin[l]);
            ma[l] = larger(top - smin[l], smax[l] - bottom);
        }
        let mr = jump * inv_h;
        let mut hit = false;
        for l in 0..LANES {
            let gx = px[l] - mx[l];
            let gv = (pv[l] - mv[l]) * i1[l];
            let ga = (pa[l] - ms[l]) * i2[l];
            let g = smaller(gx, smaller(gv, ga));
            let q = sigma[l].mul_add(ma[l], k[l].mul_add(mv[l], mr)) * iw[l];
            hit |= g * g.abs() <= ma[l].mul_add(ma[l], q * q) * wide;
        }
        if hit {
            cands.push(Candidate {
                n: j * BLOCK,
                x: b.x,
                v: b.v,
            });
        }
    }
    cands
}
