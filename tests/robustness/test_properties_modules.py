"""Property tests (hypothesis) of the robustness contract over the public functions of
``duhamel.records``, ``duhamel.spectra``, ``duhamel.events``, ``duhamel.ensemble`` and the
results of a run (issue 38).

The contract is :mod:`test_properties`' (its ``contract``, profiles and time guard): on bad
input a call returns finite results or raises ``ValueError``/``TypeError`` naming the
parameter, a ``duhamel`` error or ``KeyboardInterrupt`` — never ``AttributeError``,
``IndexError``, ``MemoryError``, numpy's broadcast errors, a crash or a hang. Each example
takes one function of the table below with good arguments and gives one parameter a bad
value: extreme and wrong scalars (``test_properties.nasty_scalars``), wrong arrays, strings,
None, containers and callables. The memory the checks see is 256 MiB whatever the machine
has, so an allocation the input sizes is refused the same way everywhere.

``test_numeric_strings_are_refused`` gives every numeric parameter of the table the string of
its good value: the issue found some read through ``float()`` where the same function's other
parameters refuse strings.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any
from unittest import mock

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import duhamel
import duhamel._engine.memory as memory
from duhamel import events
from duhamel.ensemble import Ensemble, fractiles, ida, property_bounds, solve_bounds, solve_many
from duhamel.records import GroundMotion, GroundMotionPair, Suite, match, scale_suite
from duhamel.spectra import TargetSpectrum, asce7, asce7_multi_period, eurocode8
from tests.robustness.test_properties import (
    bad_arrays,
    budget,
    check_history,
    contract,
    nasty_scalars,
)

# -- what the functions are called on ----------------------------------------------------------

_RNG = np.random.default_rng(38)
_T = np.arange(200) * 0.01
GM = GroundMotion(_RNG.standard_normal(200) * np.exp(-_T) / 5.0, 0.01, "g", name="A")
GM2 = GroundMotion(_RNG.standard_normal(200) * np.exp(-_T) / 5.0, 0.01, "g", name="B")
PAIR = GroundMotionPair(GM, GM2)
TARGET = asce7(1.0, 0.6, 8.0)
SUITE = Suite([GM, PAIR], factors=[1.0, 2.0])


def _building() -> duhamel.System:
    s = duhamel.System(np.eye(2), [[200.0, -100.0], [-100.0, 100.0]], zeta=0.05)
    return s.add_load(GM.as_load(np.ones(2)))


def _isolated(_: Any = None) -> duhamel.System:
    s = duhamel.System(np.eye(1), 10.0 * np.eye(1), zeta=0.05)
    return s.add(duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.05, weight=9.81))


SOL = duhamel.solve(_building(), duhamel.Semianalytic(), t_end=1.0, dt=0.01, dense=True)
ENSEMBLE = Ensemble([1, 2], [{"d": 1.0}, {"d": 2.0}])


def _peak(sol: Any) -> float:
    return float(np.abs(sol.x).max())


def _with_event(make: Callable[..., Any]) -> Callable[..., Any]:
    """``make(**kw)`` built and run on the building (its events located)."""

    def run(**kw: Any) -> Any:
        ev = make(**kw)
        return duhamel.solve(_building(), duhamel.Semianalytic(), t_end=0.5, dt=0.01,
                             events=[ev])  # fmt: skip

    return run


# -- the table --------------------------------------------------------------------------------

#: Run lengths: small step counts, and what is refused before the run (never a long run).
T_ENDS = st.sampled_from([0.0, -1.0, 0.3, 1.0, math.nan, math.inf, 1e300, 10**400, "1", None])
DTS = st.sampled_from([0.1, 0.05, 0.0, -0.1, math.nan, math.inf, 5e-324, 1e-300, "0.1", None])
#: Counts whose good values keep a call short (iterations, FFT lengths, periods).
#: Event functions: not callable, or returning what is no number (a function that raises
#: is the user's exception, documented to go on as it is).
EVENT_FNS = st.one_of(
    nasty_scalars,
    st.sampled_from([print, lambda t, x, v: None, lambda t, x, v: "x", lambda t, x, v: x,
                     lambda t, x, v: np.ones((2, 2)), lambda t, x, v: 1j, lambda t, x, v: True,
                     lambda t, x, v: math.nan, lambda t, x, v: [[1.0], [2.0, 3.0]]]),
)  # fmt: skip
SMALL_COUNTS = st.sampled_from([0, 1, 2, 3, -1, 2.5, math.nan, True, "2", None, 10**400, 2**70])


@dataclass
class Target:
    """One public function: `fn(**good)` runs; `numeric` are its parameters that take
    numbers (refused as strings); `strategies` replace the generic bad values of some."""

    name: str
    fn: Callable[..., Any]
    good: dict[str, Any]
    numeric: tuple[str, ...] = ()
    strategies: dict[str, st.SearchStrategy] = field(default_factory=dict)

    def __repr__(self) -> str:
        return self.name


TARGETS = [
    # records
    Target("GroundMotion", GroundMotion, {"a": GM.a, "dt": 0.01, "units": "g"}, ("dt",)),
    Target("GroundMotion.scaled", GM.scaled, {"factor": 2.0}, ("factor",)),
    Target("GroundMotion.significant_duration", GM.significant_duration,
           {"start": 0.05, "end": 0.95}, ("start", "end")),
    Target("GroundMotion.baseline_corrected", GM.baseline_corrected,
           {"order": 3, "zero_end": True}, ("order",)),
    Target("GroundMotion.filtered", GM.filtered,
           {"low": 0.5, "high": 20.0, "order": 4, "zero_phase": True, "keep_padding": False},
           ("low", "high", "order")),
    Target("GroundMotion.resampled", GM.resampled, {"dt": 0.02, "antialias": True}, ("dt",)),
    Target("GroundMotion.padded", GM.padded, {"before": 0.1, "after": 0.2}, ("before", "after")),
    Target("GroundMotion.fourier", GM.fourier, {"smoothing": 40.0, "n_fft": 256},
           ("smoothing", "n_fft"), {"n_fft": SMALL_COUNTS}),
    Target("GroundMotion.bracketed_duration", GM.bracketed_duration,
           {"threshold": 0.01, "units": "g"}, ("threshold",)),
    Target("GroundMotion.as_load", GM.as_load, {"direction_vector": np.ones(2)}),
    Target("GroundMotionPair", GroundMotionPair, {"first": GM, "second": GM2, "name": "P"}),
    Target("GroundMotionPair.rotated", PAIR.rotated, {"angle": 30.0}, ("angle",)),
    Target("GroundMotionPair.rotd", PAIR.rotd,
           {"periods": [0.1, 0.5], "percentiles": (50, 100), "damping": 0.05, "n_angles": 8},
           ("damping", "n_angles"), {"n_angles": SMALL_COUNTS}),
    Target("GroundMotionPair.rotd100", PAIR.rotd100, {"periods": [0.1, 0.5], "damping": 0.05},
           ("damping",)),
    Target("match", match,
           {"record": GM, "target": TARGET, "periods": (0.1, 1.0), "damping": 0.05,
            "tolerance": 0.3, "aim": 1.0, "max_iterations": 2, "frequency_iterations": 1,
            "n_scales": 20, "prescale": True, "baseline_order": 5},
           ("damping", "tolerance", "aim", "max_iterations", "frequency_iterations",
            "n_scales", "baseline_order"),
           {"max_iterations": SMALL_COUNTS, "frequency_iterations": SMALL_COUNTS,
            "n_scales": SMALL_COUNTS}),
    Target("scale_suite", scale_suite,
           {"records_or_pairs": [GM, PAIR], "target": TARGET, "period_range": (0.1, 1.0),
            "method": "asce7", "minimise_misfit": False, "fraction": 0.9, "damping": 0.05,
            "n_periods": 10},
           ("fraction", "damping", "n_periods"), {"n_periods": SMALL_COUNTS}),
    Target("Suite", Suite, {"records": [GM, PAIR], "factors": [1.0, 2.0], "names": ["a", "b"]}),
    Target("Suite.cases", SUITE.cases, {"orientations": (0.0, 90.0)}),
    Target("Suite.loads", SUITE.loads,
           {"case": SUITE.cases()[1], "x": np.ones(2), "y": np.zeros(2)}),
    # spectra
    Target("TargetSpectrum", TargetSpectrum,
           {"periods": [0.1, 1.0, 2.0], "sa": [9.0, 5.0, 2.0], "damping": 0.05}, ("damping",)),
    Target("TargetSpectrum.__call__", TARGET.__call__, {"periods": [0.5, 1.0]}),
    Target("asce7", asce7, {"sds": 1.0, "sd1": 0.6, "tl": 8.0, "mce": False, "t_max": 10.0},
           ("sds", "sd1", "tl", "t_max")),
    Target("asce7_multi_period", asce7_multi_period,
           {"periods": [0.0, 1.0, 2.0], "sa_mce": [0.5, 0.6, 0.3], "mce": False}),
    Target("eurocode8", eurocode8,
           {"ag": 0.25, "ground_type": "C", "spectrum_type": 1, "importance": 1.0,
            "damping": 0.05}, ("ag", "importance", "damping")),
    # events, each run on the building
    Target("Event", _with_event(duhamel.Event),
           {"fn": lambda t, x, v: x[0] - 1e-4, "direction": 0, "terminal": False, "name": "e",
            "vectorized": False}, (), {"fn": EVENT_FNS}),
    Target("events.threshold", _with_event(events.threshold),
           {"dof": 1, "value": 1e-4, "direction": 0, "terminal": False}, ("value",)),
    Target("events.drift", _with_event(events.drift),
           {"i": 1, "j": 0, "limit": 1e-4, "height": 3.0, "direction": 1, "terminal": True},
           ("limit", "height")),
    # ensembles
    Target("solve_many", solve_many,
           {"make_system": _isolated, "params": [1, 2], "integrator": duhamel.Semianalytic(),
            "t_end": 0.3, "dt": 0.1, "reduce": _peak, "workers": 1, "chunk_size": 1,
            "on_error": "raise", "basis": None},
           ("t_end", "dt"), {"t_end": T_ENDS, "dt": DTS}),
    Target("property_bounds", property_bounds,
           {"system": _isolated(), "lambdas": {"mu": (0.8, 1.3)}}),
    Target("solve_bounds", solve_bounds,
           {"system": _isolated(), "integrator": duhamel.Semianalytic(),
            "lambdas": {"mu": (0.8, 1.3)}, "t_end": 0.3, "dt": 0.1, "reduce": _peak},
           ("t_end", "dt"), {"t_end": T_ENDS, "dt": DTS}),
    Target("fractiles", fractiles, {"values": np.array([[1.0], [2.0], [np.inf]]), "q": (16, 50)}),
    Target("ida", ida,
           {"system_factory": lambda _: _isolated(), "motions": [GM], "intensities": [0.1, 0.2],
            "measure": _peak, "integrator": duhamel.Semianalytic(), "intensity": "pga",
            "period": None, "damping": 0.05, "dt": 0.05, "workers": 1},
           ("damping", "dt"), {"dt": DTS}),
    Target("Ensemble.statistics", ENSEMBLE.statistics, {"quantities": ["d"]}),
    # results
    Target("Solution.at", SOL.at, {"t": [0.1, 0.5]}),
    Target("Solution.base_shear", SOL.base_shear, {"direction": np.ones(2), "storeys": [0, 1]}),
    Target("Solution.drifts", SOL.drifts, {"floors": [0, 1], "heights": 3.0}),
    Target("Solution.peaks", lambda **kw: SOL.peaks("x", **kw), {"dofs": [0, 1]}),
    Target("Solution.floor_spectra", SOL.floor_spectra,
           {"dofs": [1], "periods": [0.1, 0.5], "damping": 0.05}, ("damping",)),
    Target("Solution.to_dataframe", SOL.to_dataframe, {"quantity": "x", "labels": ["a", "b"]}),
]  # fmt: skip

#: Bad values for any parameter.
_ODD = ["", "x", "0.1", "asce7", None, {}, {"a": 1}, [], [None], (1, 2, 3), print,
        lambda *a: None, object(), GM, TARGET]  # fmt: skip
BAD = st.one_of(nasty_scalars, bad_arrays(2), st.sampled_from(_ODD))


def _finite(result: Any) -> None:
    """What a call returned is finite (a run's history, a record, arrays, numbers)."""
    if isinstance(result, duhamel.Solution):
        check_history(result, "Solution", complete=False)
    elif isinstance(result, GroundMotion | GroundMotionPair):
        for gm in result if isinstance(result, GroundMotionPair) else [result]:
            assert np.all(np.isfinite(gm.a)) and math.isfinite(gm.dt), gm
    elif isinstance(result, TargetSpectrum):
        assert np.all(np.isfinite(result.sa)), result
    elif isinstance(result, np.ndarray) and result.dtype.kind == "f":
        assert not np.any(np.isnan(result)), result
    elif isinstance(result, float):
        assert not math.isnan(result), result


def _call(target: Target, param: str, value: Any) -> Any:
    """`target` with `param` set to `value`, under the contract and 256 MiB of memory."""
    args = {**target.good, param: value}
    with mock.patch.object(memory, "available_memory", lambda: 2**28):
        return contract(lambda: target.fn(**args), (param, *target.good))


@st.composite
def _bad_calls(draw: Any) -> tuple[Target, str, Any]:
    target = draw(st.sampled_from(TARGETS))
    param = draw(st.sampled_from(sorted(target.good)))
    return target, param, draw(target.strategies.get(param, BAD))


@budget(16.0)
@given(case=_bad_calls())
def test_public_functions_refuse_bad_values_by_name(case):
    target, param, value = case
    result = _call(target, param, value)
    if result is not None:
        _finite(result)


@pytest.mark.parametrize("target", TARGETS, ids=repr)
def test_the_good_calls_run(target):
    # the table's good arguments run: the examples above each change one of them
    with mock.patch.object(memory, "available_memory", lambda: 2**28):
        result = target.fn(**target.good)
    _finite(result)


@pytest.mark.parametrize(
    ("target", "param"),
    [(t, p) for t in TARGETS for p in t.numeric],
    ids=lambda v: v if isinstance(v, str) else repr(v),
)
def test_numeric_strings_are_refused(target, param):
    # filtered(low='0.1'), bracketed_duration('0.05'), asce7('1.0', ...): read through
    # float() where the same functions' other parameters refuse strings
    args = {**target.good, param: str(target.good[param])}
    with pytest.raises(TypeError, match=f"`{param}`"):
        target.fn(**args)
