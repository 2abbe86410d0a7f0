use super::*;
use crate::elements::materials::elastic_multilinear::ElasticMultiLinear;
use crate::elements::materials::multilinear::MultiLinear;
use crate::elements::materials::steel02::{Steel02, Transition};
use crate::elements::materials::testing::{cycles, drive, random_walk, tangent_error};

fn spring(k: f64) -> Box<dyn Material> {
    Box::new(ElasticMultiLinear::new(&[-1.0, 0.0, 1.0], &[-k, 0.0, k]).unwrap())
}

fn bilinear() -> Box<dyn Material> {
    // k0 = 1000, yield at (0.01, 10), then 100
    Box::new(MultiLinear::new(&[0.01, 1.0], &[10.0, 109.0]).unwrap())
}

fn steel() -> Box<dyn Material> {
    Box::new(
        Steel02::new(
            10.0,
            1000.0,
            0.05,
            Transition {
                r0: 20.0,
                cr1: 0.925,
                cr2: 0.15,
            },
            [0.0, 1.0, 0.0, 1.0],
            0.0,
        )
        .unwrap(),
    )
}

#[test]
fn springs_in_series_add_flexibilities() {
    let m = Series::new(vec![spring(1000.0), spring(3000.0)], 50, 1e-10).unwrap();
    assert_eq!(m.initial_tangent(), 750.0);
    let (_, out) = drive(&m, &[0.1, -0.3, 0.25]);
    for (&u, &(f, k)) in [0.1, -0.3, 0.25].iter().zip(&out) {
        assert!((f - 750.0 * u).abs() <= 1e-13 * 750.0 && (k - 750.0).abs() <= 1e-12);
    }
}

#[test]
fn elastic_and_bilinear_in_series_follow_the_closed_form() {
    // u = F/k1 + F/k0 below the yield force, F/k1 + dy + (F - Fy)/kp above
    let k1 = 2000.0;
    let m = Series::new(vec![spring(k1), bilinear()], 50, 1e-10).unwrap();
    let uy = 10.0 / k1 + 0.01;
    let us: Vec<f64> = (1..=100).map(|k| k as f64 * 0.001).collect();
    let (_, out) = drive(&m, &us);
    for (&u, &(f, k)) in us.iter().zip(&out) {
        let (exact, kt) = if u <= uy {
            (
                u / (1.0 / k1 + 1.0 / 1000.0),
                1.0 / (1.0 / k1 + 1.0 / 1000.0),
            )
        } else {
            (
                (u - 0.01 + 10.0 / 100.0) / (1.0 / k1 + 1.0 / 100.0),
                1.0 / (1.0 / k1 + 0.01),
            )
        };
        assert!((f - exact).abs() <= 1e-11 * 20.0, "{u}: {f} vs {exact}");
        assert!((k - kt).abs() <= 1e-9 * kt);
    }
}

#[test]
fn parts_carry_the_force_and_add_up_to_the_deformation() {
    let m = Series::new(vec![spring(3000.0), steel(), bilinear()], 50, 1e-10).unwrap();
    let us = random_walk(400, 0.02, 23);
    let (c, out) = drive(&m, &us);
    let f = out.last().unwrap().0;
    let parts: Vec<(f64, f64)> = (0..3)
        .map(|i| (c[HEAD + 3 * i], c[HEAD + 3 * i + 1]))
        .collect();
    let total: f64 = parts.iter().map(|p| p.0).sum();
    assert!((total - us[399]).abs() <= 1e-11 * us[399].abs().max(0.01));
    for p in &parts {
        assert!((p.1 - f).abs() <= 1e-11 * f.abs().max(1.0), "{p:?} vs {f}");
    }
    let (err, n) = tangent_error(&m, &us, 1e-9, 1000.0);
    assert!(n > 360 && err < 1e-5, "tangent error {err} over {n}");
}

#[test]
fn a_plateau_in_series_caps_the_force() {
    let flat = Box::new(MultiLinear::new(&[0.01, 0.05], &[10.0, 10.0]).unwrap());
    let m = Series::new(vec![spring(5000.0), flat], 100, 1e-10).unwrap();
    let us = cycles(&[0.005, 0.03, 0.08], 40);
    let (_, out) = drive(&m, &us);
    assert!(out.iter().all(|&(f, _)| f.abs() <= 10.0 * (1.0 + 1e-10)));
    assert!(out.iter().any(|&(f, _)| (f - 10.0).abs() <= 1e-9));
}

#[test]
fn too_few_iterations_is_an_error_not_an_answer() {
    let m = Series::new(vec![spring(2000.0), steel()], 1, 1e-10).unwrap();
    let mut c = vec![0.0; m.state_len()];
    m.initial_state(&mut c);
    let mut t = c.clone();
    let r = m.response(0.05, 0.0, &c, &mut t);
    assert!(matches!(r, Err(CoreError::NoConvergence { .. })), "{r:?}");
}

#[test]
fn bad_input_is_named() {
    let name = |r: Result<Series, CoreError>| match r {
        Err(CoreError::InvalidInput { name, .. }) => name,
        other => panic!("expected an input error, got {other:?}"),
    };
    assert_eq!(name(Series::new(vec![], 10, 1e-12)), "materials");
    assert_eq!(name(Series::new(vec![spring(1.0)], 0, 1e-12)), "max_iter");
    assert_eq!(name(Series::new(vec![spring(1.0)], 10, 0.0)), "tol");
}
