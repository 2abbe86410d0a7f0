//! Tests of the triple friction pendulum's series model.

use super::*;

const MU: [f64; 3] = [0.02, 0.06, 0.10];
const L: [f64; 3] = [0.3, 2.0, 2.5];
const D: [f64; 3] = [0.05, 0.3, 0.35];

fn bearing(uy: f64) -> TripleFrictionPendulum {
    TripleFrictionPendulum::new(0, 1, MU, L, D, 1.0, uy).unwrap()
}

/// The force and trial state at `x` from the committed `c`, with the tangent.
fn at(e: &TripleFrictionPendulum, c: &[f64; 12], x: &[f64]) -> (Vec<f64>, Vec<f64>, [f64; 12]) {
    let n = x.len();
    let (mut r, mut kx, mut cv) = (vec![0.0; n], vec![0.0; n * n], vec![0.0; n * n]);
    let mut trial = [0.0; 12];
    let h = PathState {
        committed: c,
        trial: &mut trial,
    };
    let tg = Tangent {
        kx: &mut kx,
        cv: &mut cv,
    };
    e.eval_path(x, &vec![0.0; n], 0.0, h, &mut r, Some(tg))
        .unwrap();
    (r, kx, trial)
}

/// Loads the bearing along `path` (committing each point), returning the forces.
fn follow(e: &TripleFrictionPendulum, path: &[[f64; 2]]) -> (Vec<[f64; 2]>, [f64; 12]) {
    let mut c = [0.0; 12];
    let mut out = Vec::new();
    for u in path {
        let (r, _, trial) = at(e, &c, u);
        c = trial;
        out.push([r[0], r[1]]);
    }
    (out, c)
}

#[test]
fn tangent_is_the_derivative_of_the_force() {
    let e = bearing(5e-4);
    // committed states: virgin, and after a curved excursion into regimes II-IV
    let mut path = Vec::new();
    for k in 0..=400 {
        let a = k as f64 / 400.0 * 3.0;
        path.push([0.5 * a.sin(), 0.3 * (1.0 - a.cos())]);
    }
    let (_, c1) = follow(&e, &path);
    for c in [[0.0; 12], c1] {
        for x in [[0.001, -0.0004], [0.2, 0.1], [-0.1, 0.45], [0.6, -0.05]] {
            let (_, kx, _) = at(&e, &c, &x);
            for j in 0..2 {
                let h = 1e-7;
                let (mut xp, mut xm) = (x, x);
                xp[j] += h;
                xm[j] -= h;
                let (rp, rm) = (at(&e, &c, &xp).0, at(&e, &c, &xm).0);
                for i in 0..2 {
                    let fd = (rp[i] - rm[i]) / (2.0 * h);
                    let k = kx[2 * i + j];
                    assert!(
                        (k - fd).abs() < 1e-5 * (1.0 + k.abs()),
                        "{x:?} {kx:?} {i}{j} {fd}"
                    );
                }
            }
        }
    }
}

/// The force of the series model under monotonic loading along `x` from the virgin state,
/// in closed form: a piecewise-linear curve whose breaks are the elements' yield and gap
/// closures, `(u, f)` at the breaks.
fn closed_form(e: &TripleFrictionPendulum) -> Vec<(f64, f64)> {
    let [s0, s1, s2] = e.series.segments;
    let ee = s0.e;
    let ep = |s: Segment| s.e * s.h / (s.e + s.h);
    let close = |s: Segment| ep(s) * s.gap + s.fy * (1.0 - ep(s) / ee);
    let (c0, c1, c2) = (1.0 / ep(s0), 1.0 / ep(s1), 1.0 / ep(s2));
    let (g1, g2) = (1.0 / (ep(s1) + ee), 1.0 / (ep(s2) + ee));
    let g0 = 1.0 / (ep(s0) + ee);
    // (force at the end of the stage, compliance during it)
    let stages = [
        (s0.fy, 3.0 / ee),
        (s1.fy, c0 + 2.0 / ee),
        (s2.fy, c0 + c1 + 1.0 / ee),
        (close(s1), c0 + c1 + c2),
        (close(s2), c0 + g1 + c2),
        (close(s0), c0 + g1 + g2),
        (1e3, g0 + g1 + g2),
    ];
    let mut points = vec![(0.0, 0.0)];
    for (f, c) in stages {
        let (u0, f0) = *points.last().unwrap();
        points.push((u0 + c * (f - f0), f));
    }
    points
}

#[test]
fn monotonic_loading_passes_the_five_regimes() {
    let e = bearing(1e-4);
    let curve = closed_form(&e);
    let exact = |u: f64| {
        let k = curve.iter().position(|p| p.0 >= u).unwrap().max(1);
        let ((u0, f0), (u1, f1)) = (curve[k - 1], curve[k]);
        f0 + (f1 - f0) * (u - u0) / (u1 - u0)
    };
    let n = 3000;
    let path: Vec<[f64; 2]> = (0..=n).map(|k| [0.9 * k as f64 / n as f64, 0.0]).collect();
    let (f, _) = follow(&e, &path);
    for (u, f) in path.iter().zip(&f) {
        assert!(
            (f[0] - exact(u[0])).abs() < 1e-10,
            "{u:?} {f:?} {}",
            exact(u[0])
        );
        assert_eq!(f[1], 0.0);
    }
    // Fenz & Constantinou's rigid-plastic forces and stiffnesses, to O(uy / (mu1 L))
    let curve = closed_form(&bearing(1e-6));
    let [l1, l2, l3] = L;
    let [mu1, mu2, mu3] = MU;
    let [_, d2, d3] = D;
    let fc = [mu1, mu2, mu3, mu2 + d2 / l2, mu3 + d3 / l3];
    let stiffness = [
        1.0 / (2.0 * l1),
        1.0 / (l1 + l2),
        1.0 / (l2 + l3),
        1.0 / (l1 + l3),
        0.5 / l1,
    ];
    for k in 0..5 {
        let (u0, f0) = curve[k + 1];
        let (u1, f1) = curve[k + 2];
        assert!((f0 - fc[k]).abs() < 1e-3 * fc[k], "{k} {f0} {}", fc[k]);
        let slope = (f1 - f0) / (u1 - u0);
        assert!(
            (slope - stiffness[k]).abs() < 1e-3 * stiffness[k],
            "{k} {slope}"
        );
    }
}

#[test]
fn uniaxial_is_the_bidirectional_bearing_on_a_line() {
    let one = TripleFrictionPendulum::uniaxial(2, MU, L, D, 3.0, 5e-4).unwrap();
    let two = TripleFrictionPendulum::new(2, 3, MU, L, D, 3.0, 5e-4).unwrap();
    assert_eq!(one.dofs(), &[2]);
    let (mut c1, mut c2) = ([0.0; 12], [0.0; 12]);
    for k in 0..200 {
        let x = 0.5 * (k as f64 * 0.05).sin();
        let (r1, k1, t1) = at(&one, &c1, &[x]);
        let (r2, k2, t2) = at(&two, &c2, &[x, 0.0]);
        assert_eq!(r1[0], r2[0]);
        assert_eq!(k1[0], k2[0]);
        assert_eq!(t1, t2);
        (c1, c2) = (t1, t2);
    }
}

#[test]
fn checks_name_the_parameter() {
    let err = |r: Result<TripleFrictionPendulum, CoreError>| match r {
        Err(CoreError::InvalidInput { name, .. }) => name,
        _ => panic!("accepted"),
    };
    let make = |mu, l, d, uy| TripleFrictionPendulum::new(0, 1, mu, l, d, 1.0, uy);
    assert_eq!(err(make([0.05, 0.04, 0.1], L, D, 5e-4)), "mu");
    assert_eq!(err(make([0.0, 0.04, 0.1], L, D, 5e-4)), "mu");
    assert_eq!(err(make(MU, [2.0, 1.0, 3.0], D, 5e-4)), "radius");
    assert_eq!(
        err(make(MU, L, [0.1, -0.2, 0.3], 5e-4)),
        "displacement_capacity"
    );
    assert_eq!(err(make(MU, L, D, 0.1)), "yield_displacement");
    assert_eq!(
        err(TripleFrictionPendulum::new(1, 1, MU, L, D, 1.0, 5e-4)),
        "dof_y"
    );
}

/// The bearing with its vertical dof 2 (axial stiffness `kv`, `MinFv` 50, `P0` optional).
fn spatial(kv: f64, p0: Option<f64>) -> TripleFrictionPendulum {
    let e = TripleFrictionPendulum::new(0, 1, MU, L, D, 1e3, 5e-4).unwrap();
    e.with_vertical(2, kv, 50.0, p0).unwrap()
}

#[test]
fn with_a_constant_vertical_displacement_it_is_the_bearing_under_that_weight() {
    let kv = 1e6;
    for p0 in [None, Some(800.0)] {
        let e = spatial(kv, p0);
        // N = 1234.5 from the vertical dof
        let w = -(1234.5 - p0.unwrap_or(0.0)) / kv;
        let flat = TripleFrictionPendulum::new(0, 1, MU, L, D, 1234.5, 5e-4).unwrap();
        let (mut c1, mut c2) = ([0.0; 12], [0.0; 12]);
        for k in 0..400 {
            let a = k as f64 * 0.04;
            let u = [0.5 * a.sin() * (0.3 * a).cos(), 0.3 * (0.7 * a).sin()];
            let (r1, k1, t1) = at(&e, &c1, &[u[0], u[1], w]);
            let (r2, k2, t2) = at(&flat, &c2, &u);
            for i in 0..2 {
                assert!((r1[i] - r2[i]).abs() <= 1e-12 * r2[i].abs().max(1.0));
                for j in 0..2 {
                    let (a, b) = (k1[3 * i + j], k2[2 * i + j]);
                    assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{a} {b}");
                }
            }
            // the vertical force on the dof: the change of the axial force from P0
            let expect = p0.unwrap_or(0.0) - 1234.5;
            assert!(
                (r1[2] - expect).abs() <= 1e-9 * 1234.5,
                "{} {expect}",
                r1[2]
            );
            assert_eq!(t1, t2);
            (c1, c2) = (t1, t2);
        }
    }
}

#[test]
fn vertical_tangent_is_the_derivative_of_the_force() {
    let kv = 1e6;
    for p0 in [None, Some(800.0)] {
        let e = spatial(kv, p0);
        let mut path = Vec::new();
        for k in 0..=300 {
            let a = k as f64 / 300.0 * 3.0;
            path.push([0.4 * a.sin(), 0.2 * (1.0 - a.cos()), -1e-3]);
        }
        let mut c = [0.0; 12];
        for x in &path {
            c = at(&e, &c, x).2;
        }
        // where the spring is unloaded
        let base = p0.unwrap_or(0.0) / kv;
        for x in [
            [0.001, -0.0004, base - 1e-3],
            [0.2, 0.1, base - 2e-4],
            [-0.1, 0.4, base - 3e-3],
            [0.3, 0.1, base + 1e-3], // uplift: N = MinFv
        ] {
            let (r, kx, _) = at(&e, &c, &x);
            if x[2] > base {
                assert_eq!(r[2], p0.unwrap_or(0.0) - 50.0);
            }
            for j in 0..3 {
                let h = [1e-7, 1e-7, 1e-9][j];
                let (mut xp, mut xm) = (x, x);
                xp[j] += h;
                xm[j] -= h;
                let (rp, rm) = (at(&e, &c, &xp).0, at(&e, &c, &xm).0);
                for i in 0..3 {
                    let fd = (rp[i] - rm[i]) / (2.0 * h);
                    let k = kx[3 * i + j];
                    assert!(
                        (k - fd).abs() < 1e-5 * (1.0 + k.abs()),
                        "{x:?} {i}{j} {k} {fd}"
                    );
                }
            }
        }
    }
}

#[test]
fn uniaxial_with_its_vertical_dof() {
    let one = TripleFrictionPendulum::uniaxial(0, MU, L, D, 1e3, 5e-4).unwrap();
    let one = one.with_vertical(4, 1e6, 0.0, None).unwrap();
    assert_eq!(one.dofs(), &[0, 4]);
    let two = spatial(1e6, None);
    let (r1, k1, _) = at(&one, &[0.0; 12], &[0.1, -2e-3]);
    let (r2, k2, _) = at(&two, &[0.0; 12], &[0.1, 0.0, -2e-3]);
    assert_eq!([r1[0], r1[1]], [r2[0], r2[2]]);
    assert_eq!([k1[0], k1[1], k1[2], k1[3]], [k2[0], k2[2], k2[6], k2[8]]);
    let bad = TripleFrictionPendulum::new(0, 1, MU, L, D, 1.0, 5e-4).unwrap();
    let name = |r: Result<TripleFrictionPendulum, CoreError>| match r {
        Err(CoreError::InvalidInput { name, .. }) => name,
        _ => panic!("accepted"),
    };
    assert_eq!(
        name(bad.clone().with_vertical(2, 0.0, 0.0, None)),
        "vertical_stiffness"
    );
    assert_eq!(
        name(bad.clone().with_vertical(2, 1.0, -1.0, None)),
        "min_axial_force"
    );
    assert_eq!(
        name(bad.clone().with_vertical(2, 1.0, 0.0, Some(-1.0))),
        "initial_axial_force"
    );
}

#[test]
fn pdelta_moments_on_the_rotations_and_their_tangent() {
    let kv = 1e6;
    let e = spatial(kv, None)
        .with_rotations([Some(3), Some(4), Some(5)])
        .unwrap();
    assert_eq!(e.dofs(), &[0, 1, 2, 3, 4, 5]);
    let mut c = [0.0; 12];
    for k in 0..=200 {
        let a = k as f64 / 200.0 * 3.0;
        c = at(
            &e,
            &c,
            &[0.4 * a.sin(), 0.2 * (1.0 - a.cos()), -1e-3, 0.0, 0.0, 0.0],
        )
        .2;
    }
    for x in [
        [0.2, 0.1, -2e-3, 0.01, -0.02, 0.003],
        [-0.1, 0.4, -3e-3, 0.0, 0.0, 0.0],
        [0.3, 0.1, 1e-3, 0.0, 0.0, 0.0], // uplift: N = MinFv
    ] {
        let (r, kx, _) = at(&e, &c, &x);
        let n_axial = if x[2] < 0.0 { -kv * x[2] } else { 50.0 };
        assert!((r[3] - n_axial * x[1] / 2.0).abs() <= 1e-12 * n_axial);
        assert!((r[4] + n_axial * x[0] / 2.0).abs() <= 1e-12 * n_axial);
        let torsion = (r[0] * x[1] - r[1] * x[0]) / 2.0;
        assert!((r[5] - torsion).abs() <= 1e-12 * n_axial);
        for j in 0..6 {
            let h = [1e-7, 1e-7, 1e-9, 1e-7, 1e-7, 1e-7][j];
            let (mut xp, mut xm) = (x, x);
            xp[j] += h;
            xm[j] -= h;
            let (rp, rm) = (at(&e, &c, &xp).0, at(&e, &c, &xm).0);
            for i in 0..6 {
                let fd = (rp[i] - rm[i]) / (2.0 * h);
                let k = kx[6 * i + j];
                assert!(
                    (k - fd).abs() < 1e-5 * (1.0 + k.abs()),
                    "{x:?} {i}{j} {k} {fd}"
                );
            }
        }
    }
    let name = match spatial(kv, None).with_rotations([Some(1), None, None]) {
        Err(CoreError::InvalidInput { name, .. }) => name,
        _ => panic!("accepted"),
    };
    assert_eq!(name, "dofs");
}
