use super::*;
use crate::elements::materials::multilinear::MultiLinear;
use crate::elements::materials::steel02::{Steel02, Transition};
use crate::elements::materials::testing::drive;

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
fn equals_its_material_until_a_limit_then_zero_for_good() {
    let m = MinMax::new(steel(), -0.03, 0.05).unwrap();
    let us = [0.01, 0.04, -0.02, 0.049, 0.05, 0.0, -0.01, 0.02];
    let (c, out) = drive(&m, &us);
    let (_, inner) = drive(steel().as_ref(), &us[..4]);
    assert_eq!(&out[..4], &inner[..]);
    for &(f, k) in &out[4..] {
        assert_eq!((f, k), (0.0, 1e-8 * 1000.0));
    }
    assert_eq!(c[0], 1.0);
    assert_eq!(m.stored_energy(&c, 0.02, 0.0), 0.0);
}

#[test]
fn a_trial_beyond_a_limit_is_forgotten_when_not_committed() {
    let m = MinMax::new(steel(), -0.03, 0.05).unwrap();
    let (c, _) = drive(&m, &[0.02]);
    let mut t = c.clone();
    assert_eq!(m.response(-0.04, 0.0, &c, &mut t).unwrap().0, 0.0);
    assert_eq!(t[0], 1.0);
    let after = m.response(0.01, 0.0, &c, &mut t).unwrap();
    let (ci, _) = drive(steel().as_ref(), &[0.02]);
    let mut ti = ci.clone();
    assert_eq!(after, steel().response(0.01, 0.0, &ci, &mut ti).unwrap());
    assert_eq!(t[0], 0.0);
}

#[test]
fn the_limits_are_checked_and_the_bound_kept() {
    let ml =
        || Box::new(MultiLinear::new(&[0.01, 0.02], &[1.0, 1.5]).unwrap()) as Box<dyn Material>;
    let name = |r: Result<MinMax, CoreError>| match r {
        Err(CoreError::InvalidInput { name, .. }) => name,
        other => panic!("expected an input error, got {other:?}"),
    };
    assert_eq!(name(MinMax::new(ml(), 0.1, -0.1)), "max");
    assert_eq!(name(MinMax::new(ml(), f64::NAN, 0.1)), "min");
    let m = MinMax::new(ml(), -0.1, 0.1).unwrap();
    assert_eq!(m.tangent_bound(), Some(100.0));
    assert_eq!(m.initial_tangent(), 100.0);
}
