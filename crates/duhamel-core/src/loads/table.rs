//! A tabulated function of time (a record): its value at a time, by a search of the samples
//! or, for the consecutive steps of a block, by a walk from the last sample found.

/// [`table_eval`], the segment found by walking from `*at` (a previous answer, kept):
/// the same segment as the search, `ts[i - 1] <= t < ts[i]`, hence the same value.
#[inline(always)]
pub(super) fn table_at(ts: &[f64], v: &[f64], hold: bool, t: f64, at: &mut usize) -> f64 {
    let last = ts.len() - 1;
    if t.is_nan() {
        return f64::NAN;
    }
    if t < ts[0] {
        return 0.0;
    }
    if t >= ts[last] {
        return if hold { v[last] } else { 0.0 };
    }
    // ts[0] <= t < ts[last]: the walk stops inside 1..=last
    let mut i = (*at).clamp(1, last);
    while ts[i] <= t {
        i += 1;
    }
    while ts[i - 1] > t {
        i -= 1;
    }
    *at = i;
    let (t0, t1) = (ts[i - 1], ts[i]);
    let w = (t - t0) / (t1 - t0);
    v[i - 1] + w * (v[i] - v[i - 1])
}

/// `TimeFunction::eval_before` of a table, by [`table_at`].
#[inline(always)]
pub(super) fn table_before(ts: &[f64], v: &[f64], hold: bool, t: f64, at: &mut usize) -> f64 {
    let last = ts.len() - 1;
    if t.is_nan() {
        f64::NAN
    } else if t <= ts[0] {
        0.0
    } else if t == ts[last] && !hold {
        v[last]
    } else {
        table_at(ts, v, hold, t, at)
    }
}

/// Right-continuous table value: 0 before the first sample, and after the last one unless
/// `hold` (the value at the last sample itself is the value just after it: 0 unless `hold`);
/// NaN at a NaN time. `ts` has at least two samples ([`TimeFunction::validate`]).
pub(super) fn table_eval(ts: &[f64], v: &[f64], hold: bool, t: f64) -> f64 {
    let last = ts.len() - 1;
    // NaN compares false with every sample: it would fall through to index -1 below.
    if t.is_nan() {
        return f64::NAN;
    }
    if t < ts[0] {
        return 0.0;
    }
    if t >= ts[last] {
        return if hold { v[last] } else { 0.0 };
    }
    // first index with ts[i] > t
    let i = ts.partition_point(|&x| x <= t);
    let (t0, t1) = (ts[i - 1], ts[i]);
    let w = (t - t0) / (t1 - t0);
    v[i - 1] + w * (v[i] - v[i - 1])
}

#[cfg(test)]
mod tests {
    use super::super::steps::Steps;
    use super::super::time::TimeFunction;

    /// The bases of consecutive steps (the walk) are those of each step alone (the search),
    /// bit for bit: steps off the sample grid, before, across and after the record's ends.
    #[test]
    fn walked_bases_are_the_searched_ones() {
        let ts: Vec<f64> = (0..40)
            .map(|i| 0.3 + 0.05 * i as f64 + 0.001 * (i % 3) as f64)
            .collect();
        let v: Vec<f64> = ts.iter().map(|t| (7.0 * t).sin()).collect();
        for hold in [false, true] {
            let f = TimeFunction::Table {
                t: ts.clone(),
                v: v.clone(),
                hold,
            };
            for (t0, dt) in [(0.0, 0.013), (0.31, 0.05), (0.25, 0.0071), (1.9, 0.02)] {
                let len = 250;
                let steps = Steps {
                    time: |n: usize| t0 + n as f64 * dt,
                    dt,
                    len,
                };
                let mut out = vec![[0.0; 3]; len];
                f.bases(&steps, &mut out, 0, 1);
                for (n, got) in out.iter().enumerate() {
                    let want = f.basis(t0 + n as f64 * dt, dt);
                    let same = got
                        .iter()
                        .zip(&want)
                        .all(|(a, b)| a.to_bits() == b.to_bits());
                    assert!(same, "hold {hold}, t0 {t0}, step {n}: {got:?} != {want:?}");
                }
            }
        }
    }
}
