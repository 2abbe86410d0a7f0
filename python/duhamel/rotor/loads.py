"""Rotor loads: unbalance, gravity and a sudden force, expanded into :mod:`duhamel.loads`.

A rotor load is not itself a :class:`duhamel.loads.Load` (an unbalance lives on a node's two
translations, a weight depends on the mass matrix): :meth:`RotorLoad.loads` expands it on a
:class:`~duhamel.rotor.Rotor`, and :meth:`duhamel.rotor.Rotor.system` does that for the
loads passed to it.
"""

from __future__ import annotations

from dataclasses import KW_ONLY, dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel import _core
from duhamel._engine.protocols import Model
from duhamel._engine.spellings import old_spellings
from duhamel._engine.validate import as_float_array, finite_float, positive_float
from duhamel.constants import STANDARD_GRAVITY
from duhamel.loads import Load, Step
from duhamel.loads import Unbalance as UnbalanceLoad
from duhamel.rotor._protocols import RotorModel
from duhamel.rotor._speed import constant_speed, speed_or_law
from duhamel.speed import SpeedLaw

__all__ = ["Gravity", "RotorLoad", "SuddenForce", "Unbalance", "VectorStep"]


class RotorLoad:
    """Base class of the rotor loads."""

    def loads(self, rotor: RotorModel, speed: Any = None) -> list[Load]:  # pragma: no cover
        """The :mod:`duhamel.loads` this load stands for on `rotor` at `speed`."""
        raise NotImplementedError


@old_spellings(positional=("vector", "t0"))
@dataclass(frozen=True, eq=False)
class VectorStep(Load):
    """A fixed load vector switched on at `t0` (a :class:`duhamel.loads.Load`):
    ``VectorStep(vector, *, t0=0.0)``.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.rotor import VectorStep
    >>> sys = duhamel.System(np.eye(2), np.eye(2))
    >>> VectorStep([1.0, -2.0], t0=0.5).evaluate(sys, [0.0, 1.0]).tolist()
    [[0.0, -0.0], [1.0, -2.0]]
    """

    vector: NDArray[np.float64]
    _: KW_ONLY
    t0: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "vector", as_float_array(self.vector, "vector", ndim=1))
        object.__setattr__(self, "t0", finite_float(self.t0, "t0"))

    def _pattern(self, system: Model) -> NDArray[np.float64]:
        if self.vector.shape != (system.n_dof,):
            raise ValueError(
                f"`vector` must have length n_dof = {system.n_dof}, got {self.vector.shape[0]}"
            )
        return self.vector

    def _time(self) -> _core.TimeFunction:
        return _core.TimeFunction.step(float(self.t0))

    def _scalar(self, t: NDArray) -> NDArray:
        return (t >= self.t0).astype(np.float64)


def _resolve_speed(own: Any, given: Any) -> float | SpeedLaw:
    """The unbalance's speed (a float, or a varying law): its own, or the rotor's; both must
    agree when both are given."""
    if own is None and given is None:
        raise ValueError(
            "the unbalance needs a speed: give `speed` to Unbalance or to Rotor.system"
        )
    a = None if own is None else speed_or_law(own)
    b = None if given is None else speed_or_law(given)
    if a is not None and b is not None and a != b:
        raise ValueError(
            f"the unbalance's speed {a!r} differs from the rotor's {b!r} (rad/s); give "
            "the speed once (Unbalance(speed=None) takes the rotor's)"
        )
    return a if a is not None else b  # type: ignore[return-value]


@dataclass(frozen=True)
class Unbalance(RotorLoad):
    """A mass unbalance ``m_e`` (kg m: mass times eccentricity) at a node.

    The unbalance turns with the shaft. At constant speed ``Omega`` the force on the node is
    ``m_e Omega^2 (cos(Omega t + phase), sin(Omega t + phase))`` on ``(x, y)``, a forward
    rotating force; along a speed law (a run-up) its phase is the rotation angle
    ``theta(t) + phase`` and it gains the tangential term of the angular acceleration
    (``duhamel.loads.Unbalance``, docs/speed.md). Switched on at ``t = 0``: from rest, this
    is a sudden eccentricity.

    Parameters
    ----------
    node : int
        The node.
    m_e : float
        Unbalance, mass times eccentricity (kg m), ``> 0``.
    speed : float or speed law, optional
        Spin speed (rad/s) or a :mod:`duhamel.speed` law (``LinearRunUp``); default: the
        speed given to :meth:`Rotor.system`. When both are given they must be the same.
    phase : float
        Angle of the unbalance at ``t = 0`` from the x axis towards y (rad).

    Examples
    --------
    >>> from duhamel.rotor import Unbalance, rpm
    >>> u = Unbalance.from_force(node=2, force=5e4, speed=rpm(1500))
    >>> round(u.m_e, 6)
    2.026424

    Through a critical speed: the rotor and the unbalance follow one law.

    >>> import duhamel
    >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
    >>> rotor = Rotor([Shaft(0.4, 0.05, material=STEEL)] * 2, [Disk(1, 30.0, 0.3, 0.15)],
    ...               [Bearing(0, 1e7, 1e7), Bearing(2, 1e7, 1e7)], zeta=0.02)
    >>> run_up = duhamel.speed.LinearRunUp(omega0=0.0, omega1=rpm(6000), t1=1.0)
    >>> system = rotor.system(run_up, [Unbalance(1, m_e=1e-4)])
    >>> load = system.loads[0]
    >>> load.dofs, load.speed is run_up
    ((4, 5), True)
    """

    node: int
    m_e: float
    speed: Any = None
    phase: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.node, bool) or not isinstance(self.node, int | np.integer):
            raise TypeError(f"`node` must be an integer, got {type(self.node).__name__}")
        object.__setattr__(self, "node", int(self.node))
        object.__setattr__(self, "m_e", positive_float(self.m_e, "m_e"))
        object.__setattr__(self, "phase", finite_float(self.phase, "phase"))
        if self.speed is not None:
            object.__setattr__(self, "speed", speed_or_law(self.speed))

    @classmethod
    def from_force(cls, node: int, force: float, speed: float, phase: float = 0.0) -> Unbalance:
        """The unbalance whose force amplitude at constant `speed` is `force` (N):
        ``m_e = force / speed^2``."""
        w = constant_speed(speed)
        if w == 0.0:
            raise ValueError("`speed` must be nonzero to turn a force into an unbalance")
        return cls(node, positive_float(force, "force") / w**2, w, phase)

    def loads(self, rotor: RotorModel, speed: Any = None) -> list[Load]:
        """One :class:`duhamel.loads.Unbalance` on the node's x and y, driven by the speed
        (a constant, or the law of a run-up).

        At constant speed it equals the two harmonic loads
        ``Harmonic(dof_x, amplitude=m_e W^2, omega=W, phase=phase + pi/2)`` and
        ``Harmonic(dof_y, amplitude=m_e W^2, omega=W, phase=phase)`` (docs/speed.md).
        """
        w = _resolve_speed(self.speed, speed)
        dx, dy = rotor.dof(self.node, "x"), rotor.dof(self.node, "y")
        return [UnbalanceLoad((dx, dy), m_e=self.m_e, speed=w, phase=self.phase)]


@dataclass(frozen=True)
class Gravity(RotorLoad):
    """The rotor's own weight, ``f = g M r_d``, ``r_d`` the unit rigid translation along
    `direction` in the x-y plane (default ``(0, -1)``: the weight along ``-y``, ``f = -g M r``
    with ``r = 1`` on the y translations). With the consistent mass matrix this is the
    consistent body-force load (nodal moments included); its resultant is the total weight.
    One :class:`VectorStep` at `t0`.

    Examples
    --------
    >>> from duhamel.rotor import STEEL, Gravity, Rotor, Shaft
    >>> rotor = Rotor([Shaft(1.0, 0.05, material=STEEL)])
    >>> weight = Gravity().vector(rotor)
    >>> round(float(weight.sum()), 3), round(-rotor.mass * 9.80665, 3)
    (-150.384, -150.384)
    """

    g: float = STANDARD_GRAVITY
    direction: tuple[float, float] = (0.0, -1.0)
    t0: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "g", finite_float(self.g, "g"))
        d = as_float_array(self.direction, "direction", shape=(2,))
        n = float(np.hypot(*d))
        if n == 0.0:
            raise ValueError("`direction` must be a nonzero vector (d_x, d_y)")
        object.__setattr__(self, "direction", (float(d[0] / n), float(d[1] / n)))
        object.__setattr__(self, "t0", finite_float(self.t0, "t0"))

    def vector(self, rotor: RotorModel) -> NDArray[np.float64]:
        """The load vector ``g M r`` along `direction`, length ``rotor.n_dof``."""
        r = np.zeros(rotor.n_dof)
        r[0::4], r[1::4] = self.direction
        M = getattr(rotor, "mass_matrix", None)  # a Rotor's, without evaluating its bearings
        return self.g * np.asarray((rotor.matrices().M if M is None else M) @ r)

    def loads(self, rotor: RotorModel, speed: Any = None) -> list[Load]:
        """One :class:`VectorStep` with :meth:`vector`."""
        return [VectorStep(self.vector(rotor), t0=self.t0)]


@dataclass(frozen=True)
class SuddenForce(RotorLoad):
    """A constant force ``(fx, fy)`` (N) at a node switched on at `t0` (Heaviside steps):
    the paper's sudden force.

    Examples
    --------
    >>> from duhamel.rotor import STEEL, Rotor, Shaft, SuddenForce
    >>> rotor = Rotor([Shaft(1.0, 0.05, material=STEEL)])
    >>> [(s.dof, s.amplitude) for s in SuddenForce(1, fy=-5e4).loads(rotor)]
    [(5, -50000.0)]
    """

    node: int
    fx: float = 0.0
    fy: float = 0.0
    t0: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.node, bool) or not isinstance(self.node, int | np.integer):
            raise TypeError(f"`node` must be an integer, got {type(self.node).__name__}")
        object.__setattr__(self, "node", int(self.node))
        for name in ("fx", "fy", "t0"):
            object.__setattr__(self, name, finite_float(getattr(self, name), name))

    def loads(self, rotor: RotorModel, speed: Any = None) -> list[Load]:
        """Steps on the node's x and y (only the nonzero components)."""
        out: list[Load] = []
        for direction, amplitude in (("x", self.fx), ("y", self.fy)):
            if amplitude != 0.0:
                out.append(Step(rotor.dof(self.node, direction), amplitude=amplitude, t0=self.t0))
        return out
