"""Hysteretic and device elements through the integrator (issue 13), against independent
references: a fine-step Verlet integration with the same return mapping (bilinear),
solve_ivp on the augmented ODE (Bouc-Wen, power-law damper, gap), the friction pendulum's
isolated period 2 pi sqrt(R / g); the element-level loops are tested in the core
(crates/duhamel-core/tests/hysteresis.rs)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import duhamel
from duhamel import elements as E
from duhamel import loads as L

M, KF, ZETA = 1.0, 10.0, 0.02
C = 2 * ZETA * np.sqrt(KF / M) * M
AMP, W = 3.0, 2.0
T_END = 6.0


def sdof(element: E.Element) -> duhamel.System:
    s = duhamel.System(np.array([[M]]), np.array([[KF]]), zeta=ZETA)
    s.add(element)
    s.add_load(L.Harmonic(0, amplitude=AMP, omega=W))
    return s


def ivp(rhs, y0, t) -> np.ndarray:
    sol = solve_ivp(
        rhs, (0, t[-1]), y0, method="Radau", rtol=1e-11, atol=1e-13, t_eval=t, max_step=1e-3
    )
    assert sol.success
    return sol.y


def bilinear_reference(k: float, fy: float, alpha: float, dt: float = 1e-5) -> np.ndarray:
    """Velocity Verlet with the bilinear return mapping (kinematic hardening)."""
    u_c = f_c = 0.0

    def force(u: float) -> float:
        trial = f_c + k * (u - u_c)
        return min(max(trial, alpha * k * u - (1 - alpha) * fy), alpha * k * u + (1 - alpha) * fy)

    x = v = 0.0
    a = -(C * v + KF * x + force(x)) / M
    out = [x]
    for i in range(round(T_END / dt)):
        x += dt * v + 0.5 * dt * dt * a
        f = force(x)
        u_c, f_c = x, f
        vh = v + 0.5 * dt * a
        a = (AMP * np.sin(W * (i + 1) * dt) - C * vh - KF * x - f) / M
        v = vh + 0.5 * dt * a
        out.append(x)
    return np.array(out)


@pytest.mark.parametrize("alpha", [0.0, 0.1])
def test_bilinear_sdof_against_a_fine_reference(alpha: float) -> None:
    k, fy = 100.0, 1.0
    ref = bilinear_reference(k, fy, alpha)
    errors = []
    for dt in (0.01, 0.005, 0.0025):
        sol = duhamel.solve(
            sdof(E.Bilinear(0, k=k, fy=fy, alpha=alpha)), duhamel.Semianalytic(), t_end=T_END, dt=dt
        )
        r = ref[:: round(dt / 1e-5)]
        errors.append(np.abs(sol.x[:, 0] - r).max() / np.abs(r).max())
    assert errors[-1] < 5e-5
    assert errors[2] < errors[0] / 3  # converges (about second order between yield events)


def test_bilinear_equals_the_same_law_as_a_python_callable() -> None:
    k, fy = 100.0, 1.0

    def epp(x, v, t, state):
        u_c, f_c = state
        f = min(max(f_c + k * (x[0] - u_c), -fy), fy)
        return np.array([f]), np.array([x[0], f])

    def jac(x, v, t, state):
        u_c, f_c = state
        inside = abs(f_c + k * (x[0] - u_c)) < fy
        return np.array([[k if inside else 0.0]]), np.zeros((1, 1))

    rust = duhamel.solve(
        sdof(E.Bilinear(0, k=k, fy=fy)), duhamel.Semianalytic(), t_end=3.0, dt=0.005
    )
    py = duhamel.solve(
        sdof(E.Callable([0], epp, jacobian=jac, state=[0.0, 0.0])),
        duhamel.Semianalytic(),
        t_end=3.0,
        dt=0.005,
    )
    assert np.abs(rust.x - py.x).max() <= 1e-10 * np.abs(py.x).max()


def test_bouc_wen_sdof_against_the_augmented_ode() -> None:
    k, fy, alpha, n, beta, gamma = 100.0, 1.0, 0.1, 1.0, 0.5, 0.5

    def rhs(t, y):
        x, v, z = y
        f = alpha * k * x + (1 - alpha) * fy * z
        dz = (k / fy) * v * (1 - abs(z) ** n * (beta * np.sign(v * z) + gamma))
        return [v, (AMP * np.sin(W * t) - C * v - KF * x - f) / M, dz]

    t = np.arange(0, T_END + 1e-12, 0.0025)
    ref = ivp(rhs, [0.0, 0.0, 0.0], t)[0]
    element = E.BoucWen(0, k=k, fy=fy, alpha=alpha, n=n, beta=beta, gamma=gamma)
    errors = []
    for dt in (0.01, 0.005, 0.0025):
        sol = duhamel.solve(sdof(element), duhamel.Semianalytic(), t_end=T_END, dt=dt)
        r = ref[:: round(dt / 0.0025)]
        errors.append(np.abs(sol.x[:, 0] - r).max() / np.abs(r).max())
    assert errors[-1] < 1e-4
    slope = np.log(errors[0] / errors[-1]) / np.log(4)
    assert slope > 1.7, errors


def test_power_law_damper_against_the_ode() -> None:
    c, a, v0 = 2.0, 0.35, 1e-4

    def law(v: float) -> float:
        if abs(v) >= v0:
            return c * abs(v) ** a * np.sign(v)
        # the element's odd cubic below v0: force and slope of the power law at v0
        f0, s0 = c * v0**a, c * a * v0 ** (a - 1)
        p, q = (3 * f0 - s0 * v0) / (2 * v0), (s0 * v0 - f0) / (2 * v0**3)
        return p * v + q * v**3

    def rhs(t, y):
        x, v = y
        return [v, (AMP * np.sin(W * t) - C * v - KF * x - law(v)) / M]

    t = np.arange(0, T_END + 1e-12, 0.0025)
    ref = ivp(rhs, [0.0, 0.0], t)[0]
    sol = duhamel.solve(
        sdof(E.ViscousDamper(0, c=c, exponent=a, v0=v0)),
        duhamel.Semianalytic(),
        t_end=T_END,
        dt=0.0025,
    )
    assert np.abs(sol.x[:, 0] - ref).max() <= 2e-4 * np.abs(ref).max()
    np.testing.assert_allclose(
        sol.elements[0].force[:, 0], [law(v) for v in sol.v[:, 0]], rtol=1e-9, atol=1e-12
    )


def test_gap_against_the_ode() -> None:
    gap, kg = 0.05, 1e3

    def rhs(t, y):
        x, v = y
        f = kg * (x + gap) if x < -gap else 0.0
        return [v, (AMP * np.sin(W * t) - C * v - KF * x - f) / M]

    t = np.arange(0, T_END + 1e-12, 0.001)
    ref = ivp(rhs, [0.0, 0.0], t)[0]
    assert ref.min() < -gap  # it hits the stop
    sol = duhamel.solve(
        sdof(E.Gap(0, None, gap=gap, k=kg)), duhamel.Semianalytic(), t_end=T_END, dt=0.001
    )
    assert np.abs(sol.x[:, 0] - ref).max() <= 5e-3 * np.abs(ref).max()
    assert sol.x[:, 0].min() < -gap


def test_friction_pendulum_period_is_that_of_the_pendulum() -> None:
    g, radius, weight = 9.81, 2.0, 1e5
    m = weight / g
    s = duhamel.System(m * np.eye(2), 1e-9 * np.eye(2))  # the isolator carries everything
    s.add(E.FrictionPendulum((0, 1), radius=radius, mu=0.0, weight=weight))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=12.0, dt=0.002, x0=[0.1, 0.0])
    x = sol.x[:, 0]
    crossings = sol.t[1:][np.diff(np.sign(x)) > 0]
    period = np.diff(crossings).mean()
    assert abs(period - 2 * np.pi * np.sqrt(radius / g)) < 1e-3 * period
    # with friction, launched from the centre at speed V: while it slides (v > 0, restoring
    # friction +mu W), x = mu R (cos(w t) - 1) + (V / w) sin(w t); it never exceeds mu W
    mu, speed, w = 0.06, 0.3, np.sqrt(g / radius)
    s = duhamel.System(m * np.eye(2), 1e-9 * np.eye(2))
    s.add(E.FrictionPendulum((0, 1), radius=radius, mu=mu, weight=weight))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=3.0, dt=0.001, v0=[speed, 0.0])
    el = sol.elements[0]
    friction = el.force[:, 0] - weight / radius * el.x[:, 0]
    assert np.abs(friction).max() <= mu * weight * (1 + 1e-9)
    exact_v = -mu * radius * w * np.sin(w * sol.t) + speed * np.cos(w * sol.t)
    sliding = (exact_v > 0.01) & (sol.t < np.pi / w)
    exact = mu * radius * (np.cos(w * sol.t) - 1) + speed / w * np.sin(w * sol.t)
    # the pre-sliding zone (2.5e-4 m) delays the friction by a fraction of a millimetre
    assert np.abs(sol.x[sliding, 0] - exact[sliding]).max() < 1e-3
    np.testing.assert_allclose(friction[sliding][20:], mu * weight, rtol=1e-9)


def test_direct_integrators_run_path_dependent_elements() -> None:
    """Newmark commits the hysteretic state once per step: it agrees with the semi-analytic
    run (tests/engine/test_direct_hysteretic.py measures the order)."""
    s = sdof(E.Bilinear(0, k=100.0, fy=1.0))
    a = duhamel.solve(s, duhamel.Newmark(), t_end=4.0, dt=1e-3)
    b = duhamel.solve(s, duhamel.Semianalytic(), t_end=4.0, dt=1e-3)
    assert np.abs(a.x - b.x).max() < 2e-3 * np.abs(b.x).max()


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: E.Bilinear(0, k=-1.0, fy=1.0), "`k`"),
        (lambda: E.Bilinear(0, k=1.0, fy=1.0, alpha=1.5), "`alpha`"),
        (lambda: E.BoucWen(0, k=1.0, fy=1.0, n=0.5), "`n`"),
        (lambda: E.BoucWen(0, k=1.0, fy=1.0, beta=0.5, gamma=-0.6), "`gamma`"),
        (lambda: E.FrictionPendulum((0, 1), radius=0.0), "`radius`"),
        (lambda: E.ViscousDamper(0, c=1.0, exponent=0.0), "`exponent`"),
        (lambda: E.Gap(0, gap=-1.0, k=1.0), "`gap`"),
    ],
)
def test_bad_parameters_name_themselves(make, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        make()
