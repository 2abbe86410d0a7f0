//! Real roots of a cubic `c0 + c1 x + c2 x^2 + c3 x^3`, for the closed-form solution of the
//! single-degree-of-freedom step equation (the paper's cubic).

/// The real root of `c0 + c1 x + c2 x^2 + c3 x^3` nearest to `guess`, or `None` when there is
/// none (a constant non-zero polynomial). Degenerate leading coefficients fall back to the
/// quadratic and linear formulas; each root is polished by Newton steps on the polynomial.
#[inline]
pub fn nearest_root(c: [f64; 4], guess: f64) -> Option<f64> {
    if let Some(root) = monotone_root(c, guess) {
        return Some(root);
    }
    let scale = c.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return None;
    }
    let inv = 1.0 / scale;
    let [c0, c1, c2, c3] = c.map(|v| v * inv);
    let mut roots = [0.0; 3];
    let n = if c3.abs() > 1e-14 * (c2.abs() + c1.abs() + c0.abs()) {
        let i3 = 1.0 / c3;
        cubic_roots(c2 * i3, c1 * i3, c0 * i3, &mut roots)
    } else if c2.abs() > 1e-14 * (c1.abs() + c0.abs()) {
        quadratic_roots(c2, c1, c0, &mut roots)
    } else if c1 != 0.0 {
        roots[0] = -c0 / c1;
        1
    } else {
        0
    };
    // The nearest root, then polished (polishing cannot move it past another root).
    let mut best: Option<f64> = None;
    for &r in &roots[..n] {
        if best.is_none_or(|b| (r - guess).abs() < (b - guess).abs()) {
            best = Some(r);
        }
    }
    best.map(|r| polish([c0, c1, c2, c3], r))
}

/// The one real root of a cubic without a real critical point (`c2^2 < 3 c1 c3`: strictly
/// monotone, so it is the root nearest any guess), by Halley's iteration from `guess`
/// (cubic convergence: from a guess within 1e-2 of the root, two steps reach it) and a
/// Newton step on the polynomial (as the closed forms are polished). `None` (the closed
/// forms decide) when the cubic is not of that kind or eight steps do not settle.
///
/// The step equation of a hardening element is such a cubic about its predictor: this
/// is several times cheaper than Cardano's formula, whose cube root, square root and
/// scalings took a third of the closed-form Duffing step (perf).
#[inline]
fn monotone_root(c: [f64; 4], guess: f64) -> Option<f64> {
    let [c0, c1, c2, c3] = c;
    // false for a NaN coefficient as well
    let monotone = c2 * c2 < 3.0 * c1 * c3;
    if !monotone {
        return None;
    }
    let mut x = guess;
    for _ in 0..8 {
        let p = ((c3 * x + c2) * x + c1) * x + c0;
        let d1 = (3.0 * c3 * x + 2.0 * c2) * x + c1;
        let d2 = 6.0 * c3 * x + 2.0 * c2;
        let step = 2.0 * p * d1 / (2.0 * d1 * d1 - p * d2);
        if !step.is_finite() {
            return None;
        }
        x -= step;
        if step.abs() <= 1e-4 * x.abs() || step == 0.0 {
            return Some(polish(c, x));
        }
    }
    None
}

/// Real roots of `x^3 + a x^2 + b x + c` (trigonometric form for three real roots, Cardano
/// otherwise).
fn cubic_roots(a: f64, b: f64, c: f64, out: &mut [f64; 3]) -> usize {
    let a3 = a * (1.0 / 3.0);
    let q = (a * a - 3.0 * b) * (1.0 / 9.0);
    let r = (2.0 * a * a * a - 9.0 * a * b + 27.0 * c) * (1.0 / 54.0);
    let q3 = q * q * q;
    if r * r < q3 {
        let theta = (r / q3.sqrt()).clamp(-1.0, 1.0).acos();
        let m = -2.0 * q.sqrt();
        let tau = std::f64::consts::TAU;
        out[0] = m * (theta / 3.0).cos() - a3;
        out[1] = m * ((theta + tau) / 3.0).cos() - a3;
        out[2] = m * ((theta - tau) / 3.0).cos() - a3;
        3
    } else {
        let big_a = -r.signum() * cbrt(r.abs() + (r * r - q3).sqrt());
        let big_b = if big_a == 0.0 { 0.0 } else { q / big_a };
        out[0] = big_a + big_b - a3;
        1
    }
}

/// Cube root of `x >= 0` to about 1e-15: a bit-level first guess (within a few percent)
/// and two Halley steps (cubic convergence). The roots are polished on the polynomial
/// afterwards, so this need not be correctly rounded; it is several times faster than the
/// portable software `cbrt`.
fn cbrt(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let mut y = f64::from_bits(x.to_bits() / 3 + 0x2A9F_7893_782D_A1CE);
    for _ in 0..2 {
        let y3 = y * y * y;
        y *= (y3 + 2.0 * x) / (2.0 * y3 + x);
    }
    y
}

/// Real roots of `a x^2 + b x + c` without cancellation.
fn quadratic_roots(a: f64, b: f64, c: f64, out: &mut [f64; 3]) -> usize {
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        // A near-double root lost to rounding: keep the vertex.
        out[0] = -b / (2.0 * a);
        return 1;
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    out[0] = q / a;
    if q != 0.0 {
        out[1] = c / q;
        2
    } else {
        1
    }
}

/// One Newton step on the polynomial (the closed forms lose a few digits to cancellation
/// and near multiple roots; one step squares that relative error).
fn polish(c: [f64; 4], x: f64) -> f64 {
    let p = ((c[3] * x + c[2]) * x + c[1]) * x + c[0];
    let dp = (3.0 * c[3] * x + 2.0 * c[2]) * x + c[1];
    let step = p / dp;
    if step.is_finite() {
        x - step
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly_from_roots(r: [f64; 3], lead: f64) -> [f64; 4] {
        let [a, b, c] = r;
        [
            -lead * a * b * c,
            lead * (a * b + b * c + a * c),
            -lead * (a + b + c),
            lead,
        ]
    }

    #[test]
    fn three_real_roots_pick_the_nearest() {
        let c = poly_from_roots([-2.0, 0.5, 3.0], 1.7);
        assert!((nearest_root(c, 0.4).unwrap() - 0.5).abs() < 1e-14);
        assert!((nearest_root(c, 2.0).unwrap() - 3.0).abs() < 1e-14);
        assert!((nearest_root(c, -9.0).unwrap() + 2.0).abs() < 1e-14);
    }

    #[test]
    fn one_real_root_and_scaling() {
        // x^3 + x - 10 = 0 has the single real root 2
        for s in [1e-12, 1.0, 1e12] {
            let c = [-10.0 * s, s, 0.0, s];
            assert!((nearest_root(c, 0.0).unwrap() - 2.0).abs() < 1e-14);
        }
    }

    #[test]
    fn degenerate_leading_terms() {
        assert!((nearest_root([-6.0, 3.0, 0.0, 0.0], 0.0).unwrap() - 2.0).abs() < 1e-15);
        let q = nearest_root([2.0, -3.0, 1.0, 0.0], 1.9).unwrap(); // roots 1, 2
        assert!((q - 2.0).abs() < 1e-14);
        assert!(nearest_root([1.0, 0.0, 0.0, 0.0], 0.0).is_none());
        // a tiny cubic term on a well-posed linear equation
        let r = nearest_root([-1.0, 1.0, 0.0, 1e-20], 0.0).unwrap();
        assert!((r - 1.0).abs() < 1e-14);
    }

    #[test]
    fn fast_cube_root() {
        for x in [1e-300, 1e-20, 0.3, 1.0, 27.0, 8e15, 1e300] {
            let y = cbrt(x);
            assert!((y * y * y - x).abs() <= 1e-14 * x, "{x}: {y}");
        }
        assert_eq!(cbrt(0.0), 0.0);
    }

    #[test]
    fn monotone_cubics_by_halley_agree_with_cardano() {
        // x^3 + a x^2 + b x + c with b > a^2 / 3 (no critical point), a root at r: the
        // iteration from guesses near and far lands on the root Cardano's formula gives
        let mut seed = 12345_u64;
        let mut uniform = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut iterated = 0;
        for _ in 0..2000 {
            let (r, a) = (3.0 * uniform(), 2.0 * uniform());
            let b = a * a / 3.0 + 0.01 + uniform().abs();
            let lead = 10f64.powf(6.0 * uniform());
            // (x - r)(x^2 + (a + r) x + e) with e chosen so the x term is b
            let e = b + r * (a + r);
            let c = [-r * e * lead, b * lead, a * lead, lead];
            for guess in [r + 1e-3 * uniform(), r + 0.5 * uniform(), 0.0] {
                let Some(x) = monotone_root(c, guess) else {
                    continue;
                };
                iterated += 1;
                let mut roots = [0.0; 3];
                let n = cubic_roots(a, b, -r * e, &mut roots);
                assert_eq!(n, 1);
                let cardano = polish([-r * e, b, a, 1.0], roots[0]);
                // both within what the rounding of the coefficients moves the root: a few
                // eps of sum |c_i r^i| over |p'(r)|
                let size = (r * e).abs() + (b * r).abs() + (a * r * r).abs() + (r * r * r).abs();
                let slope = (3.0 * r + 2.0 * a) * r + b;
                let bound = 8.0 * f64::EPSILON * size / slope.abs();
                assert!((x - r).abs() <= bound, "halley {x} root {r} bound {bound}");
                assert!((cardano - r).abs() <= bound, "cardano {cardano} root {r}");
            }
        }
        // near guesses always settle; far ones nearly always
        assert!(iterated > 5000, "{iterated}");
        // a cubic with critical points is left to the closed forms
        assert!(monotone_root([0.0, -1.0, 0.0, 1.0], 0.3).is_none());
    }

    #[test]
    fn duffing_like_residual() {
        // u + w u^3 = L: monotone, one root
        let (w, l) = (0.01, 2.5);
        let u = nearest_root([-l, 1.0, 0.0, w], l).unwrap();
        assert!((u + w * u * u * u - l).abs() < 1e-14);
    }
}
