//! Tests of the time functions (moved out of `time.rs` to keep it short).

use super::*;

#[test]
fn table_interpolates_and_ends() {
    let f = TimeFunction::Table {
        t: vec![0.0, 1.0, 3.0],
        v: vec![0.0, 2.0, -2.0],
        hold: false,
    };
    assert_eq!(f.eval(0.5), 1.0);
    assert_eq!(f.eval(2.0), 0.0);
    // the record ends at t = 3: -2 just before, 0 from then on
    assert_eq!(f.eval_before(3.0), -2.0);
    assert_eq!(f.eval(3.0), 0.0);
    assert_eq!(f.eval(3.5), 0.0);
    assert_eq!(f.eval(-1.0), 0.0);
    // a step [2, 3] sees the line from 0 to -2, a step [3, 4] sees zero
    assert_eq!(f.basis(2.0, 1.0), [0.0, -2.0, 0.0]);
    assert_eq!(f.basis(3.0, 1.0), [0.0, 0.0, 0.0]);
}

#[test]
fn step_jump_inside() {
    let f = TimeFunction::Step { t0: 0.25 };
    assert_eq!(f.jump_in(0.0, 1.0), Some((0.75, [1.0, 0.0, 0.0])));
    assert_eq!(f.jump_in(0.25, 1.0), None);
    assert_eq!(f.basis(0.25, 1.0), [1.0, 0.0, 0.0]);
    assert_eq!(f.basis(0.0, 1.0), [0.0, 0.0, 0.0]);
}

/// The part an unbalance leaves to the parabola at the end of a run-up is twice
/// continuously differentiable: one-sided finite differences of `f - jump polynomial`
/// agree across the break, those of `f` jump by the coefficients.
#[test]
fn unbalance_pair_bases_equal_single_bases() {
    let law = SpeedLaw::Constant(157.3);
    let make = |axis| TimeFunction::Unbalance {
        law,
        phase: 0.3,
        axis,
    };
    let (x, y) = (make(Axis::X), make(Axis::Y));
    let time = |n: usize| 0.5 + n as f64 * 1e-3;
    let (len, stride) = (40, 3);
    let steps = Steps {
        time,
        dt: 1e-3,
        len,
    };
    for (a, b) in [(&x, &y), (&y, &x)] {
        let mut single = vec![[0.0; 3]; len * stride];
        a.bases(&steps, &mut single, 0, stride);
        b.bases(&steps, &mut single, 2, stride);
        let mut pair = vec![[0.0; 3]; len * stride];
        assert!(a.pair_bases(b, &steps, &mut pair, (0, 2), stride));
        assert_eq!(single, pair);
    }
    // Not a pair: same axis, another phase, a run-up.
    let mut out = vec![[0.0; 3]; len * stride];
    assert!(!x.pair_bases(&x, &steps, &mut out, (0, 2), stride));
    let other = TimeFunction::Unbalance {
        law,
        phase: 0.4,
        axis: Axis::Y,
    };
    assert!(!x.pair_bases(&other, &steps, &mut out, (0, 2), stride));
    let runup = TimeFunction::Unbalance {
        law: SpeedLaw::LinearRunUp {
            omega0: 0.0,
            omega1: 100.0,
            t1: 1.0,
        },
        phase: 0.3,
        axis: Axis::Y,
    };
    assert!(!x.pair_bases(&runup, &steps, &mut out, (0, 2), stride));
}

#[test]
fn unbalance_break_coefficients() {
    let law = SpeedLaw::LinearRunUp {
        omega0: 3.0,
        omega1: 8.0,
        t1: 1.37,
    };
    for axis in [Axis::X, Axis::Y] {
        let f = TimeFunction::Unbalance {
            law,
            phase: 0.4,
            axis,
        };
        let (rest, j) = f.jump_in(1.3, 0.1).unwrap();
        assert!((rest - 0.03).abs() < 1e-14);
        let h = 1e-4;
        let right = |k: f64| f.eval(1.37 + k * h);
        let left = |k: f64| f.eval_before(1.37 - k * h);
        // one-sided value, first and second derivatives (second order)
        let d_right = [
            right(0.0),
            (-3.0 * right(0.0) + 4.0 * right(1.0) - right(2.0)) / (2.0 * h),
            (2.0 * right(0.0) - 5.0 * right(1.0) + 4.0 * right(2.0) - right(3.0)) / (h * h),
        ];
        let d_left = [
            left(0.0),
            (3.0 * left(0.0) - 4.0 * left(1.0) + left(2.0)) / (2.0 * h),
            (2.0 * left(0.0) - 5.0 * left(1.0) + 4.0 * left(2.0) - left(3.0)) / (h * h),
        ];
        let want = [j[0], j[1], 2.0 * j[2]];
        for k in 0..3 {
            let got = d_right[k] - d_left[k];
            assert!(
                (got - want[k]).abs() <= 1e-5 * want[k].abs().max(1.0),
                "{axis:?} derivative {k}: {got} vs {}",
                want[k]
            );
        }
    }
    // a constant speed never breaks
    let c = TimeFunction::Unbalance {
        law: SpeedLaw::Constant(5.0),
        phase: 0.0,
        axis: Axis::X,
    };
    assert_eq!(c.jump_in(0.0, 10.0), None);
    assert!((c.eval(0.3) - 25.0 * (1.5f64).cos()).abs() < 1e-13);
}

#[test]
fn harmonic_basis_is_parabola() {
    let f = TimeFunction::Harmonic {
        omega: 2.0,
        phase: 0.3,
    };
    let b = f.basis(0.1, 0.2);
    assert!((b[0] - (0.5f64).sin()).abs() < 1e-15);
    assert!((b[0] + b[1] - (0.9f64).sin()).abs() < 1e-15);
}
