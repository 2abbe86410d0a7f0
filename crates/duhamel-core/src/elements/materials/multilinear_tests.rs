use super::*;
use crate::elements::materials::testing::{cycles, drive, random_walk, tangent_error};

// kinks on a 1e-3 grid so that a history on that grid meets every kink at a point
const STRAIN: [f64; 3] = [0.002, 0.006, 0.02];
const STRESS: [f64; 3] = [10.0, 14.0, 16.0];

fn backbone(x: f64) -> f64 {
    // the backbone through the origin and the points, the last slope extended
    let (mut x0, mut f0) = (0.0, 0.0);
    for (k, (&e, &s)) in STRAIN.iter().zip(&STRESS).enumerate() {
        if x <= e || k + 1 == STRAIN.len() {
            return f0 + (s - f0) / (e - x0) * (x - x0);
        }
        (x0, f0) = (e, s);
    }
    unreachable!()
}

fn integral(x: f64) -> f64 {
    // the trapezoid on each piece between the kinks, exact
    let mut knots = vec![0.0];
    knots.extend(STRAIN.iter().copied().filter(|&e| e < x));
    knots.push(x);
    knots
        .windows(2)
        .map(|p| 0.5 * (backbone(p[0]) + backbone(p[1])) * (p[1] - p[0]))
        .sum()
}

fn grid(points: &[f64], step: f64) -> Vec<f64> {
    // straight lines between the points on a grid of `step`
    let mut out = Vec::new();
    let mut u = 0.0_f64;
    for &p in points {
        let n = ((p - u).abs() / step).round() as usize;
        for k in 1..=n {
            out.push(u + (p - u) * k as f64 / n as f64);
        }
        u = p;
    }
    out
}

#[test]
fn monotonic_loading_follows_the_backbone() {
    let m = MultiLinear::new(&STRAIN, &STRESS).unwrap();
    for sign in [1.0, -1.0] {
        let us: Vec<f64> = (1..=300).map(|k| sign * k as f64 * 1e-4).collect();
        let (_, out) = drive(&m, &us);
        for (&u, &(f, _)) in us.iter().zip(&out) {
            assert!(
                (f - sign * backbone(u.abs())).abs() <= 1e-12 * 16.0,
                "{u}: {f}"
            );
        }
    }
}

#[test]
fn unloading_follows_masing_and_the_loop_area_is_the_closed_form() {
    // kinematic hardening of parallel elastic-plastic elements: a branch from the
    // reversal (u_r, F_r) is F_r -/+ 2 B(|u - u_r| / 2), and a stable symmetric loop of
    // amplitude D encloses 8 int_0^D B - 4 D B(D)
    let m = MultiLinear::new(&STRAIN, &STRESS).unwrap();
    let d = 0.014;
    let us = grid(&[d, -d, d, -d, d], 1e-4);
    let (_, out) = drive(&m, &us);
    let fd = backbone(d);
    for (&u, &(f, _)) in us.iter().zip(&out).skip(140) {
        let down = fd - 2.0 * backbone((d - u) / 2.0);
        let up = -fd + 2.0 * backbone((u + d) / 2.0);
        assert!(
            (f - down).abs() <= 1e-11 || (f - up).abs() <= 1e-11,
            "{u}: {f} is on neither Masing branch ({down}, {up})"
        );
    }
    // the last full cycle (4 * 140 points), trapezoid exact with kinks on the grid
    let start = us.len() - 4 * 140 - 1;
    let work: f64 = (start..us.len() - 1)
        .map(|k| 0.5 * (out[k].0 + out[k + 1].0) * (us[k + 1] - us[k]))
        .sum();
    let area = 8.0 * integral(d) - 4.0 * d * fd;
    assert!((work - area).abs() <= 1e-9 * area, "{work} vs {area}");
}

#[test]
fn tangent_is_the_derivative_of_the_force() {
    let m = MultiLinear::new(&STRAIN, &STRESS).unwrap();
    for us in [
        cycles(&[0.001, 0.004, 0.01, 0.03], 37),
        random_walk(500, 0.003, 5),
    ] {
        let (err, n) = tangent_error(&m, &us, 1e-10, 5000.0);
        assert!(
            n > us.len() * 9 / 10 && err < 1e-6,
            "tangent error {err} over {n}"
        );
    }
    assert_eq!(m.tangent_bound(), Some(5000.0));
}

#[test]
fn the_same_deformation_committed_twice_changes_nothing() {
    // OpenSees repeats its yield update here and moves the elastic range (docs/materials.md)
    let m = MultiLinear::new(&STRAIN, &STRESS).unwrap();
    let (_, once) = drive(&m, &[0.01, 0.009]);
    let (_, twice) = drive(&m, &[0.01, 0.01, 0.009]);
    assert_eq!(once[1], twice[2]);
    assert!((once[1].0 - (backbone(0.01) - 5.0)).abs() <= 1e-13);
}

#[test]
fn bad_points_are_named() {
    let name = |r: Result<MultiLinear, CoreError>| match r {
        Err(CoreError::InvalidInput { name, .. } | CoreError::LengthMismatch { name, .. }) => name,
        other => panic!("expected an input error, got {other:?}"),
    };
    assert_eq!(name(MultiLinear::new(&[0.01], &[1.0])), "strain");
    assert_eq!(name(MultiLinear::new(&[0.0, 0.01], &[0.0, 1.0])), "strain");
    assert_eq!(name(MultiLinear::new(&[0.02, 0.01], &[1.0, 2.0])), "strain");
    assert_eq!(
        name(MultiLinear::new(&[0.01, 0.02], &[1.0, -2.0])),
        "stress"
    );
    assert_eq!(name(MultiLinear::new(&[0.01, 0.02], &[1.0])), "stress");
}
