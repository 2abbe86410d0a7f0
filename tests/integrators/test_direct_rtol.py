"""Steps chosen by tolerance on the direct integrators (issue 41): ``Newmark(rtol=...)`` and
the rest of the generalized-alpha family repeat the run in steps of ``dt / 2^k`` until two
successive runs differ by at most ``atol + rtol * peak``. Checked against an independent
converged reference (``Semianalytic()`` in steps of ``dt / 256``): the true error of the
returned run is at most `rtol` on linear, bilinear and cubic SDOFs under a record, for
second-order members (where it is about a third of the estimate: order 2 leaves
``1 / (2^2 - 1)`` of the difference) and a first-order one (``gamma > 1/2``, where the
estimate is the error)."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L

DT, N = 0.01, 601
T = DT * np.arange(N)
AG = 3.0 * np.convolve(np.random.default_rng(1).standard_normal(N), np.ones(5) / 5, "same")
K0 = 4 * np.pi**2


def _sdof(kind: str) -> duhamel.System:
    s = duhamel.System(np.eye(1), np.array([[K0]]), zeta=0.05)
    if kind == "bilinear":
        s.add(E.Bilinear(0, k=K0, fy=0.05 * K0, alpha=0.05))
    elif kind == "cubic":
        s.add(E.Cubic(0, k3=400.0))
    s.add_load(L.BaseAcceleration(np.ones(1), t=T, values=AG))
    return s


def _reference(kind: str) -> np.ndarray:
    return duhamel.solve(
        _sdof(kind), duhamel.Semianalytic(), t_end=T[-1], dt=DT / 256, save_every=256
    ).x[:, 0]


INTEGRATORS = {
    "newmark": lambda **k: duhamel.Newmark(**k),
    "hht": lambda **k: duhamel.HHT(-0.1, **k),
    "generalized-alpha": lambda **k: duhamel.GeneralizedAlpha(0.8, **k),
    "newmark-first-order": lambda **k: duhamel.Newmark(gamma=0.6, beta=0.3025, **k),
    "cubic-hermite": lambda **k: duhamel.CubicHermite(**k),
}


@pytest.mark.parametrize("kind", ["linear", "bilinear", "cubic"])
@pytest.mark.parametrize("name", sorted(INTEGRATORS))
def test_runs_with_rtol_meet_it(kind: str, name: str) -> None:
    ref = _reference(kind)
    for rtol in (1e-2, 1e-3):
        integrator = INTEGRATORS[name](rtol=rtol, subdivisions=7)
        sol = duhamel.solve(_sdof(kind), integrator, t_end=T[-1], dt=DT)
        assert sol.t.size == N and sol.meta["dt"] == DT  # the user's saved instants
        true = np.abs(sol.x[:, 0] - ref).max() / np.abs(ref).max()
        assert true <= rtol, (kind, name, rtol, true, sol.stats.substeps)
        assert sol.stats.error_estimate <= rtol
        assert true <= 1.05 * sol.stats.error_estimate  # the estimate bounds the error
        assert sol.stats.substeps >= 2


def test_the_second_order_difference_is_three_times_the_error() -> None:
    """Order 2: the finer run's error is a third of its difference from the coarser."""
    ref = _reference("cubic")
    sol = duhamel.solve(_sdof("cubic"), duhamel.Newmark(rtol=1e-4), t_end=T[-1], dt=DT)
    true = np.abs(sol.x[:, 0] - ref).max() / np.abs(ref).max()
    assert true == pytest.approx(sol.stats.error_estimate / 3, rel=0.1)


def test_a_run_that_cannot_meet_rtol_stops_and_keeps_its_finest_run() -> None:
    integrator = duhamel.Newmark(gamma=0.6, beta=0.3025, rtol=1e-5, subdivisions=3)
    with pytest.raises(duhamel.SolverError, match="cannot meet `rtol`=1e-05") as info:
        duhamel.solve(_sdof("linear"), integrator, t_end=T[-1], dt=DT)
    assert info.value.reason == "tolerance"
    assert info.value.partial.t.size == N


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"rtol": 0.0}, "`rtol` must be a number in \\(0, 1\\)"),
        ({"rtol": 1.5}, "`rtol` must be a number in \\(0, 1\\)"),
        ({"rtol": float("nan")}, "`rtol`"),
        ({"atol": -1.0}, "`atol` must be >= 0"),
        ({"subdivisions": 0}, "`subdivisions`"),
    ],
)
def test_bad_tolerance_options_are_refused(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        duhamel.Newmark(**kwargs)


def test_rtol_refuses_located_runs() -> None:
    with pytest.raises(ValueError, match="`rtol` of a direct integrator"):
        duhamel.solve(_sdof("linear"), duhamel.Newmark(rtol=1e-3), t_end=1.0, dt=DT, dense=True)
