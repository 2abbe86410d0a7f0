"""Steps chosen by tolerance: ``Semianalytic(rtol=..., atol=...)`` (issue 41).

The run is repeated in steps of ``dt / 2**k`` until its error estimate meets the tolerance;
the true error is measured against independent references: DOP853 at ``rtol = 1e-12``
restarted at every record sample (cubic SDOF under a record) and the exact ``cn`` solution
(Duffing).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import duhamel
from duhamel.exact import duffing
from tests.engine.test_accuracy_estimate import B3, _cubic_reference, _record, _sdof, _stiff


@pytest.mark.parametrize("rtol", [1e-2, 1e-3])
def test_cubic_sdof_under_a_record_meets_rtol(rtol):
    t_rec, ag = _record()
    x_ref = _cubic_reference(t_rec, ag)

    def system():
        return _sdof(t_rec, ag, duhamel.elements.Cubic(0, k3=B3))

    plain = duhamel.solve(system(), duhamel.Semianalytic(error_warning=None), t_end=t_rec[-1],
                          dt=0.02)  # fmt: skip
    assert plain.stats.error_bound > rtol  # the step as given is not enough (by the bound)
    sol = duhamel.solve(system(), duhamel.Semianalytic(rtol=rtol), t_end=t_rec[-1], dt=0.02)
    np.testing.assert_array_equal(sol.t, plain.t)  # the saved instants are the user's
    assert sol.meta["dt"] == 0.02 and sol.stats.substeps > 1
    assert sol.stats.error_bound <= rtol
    error = np.max(np.abs(sol.x[:, 0] - x_ref)) / np.max(np.abs(x_ref))
    assert error <= rtol, (error, sol.stats.substeps)


def test_duffing_meets_rtol_and_atol():
    system = duhamel.System(np.eye(1), np.array([[1.0]]))
    system.add(duhamel.elements.Cubic(0, k3=4.0))
    integ = duhamel.Semianalytic(rtol=1e-4, atol=1e-5, subdivisions=8)
    with warnings.catch_warnings():
        warnings.simplefilter("error", duhamel.AccuracyWarning)  # the tolerance decides
        sol = duhamel.solve(system, integ, t_end=20 * np.pi, dt=2 * np.pi / 50, x0=[1.0])
    exact, _ = duffing(sol.t, 1.0, 4.0, 1.0)
    assert sol.t.size == 10 * 50 + 1
    assert np.max(np.abs(sol.x[:, 0] - exact)) <= 1e-5 + 1e-4 * np.max(np.abs(exact))


def _record_sdof(element: duhamel.elements.Element, k0: float = 0.0) -> duhamel.System:
    """The materials' SDOF of issue 37 (mass 1, Rayleigh 5 % at 1 Hz, its 0.4 g record) with
    `element` on a linear spring `k0`."""
    from _materials_system import A0, A1, K0, record

    t, a = record()
    s = duhamel.System(np.eye(1), k0 * np.eye(1), (A0 + A1 * K0) * np.eye(1))
    s.add(element)
    s.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=a))
    return s


def _reduced_frame() -> duhamel.System:
    """A 20-storey shear frame with a yielding first storey and a cubic spring, under a
    sinusoidal base motion: run on 5 modes and the static correction."""
    n = 20
    k = 400.0 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    k[-1, -1] = 400.0
    t = np.arange(0.0, 8.0 + 0.005, 0.01)
    s = duhamel.System(np.eye(n), k, zeta=0.03)
    s.add(duhamel.elements.Bilinear(0, k=300.0, fy=3.0, alpha=0.1))
    s.add(duhamel.elements.Cubic(n // 2, k3=2e3))
    s.add_load(duhamel.loads.BaseAcceleration(np.ones(n), t=t, values=np.sin(5.0 * t)))
    return s


def _family():
    from _materials_system import DT, K0, SECONDS, sdof

    t_rec, ag = _record()
    k0 = 3 * (2 * np.pi) ** 2
    yielding = duhamel.elements.Bilinear(0, k=k0, fy=0.015 * k0, alpha=0.05)
    return {
        "bilinear": (lambda: _sdof(t_rec, ag, yielding), 0.02, float(t_rec[-1]), {}, {}),
        "Steel02": (lambda: sdof("Steel02"), DT, SECONDS, {}, {}),
        "friction pendulum": (
            lambda: _record_sdof(
                duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.06, weight=9.81)
            ),
            DT, SECONDS, {}, {},
        ),
        "gap": (
            lambda: _record_sdof(duhamel.elements.Gap(0, gap=0.02, k=10 * K0), k0=K0),
            DT, SECONDS, {}, {},
        ),
        "stiff cubic": (_stiff, 0.01, 2.0, {"x0": [1.0]}, {}),
        "reduced frame": (_reduced_frame, 0.02, 8.0, {}, {"modes": 5}),
    }  # fmt: skip


@pytest.mark.parametrize(
    "name", ["bilinear", "Steel02", "friction pendulum", "gap", "stiff cubic", "reduced frame"]
)
def test_the_estimate_family_meets_rtol(name):
    """The family of docs/accuracy.md: with ``rtol = 1e-3`` every run's true error (against
    the same run, on the same basis, at the step / 128) is at most twice ``rtol`` (the issue's
    criterion; measured 0.01-0.15 ``rtol``: the refinement goes by the bound)."""
    make, dt, t_end, kw, integ = _family()[name]
    ref = duhamel.solve(
        make(), duhamel.Semianalytic(**integ), t_end=t_end, dt=dt / 128, save_every=128, **kw
    )
    rtol = 1e-3
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", duhamel.AccuracyWarning)  # the basis's, reduced
        sol = duhamel.solve(
            make(),
            duhamel.Semianalytic(rtol=rtol, subdivisions=8, **integ),
            t_end=t_end,
            dt=dt,
            **kw,
        )
    error = np.abs(sol.x - ref.x).max() / np.abs(ref.x).max()
    assert sol.stats.error_bound <= rtol
    assert error <= 2 * rtol, (error, sol.stats.substeps)


def test_a_tolerance_out_of_reach_stops_and_says_so():
    system = duhamel.System(np.eye(1), np.array([[1.0]]))
    system.add(duhamel.elements.Cubic(0, k3=4.0))
    integ = duhamel.Semianalytic(rtol=1e-9, subdivisions=2)
    with pytest.raises(duhamel.SolverError, match="`rtol`") as info:
        duhamel.solve(system, integ, t_end=20 * np.pi, dt=2 * np.pi / 50, x0=[1.0])
    assert info.value.reason == "tolerance"
    partial = info.value.partial
    assert partial.stats.substeps == 4 and partial.stats.error_estimate > 1e-9


def test_linear_runs_meet_any_tolerance_at_once():
    system = duhamel.System(np.eye(2), np.diag([1.0, 4.0]), zeta=0.05)
    sol = duhamel.solve(system, duhamel.Semianalytic(rtol=1e-9), t_end=1.0, dt=0.1, x0=[1, 0])
    assert sol.stats.substeps == 1 and sol.stats.error_estimate == 0.0


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"rtol": 0.0}, "rtol"),
        ({"rtol": 1.5}, "rtol"),
        ({"rtol": float("nan")}, "rtol"),
        ({"rtol": 1e-3, "atol": -1.0}, "atol"),
        ({"rtol": 1e-3, "scheme": "hermite"}, "rtol"),
        ({"rtol": 1e-3, "quadrature": "exact"}, "rtol"),
    ],
)
def test_bad_tolerances_are_refused(kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        duhamel.Semianalytic(**kwargs)
