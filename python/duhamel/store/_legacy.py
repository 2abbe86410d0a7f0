"""A previous release's store: its loads, speed laws and mass law as that release wrote them,
``(kind, params)`` tuples, read back as the core values its run built from them.

This release writes each of them as the core value's data (``_to_value()``, serde: the
same classes a run builds); these readers are kept so that a store written before still
resumes, bit for bit (``tests/store/test_store_legacy_loads.py``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from duhamel import _core
from duhamel.store._codec import StoreError

__all__ = ["mass_law", "speed_law", "time_function"]


def _array(values: Any) -> Any:
    return np.ascontiguousarray(values, dtype=np.float64)


def speed_law(spec: Any) -> _core.SpeedLaw:
    """``("constant", (omega,))`` or ``("runup", (omega0, omega1, t1))``."""
    kind, params = spec
    if kind == "constant":
        return _core.SpeedLaw.constant(float(params[0]))
    if kind == "runup":
        return _core.SpeedLaw.run_up(*(float(p) for p in params))
    raise StoreError(f"the store holds an unknown speed law {kind!r}")


def time_function(kind: str, params: Any) -> _core.TimeFunction:
    """A load's ``(kind, params)``: a step, harmonic, table, unbalance or misalignment."""
    if kind == "step":
        return _core.TimeFunction.step(float(params[0]))
    if kind == "harmonic":
        return _core.TimeFunction.harmonic(float(params[0]), float(params[1]))
    if kind == "table":
        t, values, hold = params
        return _core.TimeFunction.table(_array(t), _array(values), bool(hold))
    if kind == "unbalance":
        law, phase, axis = params
        return _core.TimeFunction.unbalance(speed_law(law), float(phase), str(axis))
    if kind == "misalignment":
        law, radius, parallel, angular, axis = params
        return _core.TimeFunction.misalignment(
            speed_law(law), float(radius), tuple(parallel), tuple(angular), str(axis)
        )
    raise StoreError(f"the store holds a load of unknown kind {kind!r}")


def mass_law(spec: Any) -> _core.MassLaw:
    """``("exponential", (rate, scale))``, ``("harmonic", (amplitude, frequency))`` or
    ``("table", (t, mu))``."""
    kind, params = spec
    if kind == "exponential":
        return _core.MassLaw.exponential(float(params[0]), float(params[1]))
    if kind == "harmonic":
        return _core.MassLaw.harmonic(float(params[0]), float(params[1]))
    if kind == "table":
        return _core.MassLaw.table(_array(params[0]), _array(params[1]))
    raise StoreError(f"the store holds an unknown mass law {kind!r}")
