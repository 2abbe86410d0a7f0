"""duhamel.design.asce7 (issue 39): every function against the code's equations written out
here independently (to 1e-12), the isolators' effective properties from their own loops
against the closed forms of their idealised loops (to the effect of the yield displacement,
stated), the ELF fixed point against its equations, and the checks' verdicts."""

from __future__ import annotations

import math

import numpy as np
import pytest

import duhamel
from duhamel.design import Check, asce7, effective_properties
from duhamel.elements import Bilinear, FrictionPendulum, LeadRubberBearing

G = 9.80665


def table_17_5_1(beta: float) -> float:
    """Table 17.5-1, the interpolation written segment by segment."""
    if beta <= 0.02:
        return 0.8
    if beta <= 0.05:
        return 0.8 + (beta - 0.02) * (1.0 - 0.8) / 0.03
    if beta <= 0.10:
        return 1.0 + (beta - 0.05) * (1.2 - 1.0) / 0.05
    if beta <= 0.20:
        return 1.2 + (beta - 0.10) * (1.5 - 1.2) / 0.10
    if beta <= 0.30:
        return 1.5 + (beta - 0.20) * (1.7 - 1.5) / 0.10
    if beta <= 0.40:
        return 1.7 + (beta - 0.30) * (1.9 - 1.7) / 0.10
    if beta <= 0.50:
        return 1.9 + (beta - 0.40) * (2.0 - 1.9) / 0.10
    return 2.0


def test_damping_coefficient_is_table_17_5_1() -> None:
    for beta, b in [(0.0, 0.8), (0.02, 0.8), (0.05, 1.0), (0.1, 1.2), (0.2, 1.5), (0.3, 1.7),
                    (0.4, 1.9), (0.5, 2.0), (0.9, 2.0)]:  # fmt: skip
        assert asce7.damping_coefficient(beta) == pytest.approx(b, rel=1e-15)
    betas = np.linspace(0.0, 0.7, 701)
    ours = asce7.damping_coefficient(betas)
    np.testing.assert_allclose(ours, [table_17_5_1(b) for b in betas], rtol=1e-12, atol=0)
    for bad in (-0.01, math.nan, math.inf):
        with pytest.raises(ValueError, match="`beta`"):
            asce7.damping_coefficient(bad)


def test_displacement_period_and_shears_are_the_equations() -> None:
    rng = np.random.default_rng(39)
    for _ in range(50):
        sm1, t, beta = rng.uniform(0.2, 1.5), rng.uniform(1.0, 5.0), rng.uniform(0.0, 0.6)
        d = G * sm1 * t / (4 * math.pi**2 * table_17_5_1(beta))  # Eq. 17.5-1
        assert asce7.isolation_displacement(sm1, t, beta) == pytest.approx(d, rel=1e-12)
        w, k = rng.uniform(1e6, 1e8), rng.uniform(1e5, 1e8)
        assert asce7.effective_period(w, k) == pytest.approx(
            2 * math.pi * math.sqrt(w / (k * G)), rel=1e-12
        )  # Eq. 17.5-2
        assert asce7.base_shear(k, d) == pytest.approx(k * d, rel=1e-12)  # Eq. 17.5-5
        ws = rng.uniform(0.5, 1.0) * w
        for abrupt, c in ((False, 2.5), (True, 3.5)):  # Eq. 17.5-7 and its exception
            v = k * d * (ws / w) ** (1 - c * beta)
            assert asce7.unreduced_shear(k * d, w, ws, beta, abrupt=abrupt) == pytest.approx(
                v, rel=1e-12
            )
        ri = rng.uniform(1.0, 2.0)
        assert asce7.structure_shear(v, ri) == pytest.approx(v / ri, rel=1e-12)  # Eq. 17.5-6
    # the g the user gives enters D linearly
    assert asce7.isolation_displacement(1.0, 2.0, 0.05, g=9.81) == pytest.approx(
        9.81 * 2.0 / (4 * math.pi**2), rel=1e-12
    )
    with pytest.raises(ValueError, match="`r_i`"):
        asce7.structure_shear(1e5, 2.5)
    with pytest.raises(ValueError, match="`weight_above`"):
        asce7.unreduced_shear(1e5, 1e6, 2e6, 0.1)
    with pytest.raises(ValueError, match="`sm1`"):
        asce7.isolation_displacement(-0.5, 2.0, 0.1)


def test_total_displacement_and_torsion() -> None:
    # Eq. 17.5-3 with its lower limit 1.15 D_M
    dm, y, e, b, d, pt = 0.4, 15.0, 2.0, 30.0, 20.0, 1.1
    expected = dm * (1 + (y / pt**2) * 12 * e / (b**2 + d**2))
    got = asce7.total_displacement(dm, y=y, eccentricity=e, b=b, d=d, p_t=pt)
    assert got == pytest.approx(expected, rel=1e-12)
    assert asce7.total_displacement(dm) == pytest.approx(1.15 * dm, rel=1e-15)
    small = asce7.total_displacement(dm, y=1.0, eccentricity=0.5, b=b, d=d, p_t=pt)
    assert small == pytest.approx(1.15 * dm, rel=1e-15)  # the factor below 1.15
    with pytest.raises(ValueError, match="`b`"):
        asce7.total_displacement(dm, y=y, eccentricity=e)
    # P_T of a regular grid: sqrt(mean(x^2 + y^2)) / sqrt((b^2 + d^2) / 12)
    xs, ys = np.meshgrid(np.linspace(-12, 12, 5), np.linspace(-8, 8, 3))
    pt = asce7.torsion_period_ratio(xs.ravel(), ys.ravel(), 30.0, 20.0)
    ref = math.sqrt(np.mean(xs**2 + ys**2)) / math.sqrt((30.0**2 + 20.0**2) / 12)
    assert pt == pytest.approx(ref, rel=1e-12)


def test_vertical_distribution_is_17_5_5() -> None:
    w = np.array([2e6, 1.8e6, 1.5e6])
    h = np.array([4.0, 7.5, 11.0])
    vs, vb, vst, ri, beta, tfb = 5e5, 1.5e6, 1.1e6, 2.0, 0.18, 0.6
    k = 14 * beta * tfb  # Eq. 17.5-11
    cv = w * h**k / np.sum(w * h**k)  # Eq. 17.5-10
    f = asce7.vertical_distribution(vs, vb, vst, ri, w, h, beta, tfb)
    assert f[0] == pytest.approx((vb - vst) / ri, rel=1e-12)  # Eq. 17.5-8
    np.testing.assert_allclose(f[1:], cv * vs, rtol=1e-12)  # Eq. 17.5-9
    assert f[1:].sum() == pytest.approx(vs, rel=1e-12)


def test_suite_values_and_drift_checks() -> None:
    rng = np.random.default_rng(1)
    seven = rng.uniform(0.001, 0.02, size=(7, 4))
    np.testing.assert_allclose(asce7.suite_value(seven), seven.mean(axis=0), rtol=1e-15)
    np.testing.assert_array_equal(asce7.suite_value(seven[:6]), seven[:6].max(axis=0))
    # Table 12.12-1 and chapter 16's two times it, on the storey with the largest mean
    assert [asce7.allowable_drift(rc) for rc in ("I", "II", "III", "IV")] == [
        0.020, 0.020, 0.015, 0.010
    ]  # fmt: skip
    assert asce7.allowable_drift("II", "low-rise") == 0.025
    assert asce7.allowable_drift("IV", "masonry") == 0.007
    c = asce7.drift_acceptance(seven, risk_category="III")
    k = int(np.argmax(seven.mean(axis=0)))
    assert c.value == pytest.approx(seven.mean(axis=0)[k], rel=1e-15)
    assert c.limit == pytest.approx(2 * 0.015, rel=1e-15) and c.kind == "maximum"
    assert c.clause == "ASCE 7-22 16.4.1.2" and f"storey {k + 1}" in c.quantity
    assert c.passes == (c.value <= c.limit)
    iso = asce7.isolated_drift_check(seven)
    assert iso.limit == 0.020 and iso.value == pytest.approx(c.value, rel=1e-15)
    iso6 = asce7.isolated_drift_check(seven[:6])  # fewer than 7: the largest
    assert iso6.value == pytest.approx(seven[:6].max(axis=0).max(), rel=1e-15)
    assert not asce7.isolated_drift_check([[0.03]] * 7).passes
    with pytest.raises(ValueError, match="`risk_category`"):
        asce7.allowable_drift("V")
    with pytest.raises(ValueError, match="`drift_ratios`"):
        asce7.isolated_drift_check([[np.nan]])


def test_lower_limits_of_17_6_4() -> None:
    from types import SimpleNamespace

    elf = SimpleNamespace(d_tm=0.5, v_b=2.0e6, v_s=6.0e5, r_i=1.6)
    values = {"isolator_displacement": 0.41, "base_shear_below": 1.7e6, "base_shear_above": 8e5}
    d, vb, vs = asce7.lower_limit_checks(values, elf)
    assert (d.value, d.limit, d.passes) == (0.41, pytest.approx(0.8 * 0.5), True)
    assert (vb.value, vb.limit, vb.passes) == (1.7e6, pytest.approx(0.9 * 2.0e6), False)
    # above the base level: the response-history shear reduced by R_I against 60 % V_s
    assert vs.value == pytest.approx(8e5 / 1.6, rel=1e-15)
    assert vs.limit == pytest.approx(0.6 * 6e5, rel=1e-15) and vs.passes
    irregular = asce7.lower_limit_checks(values, elf, regular=False)[2]
    assert irregular.limit == pytest.approx(0.8 * 6e5, rel=1e-15)
    assert [c.kind for c in (d, vb, vs)] == ["minimum"] * 3


def test_check_verdicts() -> None:
    assert Check("c", "q", 1.0, 1.0, "maximum").passes
    assert Check("c", "q", 1.0 + 1e-13, 1.0, "maximum").passes  # round-off
    assert not Check("c", "q", 1.0 + 1e-9, 1.0, "maximum").passes
    assert Check("c", "q", 1.0, 1.0, "minimum").verdict == "pass"
    assert Check("c", "q", 0.9, 1.0, "minimum").verdict == "fail"
    with pytest.raises(ValueError, match="`kind`"):
        Check("c", "q", 1.0, 1.0, "at most")


# ----------------------------------------------------------------- effective properties


@pytest.mark.parametrize("d", [0.02, 0.1, 0.4])
def test_friction_pendulum_effective_properties(d: float) -> None:
    """The loop of a friction pendulum gives k_eff = W/R + mu W/D and, against the idealised
    (rigid-plastic) 2 mu / (pi (mu + D/R)), beta_eff smaller by exactly the factor
    (1 - u_y/D) of its pre-sliding displacement u_y: the loop is bilinear with the
    characteristic strength mu W and the yield displacement u_y, E = 4 mu W (D - u_y)."""
    w, r, mu, uy = 2e6, 2.5, 0.06, 2.5e-4
    p = effective_properties(
        FrictionPendulum(3, radius=r, mu=mu, weight=w, yield_displacement=uy), d
    )
    assert p.displacement == pytest.approx(d, rel=1e-6)
    d = p.displacement  # the loop's amplitude (the drive reaches the one asked for)
    k = w / r + mu * w / d
    assert p.stiffness == pytest.approx(k, rel=1e-6)
    assert p.energy == pytest.approx(4 * mu * w * (d - uy), rel=1e-6)
    ideal = 2 * mu / (math.pi * (mu + d / r))
    assert abs(p.damping / ideal - 1) <= uy / d * (1 + 1e-3)  # the stated bound
    assert p.damping == pytest.approx(ideal * (1 - uy / d), rel=1e-6)
    # the bidirectional bearing driven along x measures the same
    two = effective_properties(
        FrictionPendulum((0, 1), radius=r, mu=mu, weight=w, yield_displacement=uy), d
    )
    assert two.stiffness == pytest.approx(p.stiffness, rel=1e-6)
    assert two.damping == pytest.approx(p.damping, rel=1e-6)


def bilinear_loop(k: float, fy: float, alpha: float, d: float) -> tuple[float, float]:
    """k_eff and beta_eff of the bilinear loop: Q_d = (1 - alpha) fy, k_d = alpha k,
    D_y = fy / k, E = 4 Q_d (D - D_y)."""
    qd, kd, dy = (1 - alpha) * fy, alpha * k, fy / k
    keff = qd / d + kd
    return keff, 4 * qd * (d - dy) / (2 * math.pi * keff * d * d)


def test_bilinear_effective_properties_are_the_bilinear_formulas() -> None:
    for d in (0.03, 0.1, 0.3):
        p = effective_properties(Bilinear(0, k=2e7, fy=2e5, alpha=0.1), d)
        keff, beta = bilinear_loop(2e7, 2e5, 0.1, p.displacement)
        assert p.stiffness == pytest.approx(keff, rel=1e-6)
        assert p.damping == pytest.approx(beta, rel=1e-6)


def test_lead_rubber_bearing_tends_to_the_bilinear_formulas() -> None:
    """The smooth (eta = 1) Bouc-Wen loop of a lead-rubber bearing against the bilinear
    formulas with the same k, fy, alpha: k_eff agrees (the loop's tips are on the
    post-yield lines), beta_eff differs by about 0.27 D_y / D (measured: the rounded corners
    of the loop), so first order in D_y / D."""
    k, fy, alpha = 2e7, 2e5, 0.1
    dy = fy / k
    errors = []
    for ratio in (10, 20, 40, 80):
        d = ratio * dy
        p = effective_properties(LeadRubberBearing(0, k=k, fy=fy, alpha=alpha), d, points=1000)
        keff, beta = bilinear_loop(k, fy, alpha, d)
        assert p.stiffness == pytest.approx(keff, rel=1e-4)
        errors.append(abs(p.damping / beta - 1))
        assert errors[-1] <= 0.35 * dy / d  # the stated bound
    slope = np.polyfit(np.log([10, 20, 40, 80]), np.log(errors), 1)[0]
    assert slope == pytest.approx(-1.0, abs=0.1)


@pytest.mark.parametrize("dofs", [(0, None, 1), (0, 1, 2)], ids=["2-D", "3-D"])
@pytest.mark.parametrize("d", [0.05, 0.2])
def test_pendulum_with_its_vertical_dof_measured_under_its_axial_force(dofs, d) -> None:
    """A friction pendulum with its vertical dof (as ``from_opensees`` imports
    ``singleFPBearing``) is driven along x with its axial force held at
    ``initial_axial_force`` P, as a prototype test holds it: on the sliding branch its
    normal force on the dish is ``N = P + V u / R`` (OpenSees'), so ``V = P (u/R + mu) /
    (1 - (u/R)(u/R + mu))`` at the peak, the closed form of ``k_eff`` to 1e-9. Before, it
    was refused (the ASCE 7 study of an imported isolated frame stopped there)."""
    p, r, mu = 6.867e5, 2.0, 0.06
    fp = FrictionPendulum(
        dofs, radius=r, mu=mu, weight=p, yield_displacement=1e-3, vertical_stiffness=1e11,
        initial_axial_force=p,
    )  # fmt: skip
    got = effective_properties(fp, d)
    x = d / r
    assert got.stiffness == pytest.approx(p * (x + mu) / (1.0 - x * (x + mu)) / d, rel=1e-9)
    flat = effective_properties(FrictionPendulum(0, radius=r, mu=mu, weight=p), d)
    assert got.stiffness / flat.stiffness - 1.0 == pytest.approx(x * (x + mu), rel=0.05)
    without = FrictionPendulum(dofs, radius=r, mu=mu, weight=p, vertical_stiffness=1e11)
    with pytest.raises(TypeError, match="`initial_axial_force`"):
        effective_properties(without, d)


def test_effective_properties_refuse_bad_input() -> None:
    fp = FrictionPendulum(0, radius=2.0, mu=0.05, weight=1e6)
    with pytest.raises(ValueError, match="`displacement`"):
        effective_properties(fp, 0.0)
    with pytest.raises(ValueError, match="`points`"):
        effective_properties(fp, 0.1, points=7)
    with pytest.raises(TypeError, match="`element`"):
        effective_properties(duhamel.elements.Cubic(0, k3=1.0), 0.1)


# ------------------------------------------------------------------------- the ELF fixed point


def test_isolated_elf_is_the_fixed_point_of_its_equations() -> None:
    """Given the loops isolated_elf reports at its D_M, every value is the code's equation
    of them (1e-12), D_M is the fixed point of Eq. 17.5-1 (1e-12), and for friction
    pendulums the loop values are the bilinear closed forms (the loop's accuracy)."""
    w, ws = 1.2e7, 0.9e7
    fps = [FrictionPendulum(0, radius=3.0, mu=0.06, weight=w / 4) for _ in range(4)]
    elf = asce7.isolated_elf(fps, sm1=1.1, weight=w, weight_above=ws, r_i=1.8, points=500)
    b = elf.bounds["nominal"]
    d = b.amplitude  # the loops' amplitude: D_M to the loops' accuracy
    assert b.residual < 1e-6 and b.d_m == pytest.approx(d, rel=1e-6)
    assert all(p.displacement == pytest.approx(d, rel=1e-6) for p in b.isolators)
    k = sum(p.stiffness for p in b.isolators)
    beta = sum(p.energy for p in b.isolators) / (2 * math.pi * k * d**2)
    t = 2 * math.pi * math.sqrt(w / (k * G))
    assert b.k_m == pytest.approx(k, rel=1e-12)
    assert b.beta_m == pytest.approx(beta, rel=1e-12)
    assert b.t_m == pytest.approx(t, rel=1e-12)
    assert b.b_m == pytest.approx(table_17_5_1(beta), rel=1e-12)
    assert b.d_m == pytest.approx(G * 1.1 * t / (4 * math.pi**2 * table_17_5_1(beta)), rel=1e-12)
    assert b.d_tm == pytest.approx(1.15 * b.d_m, rel=1e-12)
    assert b.v_b == pytest.approx(k * b.d_m, rel=1e-12)
    assert b.v_st == pytest.approx(k * b.d_m * (ws / w) ** (1 - 2.5 * beta), rel=1e-12)
    assert b.v_s >= b.v_st / 1.8 * (1 - 1e-15)
    # the closed forms of the pendulum's loop: k = W/R + mu W/D, E = 4 mu W (D - u_y)
    a = b.isolators[0].displacement  # the loop's own amplitude
    assert k == pytest.approx(w / 3.0 + 0.06 * w / a, rel=1e-6)
    assert beta == pytest.approx(4 * 0.06 * w * (a - 2.5e-4) / (2 * math.pi * k * d**2), rel=1e-6)


def test_isolated_elf_bounds_on_a_building() -> None:
    """With lambdas the lower-bound model is softer (larger D_M, longer T_M), the upper one
    stiffer; the governing values are the largest; the scaling range spans them."""
    m = np.diag([3e5, 2e5, 2e5])
    k = 4e8 * np.array([[1.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    s = duhamel.System(m, k, zeta=0.03)
    s.add(FrictionPendulum(0, radius=2.5, mu=0.05, weight=7e5 * G))
    building = duhamel.design.Building(s, [0, 1, 2], [3.5, 3.5])
    assert building.weight == pytest.approx(7e5 * G, rel=1e-15)
    assert building.weight_above == pytest.approx(4e5 * G, rel=1e-15)
    elf = asce7.isolated_elf(building, sm1=0.9, lambdas={"mu": (0.8, 1.3)}, points=500)
    lo, nom, up = (elf.bounds[n] for n in ("lower", "nominal", "upper"))
    assert lo.d_m > nom.d_m > up.d_m and lo.t_m > nom.t_m > up.t_m
    assert lo.beta_m < nom.beta_m < up.beta_m
    assert elf.d_m == lo.d_m and elf.v_b == max(b.v_b for b in (lo, nom, up))
    assert elf.period_range() == pytest.approx((0.75 * up.t_m, 1.25 * lo.t_m), rel=1e-15)
    # section 17.5.4.3 item 3: V_s at least V_st of the activation force (1.5 nominal, or
    # the upper bound's), here the friction mu W at zero displacement
    act = max(1.5 * nom.activation, up.activation)
    assert nom.activation == pytest.approx(0.05 * 7e5 * G, rel=1e-5)
    for b in (lo, nom, up):
        v_act = act * (4.0 / 7.0) ** (1 - 2.5 * b.beta_m)
        assert b.v_s == pytest.approx(max(b.v_st / 2.0, v_act), rel=1e-12)
    with pytest.raises(ValueError, match="`weight`"):
        asce7.isolated_elf([FrictionPendulum(0, radius=2.0, mu=0.05, weight=1e6)], sm1=0.9)
