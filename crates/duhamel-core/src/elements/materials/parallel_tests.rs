use super::*;
use crate::elements::materials::elastic_multilinear::ElasticMultiLinear;
use crate::elements::materials::steel02::{Steel02, Transition};
use crate::elements::materials::takeda::Takeda;
use crate::elements::materials::testing::{drive, random_walk, tangent_error};

fn parts() -> Vec<Box<dyn Material>> {
    vec![
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
        ),
        Box::new(Takeda::new(&[0.01, 0.05], &[5.0, 7.0], None, 0.4).unwrap()),
        Box::new(ElasticMultiLinear::new(&[-1.0, 1.0], &[-50.0, 50.0]).unwrap()),
    ]
}

#[test]
fn force_and_tangent_are_the_weighted_sums() {
    let us = random_walk(500, 0.01, 13);
    let w = [2.0, 0.5, -1.0];
    let m = Parallel::new(parts(), Some(w.to_vec())).unwrap();
    let (_, out) = drive(&m, &us);
    let each: Vec<_> = parts().iter().map(|p| drive(p.as_ref(), &us).1).collect();
    for (k, &(f, kt)) in out.iter().enumerate() {
        let fs: f64 = (0..3).map(|i| w[i] * each[i][k].0).sum();
        let ks: f64 = (0..3).map(|i| w[i] * each[i][k].1).sum();
        assert!((f - fs).abs() <= 1e-13 * 20.0 && (kt - ks).abs() <= 1e-13 * 1000.0);
    }
    assert_eq!(m.initial_tangent(), 2.0 * 1000.0 + 0.5 * 500.0 - 50.0);
    assert!(!m.passive(), "a negative factor");
    let (err, n) = tangent_error(&Parallel::new(parts(), None).unwrap(), &us, 1e-9, 1000.0);
    assert!(n > 450 && err < 1e-5, "tangent error {err} over {n}");
}

#[test]
fn stored_energy_is_the_sum_of_the_parts() {
    let m = Parallel::new(parts(), None).unwrap();
    let us = [0.02, 0.035, 0.01];
    let (c, out) = drive(&m, &us);
    let mut sum = 0.0;
    for p in parts() {
        let (ci, oi) = drive(p.as_ref(), &us);
        sum += p.stored_energy(&ci, 0.01, oi[2].0);
    }
    assert_eq!(m.stored_energy(&c, 0.01, out[2].0), sum);
}

#[test]
fn bad_input_is_named() {
    let name = |r: Result<Parallel, CoreError>| match r {
        Err(CoreError::InvalidInput { name, .. } | CoreError::LengthMismatch { name, .. }) => name,
        other => panic!("expected an input error, got {other:?}"),
    };
    assert_eq!(name(Parallel::new(vec![], None)), "materials");
    assert_eq!(name(Parallel::new(parts(), Some(vec![1.0]))), "factors");
    assert_eq!(
        name(Parallel::new(parts(), Some(vec![1.0, f64::NAN, 1.0]))),
        "factors"
    );
}
