//! Tests of `friction.rs`.

use super::*;

#[test]
fn length_is_hypot_bit_for_bit() {
    for a in [
        0.0,
        -0.0,
        3.0,
        -2.5e-300,
        1.7e308,
        f64::INFINITY,
        f64::NAN,
        5e-324,
    ] {
        for b in [0.0, -0.0, a, 4.0] {
            assert_eq!(length(a, b).to_bits(), a.hypot(b).to_bits(), "{a} {b}");
            assert_eq!(length(b, a).to_bits(), b.hypot(a).to_bits(), "{b} {a}");
        }
    }
}

#[test]
fn sticks_then_slides_radially() {
    let e = FrictionPendulum::new(0, 1, 2.0, 0.1, 50.0, 1e-3).unwrap(); // mu W = 5
    let (f, kt) = e.friction([0.0; 2], [0.0; 2], [3e-4, -4e-4]);
    assert!((f[0] - 1.5).abs() < 1e-14 && (f[1] + 2.0).abs() < 1e-14);
    assert_eq!(kt, [5000.0, 0.0, 0.0, 5000.0]);
    let (f, kt) = e.friction([0.0; 2], [0.0; 2], [0.03, 0.04]);
    assert!((f[0] - 3.0).abs() < 1e-14 && (f[1] - 4.0).abs() < 1e-14);
    // tangent: k0 (mu W / |f_trial|) (I - n n^T), |f_trial| = 250
    let s = 5000.0 * 5.0 / 250.0;
    let want = [s * 0.64, -s * 0.48, -s * 0.48, s * 0.36];
    assert!(kt.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12));
}

/// Central differences of the force at `(x, v)` from the committed `c`.
fn numeric(e: &FrictionPendulum, c: &[f64; 4], x: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = x.len();
    let force = |x: &[f64], v: &[f64]| {
        let mut r = vec![0.0; n];
        let mut trial = [0.0; 4];
        let h = PathState {
            committed: c,
            trial: &mut trial,
        };
        e.eval_path(x, v, 0.0, h, &mut r, None).unwrap();
        r
    };
    let (mut kx, mut cv) = (vec![0.0; n * n], vec![0.0; n * n]);
    for j in 0..n {
        for (which, dst) in [(0, &mut kx), (1, &mut cv)] {
            let h = 1e-7;
            let (mut xp, mut vp, mut xm, mut vm) = (x.to_vec(), v.to_vec(), x.to_vec(), v.to_vec());
            if which == 0 {
                xp[j] += h;
                xm[j] -= h;
            } else {
                vp[j] += h;
                vm[j] -= h;
            }
            let (rp, rm) = (force(&xp, &vp), force(&xm, &vm));
            for i in 0..n {
                dst[i * n + j] = (rp[i] - rm[i]) / (2.0 * h);
            }
        }
    }
    (kx, cv)
}

#[test]
fn velocity_dependent_tangents_are_consistent() {
    let e = FrictionPendulum::new(0, 1, 2.0, 0.1, 50.0, 1e-3)
        .unwrap()
        .with_velocity(0.04, 20.0)
        .unwrap();
    let c = [0.0, 0.0, 1.0, -0.5];
    for (x, v) in [([0.03, 0.01], [0.05, 0.02]), ([1e-4, 0.0], [0.0, 0.0])] {
        let (mut r, mut kx, mut cv) = ([0.0; 2], [0.0; 4], [0.0; 4]);
        let mut trial = [0.0; 4];
        let h = PathState {
            committed: &c,
            trial: &mut trial,
        };
        let tg = Tangent {
            kx: &mut kx,
            cv: &mut cv,
        };
        e.eval_path(&x, &v, 0.0, h, &mut r, Some(tg)).unwrap();
        let (nk, nc) = numeric(&e, &c, &x, &v);
        for k in 0..4 {
            assert!(
                (kx[k] - nk[k]).abs() < 1e-5 * (1.0 + kx[k].abs()),
                "{kx:?} {nk:?}"
            );
            assert!(
                (cv[k] - nc[k]).abs() < 1e-5 * (1.0 + cv[k].abs()),
                "{cv:?} {nc:?}"
            );
        }
    }
    // sliding fast: the force is mu_fast W; at rest the surface is mu_slow W
    let (mu, _) = e.coefficient(10.0);
    assert!((mu - 0.1).abs() < 1e-12);
    assert_eq!(e.coefficient(0.0).0, 0.04);
}

#[test]
fn uniaxial_is_the_bidirectional_bearing_on_a_line() {
    let one = FrictionPendulum::uniaxial(3, 2.0, 0.1, 50.0, 1e-3).unwrap();
    let two = FrictionPendulum::new(3, 4, 2.0, 0.1, 50.0, 1e-3).unwrap();
    assert_eq!(one.dofs(), &[3]);
    let c = [0.001, 0.0, 4.0, 0.0];
    for x in [-0.02, 0.0015, 0.05] {
        let (mut r1, mut r2) = ([0.0; 1], [0.0; 2]);
        let (mut k1, mut c1, mut k2, mut c2) = ([0.0; 1], [0.0; 1], [0.0; 4], [0.0; 4]);
        let (mut t1, mut t2) = ([0.0; 4], [0.0; 4]);
        one.eval_path(
            &[x],
            &[0.1],
            0.0,
            PathState {
                committed: &c,
                trial: &mut t1,
            },
            &mut r1,
            Some(Tangent {
                kx: &mut k1,
                cv: &mut c1,
            }),
        )
        .unwrap();
        two.eval_path(
            &[x, 0.0],
            &[0.1, 0.0],
            0.0,
            PathState {
                committed: &c,
                trial: &mut t2,
            },
            &mut r2,
            Some(Tangent {
                kx: &mut k2,
                cv: &mut c2,
            }),
        )
        .unwrap();
        assert_eq!(r1[0], r2[0]);
        assert_eq!(k1[0], k2[0]);
        assert_eq!(t1, t2);
    }
}

#[test]
fn no_friction_is_a_pendulum() {
    let e = FrictionPendulum::new(0, 1, 2.0, 0.0, 50.0, 1e-3).unwrap();
    let mut r = [0.0; 2];
    e.eval(&[0.2, -0.1], &[1.0, 1.0], 0.0, &mut r, None)
        .unwrap();
    assert_eq!(r, [5.0, -2.5]);
}
