//! Inputs that used to panic (or wrap an integer) in the core, and now give an answer or an
//! `InvalidInput`/`LengthMismatch` naming the parameter.

use duhamel_core::background::first_order::{integrate, FirstOrderModes};
use duhamel_core::elements::spring::Spring;
use duhamel_core::elements::Element;
use duhamel_core::loads::TimeFunction;
use duhamel_core::output::Outputs;
use duhamel_core::problem::SaveGrid;
use duhamel_core::pseudo::first_order::Nonlinear;
use duhamel_core::{CoreError, ModalProblem, Unattended};

fn name_of(e: &CoreError) -> &'static str {
    match e {
        CoreError::InvalidInput { name, .. } | CoreError::LengthMismatch { name, .. } => name,
        other => panic!("not an input error: {other:?}"),
    }
}

fn problem<'a>(k: &'a [f64], zeros: &'a [f64]) -> ModalProblem<'a> {
    ModalProblem {
        k,
        c: zeros,
        q0: zeros,
        v0: zeros,
        loads: &[],
        t0: 0.0,
        step0: 0,
        dt: 0.1,
        n_steps: 10,
        save_every: 1,
        threads: Some(1),
    }
}

/// One real mode as two first-order coordinates, for the coupled route.
fn modes<'a>(gains: &'a [f64], zeros: &'a [f64], ones: &'a [f64]) -> FirstOrderModes<'a> {
    FirstOrderModes {
        lambda_re: zeros,
        lambda_im: ones,
        gain_re: gains,
        gain_im: gains,
        eta0_re: zeros,
        eta0_im: zeros,
    }
}

/// A table at a NaN time used to index sample -1.
#[test]
fn table_at_nan_time_is_nan() {
    let f = TimeFunction::Table {
        t: vec![0.0, 1.0],
        v: vec![0.0, 2.0],
        hold: true,
    };
    f.validate().unwrap();
    assert!(f.eval(f64::NAN).is_nan());
    assert!(f.eval_before(f64::NAN).is_nan());
    assert_eq!(f.eval(0.5), 1.0);
}

/// Saving every one of `usize::MAX` steps used to wrap the count of saved instants to 0.
#[test]
fn saved_instants_saturate() {
    assert_eq!(SaveGrid::new(usize::MAX, 1).count(), usize::MAX);
    assert_eq!(SaveGrid::new(usize::MAX, usize::MAX).count(), 2);
    assert_eq!(SaveGrid::new(10, 3).count(), 5);
}

/// `width * n_cols` used to wrap.
#[test]
fn output_columns_that_overflow() {
    let outputs = Outputs {
        map: &[],
        loads: &[],
        n_cols: usize::MAX,
    };
    assert_eq!(name_of(&outputs.check(4, 0).unwrap_err()), "n_cols");
}

/// With no first-order coordinates, `n_cols` is not bounded by the map: the history's width
/// used to wrap.
#[test]
fn output_columns_without_coordinates() {
    let (k, zeros) = ([1.0], [0.0]);
    let outputs = Outputs {
        map: &[],
        loads: &[],
        n_cols: usize::MAX,
    };
    let empty = modes(&[], &[], &[]);
    let err = integrate(
        &problem(&k, &zeros),
        &empty,
        Some(&outputs),
        None,
        None,
        &mut Unattended,
    )
    .unwrap_err();
    assert_eq!(name_of(&err.error), "save_every");
}

/// The coupled route's elements read `phi` rows up to `n_dof x n_modes` without a check.
#[test]
fn first_order_elements_check_the_mode_shapes() {
    let (k, zeros) = ([1.0, 4.0], [0.0, 0.0]);
    let (gains, ones) = ([1.0; 4], [1.0, 1.0]);
    let spring = Spring::new(1, None, 1.0, 1.0).unwrap();
    let elements: [&dyn Element; 1] = [&spring];
    let nonlinear = Nonlinear {
        phi: &[1.0, 0.0, 0.0],
        n_dof: 2,
        elements: &elements,
        back: &[0.0; 16],
        tol: 1e-9,
        max_iter: 10,
        element_state: None,
        guard_state: None,
        growth_limit: f64::INFINITY,
    };
    let err = integrate(
        &problem(&k, &zeros),
        &modes(&gains, &zeros, &ones),
        None,
        Some(&nonlinear),
        None,
        &mut Unattended,
    )
    .unwrap_err();
    assert_eq!(name_of(&err.error), "phi");
}
