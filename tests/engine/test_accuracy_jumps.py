"""The error estimate of runs whose element forces jump inside a step (issue 41).

A ``MinMax`` material that fails drops its force to zero inside a step: a first-order error
that the estimate's parabola term does not see (before: at the record's step / 4, 3.7e-3
off with an estimate of 9.6e-5 saved at the record's instants, 3.6e-4 saved every step).
The estimate adds the jumps' expected error (docs/accuracy.md, "Force jumps inside a
step"). Checked against the same run at ``dt / 1024`` (the errors compared fall like ``dt``:
the reference is 64 times closer than the finest run checked), on the materials' SDOF of
issue 37 (``tests/_support/_materials_system.py``: mass 1, 1 Hz, under a 0.4 g record),
with a smooth-yielding ``Steel02`` and a ``Bilinear`` SDOF in the same family (no jump:
their estimates are the parabola term's, unchanged).
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest
from _materials_system import DT, FY, K0, SECONDS, sdof

import duhamel
from duhamel import elements as E

#: steps per record interval; every run is also made saving every step
SUBSTEPS = (1, 2, 4, 8, 16)
REFERENCE = 1024


def _bilinear() -> duhamel.System:
    s = sdof("Steel02")
    s.elements[0] = E.Bilinear(0, k=K0, fy=FY, alpha=0.05)
    return s


def _swapped(element: E.Element) -> duhamel.System:
    s = sdof("Steel02")
    s.elements[0] = element
    return s


SYSTEMS = {
    "MinMax": lambda: sdof("MinMax"),
    "Steel02": lambda: sdof("Steel02"),
    "Bilinear": _bilinear,
}
#: the estimate's family: these, a sliding friction pendulum and a gap closing on a spring
ESTIMATED = {
    **SYSTEMS,
    "FrictionPendulum": lambda: _swapped(E.FrictionPendulum(0, radius=2.0, mu=0.06, weight=9.81)),
    "Gap": lambda: _gapped(),
}


def _gapped() -> duhamel.System:
    s = sdof("Steel02")
    s.elements[0] = E.Spring(0, k=K0)
    s.add(E.Gap(0, gap=0.02, k=10 * K0))
    return s


def _run(kind: str, k: int, save_every: int, **kw) -> duhamel.Solution:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", duhamel.AccuracyWarning)
        return duhamel.solve(
            ESTIMATED[kind](),
            duhamel.Semianalytic(**kw),
            t_end=SECONDS,
            dt=DT / k,
            save_every=save_every,
        )


@functools.cache
def _reference(kind: str) -> np.ndarray:
    return _run(kind, REFERENCE, REFERENCE).x[:, 0]


@functools.cache
def _family(kind: str) -> list[tuple[int, int, float, float, float]]:
    """``(k, save_every, true error, estimate, bound)`` of the runs of `kind`."""
    ref = _reference(kind)
    out = []
    for k in SUBSTEPS:
        for save in sorted({1, k}):
            sol = _run(kind, k, save)
            x = sol.x[::k, 0] if save == 1 else sol.x[:, 0]
            error = float(np.abs(x - ref).max() / np.abs(ref).max())
            out.append((k, save, error, sol.stats.error_estimate, sol.stats.error_bound))
    return out


def test_minmax_failure_is_estimated_never_far_below_the_error():
    rows = _family("MinMax")
    for k, save, error, estimate, bound in rows:
        # the failure's error is first order: well above the parabola term's
        assert estimate >= error / 3, (k, save, error, estimate)
        assert bound >= estimate
    # first order: the estimate halves with the step (one jump; the true error, with the
    # failure's place in the step, scatters about it: 5.8e-3, 1.3e-2, 3.7e-3, 1e-3, 1.4e-3)
    by_k = {k: est for k, save, _, est, _ in rows if save == 1}
    for k in SUBSTEPS[1:]:
        assert by_k[k] / by_k[k // 2] == pytest.approx(0.5, abs=0.05), by_k


def test_the_family_is_bounded_within_a_factor_3():
    """The bound (what the warning and ``rtol`` go by): within a factor 3 of the true error
    in 26 of these 27 runs, never below a third of it."""
    rows = [row for kind in SYSTEMS for row in _family(kind)]
    ratios = [bound / error for _, _, error, _, bound in rows]
    within = sum(1 / 3 <= r <= 3 for r in ratios)
    assert within >= 0.9 * len(ratios), ratios
    assert min(ratios) >= 1 / 3, ratios


def test_the_family_is_estimated_near_the_error():
    """The propagated estimate, carried at the run's tangent with its kinks' errors where
    that stays within the bound: measured 0.30 to 3.4 times the true error, within a factor
    3 in 42 of these 45 runs (the two below are the yielding ``Bilinear`` at the record's
    step / 4, where the tangent's carriage rises above the bound and the secant's is kept,
    0.30, on a true error of 6e-5; the one above a ``MinMax`` failing at the record's step),
    never below a third of a true error above 1e-3 (docs/accuracy.md)."""
    rows = [row for kind in ESTIMATED for row in _family(kind)]
    ratios = [estimate / error for _, _, error, estimate, _ in rows]
    assert sum(1 / 3 <= r <= 3 for r in ratios) >= 0.9 * len(ratios), ratios
    assert all(r >= 1 / 3 for r, (_, _, e, _, _) in zip(ratios, rows, strict=True) if e > 1e-3)
    assert max(ratios) <= 3.5, ratios


def test_a_failing_minmax_warns_where_it_was_silent():
    # 3.7e-3 off at dt / 4 (saved at the record's step): the estimate was 9.6e-5
    with pytest.warns(duhamel.AccuracyWarning, match="error bound"):
        duhamel.solve(
            sdof("MinMax"),
            duhamel.Semianalytic(error_warning=1e-3),
            t_end=SECONDS,
            dt=DT / 4,
            save_every=4,
        )


@pytest.mark.parametrize("rtol", [1e-2, 5e-3, 2e-3])
def test_steps_chosen_by_tolerance_meet_it_through_a_failure(rtol):
    # before the jump term, rtol = 2e-3 took the record's step (estimate 1.5e-3) and was
    # 5.7e-3 off; now the steps are refined until the failure's error is estimated within
    # it (the acceptance: the true error at most 2 rtol)
    sol = _run("MinMax", 1, 1, rtol=rtol, subdivisions=6)
    ref = _reference("MinMax")
    error = float(np.abs(sol.x[:, 0] - ref).max() / np.abs(ref).max())
    assert sol.stats.error_bound <= rtol
    assert error <= 2 * rtol, (error, sol.stats.substeps)
