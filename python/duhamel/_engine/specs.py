"""The one place where the model's own descriptions become the core's typed values.

Loads, mass and speed laws describe themselves with small private tuples
(``_time()``, ``_spec()``); the functions here turn them into the classes of
:mod:`duhamel._core` (``TimeFunction``, ``SpeedLaw``, ``MassLaw``, ``Element``), which the
core checks once, when they are made. Imports only numpy and the core, so every model module
may use it.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from duhamel import _core

__all__ = [
    "ScaledSpec",
    "elements",
    "load",
    "mass",
    "mass_law",
    "speed_law",
    "time_function",
]


class ScaledSpec(NamedTuple):
    """A coupling scaled by a speed law: ``law(t) (K x + C x')`` (modal or physical)."""

    k: Any
    c: Any
    law: Any  # _core.SpeedLaw


def speed_law(spec: tuple[str, tuple]) -> Any:
    """``("constant", (omega,))`` or ``("runup", (omega0, omega1, t1))`` as a core law."""
    kind, params = spec
    if kind == "constant":
        return _core.SpeedLaw.constant(float(params[0]))
    if kind == "runup":
        return _core.SpeedLaw.run_up(*(float(p) for p in params))
    raise ValueError(f"unknown speed law {kind!r}")


def time_function(kind: str, params: tuple) -> Any:
    """A load's ``_time()`` (or an unbalance axis term) as a core time function."""
    if kind == "step":
        return _core.TimeFunction.step(float(params[0]))
    if kind == "harmonic":
        return _core.TimeFunction.harmonic(float(params[0]), float(params[1]))
    if kind == "table":
        t, values, hold = params
        return _core.TimeFunction.table(
            np.ascontiguousarray(t, dtype=np.float64),
            np.ascontiguousarray(values, dtype=np.float64),
            bool(hold),
        )
    if kind == "unbalance":
        law, phase, axis = params
        return _core.TimeFunction.unbalance(speed_law(law), float(phase), str(axis))
    if kind == "misalignment":
        law, radius, parallel, angular, axis = params
        return _core.TimeFunction.misalignment(
            speed_law(law), float(radius), tuple(parallel), tuple(angular), str(axis)
        )
    raise ValueError(f"unknown load kind {kind!r}")


def load(pattern: NDArray[np.float64], kind: str, params: tuple) -> Any:
    """One load term for the core, ``pattern * s(t)``, `s` of a load's ``_time()``."""
    return _core.Load(np.ascontiguousarray(pattern, dtype=np.float64), time_function(kind, params))


def mass(spec: tuple[str, tuple], form: str, scale_stiffness: bool, treatment: str) -> Any:
    """A mass law as it enters a run (``_core.Mass``)."""
    return _core.Mass(mass_law(spec), form, bool(scale_stiffness), treatment)


def mass_law(spec: tuple[str, tuple]) -> Any:
    """A mass law's ``_spec()`` as a core mass law."""
    kind, params = spec
    if kind == "exponential":
        return _core.MassLaw.exponential(float(params[0]), float(params[1]))
    if kind == "harmonic":
        return _core.MassLaw.harmonic(float(params[0]), float(params[1]))
    if kind == "table":
        return _core.MassLaw.table(
            np.ascontiguousarray(params[0], dtype=np.float64),
            np.ascontiguousarray(params[1], dtype=np.float64),
        )
    raise ValueError(f"unknown mass law {kind!r}")


def elements(items: Any) -> list[Any]:
    """The core elements a run evaluates: a model's elements (``duhamel.elements`` classes,
    defined in the core), the remainder of one whose linear part went into the background
    (its ``core`` element), couplings left out (a ``LinearCoupling`` is a coupling of the
    background or a pseudo-force of its own, never an element)."""
    out = []
    for item in items:
        core = getattr(item, "core", item)
        if isinstance(core, _core.Element):
            out.append(core)
    return out
