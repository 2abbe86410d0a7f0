use super::*;
use crate::elements::materials::testing::{drive, random_walk, tangent_error};

const STRAIN: [f64; 5] = [-0.02, -0.005, 0.0, 0.01, 0.03];
const STRESS: [f64; 5] = [-30.0, -20.0, 0.0, 15.0, 20.0];

/// The polyline through the points, extended with the end slopes (written independently:
/// `numpy.interp` plus the end lines).
fn polyline(u: f64) -> f64 {
    let n = STRAIN.len();
    if u <= STRAIN[0] {
        let k = (STRESS[1] - STRESS[0]) / (STRAIN[1] - STRAIN[0]);
        return STRESS[0] + k * (u - STRAIN[0]);
    }
    if u >= STRAIN[n - 1] {
        let k = (STRESS[n - 1] - STRESS[n - 2]) / (STRAIN[n - 1] - STRAIN[n - 2]);
        return STRESS[n - 1] + k * (u - STRAIN[n - 1]);
    }
    let j = STRAIN.iter().rposition(|&e| e <= u).unwrap();
    let w = (u - STRAIN[j]) / (STRAIN[j + 1] - STRAIN[j]);
    STRESS[j] + w * (STRESS[j + 1] - STRESS[j])
}

#[test]
fn force_is_the_polyline_on_any_path() {
    let m = ElasticMultiLinear::new(&STRAIN, &STRESS).unwrap();
    let us = random_walk(2000, 0.01, 3);
    assert!(us.iter().any(|&u| u < -0.03) && us.iter().any(|&u| u > 0.04));
    let (_, out) = drive(&m, &us);
    for (&u, &(f, _)) in us.iter().zip(&out) {
        assert!(
            (f - polyline(u)).abs() <= 1e-12 * 30.0,
            "{u}: {f} vs {}",
            polyline(u)
        );
    }
    let (err, n) = tangent_error(&m, &us, 1e-9, 2000.0);
    assert!(n > 1900 && err < 1e-6, "tangent error {err} over {n}");
    assert_eq!(m.initial_tangent(), 1500.0);
}

#[test]
fn stored_energy_is_the_integral_of_the_force() {
    let m = ElasticMultiLinear::new(&STRAIN, &STRESS).unwrap();
    for u in [
        -0.05_f64, -0.02, -0.011, -0.003, 0.0, 0.004, 0.01, 0.02, 0.07,
    ] {
        // Simpson on a fine grid through 0, u and the kinks between (exact on each piece)
        let mut knots = vec![0.0, u];
        knots.extend(STRAIN.iter().filter(|&&e| e > u.min(0.0) && e < u.max(0.0)));
        knots.sort_by(f64::total_cmp);
        let mut w: f64 = knots
            .windows(2)
            .map(|p| {
                (p[1] - p[0])
                    * (polyline(p[0]) + 4.0 * polyline(0.5 * (p[0] + p[1])) + polyline(p[1]))
                    / 6.0
            })
            .sum();
        if u < 0.0 {
            w = -w;
        }
        let got = m.stored_energy(&[], u, polyline(u));
        assert!((got - w).abs() <= 1e-14 * 2.0, "{u}: {got} vs {w}");
        assert!(got >= 0.0);
    }
    assert!(m.passive());
    let shifted = ElasticMultiLinear::new(&[0.0, 1.0], &[1.0, 2.0]).unwrap();
    assert!(
        !shifted.passive(),
        "a force at rest stores energy of either sign"
    );
}

#[test]
fn bad_points_are_named() {
    let name = |r: Result<ElasticMultiLinear, CoreError>| match r {
        Err(CoreError::InvalidInput { name, .. } | CoreError::LengthMismatch { name, .. }) => name,
        other => panic!("expected an input error, got {other:?}"),
    };
    assert_eq!(name(ElasticMultiLinear::new(&[0.0], &[0.0])), "strain");
    assert_eq!(name(ElasticMultiLinear::new(&[0.0, 1.0], &[0.0])), "stress");
    assert_eq!(
        name(ElasticMultiLinear::new(&[0.0, 0.0], &[0.0, 1.0])),
        "strain"
    );
    assert_eq!(
        name(ElasticMultiLinear::new(&[0.0, 1.0], &[0.0, f64::NAN])),
        "stress"
    );
}
