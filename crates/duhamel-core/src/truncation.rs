//! The basis-truncation estimate's oscillators (`duhamel._engine.truncation`): the exact
//! step of uncoupled two-state oscillators under inputs linear between samples, all modes
//! in one call (the Python side makes each mode's step, from the matrix exponential, once).

/// Values per row of [`hold_response`]'s `steps`: the step matrix `A` (row-major), the
/// transfers `p` of the sample at the step's start and `r` of the one at its end, and the
/// scale of the output (the first state times it).
pub const STEP_VALUES: usize = 9;

/// Per row `m` of `g` (`steps.len() / STEP_VALUES` rows of `len` values, row-major), the
/// output `scale x_k[0]` of `x_{k+1} = A x_k + p g_k + r g_{k+1}` from `x_0 = 0`, with
/// `steps[9m..9m+9] = (A00, A01, A10, A11, p0, p1, r0, r1, scale)`: the oscillator from rest
/// at the first sample, its input linear between samples. A NaN input gives NaN outputs
/// from its step on.
pub fn hold_response(steps: &[f64], g: &[f64], len: usize) -> Vec<f64> {
    let rows = steps.len() / STEP_VALUES;
    let mut y = vec![0.0; rows * len];
    for m in 0..rows {
        let s = &steps[STEP_VALUES * m..STEP_VALUES * (m + 1)];
        let input = &g[m * len..(m + 1) * len];
        let output = &mut y[m * len..(m + 1) * len];
        let (mut x0, mut x1) = (0.0_f64, 0.0_f64);
        for (out, pair) in output[1..].iter_mut().zip(input.windows(2)) {
            let (g0, g1) = (pair[0], pair[1]);
            let next0 = s[0] * x0 + s[1] * x1 + s[4] * g0 + s[6] * g1;
            x1 = s[2] * x0 + s[3] * x1 + s[5] * g0 + s[7] * g1;
            x0 = next0;
            *out = s[8] * x0;
        }
    }
    y
}

#[cfg(test)]
mod tests {
    use super::hold_response;

    /// `x_k = sum_j A^(k-1-j) (p g_j + r g_{j+1})`: the same response as a convolution
    /// with the powers of `A`.
    fn convolution(s: &[f64], g: &[f64]) -> Vec<f64> {
        let mut powers = vec![[1.0, 0.0, 0.0, 1.0]];
        for _ in 1..g.len() {
            let p = powers[powers.len() - 1];
            powers.push([
                s[0] * p[0] + s[1] * p[2],
                s[0] * p[1] + s[1] * p[3],
                s[2] * p[0] + s[3] * p[2],
                s[2] * p[1] + s[3] * p[3],
            ]);
        }
        let mut y = vec![0.0; g.len()];
        for k in 1..g.len() {
            let mut x0 = 0.0;
            for j in 0..k {
                let (u0, u1) = (s[4] * g[j] + s[6] * g[j + 1], s[5] * g[j] + s[7] * g[j + 1]);
                let a = powers[k - 1 - j];
                x0 += a[0] * u0 + a[1] * u1;
            }
            y[k] = s[8] * x0;
        }
        y
    }

    #[test]
    fn rows_equal_the_convolution_with_the_steps_powers() {
        let len = 300;
        let g: Vec<f64> = (0..2 * len)
            .map(|i| ((i as f64) * 0.37).cos() + 0.1 * (i % 7) as f64)
            .collect();
        // a rotation slowly decaying and a strongly damped step, each with its transfers
        let (r, t) = (0.999_f64, 0.3_f64);
        let steps = [
            r * t.cos(),
            r * t.sin(),
            -r * t.sin(),
            r * t.cos(),
            0.2,
            0.1,
            0.3,
            -0.05,
            2.0,
            0.5,
            0.1,
            -0.2,
            0.3,
            1.0,
            0.0,
            0.4,
            0.7,
            0.5,
        ];
        let y = hold_response(&steps, &g, len);
        for m in 0..2 {
            let want = convolution(&steps[9 * m..9 * m + 9], &g[m * len..(m + 1) * len]);
            let scale = want.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            assert_eq!(y[m * len], 0.0, "from rest");
            for (got, want) in y[m * len..(m + 1) * len].iter().zip(&want) {
                assert!((got - want).abs() <= 1e-12 * scale, "{got} against {want}");
            }
        }
    }

    #[test]
    fn a_nan_input_gives_nan_outputs_from_its_step() {
        let steps = [0.5, 0.1, -0.1, 0.5, 1.0, 0.0, 1.0, 0.0, 1.0];
        let y = hold_response(&steps, &[1.0, 2.0, f64::NAN, 1.0], 4);
        assert_eq!(y[0], 0.0);
        assert_eq!(y[1], 3.0);
        assert!(y[2].is_nan() && y[3].is_nan());
    }
}
