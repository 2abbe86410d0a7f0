//! Orientation-independent spectra (Boore 2010): the oscillator's displacement under two
//! horizontal components, `x1(t)` and `x2(t)`, projected on each direction `theta` of a set
//! as `x1 cos theta + x2 sin theta`; RotDnn is the nn-th percentile over the directions of
//! the peak of that projection (RotD50 the median, RotD100 the largest).

use super::common::{check, map_tasks, Record, Step};
use crate::error::CoreError;

/// Displacement history of one oscillator under `-acc`.
fn displacement(acc: &[f64], s: &Step) -> Vec<f64> {
    let (mut x, mut v) = (0.0, 0.0);
    let mut out = Vec::with_capacity(acc.len());
    out.push(0.0);
    for w in acc.windows(2) {
        (x, v) = s.apply(x, v, -w[0], -w[1]);
        out.push(x);
    }
    out
}

/// Peak displacement along each of `n_angles` directions `theta_j = j pi / n_angles`
/// (`j = 0..n_angles`; directions `theta` and `theta + pi` give the same peak), laid out
/// `[damping][period][angle]`, for the components `first` and `second` (same `dt` and
/// length). A period of 0 gives zeros.
pub fn rotd(
    first: Record,
    second: Record,
    periods: &[f64],
    dampings: &[f64],
    n_angles: usize,
    threads: Option<usize>,
) -> Result<Vec<f64>, CoreError> {
    check(&[first, second], periods, dampings)?;
    if first.acc.len() != second.acc.len() || first.dt != second.dt {
        return Err(CoreError::InvalidInput {
            name: "motion_2",
            problem: format!(
                "must have the first component's sampling: {} samples at dt = {}, got {} at {}",
                first.acc.len(),
                first.dt,
                second.acc.len(),
                second.dt
            ),
        });
    }
    if n_angles == 0 {
        return Err(CoreError::InvalidInput {
            name: "n_angles",
            problem: "must be at least 1".into(),
        });
    }
    let (cos, sin): (Vec<f64>, Vec<f64>) = (0..n_angles)
        .map(|j| (j as f64 * std::f64::consts::PI / n_angles as f64).sin_cos())
        .map(|(s, c)| (c, s))
        .unzip();
    let tasks: Vec<(usize, usize)> = (0..dampings.len())
        .flat_map(|d| (0..periods.len()).map(move |p| (d, p)))
        .collect();
    let task = |&(d, p): &(usize, usize)| -> Result<Vec<f64>, CoreError> {
        let mut peak = vec![0.0f64; n_angles];
        if periods[p] == 0.0 {
            return Ok(peak);
        }
        let omega = 2.0 * std::f64::consts::PI / periods[p];
        let s = Step::new(omega, dampings[d], first.dt)?;
        let (x1, x2) = (displacement(first.acc, &s), displacement(second.acc, &s));
        for (&u, &w) in x1.iter().zip(&x2) {
            for ((m, &c), &sn) in peak.iter_mut().zip(&cos).zip(&sin) {
                *m = m.max((c * u + sn * w).abs());
            }
        }
        let finite = x1.iter().chain(&x2).chain(&peak).all(|y| y.is_finite());
        if !finite {
            return Err(CoreError::InvalidInput {
                name: "motions",
                problem: format!(
                    "the oscillator response overflows at period {} s; check the records' \
                     units and values",
                    periods[p]
                ),
            });
        }
        Ok(peak)
    };
    let out = map_tasks(threads, &tasks, task)?;
    Ok(out.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two identical components: the orbit is the line `x1 = x2`, so the peak along `theta`
    /// is `|cos theta + sin theta| max|x|`; RotD100 at 45 degrees is `sqrt 2` times the
    /// component's peak.
    #[test]
    fn identical_components_give_a_line_orbit() {
        let acc: Vec<f64> = (0..1000).map(|k| (0.05 * k as f64).sin()).collect();
        let r = Record {
            acc: &acc,
            dt: 0.01,
        };
        let peaks = rotd(r, r, &[0.7], &[0.05], 4, Some(1)).unwrap();
        let sd = super::super::elastic(&[r], &[0.7], &[0.05], Some(1))
            .unwrap()
            .sd[0];
        let expect = [1.0, 2f64.sqrt(), 1.0, 0.0];
        for (p, e) in peaks.iter().zip(expect) {
            assert!((p - e * sd).abs() <= 1e-13 * sd, "{p} vs {}", e * sd);
        }
    }
}
