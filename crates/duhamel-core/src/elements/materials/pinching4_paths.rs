//! The unload-reload paths of [`Pinching4`](super::pinching4::Pinching4): four points from
//! the last reversal to the target on the other side (trilinear with pinching when the path
//! crosses zero deformation, linear otherwise), with OpenSees' corrections when the points
//! come out of order — `getState3` (towards negative) and `getState4` (towards positive),
//! line for line (they are not mirror images of each other, so both are kept), and
//! `Envlp3Stress`/`Envlp3Tangent` ([`piecewise`]).

use super::pinching4_def::Work;

type Path = ([f64; 4], [f64; 4]);

/// Points 2 and 3 at 0.33 and 0.67 of the straight line from point 1 to point 4.
fn linear(s: &mut [f64; 4], f: &mut [f64; 4]) {
    let du = s[3] - s[0];
    let df = f[3] - f[0];
    s[1] = s[0] + 0.33 * du;
    s[2] = s[0] + 0.67 * du;
    f[1] = f[0] + 0.33 * df;
    f[2] = f[0] + 0.67 * df;
}

/// Both points moved so that their average force is kept, 1 % apart.
fn average(s: &mut [f64; 4], f: &mut [f64; 4]) {
    let avg = 0.5 * (f[2] + f[1]);
    let dfr = if avg < 0.0 { -avg / 100.0 } else { avg / 100.0 };
    let slope12 = (f[1] - f[0]) / (s[1] - s[0]);
    let slope34 = (f[3] - f[2]) / (s[3] - s[2]);
    f[1] = avg - dfr;
    f[2] = avg + dfr;
    s[1] = s[0] + (f[1] - f[0]) / slope12;
    s[2] = s[3] - (f[3] - f[2]) / slope34;
}

/// OpenSees' final check: a decreasing segment makes the path linear, and a linear path
/// flatter than the secant to point 1 goes through the origin.
fn final_check(s: &mut [f64; 4], f: &mut [f64; 4]) {
    let check_slope = f[0] / s[0];
    let mut slope = 0.0;
    let mut i = 0;
    while i < 3 {
        let du = s[i + 1] - s[i];
        let df = f[i + 1] - f[i];
        if du < 0.0 || df < 0.0 {
            let du = s[3] - s[0];
            let df = f[3] - f[0];
            linear(s, f);
            slope = df / du;
            i = 3;
        }
        if slope > 1e-8 && slope < check_slope {
            s[1] = 0.0;
            f[1] = 0.0;
            s[2] = s[3] / 2.0;
            f[2] = f[3] / 2.0;
        }
        i += 1;
    }
}

/// OpenSees' `getState3`: the path from the reversal (point 4, `hgh`) towards the
/// negative target (point 1, `low`), unloading stiffness `kunload`.
pub(crate) fn path3(w: &Work<'_>, kunload: f64) -> Path {
    let (t, m) = (&w.t, w.m);
    let mut s = [t.low_strain, 0.0, 0.0, t.hgh_strain];
    let mut f = [t.low_stress, 0.0, 0.0, t.hgh_stress];
    let kneg = w.k_neg_d;
    let kmax = if kunload > kneg { kunload } else { kneg };
    let [r_disp, r_force, u_force] = m.p.pinch_neg;
    let nd = &w.neg_d;
    if s[0] * s[3] < 0.0 {
        s[1] = t.low_strain * r_disp;
        if r_force - u_force > 1e-8 {
            f[1] = t.low_stress * r_force;
        } else {
            let st1 = if t.min_dmnd < m.neg_strain[3] {
                t.low_stress * u_force * (1.0 + 1e-6)
            } else {
                nd[3] * u_force * (1.0 + 1e-6)
            };
            let st2 = nd[4] * (1.0 + 1e-6);
            f[1] = if st1 < st2 { st1 } else { st2 };
        }
        if (f[1] - f[0]) / (s[1] - s[0]) > kneg {
            s[1] = t.low_strain + (f[1] - f[0]) / kneg;
        }
        if s[1] > s[3] {
            linear(&mut s, &mut f);
        } else {
            f[2] = if t.min_dmnd < m.neg_strain[3] {
                u_force * nd[4]
            } else {
                u_force * nd[3]
            };
            s[2] = t.hgh_strain - (t.hgh_stress - f[2]) / kunload;
            if s[2] > s[3] {
                let du = s[3] - s[1];
                let df = f[3] - f[1];
                s[2] = s[1] + 0.5 * du;
                f[2] = f[1] + 0.5 * df;
            } else if (f[2] - f[1]) / (s[2] - s[1]) > kmax {
                linear(&mut s, &mut f);
            } else if s[2] < s[1] || (f[2] - f[1]) / (s[2] - s[1]) < 0.0 {
                if s[2] < 0.0 {
                    let du = s[3] - s[1];
                    let df = f[3] - f[1];
                    s[2] = s[1] + 0.5 * du;
                    f[2] = f[1] + 0.5 * df;
                } else if s[1] > 0.0 {
                    let du = s[2] - s[0];
                    let df = f[2] - f[0];
                    s[1] = s[0] + 0.5 * du;
                    f[1] = f[0] + 0.5 * df;
                } else {
                    average(&mut s, &mut f);
                }
            }
        }
    } else {
        linear(&mut s, &mut f);
    }
    final_check(&mut s, &mut f);
    (s, f)
}

/// OpenSees' `getState4`: the path from the reversal (point 1, `low`) towards the positive
/// target (point 4, `hgh`), unloading stiffness `kunload`.
pub(crate) fn path4(w: &Work<'_>, kunload: f64) -> Path {
    let (t, m) = (&w.t, w.m);
    let mut s = [t.low_strain, 0.0, 0.0, t.hgh_strain];
    let mut f = [t.low_stress, 0.0, 0.0, t.hgh_stress];
    let kpos = w.k_pos_d;
    let kmax = if kunload > kpos { kunload } else { kpos };
    let [r_disp, r_force, u_force] = m.p.pinch_pos;
    let pd = &w.pos_d;
    if s[0] * s[3] < 0.0 {
        s[2] = t.hgh_strain * r_disp;
        if u_force == 0.0 || r_force - u_force > 1e-8 {
            f[2] = t.hgh_stress * r_force;
        } else {
            let st1 = if t.max_dmnd > m.pos_strain[3] {
                t.hgh_stress * u_force * (1.0 + 1e-6)
            } else {
                pd[3] * u_force * (1.0 + 1e-6)
            };
            let st2 = pd[4] * (1.0 + 1e-6);
            f[2] = if st1 > st2 { st1 } else { st2 };
        }
        if (f[3] - f[2]) / (s[3] - s[2]) > kpos {
            s[2] = t.hgh_strain - (f[3] - f[2]) / kpos;
        }
        if s[2] < s[0] {
            linear(&mut s, &mut f);
        } else {
            f[1] = if t.max_dmnd > m.pos_strain[3] {
                u_force * pd[4]
            } else {
                u_force * pd[3]
            };
            s[1] = t.low_strain + (-t.low_stress + f[1]) / kunload;
            if s[1] < s[0] {
                let du = s[2] - s[0];
                let df = f[2] - f[0];
                s[1] = s[0] + 0.5 * du;
                f[1] = f[0] + 0.5 * df;
            } else if (f[2] - f[1]) / (s[2] - s[1]) > kmax {
                linear(&mut s, &mut f);
            } else if s[2] < s[1] || (f[2] - f[1]) / (s[2] - s[1]) < 0.0 {
                if s[1] > 0.0 {
                    let du = s[2] - s[0];
                    let df = f[2] - f[0];
                    s[1] = s[0] + 0.5 * du;
                    f[1] = f[0] + 0.5 * df;
                } else if s[2] < 0.0 {
                    let du = s[3] - s[1];
                    let df = f[3] - f[1];
                    s[2] = s[1] + 0.5 * du;
                    f[2] = f[1] + 0.5 * df;
                } else {
                    average(&mut s, &mut f);
                }
            }
        }
    } else {
        linear(&mut s, &mut f);
    }
    final_check(&mut s, &mut f);
    (s, f)
}

/// OpenSees' `Envlp3Stress`/`Envlp3Tangent` (and the identical `Envlp4*`): the last segment
/// whose start is at or before `u`, the first segment before the path, and a flat segment
/// replaced by the first or last one (as OpenSees does): `(f, k)`.
pub(crate) fn piecewise(s: &[f64; 4], f: &[f64; 4], u: f64) -> (f64, f64) {
    let (mut k, mut out) = (0.0, 0.0);
    for i in 0..3 {
        if u >= s[i] {
            k = (f[i + 1] - f[i]) / (s[i + 1] - s[i]);
            out = f[i] + (u - s[i]) * k;
        }
    }
    if k == 0.0 {
        let i = if u < s[0] { 0 } else { 2 };
        k = (f[i + 1] - f[i]) / (s[i + 1] - s[i]);
        out = f[i] + (u - s[i]) * k;
    }
    (out, k)
}
