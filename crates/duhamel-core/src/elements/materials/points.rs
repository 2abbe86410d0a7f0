//! What the multilinear materials share: the checks of their `(strain, stress)` point
//! lists, and the backbone through points on one side of the origin.

use crate::error::CoreError;

/// Checks that `strain` and `stress` (named by `names`) have the same length, at least
/// `min` entries, finite values, strictly increasing strains — positive ones when
/// `positive` (a backbone from the origin) — and, when `positive`, positive stresses.
pub(crate) fn check_points(
    names: (&'static str, &'static str),
    strain: &[f64],
    stress: &[f64],
    min: usize,
    positive: bool,
) -> Result<(), CoreError> {
    let (ns, nf) = names;
    let bad = |name: &'static str, problem: String| Err(CoreError::InvalidInput { name, problem });
    if strain.len() != stress.len() {
        return Err(CoreError::LengthMismatch {
            name: nf,
            got: stress.len(),
            expected: strain.len(),
        });
    }
    if strain.len() < min {
        return bad(
            ns,
            format!("needs at least {min} points, got {}", strain.len()),
        );
    }
    for (name, values) in [(ns, strain), (nf, stress)] {
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            return bad(name, format!("must be finite, got {v}"));
        }
    }
    if let Some(k) = (1..strain.len()).find(|&k| strain[k] <= strain[k - 1]) {
        return bad(
            ns,
            format!(
                "must be strictly increasing, got {} after {}",
                strain[k],
                strain[k - 1]
            ),
        );
    }
    if positive && strain[0] <= 0.0 {
        return bad(ns, format!("must be > 0, got {}", strain[0]));
    }
    if positive && stress.iter().any(|&s| s <= 0.0) {
        return bad(nf, "must be > 0 (a backbone from the origin)".to_string());
    }
    Ok(())
}

/// A backbone on one side of the origin: `F(x)` for `x >= 0` through `(0, 0)` and the
/// points `(x_k, f_k)`, extended beyond the last point with the last slope.
#[derive(Debug, Clone)]
pub(crate) struct Backbone {
    x: Vec<f64>,
    f: Vec<f64>,
    slope: Vec<f64>,
}

impl Backbone {
    /// The backbone through checked points (`check_points(.., positive = true)`).
    pub(crate) fn new(x: &[f64], f: &[f64]) -> Self {
        let mut slope = Vec::with_capacity(x.len());
        let (mut x0, mut f0) = (0.0, 0.0);
        for (&xk, &fk) in x.iter().zip(f) {
            slope.push((fk - f0) / (xk - x0));
            (x0, f0) = (xk, fk);
        }
        Self {
            x: x.to_vec(),
            f: f.to_vec(),
            slope,
        }
    }

    /// The first point (the yield point): `(x_1, f_1)`.
    pub(crate) fn first(&self) -> (f64, f64) {
        (self.x[0], self.f[0])
    }

    /// The initial slope `f_1 / x_1`.
    pub(crate) fn k0(&self) -> f64 {
        self.slope[0]
    }

    /// The slopes of the segments (the last one extended).
    pub(crate) fn slopes(&self) -> &[f64] {
        &self.slope
    }

    /// The segment holding `x >= 0`: the first whose end is beyond `x` (the last one past
    /// the last point).
    fn segment(&self, x: f64) -> usize {
        self.x
            .iter()
            .position(|&xk| x < xk)
            .unwrap_or(self.x.len() - 1)
    }

    /// The start of segment `j`: `(x, F)`.
    fn start(&self, j: usize) -> (f64, f64) {
        if j == 0 {
            (0.0, 0.0)
        } else {
            (self.x[j - 1], self.f[j - 1])
        }
    }

    /// `(F(x), F'(x))` for `x >= 0`.
    pub(crate) fn eval(&self, x: f64) -> (f64, f64) {
        let j = self.segment(x);
        let (xs, fs) = self.start(j);
        (fs + self.slope[j] * (x - xs), self.slope[j])
    }

    /// The first `x >= from` where the line `k (x - x0)` (below the backbone at `from`)
    /// meets the backbone; infinity when it never does.
    pub(crate) fn meet(&self, k: f64, x0: f64, from: f64) -> f64 {
        for j in self.segment(from)..self.x.len() {
            let m = self.slope[j];
            if k <= m {
                continue; // the line does not gain on this segment
            }
            let (xs, fs) = self.start(j);
            let x = (fs - m * xs + k * x0) / (k - m);
            let end = if j + 1 == self.x.len() {
                f64::INFINITY
            } else {
                self.x[j]
            };
            if x <= end {
                return x.max(from);
            }
        }
        f64::INFINITY
    }
}
