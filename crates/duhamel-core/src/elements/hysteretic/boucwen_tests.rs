//! Tests of `boucwen.rs`.

use super::*;

/// A grounded element at dof 0 of `[k, fy, alpha, n, beta, gamma]`.
pub(super) fn grounded([k, fy, alpha, n, beta, gamma]: [f64; 6]) -> Result<BoucWen, CoreError> {
    let params = BoucWenParams {
        k,
        fy,
        alpha,
        n,
        beta,
        gamma,
    };
    BoucWen::new(0, None, params)
}

#[test]
fn rk4_matches_the_exact_linear_flow() {
    // n = 1 integrated both ways, across the switch at w = 0 and into saturation
    for (beta, gamma) in [(0.5, 0.5), (0.25, 0.75), (0.8, 0.2), (1.0, -0.5)] {
        let e = grounded([1.0, 1.0, 0.0, 1.0, beta, gamma]).unwrap();
        for w0 in [-0.95 / (beta + gamma), -0.3, 0.0, 0.4] {
            for xi in [1e-3, 0.05, 0.3, 1.0, 2.5, 40.0] {
                let exact = e.advance_linear(w0, xi);
                let rk4 = e.advance_rk4(w0, xi);
                assert!(
                    (exact - rk4).abs() < 1e-10,
                    "beta {beta} gamma {gamma} w0 {w0} xi {xi}: {exact} vs {rk4}"
                );
            }
        }
    }
}

#[test]
fn saturates_at_z_max_for_huge_increments() {
    for n in [1.0, 2.0, 2.5, 25.0] {
        let e = grounded([2.0, 1.0, 0.1, n, 0.3, 0.5]).unwrap();
        let (z, _, kt) = e.response(0.0, -0.2, 1e9);
        assert!((z - e.z_max()).abs() < 1e-12, "n {n}: {z}");
        assert!((kt - 0.2).abs() < 1e-10, "n {n}: {kt}");
    }
}

#[test]
fn validates_parameters() {
    let name = |e: CoreError| match e {
        CoreError::InvalidInput { name, .. } => name,
        other => panic!("{other:?}"),
    };
    let make = |n, beta, gamma| grounded([1.0, 1.0, 0.1, n, beta, gamma]);
    assert_eq!(name(make(0.5, 0.5, 0.5).unwrap_err()), "n");
    assert_eq!(name(make(f64::INFINITY, 0.5, 0.5).unwrap_err()), "n");
    assert_eq!(name(make(1.0, 0.0, 0.5).unwrap_err()), "beta");
    assert_eq!(name(make(1.0, 0.5, -0.5).unwrap_err()), "gamma");
    let e = grounded([1.0, 0.0, 0.1, 1.0, 0.5, 0.5]);
    assert_eq!(name(e.unwrap_err()), "fy");
}
