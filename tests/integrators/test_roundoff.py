"""Round-off over many short steps (the increment form of the exact step).

The semi-analytic steps add each step's increment to the state last (``A - 1`` on the
transition's diagonal, formed without cancellation): written as ``A x`` the state rounds at
its own scale on every step and, because the rounded transition's determinant is an ulp off
one, the energy of an undamped oscillator drifts steadily (7e-11 of the Duffing energy over
256,000 steps, a floor of 2.7e-9 in the fourth-order step's error over 100 periods). The
references are exact: the Duffing oscillator's ``cn`` solution and the conserved energies.
"""

from __future__ import annotations

import numpy as np

import duhamel
from duhamel.exact import duffing

PERIODS = 100
N_OUT = 2000
T_END = PERIODS * 2 * np.pi


def _duffing(steps: int) -> duhamel.Solution:
    """``x'' + x + 4 x^3 = 0`` from ``x0 = 1`` over 100 periods of the linear background,
    ``steps`` fourth-order steps per output interval (2,000 intervals)."""
    system = duhamel.System(np.eye(1), np.array([[1.0]]))
    system.add(duhamel.elements.Cubic(0, k3=4.0))
    integrator = duhamel.Semianalytic(scheme="hermite", error_warning=None)
    dt = T_END / (N_OUT * steps)
    return duhamel.solve(system, integrator, t_end=T_END, dt=dt, x0=[1.0], save_every=steps)


def test_fourth_order_slope_continues_below_the_old_round_off_floor():
    """Slopes 4 down to 1e-10 (the ``A x`` form stopped at 2.7e-9: 1.9e-8, 3.7e-9, 2.7e-9)."""
    t = np.linspace(0.0, T_END, N_OUT + 1)
    exact = duffing(t, 1.0, 4.0, 1.0)[0]
    steps = [64, 128, 256]
    errors = [float(np.max(np.abs(_duffing(s).x[:, 0] - exact))) for s in steps]
    slopes = -np.diff(np.log(errors)) / np.diff(np.log(steps))
    print(f"\nerrors {errors}, slopes {slopes}")
    assert np.all((slopes > 3.8) & (slopes < 4.3)), slopes
    assert errors[-1] < 1e-10


def test_duffing_energy_does_not_drift():
    """Energy ``v^2/2 + x^2/2 + x^4`` conserved to 5e-12 over 512,000 steps (measured 7.8e-13;
    the ``A x`` form drifted by 3.6e-11)."""
    sol = _duffing(256)
    x, v = sol.x[:, 0], sol.v[:, 0]
    energy = 0.5 * v**2 + 0.5 * x**2 + x**4
    drift = float(np.max(np.abs(energy - 1.5)))
    print(f"\nenergy drift {drift:.2e}")
    assert drift < 5e-12


def test_linear_oscillator_energy_does_not_drift():
    """The linear route: an undamped mode over a million short steps keeps its energy to
    round-off of one step, not of a million (measured 4.8e-14 and 5.3e-14 against the ``A x``
    form's 7.9e-12 and 7.9e-12)."""
    system = duhamel.System(np.eye(1), np.array([[1.0]]))
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=1000.0, dt=1e-3, x0=[1.0],
                        save_every=1000)  # fmt: skip
    x, v = sol.x[:, 0], sol.v[:, 0]
    drift = float(np.max(np.abs(0.5 * (x**2 + v**2) - 0.5)))
    exact = float(np.max(np.abs(x - np.cos(sol.t))))
    print(f"\nlinear: energy drift {drift:.2e}, displacement error {exact:.2e}")
    assert drift < 1e-12
    assert exact < 1e-12
