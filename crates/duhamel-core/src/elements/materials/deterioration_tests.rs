//! Properties of the deteriorating and pinching materials (their agreement with OpenSees is
//! tested from Python, tests/elements/test_materials_imk.py and
//! tests/elements/test_materials_pinching.py):
//! backbones against their closed forms, the strength reaching zero past the ultimate
//! deformation, the energy-based deterioration against its formula, and each tangent
//! against central differences of the force at fixed committed variables.

use super::hysteretic::{HystState, Hysteretic, HystereticParams};
use super::imk::ModImkPeakOriented;
use super::imk_bilin::{BilinState, ImkBilin, ImkBilinParams};
use super::imk_params::{ImkState, ModImkParams};
use super::pinching4_def::{Pinching4, Pinching4Damage, Pinching4Params};
use super::Material;
use crate::error::CoreError;

fn imk(n_factor: f64) -> ModImkParams {
    ModImkParams {
        k0: 1.0e4,
        as_plus: 0.03,
        as_neg: 0.02,
        my_plus: 100.0,
        my_neg: -80.0,
        lambda_s: 2.0,
        lambda_c: 2.0,
        lambda_a: 2.0,
        lambda_k: 2.0,
        c_s: 1.0,
        c_c: 1.0,
        c_a: 1.0,
        c_k: 1.0,
        theta_p_plus: 0.03,
        theta_p_neg: 0.025,
        theta_pc_plus: 0.1,
        theta_pc_neg: 0.12,
        res_plus: 0.4,
        res_neg: 0.3,
        theta_u_plus: 0.2,
        theta_u_neg: 0.22,
        d_plus: 1.0,
        d_neg: 0.8,
        n_factor,
    }
}

fn bilin() -> ImkBilinParams {
    ImkBilinParams {
        ke: 1.0e4,
        theta_p_plus: 0.03,
        theta_pc_plus: 0.1,
        theta_u_plus: 0.2,
        my_plus: 100.0,
        mmax_my_plus: 1.1,
        res_plus: 0.4,
        theta_p_neg: 0.025,
        theta_pc_neg: 0.12,
        theta_u_neg: 0.22,
        my_neg: 80.0,
        mmax_my_neg: 1.15,
        res_neg: 0.3,
        lambda_s: 2.0,
        lambda_c: 2.0,
        lambda_k: 2.0,
        c_s: 1.0,
        c_c: 1.0,
        c_k: 1.0,
        d_plus: 1.0,
        d_neg: 0.8,
    }
}

fn hysteretic(third: bool) -> HystereticParams {
    let (pos, neg) = if third {
        (
            vec![(100.0, 0.01), (130.0, 0.04), (60.0, 0.1)],
            vec![(-90.0, -0.01), (-120.0, -0.05), (-50.0, -0.12)],
        )
    } else {
        (
            vec![(100.0, 0.01), (130.0, 0.04)],
            vec![(-90.0, -0.01), (-120.0, -0.05)],
        )
    };
    HystereticParams {
        pos,
        neg,
        pinch_x: 0.6,
        pinch_y: 0.3,
        damage1: 0.01,
        damage2: 0.05,
        beta: 0.3,
    }
}

fn pinching4(damage: Pinching4Damage) -> Pinching4Params {
    Pinching4Params {
        pos: [(100.0, 0.005), (150.0, 0.015), (170.0, 0.03), (40.0, 0.06)],
        neg: [
            (-90.0, -0.005),
            (-140.0, -0.015),
            (-160.0, -0.03),
            (-35.0, -0.06),
        ],
        pinch_pos: [0.5, 0.25, 0.05],
        pinch_neg: [0.5, 0.25, 0.05],
        gk: [1.0, 0.2, 0.3, 0.2, 0.9],
        gd: [0.5, 0.5, 2.0, 2.0, 0.5],
        gf: [1.0, 0.0, 1.0, 1.0, 0.9],
        ge: 10.0,
        damage,
    }
}

/// Points from 0 through the corners `pts`, `n` per leg.
fn ramp(pts: &[f64], n: usize) -> Vec<f64> {
    let mut out = vec![0.0];
    let mut a = 0.0;
    for &b in pts {
        for k in 1..=n {
            out.push(a + (b - a) * k as f64 / n as f64);
        }
        a = b;
    }
    out
}

/// Cycles of growing amplitude `amps` (two per amplitude).
fn cycles(amps: &[f64], n: usize) -> Vec<f64> {
    let pts: Vec<f64> = amps.iter().flat_map(|&a| [a, -a, a, -a]).collect();
    ramp(&pts, n)
}

/// Drives `m` through `u` with a commit after each point: `(F, kt, state after)`.
fn drive(m: &dyn Material, u: &[f64]) -> Vec<(f64, f64, Vec<f64>)> {
    let mut c = vec![0.0; m.state_len()];
    m.initial_state(&mut c);
    let mut t = c.clone();
    u.iter()
        .map(|&x| {
            let (f, k) = m.response(x, 0.0, &c, &mut t).unwrap();
            c.copy_from_slice(&t);
            (f, k, c.clone())
        })
        .collect()
}

/// The tangent at every point of `u` against central differences of the force at the same
/// committed variables, where the one-sided differences agree (no kink within `h`).
fn check_tangents(m: &dyn Material, u: &[f64], h: f64, scale: f64) -> usize {
    let mut c = vec![0.0; m.state_len()];
    m.initial_state(&mut c);
    let mut t = c.clone();
    let mut checked = 0;
    for &x in u {
        let f_at = |y: f64| m.response(y, 0.0, &c, &mut t.clone()).unwrap().0;
        let (f0, fp, fm) = (f_at(x), f_at(x + h), f_at(x - h));
        let (right, left) = ((fp - f0) / h, (f0 - fm) / h);
        let (f, k) = m.response(x, 0.0, &c, &mut t).unwrap();
        assert_eq!(f, f0);
        if (right - left).abs() <= 1e-6 * scale {
            let central = 0.5 * (right + left);
            assert!(
                (k - central).abs() <= 1e-6 * scale,
                "tangent {k} against the difference {central} at u = {x}"
            );
            checked += 1;
        }
        c.copy_from_slice(&t);
    }
    checked
}

#[test]
fn mod_imk_backbone_is_its_closed_form() {
    let p = imk(0.0);
    let m = ModImkPeakOriented::new(p).unwrap();
    let u = ramp(&[1.1 * p.theta_u_plus], 4000);
    let dy = p.my_plus / p.k0;
    let ucap = dy + p.theta_p_plus;
    let fpeak = p.my_plus + p.as_plus * p.k0 * p.theta_p_plus;
    let kpc = -fpeak / p.theta_pc_plus;
    let fres = p.res_plus * p.my_plus;
    let ures = ucap + (fres - fpeak) / kpc;
    for (x, (f, _, _)) in u.iter().zip(drive(&m, &u)) {
        let exact = if *x <= dy {
            p.k0 * x
        } else if *x <= ucap {
            p.my_plus + p.as_plus * p.k0 * (x - dy)
        } else if *x <= ures {
            fpeak + kpc * (x - ucap)
        } else if *x < p.theta_u_plus {
            fres + 1e-7 * x // OpenSees' residual branch: Res + 1e-7 d
        } else {
            0.0
        };
        assert!(
            (f - exact).abs() <= 1e-9 * fpeak,
            "u = {x}: {f} against {exact}"
        );
    }
}

#[test]
fn mod_imk_amplified_spring_in_series_gives_the_member_slopes() {
    // Ibarra & Krawinkler (2005), appendix B: the spring K0 (1+n) in series with an elastic
    // element K0 (1+n)/n has the member's hardening as K0 and post-capping slopes
    let n = 10.0;
    let p = imk(n);
    let m = ModImkPeakOriented::new(p).unwrap();
    let u = ramp(&[0.15], 3000);
    let out = drive(&m, &u);
    let k_el = p.k0 * (1.0 + n) / n;
    let series = |k: f64| 1.0 / (1.0 / k + 1.0 / k_el);
    let hardening = out.iter().find(|o| o.0 > 1.01 * p.my_plus).unwrap();
    let member_h = series(hardening.1);
    assert!(
        (member_h - p.as_plus * p.k0).abs() <= 1e-9 * p.k0,
        "{member_h}"
    );
    let capping = out.iter().find(|o| o.1 < 0.0).unwrap();
    let s = ImkState::load(&capping.2);
    let member_c = series(capping.1);
    assert!((member_c + s.f_peak_pos / p.theta_pc_plus).abs() <= 1e-9 * p.k0);
}

#[test]
fn imk_strength_reaches_zero_past_the_ultimate_deformation() {
    let materials: [Box<dyn Material>; 2] = [
        Box::new(ModImkPeakOriented::new(imk(0.0)).unwrap()),
        Box::new(ImkBilin::new(bilin()).unwrap()),
    ];
    let u = cycles(&[0.01, 0.03, 0.06, 0.1, 0.15, 0.21, 0.3], 50);
    for m in &materials {
        let out = drive(m.as_ref(), &u);
        // past the ultimate deformation in both directions (IMKBilin loses each side's
        // strength at its own ultimate deformation; ModIMKPeakOriented both at the first)
        let past = u.iter().position(|&x| x <= -0.22).unwrap();
        let peak = out.iter().map(|o| o.0.abs()).fold(0.0, f64::max);
        assert!(peak > 100.0);
        for (k, o) in out.iter().enumerate().skip(past + 1) {
            assert!(o.0.abs() <= 1e-9 * peak, "{m:?}: F = {} at {k}", o.0);
        }
    }
}

#[test]
fn imk_bilin_energy_exhaustion_removes_the_strength() {
    // a small reference energy is used up by cycles well within the ultimate deformation
    // (ModIMKPeakOriented keeps its residual strength: its energy checks scale the yield
    // strength and the unloading stiffness, whose recoverable energy grows as it degrades)
    let m = ImkBilin::new(ImkBilinParams {
        lambda_s: 0.2,
        ..bilin()
    })
    .unwrap();
    let u = cycles(&[0.03; 12], 40);
    let out = drive(&m, &u);
    let failed = out
        .iter()
        .position(|o| BilinState::load(&o.2).failure_state == 5.0);
    let failed = failed.expect("the strength is used up");
    assert!(failed < u.len() / 2);
    assert!(out[failed..].iter().all(|o| o.0 == 0.0));
}

#[test]
fn mod_imk_deterioration_follows_the_energy_formula() {
    // load past yield, then unload until the force changes sign: the negative side's yield
    // strength becomes My_neg (1 - beta_s D_neg), beta_s = (E_c / (E_ts - E_tot))^c_s, with
    // the energy integrated here from the returned forces
    let p = ModImkParams {
        c_s: 1.3,
        lambda_s: 0.05,
        ..imk(0.0)
    };
    let m = ModImkPeakOriented::new(p).unwrap();
    let u = ramp(&[0.02, -0.005], 400);
    let out = drive(&m, &u);
    let k = (1..u.len()).find(|&k| out[k].0 < 0.0).unwrap();
    let energy: f64 = (1..=k)
        .map(|j| 0.5 * (out[j].0 + out[j - 1].0) * (u[j] - u[j - 1]))
        .sum();
    let e_ts = p.lambda_s * p.my_plus;
    let beta = (energy / (e_ts - energy)).powf(p.c_s);
    let s = ImkState::load(&out[k].2);
    let expected = p.my_neg * (1.0 - beta * p.d_neg);
    assert!(
        (s.fy_neg - expected).abs() <= 1e-12 * p.my_plus,
        "{} {expected}",
        s.fy_neg
    );
    assert!(beta > 0.05, "the check must see a deterioration: {beta}");
    assert_eq!(ImkState::load(&out[k - 1].2).fy_neg, p.my_neg);
}

#[test]
fn imk_bilin_deterioration_follows_the_energy_formula() {
    // a positive excursion past yield, unloading and reloading negative: at the new
    // excursion the negative yield strength is scaled by 1 - beta_s D with
    // beta_s = (E_i / (E_ref - E_acc))^c_s
    let b = ImkBilinParams {
        c_s: 1.3,
        lambda_s: 0.05,
        ..bilin()
    };
    let m = ImkBilin::new(b).unwrap();
    let u = ramp(&[0.02, -0.005], 400);
    let out = drive(&m, &u);
    let k = (1..u.len()).find(|&k| out[k].0 < 0.0).unwrap();
    let energy: f64 = (1..k)
        .map(|j| 0.5 * (out[j].0 + out[j - 1].0) * (u[j] - u[j - 1]))
        .sum();
    let beta = (energy / (b.lambda_s * b.my_plus - energy)).powf(b.c_s);
    let s = BilinState::load(&out[k].2);
    let expected = -b.my_neg * (1.0 - beta * b.d_neg);
    assert!(
        (s.neg_fy - expected).abs() <= 1e-12 * b.my_plus,
        "{} {expected}",
        s.neg_fy
    );
    assert!(beta > 0.05, "{beta}");
}

#[test]
fn tangents_are_the_derivatives_of_the_forces() {
    let mut rng = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let walk: Vec<f64> = (0..600)
        .scan(0.0, |x: &mut f64, _| {
            *x = (*x + 0.012 * next()).clamp(-0.15, 0.15);
            Some(*x)
        })
        .collect();
    let materials: Vec<(Box<dyn Material>, f64)> = vec![
        (Box::new(ModImkPeakOriented::new(imk(0.0)).unwrap()), 1e4),
        (Box::new(ModImkPeakOriented::new(imk(5.0)).unwrap()), 6e4),
        (Box::new(ImkBilin::new(bilin()).unwrap()), 1e4),
        (Box::new(Hysteretic::new(hysteretic(true)).unwrap()), 1e4),
        (Box::new(Hysteretic::new(hysteretic(false)).unwrap()), 1e4),
        (
            Box::new(Pinching4::new(pinching4(Pinching4Damage::Energy)).unwrap()),
            2e4,
        ),
        (
            Box::new(Pinching4::new(pinching4(Pinching4Damage::Cycle)).unwrap()),
            2e4,
        ),
    ];
    for (m, scale) in &materials {
        let u = ramp(&walk, 4);
        let checked = check_tangents(m.as_ref(), &u, 1e-7, *scale);
        assert!(checked > u.len() * 3 / 4, "{m:?}: {checked} of {}", u.len());
    }
}

#[test]
fn hysteretic_envelope_and_damage_follow_their_formulas() {
    let p = hysteretic(true);
    let m = Hysteretic::new(p.clone()).unwrap();
    // the trilinear envelope
    let u = ramp(&[0.15], 300);
    for (x, (f, _, _)) in u.iter().zip(drive(&m, &u)) {
        let exact = if *x <= 0.01 {
            1e4 * x
        } else if *x <= 0.04 {
            100.0 + 1000.0 * (x - 0.01)
        } else if *x <= 0.1 {
            130.0 - 70.0 / 0.06 * (x - 0.04)
        } else {
            60.0
        };
        assert!((f - exact).abs() <= 1e-10 * 130.0, "{x}: {f} {exact}");
    }
    // the two-point envelope is the three-point one through the midpoint
    let two = Hysteretic::new(hysteretic(false)).unwrap();
    let mid = Hysteretic::new(HystereticParams {
        pos: vec![(100.0, 0.01), (115.0, 0.025), (130.0, 0.04)],
        neg: vec![(-90.0, -0.01), (-105.0, -0.03), (-120.0, -0.05)],
        ..hysteretic(false)
    })
    .unwrap();
    let u = cycles(&[0.005, 0.02, 0.05, 0.08], 30);
    for (a, b) in drive(&two, &u).iter().zip(drive(&mid, &u)) {
        assert!((a.0 - b.0).abs() <= 1e-10 * 130.0);
    }
    // damage: reloading towards positive after a negative excursion past yield, the peak to
    // aim at grows to rot_max (1 + damage1 (rot_min - e1n)/e1n + damage2 E / E_a), E the
    // dissipated energy (committed energy less the elastic energy of unloading)
    let u = ramp(&[0.03, -0.02, 0.03], 100);
    let out = drive(&m, &u);
    let back = 201;
    assert!(u[back] > u[back - 1] && u[back - 1] < u[back - 2]);
    let c = HystState::load(&out[back - 1].2);
    let t = HystState::load(&out[back].2);
    let e_a = 0.5 * (0.01 * 100.0 + 0.03 * 230.0 + 0.06 * 190.0)
        + 0.5 * (0.01 * 90.0 + 0.04 * 210.0 + 0.07 * 170.0);
    let kn = (c.rot_min / -0.01).powf(p.beta);
    let kn = if kn < 1.0 { 1.0 } else { 1.0 / kn };
    let eun = 1e4 * 0.9;
    let energy = c.energy_d - 0.5 * c.stress * c.stress / (eun * kn);
    let mut damfc = 0.0;
    if c.rot_min < -0.01 {
        damfc = p.damage2 * energy / e_a + p.damage1 * (c.rot_min + 0.01) / -0.01;
    }
    assert!(c.stress < 0.0 && (c.rot_max - 0.03).abs() < 1e-15 && (c.rot_min + 0.02).abs() < 1e-15);
    assert!(
        (t.rot_max - 0.03 * (1.0 + damfc)).abs() <= 1e-14,
        "{}",
        t.rot_max
    );
    assert!(damfc > 0.0);
}

#[test]
fn pinching4_envelope_is_its_closed_form() {
    let m = Pinching4::new(pinching4(Pinching4Damage::Energy)).unwrap();
    let u = ramp(&[0.06], 600);
    let pts = [
        (0.0, 0.0),
        (0.005, 100.0),
        (0.015, 150.0),
        (0.03, 170.0),
        (0.06, 40.0),
    ];
    for (x, (f, _, _)) in u.iter().zip(drive(&m, &u)) {
        let i = (1..5).find(|&i| *x <= pts[i].0).unwrap();
        let (a, b) = (pts[i - 1], pts[i]);
        let exact = a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0);
        assert!((f - exact).abs() <= 1e-10 * 170.0, "{x}: {f} {exact}");
    }
}

#[test]
fn parameters_out_of_their_domain_are_named() {
    let name = |e: CoreError| match e {
        CoreError::InvalidInput { name, .. } => name,
        other => panic!("{other}"),
    };
    let e = ModImkPeakOriented::new(ModImkParams {
        my_neg: 80.0,
        ..imk(0.0)
    });
    assert_eq!(name(e.unwrap_err()), "My_neg");
    let e = ModImkPeakOriented::new(ModImkParams {
        theta_pc_plus: 0.0,
        ..imk(0.0)
    });
    assert_eq!(name(e.unwrap_err()), "theta_pc_plus");
    let e = ImkBilin::new(ImkBilinParams {
        ke: f64::NAN,
        ..bilin()
    });
    assert_eq!(name(e.unwrap_err()), "Ke");
    let e = ImkBilin::new(ImkBilinParams {
        d_neg: 1.5,
        ..bilin()
    });
    assert_eq!(name(e.unwrap_err()), "D_neg");
    let mut h = hysteretic(true);
    h.pos[2].1 = 0.03;
    assert_eq!(name(Hysteretic::new(h).unwrap_err()), "e3p");
    let mut h = hysteretic(true);
    h.pinch_y = 1.5;
    assert_eq!(name(Hysteretic::new(h).unwrap_err()), "pinch_y");
    let mut q = pinching4(Pinching4Damage::Energy);
    q.neg[1].1 = -0.001;
    assert_eq!(name(Pinching4::new(q).unwrap_err()), "eNd2");
    let mut q = pinching4(Pinching4Damage::Energy);
    q.gd[4] = -1.0;
    assert_eq!(name(Pinching4::new(q).unwrap_err()), "gDLim");
}
