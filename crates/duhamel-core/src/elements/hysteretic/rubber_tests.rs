//! Tests of `rubber.rs`.

use super::*;

fn bearing(y: Option<usize>) -> LeadRubberBearing {
    LeadRubberBearing::new(0, y, (1e6, 5e4, 0.1), (1.0, 0.5, 0.5)).unwrap()
}

#[test]
fn yields_to_the_unit_circle_and_hardens() {
    let e = bearing(Some(1));
    let uy = 0.05;
    let (z, _) = e
        .evolve([0.0; 2], [0.0; 2], [10.0 * uy, 10.0 * uy])
        .unwrap();
    // |z| -> 1 like exp(-|u| / uy) (eta = 1): 1 - |z| ~ exp(-14)
    let nz = z[0].hypot(z[1]);
    assert!((nz - 1.0).abs() < 2e-5, "{z:?}");
    assert!((z[0] - z[1]).abs() < 1e-12);
    // small increments are elastic: z = u / uy (to first order in |u| / uy = 4.5e-5)
    let (z, d) = e.evolve([0.0; 2], [0.0; 2], [1e-6, -2e-6]).unwrap();
    assert!((z[0] - 1e-6 / uy).abs() < 1e-4 * 1e-6 / uy);
    assert!((z[1] + 2e-6 / uy).abs() < 1e-4 * 2e-6 / uy);
    assert!((d[0] - 1.0 / uy).abs() < 1e-4 * (1.0 / uy));
}

#[test]
fn tangent_is_the_derivative_of_the_update() {
    for y in [Some(1), None] {
        let e = bearing(y);
        let n = if y.is_some() { 2 } else { 1 };
        let c = [0.01, -0.02, 0.6, -0.5];
        let x = [0.043, -0.011];
        let force = |x: &[f64]| {
            let mut r = vec![0.0; n];
            let mut trial = [0.0; 4];
            let h = PathState {
                committed: &c,
                trial: &mut trial,
            };
            e.eval_path(&x[..n], &[0.0; 2][..n], 0.0, h, &mut r, None)
                .unwrap();
            r
        };
        let (mut r, mut kx, mut cv) = (vec![0.0; n], vec![0.0; n * n], vec![0.0; n * n]);
        let mut trial = [0.0; 4];
        let h = PathState {
            committed: &c,
            trial: &mut trial,
        };
        let tg = Tangent {
            kx: &mut kx,
            cv: &mut cv,
        };
        e.eval_path(&x[..n], &[0.0; 2][..n], 0.0, h, &mut r, Some(tg))
            .unwrap();
        for j in 0..n {
            let (mut xp, mut xm) = (x, x);
            xp[j] += 1e-7;
            xm[j] -= 1e-7;
            let (rp, rm) = (force(&xp), force(&xm));
            for i in 0..n {
                let num = (rp[i] - rm[i]) / 2e-7;
                assert!(
                    (kx[i * n + j] - num).abs() < 1e-5 * (1e6 + num.abs()),
                    "{kx:?} {num}"
                );
            }
        }
    }
}

#[test]
fn uniaxial_is_the_bidirectional_bearing_on_a_line() {
    let (one, two) = (bearing(None), bearing(Some(1)));
    let (z1, d1) = one.evolve([0.01, 0.0], [0.3, 0.0], [-0.2, 0.0]).unwrap();
    let (z2, d2) = two.evolve([0.01, 0.0], [0.3, 0.0], [-0.2, 0.0]).unwrap();
    assert_eq!(z1, z2);
    assert_eq!(d1[0], d2[0]);
}
