"""The one place where the model's own descriptions become the core's typed values.

Loads, elements, mass and speed laws describe themselves with small private tuples
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
    "element",
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


def element(spec: tuple) -> Any:
    """An element's ``_spec()`` as a core element."""
    kind, *args = spec
    if kind == "polynomial":
        dof, coefficients = args
        return _core.Element.polynomial(int(dof), np.ascontiguousarray(coefficients, dtype=float))
    if kind == "spring":
        return _core.Element.spring(*args)
    if kind == "damper":
        return _core.Element.damper(*args)
    if kind == "contact":
        return _core.Element.contact(*args)
    if kind == "speed_table":
        *table, law = args
        return _core.Element.speed_table(*table, speed_law(law))
    if kind == "journal":
        dof_x, dof_y, *geometry, law = args
        return _core.Element.journal_bearing((dof_x, dof_y), *geometry, speed_law(law))
    if kind == "crack":
        *crack, law = args
        return _core.Element.breathing_crack(*crack, speed_law(law))
    if kind == "bilinear":
        return _core.Element.bilinear(*args)
    if kind == "device":
        return _core.Element.device(*args)
    if kind == "bouc_wen":
        i, j, k, fy, alpha, *shape = args
        return _core.Element.bouc_wen(i, j, k, fy, alpha, tuple(shape))
    if kind == "friction_pendulum":
        dof_x, dof_y, radius, mu, weight, yd, *rest = args
        slow, rate = (rest[0], rest[1]) if len(rest) == 2 else (None, 0.0)
        velocity = None if slow is None or not rate else (float(slow), float(rate))
        y = None if dof_y is None else int(dof_y)
        return _core.Element.friction_pendulum(int(dof_x), y, radius, mu, weight, yd, velocity)
    if kind == "lead_rubber":
        dof_x, dof_y, strength, shape = args
        y = None if dof_y is None else int(dof_y)
        return _core.Element.lead_rubber(
            int(dof_x), y, tuple(map(float, strength)), tuple(map(float, shape))
        )
    if kind == "viscous_damper":
        return _core.Element.viscous_damper(*args)
    if kind == "friction_pendulum_axial":
        dofs, radius, mu, weight, yd, kv, velocity, pressure = args
        return _core.Element.friction_pendulum_axial(
            list(dofs), radius, mu, (weight, yd), kv, velocity, pressure
        )
    if kind == "maxwell_damper":
        i, j, c, exponent, v0, kb = args
        return _core.Element.maxwell_damper(i, j, (c, exponent, v0), kb)
    if kind == "gap":
        return _core.Element.gap(*args)
    if kind == "shifted":
        inner, k0, c0 = args
        return _core.Element.shifted(
            element(inner),
            np.ascontiguousarray(k0, float).ravel(),
            np.ascontiguousarray(c0, float).ravel(),
        )
    if kind == "callable":
        dofs, fn, jacobian, *state = args
        return _core.Element.callable(list(dofs), fn, jacobian, state[0] if state else None)
    raise ValueError(f"unknown element kind {kind!r}")


def elements(items: Any) -> list[Any]:
    """The core elements of a model's elements, couplings left out (a ``LinearCoupling`` is
    a coupling of the background or a pseudo-force of its own, never an element)."""
    return [element(spec) for spec in (e._spec() for e in items) if spec[0] != "coupling"]
