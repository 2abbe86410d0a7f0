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

/// A misalignment's kink inside a step of a run-up: located at the law's time of the kink
/// angle, with the jumps of the first two time derivatives of one-sided finite differences.
#[test]
fn misalignment_kink_coefficients() {
    use crate::loads::Coupling;
    let law = SpeedLaw::LinearRunUp {
        omega0: 30.0,
        omega1: 90.0,
        t1: 2.0,
    };
    let coupling = Coupling {
        radius: 0.01,
        delta: [1e-4, 2e-4],
        radial_stiffness: 1e5,
        angle: 0.05,
        bending_stiffness: 2e5,
    };
    for axis in [Axis::X, Axis::Y] {
        let f = TimeFunction::Misalignment {
            coupling,
            law,
            axis,
        };
        let dt = 0.01;
        let t = (0..100)
            .map(|i| 0.7 + i as f64 * 0.003)
            .find(|&t| f.jump_in(t, dt).is_some())
            .unwrap();
        let (rest, j) = f.jump_in(t, dt).unwrap();
        let tk = t + dt - rest;
        let angle = law.theta(tk);
        let sixth = std::f64::consts::FRAC_PI_3;
        assert!((angle / sixth - (angle / sixth).round()).abs() < 1e-13);
        let h = 1e-5;
        let right = |k: f64| f.eval(tk + k * h);
        let left = |k: f64| f.eval(tk - k * h);
        let d1 = (-3.0 * right(0.0) + 4.0 * right(1.0) - right(2.0)) / (2.0 * h)
            - (3.0 * left(0.0) - 4.0 * left(1.0) + left(2.0)) / (2.0 * h);
        let d2 = (2.0 * right(0.0) - 5.0 * right(1.0) + 4.0 * right(2.0) - right(3.0)) / (h * h)
            - (2.0 * left(0.0) - 5.0 * left(1.0) + 4.0 * left(2.0) - left(3.0)) / (h * h);
        assert_eq!(j[0], 0.0);
        let scale = j[1].abs().max(j[2].abs() * h).max(1.0);
        assert!(
            (d1 - j[1]).abs() < 1e-4 * scale,
            "{axis:?}: {d1} vs {}",
            j[1]
        );
        assert!(
            (d2 - 2.0 * j[2]).abs() < 1e-2 * (2.0 * j[2]).abs().max(j[1].abs()),
            "{axis:?}: {d2} vs {}",
            2.0 * j[2]
        );
    }
    // a step with two kinks, or none: left to the parabola
    let f = TimeFunction::Misalignment {
        coupling,
        law,
        axis: Axis::X,
    };
    assert!(f.jump_in(0.7, 0.5).is_none());
}

/// A stored run keeps its loads as this JSON: every function reads back equal, its floats
/// bit for bit (shortest round-trip digits, awkward values included).
#[test]
fn serde_round_trip_is_exact() {
    let awkward = [
        0.1 + 0.2,
        -0.0,
        5e-324,
        1.0 / 3.0,
        -2.2250738585072014e-308,
        1e300,
    ];
    let law = SpeedLaw::LinearRunUp {
        omega0: 0.1 + 0.2,
        omega1: 1.0 / 3.0,
        t1: 7.0 / 9.0,
    };
    let functions = vec![
        TimeFunction::Step { t0: 0.1 + 0.7 },
        TimeFunction::Harmonic {
            omega: 2.0 * std::f64::consts::PI / 3.0,
            phase: -0.0,
        },
        TimeFunction::Table {
            t: (0..6).map(|k| k as f64 * 0.1).collect(),
            v: awkward.to_vec(),
            hold: true,
        },
        TimeFunction::Unbalance {
            law,
            phase: 1.0 / 7.0,
            axis: Axis::Y,
        },
        TimeFunction::Misalignment {
            coupling: Coupling {
                radius: 0.0095,
                delta: [2e-4, 1.0 / 3e4],
                radial_stiffness: 40e3,
                angle: 0.1 + 0.2,
                bending_stiffness: 1.0 / 3.0,
            },
            law: SpeedLaw::Constant(1.0 / 3.0),
            axis: Axis::X,
        },
    ];
    for f in functions {
        let text = serde_json::to_string(&f).unwrap();
        let back: TimeFunction = serde_json::from_str(&text).unwrap();
        assert_eq!(format!("{back:?}"), format!("{f:?}"), "{text}");
        let bits = |x: &TimeFunction| match x {
            TimeFunction::Table { v, .. } => v.iter().map(|a| a.to_bits()).collect(),
            _ => vec![],
        };
        assert_eq!(bits(&back), bits(&f), "{text}");
    }
    // an unknown kind or field is refused, never read as something else
    assert!(serde_json::from_str::<TimeFunction>(r#"{"ramp": {"t0": 0.0}}"#).is_err());
    assert!(serde_json::from_str::<TimeFunction>(r#"{"step": {"t0": 0.0, "t1": 1.0}}"#).is_err());
}
