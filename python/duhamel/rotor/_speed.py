"""Spin speed of the rotor: a constant speed (rad/s) now, speed laws (run-up) through one seam.

Everything speed-dependent in :mod:`duhamel.rotor` goes through :func:`constant_speed`: a
number is a constant speed; a speed-law object (``duhamel.speed.ConstantSpeed`` /
``LinearRunUp``, recognised by its ``constant_value()`` method, which returns the speed or
None when it varies) is accepted when it is constant. A varying law raises
``NotImplementedError`` until the rotor is wired to the engine's run-up support: the
gyroscopic ``LinearCoupling(C=G, scale=law)`` in :meth:`duhamel.rotor.Rotor.system` and the
run-up unbalance load in :meth:`duhamel.rotor.Unbalance.loads` (docs/rotor.md, "Run-up").
"""

from __future__ import annotations

import math
from typing import Any

from duhamel._validate import finite_float

__all__ = ["constant_speed", "rpm"]


def rpm(value: float) -> float:
    """Convert revolutions per minute to rad/s.

    Examples
    --------
    >>> from duhamel.rotor import rpm
    >>> round(rpm(1500), 4)
    157.0796
    """
    return finite_float(value, "value") * math.pi / 30.0


def constant_speed(speed: Any, name: str = "speed") -> float:
    """The constant spin speed (rad/s) of `speed`: a number, or a constant speed law.

    Raises
    ------
    NotImplementedError
        For a speed law whose speed varies (a run-up): not wired yet.
    TypeError
        For anything else (the message names `name`).

    Examples
    --------
    >>> from duhamel.rotor import constant_speed
    >>> constant_speed(100)
    100.0
    """
    if hasattr(speed, "constant_value") and callable(speed.constant_value):
        value = speed.constant_value()
        if value is None:
            raise NotImplementedError(
                f"the rotor cannot run the varying speed law {speed!r} yet: the run-up needs "
                "the gyroscopic coupling scaled by omega(t) and the run-up unbalance load, "
                "which duhamel.rotor does not wire in yet (docs/rotor.md, 'Run-up'). Use a "
                "constant speed (a number in rad/s)"
            )
        return finite_float(value, name)
    return finite_float(speed, name)
