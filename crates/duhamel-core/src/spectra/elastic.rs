//! Elastic response spectra: peak relative displacement, relative velocity and absolute
//! acceleration of damped oscillators under piecewise-linear records.

use super::common::{check, map_tasks, Record, Step};
use crate::error::CoreError;

/// Oscillators advanced together in one pass over a record (independent recurrences, so the
/// loop runs at the machine's throughput and vectorises across them).
pub const LANES: usize = 8;

/// Peak responses, each laid out `[record][damping][period]` (row-major).
#[derive(Debug, Clone, PartialEq)]
pub struct Peaks {
    /// Peak relative displacement `max |x|`.
    pub sd: Vec<f64>,
    /// Peak relative velocity `max |x'|`.
    pub sv: Vec<f64>,
    /// Peak absolute acceleration `max |x'' + a_g| = max |2 zeta omega x' + omega^2 x|`.
    pub sa: Vec<f64>,
}

/// Structure of arrays of [`LANES`] oscillators' steps (padding lanes are at rest).
#[derive(Default)]
struct Lanes {
    a: [[[f64; LANES]; 2]; 2],
    b0: [[f64; LANES]; 2],
    b1: [[f64; LANES]; 2],
    /// `omega^2` and `2 zeta omega`, for the absolute acceleration.
    k: [f64; LANES],
    c: [f64; LANES],
}

impl Lanes {
    fn set(&mut self, l: usize, s: &Step, omega: f64, zeta: f64) {
        for r in 0..2 {
            for q in 0..2 {
                self.a[r][q][l] = s.a[r][q];
            }
            self.b0[r][l] = s.b0[r];
            self.b1[r][l] = s.b1[r];
        }
        self.k[l] = omega * omega;
        self.c[l] = 2.0 * zeta * omega;
    }
}

/// `max(m, y)` as one `maxpd` (`f64::max`'s NaN rule costs a compare and blend per lane; a
/// NaN here is caught by the finiteness check of the final state).
#[inline(always)]
fn larger(m: f64, y: f64) -> f64 {
    if y > m {
        y
    } else {
        m
    }
}

/// Peaks `[sd, sv, sa]` of the lanes over the record `acc` (load `-acc`), and whether the
/// final states are finite (an overflow shows there, even where `max` skipped a NaN).
///
/// Every coefficient is copied to a local fixed-size array and every lane loop has a
/// constant trip count, so the compiler keeps the state in vector registers and vectorises
/// across the lanes.
fn run(acc: &[f64], o: &Lanes) -> ([[f64; LANES]; 3], bool) {
    let [[a00, a01], [a10, a11]] = o.a;
    let [b0x, b0v] = o.b0;
    let [b1x, b1v] = o.b1;
    let (k, c) = (o.k, o.c);
    let (mut x, mut v) = ([0.0; LANES], [0.0; LANES]);
    let (mut px, mut pv, mut pa) = ([0.0f64; LANES], [0.0f64; LANES], [0.0f64; LANES]);
    let mut p0 = -acc[0];
    for &next in &acc[1..] {
        let p1 = -next;
        for l in 0..LANES {
            let xn = a00[l].mul_add(x[l], a01[l].mul_add(v[l], b0x[l].mul_add(p0, b1x[l] * p1)));
            let vn = a10[l].mul_add(x[l], a11[l].mul_add(v[l], b0v[l].mul_add(p0, b1v[l] * p1)));
            x[l] = xn;
            v[l] = vn;
            px[l] = larger(px[l], xn.abs());
            pv[l] = larger(pv[l], vn.abs());
            pa[l] = larger(pa[l], k[l].mul_add(xn, c[l] * vn).abs());
        }
        p0 = p1;
    }
    let peak = [px, pv, pa];
    let finite = x
        .iter()
        .chain(&v)
        .chain(peak.iter().flatten())
        .all(|y| y.is_finite());
    (peak, finite)
}

/// Elastic spectra of `records` for every damping ratio in `dampings` and period (s) in
/// `periods`, on `threads` workers (None: rayon's global pool).
///
/// A period of 0 is the rigid oscillator: `sd = sv = 0` and `sa` the peak ground
/// acceleration. Errors: invalid inputs name their parameter; a response that overflows
/// (absurd amplitudes) is reported, never returned as inf.
pub fn elastic(
    records: &[Record],
    periods: &[f64],
    dampings: &[f64],
    threads: Option<usize>,
) -> Result<Peaks, CoreError> {
    check(records, periods, dampings)?;
    let (nr, nd, np) = (records.len(), dampings.len(), periods.len());
    let chunks = np.div_ceil(LANES);
    let tasks: Vec<(usize, usize, usize)> = (0..nr)
        .flat_map(|r| (0..nd).flat_map(move |d| (0..chunks).map(move |c| (r, d, c))))
        .collect();
    let task = |&(r, d, c): &(usize, usize, usize)| -> Result<Vec<[f64; 3]>, CoreError> {
        let rec = records[r];
        let zeta = dampings[d];
        let span = &periods[c * LANES..np.min((c + 1) * LANES)];
        let mut lanes = Lanes::default();
        for (l, &t) in span.iter().enumerate() {
            if t > 0.0 {
                let omega = 2.0 * std::f64::consts::PI / t;
                lanes.set(l, &Step::new(omega, zeta, rec.dt)?, omega, zeta);
            }
        }
        let (peak, finite) = run(rec.acc, &lanes);
        if !finite {
            return Err(CoreError::InvalidInput {
                name: "motions",
                problem: format!(
                    "record {r}: the oscillator response overflows (damping {zeta}, periods \
                     {span:?}); check the record's units and values"
                ),
            });
        }
        let pga = if span.contains(&0.0) {
            rec.acc.iter().fold(0.0f64, |m, a| m.max(a.abs()))
        } else {
            0.0 // unused
        };
        Ok(span
            .iter()
            .enumerate()
            .map(|(l, &t)| {
                if t > 0.0 {
                    [peak[0][l], peak[1][l], peak[2][l]]
                } else {
                    [0.0, 0.0, pga]
                }
            })
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

    /// Closed form: undamped oscillator under a constant acceleration `-g0` from rest,
    /// `x = -(g0 / omega^2)(1 - cos omega t)`; peak `2 g0 / omega^2` once `t >= pi / omega`.
    #[test]
    fn constant_record_against_closed_form() {
        let acc = vec![1.5; 2001];
        let rec = [Record {
            acc: &acc,
            dt: 0.01,
        }];
        let periods = [0.0, 0.05, 0.5, 1.0, 2.0, 4.0, 7.0, 9.0, 11.0];
        let p = elastic(&rec, &periods, &[0.0], Some(1)).unwrap();
        for (i, &t) in periods.iter().enumerate().skip(1) {
            let w = 2.0 * std::f64::consts::PI / t;
            // sample nearest the first peak at t = pi / omega (record is 20 s long)
            let n = (0..2001).map(|k| k as f64 * 0.01);
            let peak = n
                .map(|s| 1.5 / (w * w) * (1.0 - (w * s).cos()))
                .fold(0.0, f64::max);
            assert!(
                (p.sd[i] - peak).abs() <= 1e-12 * peak,
                "T = {t}: {} vs {peak}",
                p.sd[i]
            );
        }
        assert_eq!((p.sd[0], p.sv[0], p.sa[0]), (0.0, 0.0, 1.5));
    }

    #[test]
    fn errors_name_their_parameter() {
        let acc = [0.0, 1.0, f64::NAN];
        let e = elastic(
            &[Record {
                acc: &acc,
                dt: 0.01,
            }],
            &[1.0],
            &[0.05],
            None,
        );
        assert!(e.unwrap_err().to_string().contains("`motions`"));
        let acc = [0.0, 1.0];
        let r = [Record {
            acc: &acc,
            dt: 0.01,
        }];
        let e = elastic(&r, &[-1.0], &[0.05], None).unwrap_err();
        assert!(e.to_string().contains("`periods`"));
        let e = elastic(&r, &[1.0], &[-0.05], None).unwrap_err();
        assert!(e.to_string().contains("`damping`"));
        let e = elastic(&[Record { acc: &acc, dt: 0.0 }], &[1.0], &[0.0], None).unwrap_err();
        assert!(e.to_string().contains("`dt`"));
    }

    #[test]
    fn overflow_is_an_error() {
        let acc = [0.0, 1e308, -1e308, 1e308];
        let e = elastic(&[Record { acc: &acc, dt: 1e3 }], &[1e4], &[0.0], None).unwrap_err();
        assert!(e.to_string().contains("overflows"), "{e}");
    }
}
