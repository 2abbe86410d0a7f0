"""Spin speed of the rotor: a constant speed (rad/s) or a speed law (a run-up).

Everything speed-dependent in :mod:`duhamel.rotor` goes through this module:

* :func:`constant_speed` for what needs one constant speed (complex modes, Campbell
  diagrams, :meth:`duhamel.rotor.Unbalance.from_force`): a number, or a speed law whose speed
  does not change (``duhamel.speed.ConstantSpeed``, a ``LinearRunUp`` with ``omega0 ==
  omega1``; recognised by its ``constant_value()`` method);
* :func:`speed_or_law` for the time integration (:meth:`duhamel.rotor.Rotor.system`,
  :meth:`duhamel.rotor.Unbalance.loads`): a constant speed as a float, a varying law as the
  :class:`duhamel.speed.SpeedLaw` itself, which the engine follows in time (the gyroscopic
  ``LinearCoupling(C=G, scale=law)`` and the run-up ``duhamel.loads.Unbalance``).
"""

from __future__ import annotations

import math
from typing import Any

from duhamel._engine.validate import finite_float
from duhamel.speed import SpeedLaw

__all__ = ["constant_speed", "rpm", "speed_or_law"]


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
    ValueError
        For a speed law whose speed varies (a run-up), where one constant speed is needed
        (the message names `name`).
    TypeError
        For anything else (the message names `name`).

    Examples
    --------
    >>> from duhamel.rotor import constant_speed
    >>> from duhamel.speed import ConstantSpeed
    >>> constant_speed(100), constant_speed(ConstantSpeed(157.0))
    (100.0, 157.0)
    """
    if hasattr(speed, "constant_value") and callable(speed.constant_value):
        value = speed.constant_value()
        if value is None:
            raise ValueError(
                f"`{name}` must be a constant speed here, got the varying speed law {speed!r}: "
                "complex modes, Campbell diagrams and Unbalance.from_force are per constant "
                "speed (Rotor.system and Unbalance accept a run-up)"
            )
        return finite_float(value, name)
    return finite_float(speed, name)


def speed_or_law(speed: Any, name: str = "speed") -> float | SpeedLaw:
    """`speed` for a time integration: a float for a constant speed (a number or a constant
    law), the :class:`duhamel.speed.SpeedLaw` itself when it varies.

    Raises
    ------
    TypeError
        A varying law that is not a :class:`duhamel.speed.SpeedLaw` (the engine evaluates
        only its own laws), or anything else that is not a speed.

    Examples
    --------
    >>> from duhamel.rotor._speed import speed_or_law
    >>> from duhamel.speed import ConstantSpeed, LinearRunUp
    >>> speed_or_law(ConstantSpeed(50.0)), speed_or_law(LinearRunUp(0.0, 50.0, 2.0))
    (50.0, LinearRunUp(omega0=0.0, omega1=50.0, t1=2.0))
    """
    if hasattr(speed, "constant_value") and callable(speed.constant_value):
        value = speed.constant_value()
        if value is not None:
            return finite_float(value, name)
        if not isinstance(speed, SpeedLaw):
            raise TypeError(
                f"`{name}` must be a number (rad/s) or a duhamel.speed law (ConstantSpeed, "
                f"LinearRunUp), got {type(speed).__name__}"
            )
        return speed
    return finite_float(speed, name)
