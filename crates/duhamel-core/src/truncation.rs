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
    if len < 2 {
        return y;
    }
    // LANES rows stepped side by side: each row's step depends on its last one, the rows
    // are independent (the processor overlaps them); a last group's spare lanes repeat its
    // last row and are not written
    for start in (0..rows).step_by(LANES) {
        let width = LANES.min(rows - start);
        let row = |l: usize| start + l.min(width - 1);
        let s: [&[f64]; LANES] =
            std::array::from_fn(|l| &steps[STEP_VALUES * row(l)..STEP_VALUES * (row(l) + 1)]);
        let input: [&[f64]; LANES] = std::array::from_fn(|l| &g[row(l) * len..(row(l) + 1) * len]);
        let (mut x0, mut x1) = ([0.0_f64; LANES], [0.0_f64; LANES]);
        for k in 1..len {
            for l in 0..LANES {
                let (s, g0, g1) = (s[l], input[l][k - 1], input[l][k]);
                let next0 = s[0] * x0[l] + s[1] * x1[l] + s[4] * g0 + s[6] * g1;
                x1[l] = s[2] * x0[l] + s[3] * x1[l] + s[5] * g0 + s[7] * g1;
                x0[l] = next0;
            }
            for l in 0..width {
                y[(start + l) * len + k] = s[l][8] * x0[l];
            }
        }
    }
    y
}

/// Rows of [`hold_response`] stepped together.
const LANES: usize = 4;

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
        // six rows (a group of four and a partial one): the two above, then repeated
        let rows = 6;
        let steps: Vec<f64> = (0..rows)
            .flat_map(|m| steps[9 * (m % 2)..9 * (m % 2) + 9].to_vec())
            .collect();
        let g: Vec<f64> = (0..rows * len)
            .map(|i| g[i % (2 * len)] * (1.0 + (i / len) as f64))
            .collect();
        let y = hold_response(&steps, &g, len);
        for m in 0..rows {
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
