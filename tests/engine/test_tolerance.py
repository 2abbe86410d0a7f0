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
from tests.engine.test_accuracy_estimate import B3, _cubic_reference, _record, _sdof


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
