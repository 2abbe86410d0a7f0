//! Bouc-Wen with a large exponent (`n > 16`): RK4 substeps that follow the local stiffness
//! of `g`, so that the work per increment does not grow with `n` (see
//! [`Flow::advance_adaptive`]).

use super::substeps::{TooManySubsteps, MAX_ADAPTIVE};
use super::{Flow, H0};

impl Flow {
    /// A bound of the `k`-th roots of the derivatives of `g` at `|w| <= a` for large `n`:
    /// `|g^(k)| ~ c n^k |w|^(n - k)`, whose `k`-th root is at most `max(c, 1) n
    /// |w|^(n / 4 - 1)` for `k <= 4` and `|w| <= 1` (and grows with `|w|` beyond).
    fn local_rate(&self, a: f64) -> f64 {
        let c = (self.gamma - self.beta)
            .abs()
            .max(self.beta + self.gamma)
            .max(1.0);
        (c * self.n * a.abs().powf(0.25 * self.n - 1.0)).max(1.0)
    }

    /// `n > 16` from an admissible state (`g(w0) > 0`): RK4 with substeps `H0 / rate(w)`
    /// following the local stiffness of `g` (tiny while `|w|^n` is, `~ n` near `z_max`),
    /// the crossing of `w = 0` located as in [`Self::advance_rk4`], and the integration
    /// stopped once `g` is zero to the rounding of `|w|^n` (`w` at `z_max`) or a substep
    /// no longer moves `w` (its increment `h g(w)` below half an ulp: the substeps that
    /// would follow change nothing, where they ran to the bound before). The work per
    /// increment is then bounded whatever `n` (about `(len + 80) / H0` substeps), where the
    /// uniform substeps cost `100 n` per unit of `xi` (n = 1e6 took 30 s for 100 steps).
    pub(super) fn advance_adaptive(&self, w0: f64, xi: f64) -> Result<f64, TooManySubsteps> {
        let (mut w, mut rest) = (w0, xi);
        let settled = 64.0 * self.n * f64::EPSILON;
        // the substep keeps `h rate <= 2 H0` over its whole span (the rate grows with |w|)
        let step = |w: f64, positive: bool| -> f64 {
            let (mut h, speed) = (H0 / self.local_rate(w), self.g(w, positive).abs());
            for _ in 0..64 {
                if h * self.local_rate(w.abs() + h * speed) <= 2.0 * H0 {
                    break;
                }
                h *= 0.5;
            }
            h
        };
        let mut count = 0usize;
        if w < 0.0 {
            while rest > 0.0 && count < MAX_ADAPTIVE {
                let h = step(w, false).min(rest);
                let next = self.rk4_step(w, h, false);
                count += 1;
                if next == w {
                    return Ok(w); // the increment h g(w) rounds away: w moves no more
                }
                if next >= 0.0 {
                    let d =
                        -w / 6.0 * (1.0 / self.g(w, false) + 4.0 / self.g(0.5 * w, false) + 1.0);
                    rest -= d.clamp(0.0, h);
                    w = 0.0;
                    break;
                }
                w = next;
                rest -= h;
            }
            if w < 0.0 {
                return self.settled_within(rest, count, w);
            }
        }
        while rest > 0.0 && count < MAX_ADAPTIVE {
            if self.g(w, true).abs() <= settled {
                return Ok(w); // at z_max to round-off: the state no longer moves
            }
            let h = step(w, true).min(rest);
            let next = self.rk4_step(w, h, true);
            if next == w {
                return Ok(w); // at z_max to the rounding of w + h g(w): no more motion
            }
            w = next;
            rest -= h;
            count += 1;
        }
        self.settled_within(rest, count, w)
    }

    /// `w` when the increment was integrated whole (`rest <= 0`) within the bound; else
    /// the refusal (the bound reached with `rest` of the increment left).
    fn settled_within(&self, rest: f64, count: usize, w: f64) -> Result<f64, TooManySubsteps> {
        if rest > 0.0 && count >= MAX_ADAPTIVE {
            Err(TooManySubsteps {
                needed: MAX_ADAPTIVE as f64,
            })
        } else {
            Ok(w)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::grounded;

    /// The adaptive substeps (n > 16) agree with the uniform ones (the reference, 1e-11)
    /// over loading, unloading through zero and saturation, and their work does not grow
    /// with `n`.
    #[test]
    fn adaptive_substeps_match_uniform_ones() {
        for n in [17.0, 20.0, 33.5, 64.0, 200.0] {
            for (beta, gamma) in [(0.5, 0.5), (0.25, 0.75), (0.8, 0.2)] {
                let e = grounded([2.0, 1.0, 0.1, n, beta, gamma]).unwrap();
                let zm = e.z_max();
                for w0 in [-0.99 * zm, -0.5, 0.0, 0.3, 0.9 * zm, 0.999 * zm] {
                    for xi in [1e-3, 0.05, 0.4, 1.0, 2.5, 40.0] {
                        let (a, b) = (
                            e.flow.advance_adaptive(w0, xi).unwrap(),
                            e.flow.advance_rk4(w0, xi).unwrap(),
                        );
                        assert!((a - b).abs() <= 1e-9, "n {n} w0 {w0} xi {xi}: {a} vs {b}");
                    }
                }
            }
        }
        for n in [1e3, 1e6, 1e12] {
            let e = grounded([2.0, 1.0, 0.1, n, 0.5, 0.5]).unwrap();
            // z reaches 1 (z_max) after xi ~ 1 and stays; by 0.5 it is 0.5 exactly enough
            let z = e.flow.advance_adaptive(0.0, 0.5).unwrap();
            assert!((z - 0.5).abs() < 1e-9, "n {n}: {z}");
            let z = e.flow.advance_adaptive(-0.5, 1e9).unwrap();
            assert!((z - 1.0).abs() < 1e-9, "n {n}: {z}");
        }
    }
}
