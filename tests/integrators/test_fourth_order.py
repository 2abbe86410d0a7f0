"""The fourth-order semi-analytic step (``Semianalytic(scheme="hermite")``, issue 41).

Orders are measured as slopes against independent references: the Duffing oscillator
against its exact ``cn`` solution (:func:`duhamel.exact.duffing`), a damped cubic SDOF under
a ground-acceleration record against ``solve_ivp`` (DOP853 at ``rtol = 1e-12``, restarted at
every sample of the record, where the record has its kinks), a two-storey frame with a
cubic spring and a velocity-dependent damper against the same, and the stability of the
step on the linear test equation against its amplification matrix (numpy eigenvalues).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import duhamel
from duhamel.exact import duffing

HERMITE = duhamel.Semianalytic(scheme="hermite")


def _slopes(dts: list[float], errors: list[float]) -> np.ndarray:
    return np.diff(np.log(errors)) / np.diff(np.log(dts))


def _duffing_error(integrator: object, n: int, periods: int = 10) -> float:
    """Max displacement error of ``x'' + x + 4 x^3 = 0`` from ``x0 = 1`` at ``dt = 2 pi / n``."""
    system = duhamel.System(np.eye(1), np.array([[1.0]]))
    system.add(duhamel.elements.Cubic(0, k3=4.0))
    dt = 2 * np.pi / n
    sol = duhamel.solve(system, integrator, t_end=periods * 2 * np.pi, dt=dt, x0=[1.0])
    exact, _ = duffing(sol.t, 1.0, 4.0, 1.0)
    return float(np.max(np.abs(sol.x[:, 0] - exact)))


def test_duffing_converges_at_fourth_order():
    ns = [100, 200, 400, 800]
    errors = [_duffing_error(HERMITE, n) for n in ns]
    slopes = _slopes([2 * np.pi / n for n in ns], errors)
    assert np.all(slopes[1:] > 3.85), (errors, slopes)
    assert errors[-1] < 1e-7
    # the second-order default at the same steps, for scale
    assert _duffing_error(duhamel.Semianalytic(), 800) > 100 * errors[-1]


def test_scheme_hermite_is_solved_alike_on_scalars_and_by_the_modal_newton():
    a = _duffing_error(HERMITE, 200, periods=2)
    b = _duffing_error(duhamel.Semianalytic(scheme="hermite", solver="modal-newton"), 200, 2)
    assert a == pytest.approx(b, rel=1e-6)


def _record(dt_rec: float = 0.02, duration: float = 4.0) -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(0.0, duration + dt_rec / 2, dt_rec)
    rng = np.random.default_rng(41)
    ag = 3.0 * np.sin(7.0 * t) * np.exp(-0.3 * t) + rng.normal(0.0, 0.5, t.size)
    ag[0] = 0.0
    return t, ag


def _cubic_sdof(t_rec: np.ndarray, ag: np.ndarray) -> duhamel.System:
    omega, zeta = 2 * np.pi, 0.05
    system = duhamel.System(np.eye(1), np.array([[omega**2]]), zeta=zeta)
    system.add(duhamel.elements.Cubic(0, k3=400.0))
    system.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t_rec, ag))
    return system


def _cubic_sdof_reference(t_rec: np.ndarray, ag: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """DOP853 at rtol 1e-12, interval by interval of the record (its kinks)."""
    omega, zeta, b = 2 * np.pi, 0.05, 400.0
    y = np.zeros(2)
    xs = [0.0]
    for k in range(t_rec.size - 1):
        t0, t1 = t_rec[k], t_rec[k + 1]
        a0, a1 = ag[k], ag[k + 1]

        def rhs(t, z, t0=t0, t1=t1, a0=a0, a1=a1):
            a = a0 + (a1 - a0) * (t - t0) / (t1 - t0)
            x, v = z
            return [v, -a - 2 * zeta * omega * v - omega**2 * x - b * x**3]

        y = solve_ivp(rhs, (t0, t1), y, method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
        xs.append(y[0])
    return t_rec, np.array(xs)


def test_cubic_sdof_under_a_record_converges_at_fourth_order():
    t_rec, ag = _record()
    _, x_ref = _cubic_sdof_reference(t_rec, ag)
    peak = np.max(np.abs(x_ref))
    dts, errors = [], []
    for k in (1, 2, 4, 8):
        dt = 0.02 / k
        sol = duhamel.solve(_cubic_sdof(t_rec, ag), HERMITE, t_end=t_rec[-1], dt=dt)
        x = sol.x[::k, 0]
        assert x.size == x_ref.size
        dts.append(dt)
        errors.append(float(np.max(np.abs(x - x_ref)) / peak))
    slopes = _slopes(dts, errors)
    assert np.all(slopes > 3.7), (errors, slopes)
    assert errors[-1] < 1e-7


def test_velocity_dependent_element_on_two_modes_converges_at_fourth_order():
    """Two modes (the modal Newton on 2 n unknowns), a cubic spring at the first storey and
    a nonlinear (cubic) viscous damper at the roof: the Hermite velocity's odd error integrates
    out."""
    m = np.diag([1.0, 1.0])
    k = np.array([[800.0, -400.0], [-400.0, 400.0]])
    t_end = 3.0

    def make() -> duhamel.System:
        system = duhamel.System(m, k, rayleigh=(0.1, 0.001))
        system.add(duhamel.elements.Cubic(0, k3=2e4))
        system.add(duhamel.elements.ViscousDamper(1, c=0.05, exponent=3.0))
        system.add_load(duhamel.loads.Harmonic(1, 300.0, 9.0))
        return system

    C = 0.1 * m + 0.001 * k  # rayleigh=(a0, a1): C = a0 M + a1 K

    def rhs(t, z):
        x, v = z[:2], z[2:]
        f = np.array([0.0, 300.0 * np.sin(9.0 * t)])
        r = np.array([2e4 * x[0] ** 3, 0.0])
        r[1] += 0.05 * v[1] ** 3
        return np.concatenate([v, f - C @ v - k @ x - r])

    dts, errors = [], []
    # from omega_c dt = 0.6 at the stiffest state down: the asymptotic range
    for n in (400, 800, 1600, 3200):
        dt = t_end / n
        sol = duhamel.solve(make(), HERMITE, t_end=t_end, dt=dt)
        ref = solve_ivp(
            rhs, (0, t_end), np.zeros(4), method="DOP853", rtol=1e-12, atol=1e-14, t_eval=sol.t
        )
        dts.append(dt)
        errors.append(float(np.max(np.abs(sol.x - ref.y[:2].T)) / np.max(np.abs(ref.y[:2]))))
    slopes = _slopes(dts, errors)
    assert np.all(slopes > 3.8), (errors, slopes)


@pytest.mark.parametrize("alpha", [0.5, 4.0, 100.0, 1e4])
def test_hermite_step_is_stable_whatever_share_of_the_stiffness_is_a_pseudo_force(alpha):
    """``x'' + 2 zeta x' + x = -alpha x``: the whole element a pseudo-force on the background
    oscillator; the spectral radius of one step (measured from two runs of one step) stays
    at most 1 up to ``omega_c dt`` = 1.9 (the stiffness watch holds every scheme's step below
    ``omega_c dt = 2``; beyond it the run stops, so larger steps are not reachable)."""
    worst = 0.0
    for wdt in np.geomspace(0.05, 1.9, 25) / np.sqrt(1 + alpha):
        amp = np.zeros((2, 2))
        for col, (x0, v0) in enumerate(((1.0, 0.0), (0.0, 1.0))):
            system = duhamel.System(np.eye(1), np.array([[1.0]]), zeta=0.02)
            system.add(duhamel.elements.Spring(0, k=alpha))
            integ = duhamel.Semianalytic(
                scheme="hermite",
                linear_parts="pseudo-force",
                subdivisions=0,
                growth_limit=None,
            )
            sol = duhamel.solve(system, integ, t_end=wdt, dt=wdt, x0=[x0], v0=[v0])
            amp[:, col] = [sol.x[-1, 0], sol.v[-1, 0]]
        worst = max(worst, float(np.max(np.abs(np.linalg.eigvals(amp)))))
    assert worst <= 1.0 + 1e-9


def test_hermite_takes_only_the_parabolic_quadrature():
    assert duhamel.Semianalytic(scheme="hermite").quadrature == "parabolic"
    assert duhamel.Semianalytic().quadrature == "trapezoid"
    with pytest.raises(ValueError, match="`quadrature`"):
        duhamel.Semianalytic(scheme="hermite", quadrature="exact")
