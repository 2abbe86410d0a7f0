use super::*;

/// Force, tangents `(kx, cv)` and trial state at `(x, v)` from the committed `c`.
fn eval(e: &AxialFrictionPendulum, x: &[f64], v: &[f64], c: &[f64]) -> [Vec<f64>; 4] {
    let n = x.len();
    let (mut r, mut kx, mut cv) = (vec![0.0; n], vec![0.0; n * n], vec![0.0; n * n]);
    let mut trial = vec![0.0; c.len()];
    let history = PathState {
        committed: c,
        trial: &mut trial,
    };
    let tangent = Tangent {
        kx: &mut kx,
        cv: &mut cv,
    };
    e.eval_path(x, v, 0.0, history, &mut r, Some(tangent))
        .unwrap();
    [r, kx, cv, trial]
}

/// The analytic tangents against central differences of the force.
fn check_tangents(e: &AxialFrictionPendulum, x: &[f64], v: &[f64], c: &[f64]) {
    let n = x.len();
    let [_, kx, cv, _] = eval(e, x, v, c);
    for j in 0..n {
        for (which, an) in [(0, &kx), (1, &cv)] {
            let h = 1e-8;
            let (mut xp, mut xm, mut vp, mut vm) = (x.to_vec(), x.to_vec(), v.to_vec(), v.to_vec());
            if which == 0 {
                xp[j] += h;
                xm[j] -= h;
            } else {
                vp[j] += h;
                vm[j] -= h;
            }
            let rp = &eval(e, &xp, &vp, c)[0];
            let rm = &eval(e, &xm, &vm, c)[0];
            for i in 0..n {
                let fd = (rp[i] - rm[i]) / (2.0 * h);
                let a = an[i * n + j];
                assert!(
                    (a - fd).abs() <= 1e-5 * (1.0 + a.abs().max(fd.abs())),
                    "{which} {i}{j}: {a} {fd} at {x:?} {v:?} {c:?}"
                );
            }
        }
    }
}

#[test]
fn normal_force_balances_and_tangent_is_consistent() {
    let e = AxialFrictionPendulum::new((0, 1), 2.0, 0.05, (1e3, 1e-3), 1e5).unwrap();
    for (x, up) in [
        ([0.3, -0.01], 0.0),
        ([0.3, -0.01], 0.2995),
        ([-0.2, -0.012], 0.1),
    ] {
        let [r, _, _, trial] = eval(&e, &x, &[0.0; 2], &[up]);
        let p = -1e5 * x[1];
        assert!((r[1] + p).abs() < 1e-9);
        // N = P + V u / R and, sliding, |V - N u / R| = mu N
        let n = p + r[0] * x[0] / 2.0;
        let f = r[0] - n * x[0] / 2.0;
        assert!(f.abs() <= 0.05 * n * (1.0 + 1e-12));
        if trial[0] != up {
            assert!((f.abs() - 0.05 * n).abs() < 1e-9 * n);
        }
        check_tangents(&e, &x, &[0.0; 2], &[up]);
    }
    // uplift: nothing carried, the slider follows
    let [r, k, _, trial] = eval(&e, &[0.1, 0.001], &[0.0; 2], &[0.0]);
    assert_eq!((r, k, trial), (vec![0.0; 2], vec![0.0; 4], vec![0.1]));
}

fn bearings() -> Vec<AxialFrictionPendulum> {
    let two = AxialFrictionPendulum::bidirectional((0, 1, 2), 2.0, 0.08, (1e3, 1e-3), 1e5);
    let two = two.unwrap();
    let fast = two.clone().with_velocity(0.03, 15.0).unwrap();
    let pressed = fast.clone().with_pressure(0.5, 0.04, 0.01).unwrap();
    let only_pressure = two.clone().with_pressure(0.5, 0.04, 0.01).unwrap();
    vec![two, fast, pressed, only_pressure]
}

#[test]
fn bidirectional_tangents_are_consistent_sticking_and_sliding() {
    let states: [([f64; 3], [f64; 3], [f64; 2]); 4] = [
        // sliding at an angle to the velocity
        ([0.3, -0.2, -0.01], [0.4, 0.3, 0.0], [0.0, 0.0]),
        ([0.3, -0.2, -0.012], [-0.1, 0.5, 0.0], [0.299, -0.1995]),
        // sticking near the committed state
        ([0.3, -0.2, -0.01], [0.02, -0.01, 0.0], [0.29995, -0.19998]),
        ([-0.05, 0.1, -0.011], [0.0, 0.0, 0.0], [-0.04996, 0.09998]),
    ];
    for e in bearings() {
        for (x, v, c) in states {
            check_tangents(&e, &x, &v, &c);
            let [r, _, _, trial] = eval(&e, &x, &v, &c);
            let p = -1e5 * x[2];
            let n = p + (r[0] * x[0] + r[1] * x[1]) / 2.0;
            let f = [r[0] - n * x[0] / 2.0, r[1] - n * x[1] / 2.0];
            let s =
                (v[0] * v[0] + v[1] * v[1] + ((x[0] * v[0] + x[1] * v[1]) / 2.0).powi(2)).sqrt();
            let (mu, _, _) = e.law.friction.at(s, n);
            assert!(f[0].hypot(f[1]) <= mu * n * (1.0 + 1e-12));
            if trial != c {
                // sliding: at the surface, along the plastic increment
                assert!((f[0].hypot(f[1]) - mu * n).abs() < 1e-9 * n);
                let dp = [trial[0] - c[0], trial[1] - c[1]];
                assert!((f[0] * dp[1] - f[1] * dp[0]).abs() < 1e-9 * n * dp[0].hypot(dp[1]));
            }
        }
    }
}

#[test]
fn bidirectional_along_x_is_the_uniaxial_bearing() {
    let one = AxialFrictionPendulum::new((0, 1), 2.0, 0.08, (1e3, 1e-3), 1e5)
        .unwrap()
        .with_velocity(0.03, 15.0)
        .unwrap();
    let two = AxialFrictionPendulum::bidirectional((0, 1, 2), 2.0, 0.08, (1e3, 1e-3), 1e5)
        .unwrap()
        .with_velocity(0.03, 15.0)
        .unwrap();
    for (u, w, v, c) in [(0.3, -0.01, 0.2, 0.0), (0.1, -0.01, 0.0, 0.09995)] {
        let [r1, k1, c1, t1] = eval(&one, &[u, w], &[v, 0.0], &[c]);
        let [r2, k2, c2, t2] = eval(&two, &[u, 0.0, w], &[v, 0.0, 0.0], &[c, 0.0]);
        assert_eq!([r1[0], r1[1]], [r2[0], r2[2]]);
        assert_eq!([k1[0], k1[1], k1[3]], [k2[0], k2[2], k2[8]]);
        assert_eq!(c1[0], c2[0]);
        assert_eq!(t1[0], t2[0]);
    }
}

#[test]
fn friction_coefficients_follow_opensees() {
    let e = &bearings()[2];
    let f = &e.law.friction;
    // VelPressureDep: mu_f = 0.08 - 0.04 tanh(0.01 N / 0.5), mu = mu_f - (mu_f - 0.03) e^{-15 s}
    let (n, s): (f64, f64) = (30.0, 0.1);
    let mu_f = 0.08 - 0.04 * (0.01 * n / 0.5_f64).tanh();
    let want = mu_f - (mu_f - 0.03) * (-15.0 * s).exp();
    assert!((f.at(s, n).0 - want).abs() < 1e-15);
    assert_eq!(f.at(0.0, n).0, 0.03);
    assert!((bearings()[1].law.friction.at(1e3, n).0 - 0.08).abs() < 1e-15);
    assert_eq!(bearings()[0].law.friction.at(0.5, n).0, 0.08);
}

#[test]
fn bidirectional_uplift_and_checks() {
    let e = &bearings()[1];
    let [r, k, c, trial] = eval(e, &[0.1, -0.2, 0.001], &[1.0; 3], &[0.0, 0.0]);
    assert_eq!(
        (r, k, c, trial),
        (vec![0.0; 3], vec![0.0; 9], vec![0.0; 9], vec![0.1, -0.2])
    );
    let bad = |dofs| {
        AxialFrictionPendulum::bidirectional(dofs, 2.0, 0.08, (1e3, 1e-3), 1e5)
            .unwrap_err()
            .to_string()
    };
    assert!(bad((0, 0, 2)).contains("dof_y"));
    assert!(bad((0, 1, 1)).contains("dof_z"));
    let two = AxialFrictionPendulum::new((0, 1), 2.0, 0.08, (1e3, 1e-3), 1e5).unwrap();
    assert!(two
        .clone()
        .with_velocity(0.1, 1.0)
        .unwrap_err()
        .to_string()
        .contains("mu_slow"));
    assert!(two
        .clone()
        .with_pressure(0.0, 0.01, 1.0)
        .unwrap_err()
        .to_string()
        .contains("contact_area"));
    assert!(two
        .with_pressure(1.0, 0.09, 1.0)
        .unwrap_err()
        .to_string()
        .contains("delta_mu"));
}
