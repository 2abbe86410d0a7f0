"""Rotor faults as force elements: the breathing crack (Gasch's switching crack, Mayes &
Davies' cosine breathing) at a shaft node, in Rust (``crates/duhamel-core/src/elements/
crack.rs``).

The crack is the loss of the shaft's stiffness in the frame turning with the rotor at the
angle ``phi = theta(t) + phase`` (``theta`` of the speed law): with ``xi = x cos(phi) +
y sin(phi)`` (across the crack front) and ``eta = -x sin(phi) + y cos(phi)``, the open crack
lowers the stiffness by `dk_xi` along ``xi`` and `dk_eta` along ``eta``. The element adds
``r = -f R(phi) diag(dk_xi, dk_eta) R(phi)^T (x, y)`` to the uncracked shaft (which the
model's stiffness carries), ``f`` the breathing function: ``"switching"`` ``f = 1`` while
``xi > 0`` (the crack opens under tension; Gasch 1993), ``"cosine"``
``f = (1 + cos(phi)) / 2`` (Mayes & Davies 1984: ``k(phi) = k0 - dk (1 + cos(phi)) / 2``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float
from duhamel.elements.base import Element, TwoAxis, nonneg
from duhamel.speed import ConstantSpeed, SpeedLaw

__all__ = ["BreathingCrack"]

_BREATHING = ("switching", "cosine")


def _law(speed: Any) -> SpeedLaw:
    if isinstance(speed, SpeedLaw):
        return speed
    return ConstantSpeed(finite_float(speed, "speed"))


@dataclass(frozen=True)
class BreathingCrack(TwoAxis, Element):
    """A breathing transverse crack on the lateral dofs ``(dof_x, dof_y)`` of a shaft node:
    the open crack's stiffness losses `dk_xi` (across the crack front) and `dk_eta` (along
    it), N/m, in the frame turning at `speed` (rad/s, or a :mod:`duhamel.speed` law),
    `phase` the angle (rad) of the crack's ``xi`` axis from ``x`` at ``t = 0``, and
    `breathing` ``"switching"`` (Gasch: open while the node's displacement has a positive
    ``xi`` component) or ``"cosine"`` (Mayes & Davies: ``f = (1 + cos(phi)) / 2``, fully open
    when ``xi`` points along ``+x``... at ``phi = 0``). The uncracked shaft stays in the
    model's stiffness; the element is the loss, a restoring force
    ``-f R diag(dk_xi, dk_eta) R^T x``.

    Examples
    --------
    >>> from duhamel.rotor import BreathingCrack
    >>> crack = BreathingCrack(0, 1, dk_xi=2e4, breathing="cosine", speed=100.0)
    >>> r, K, C = crack.evaluate([1e-3, 0.0], t=0.0)  # fully open, xi along x
    >>> K.tolist()
    [[-20000.0, 0.0], [0.0, 0.0]]
    """

    dof_x: int
    dof_y: int
    dk_xi: float
    dk_eta: float = 0.0
    breathing: str = "cosine"
    speed: Any = 0.0
    phase: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "dk_xi", nonneg(self.dk_xi, "dk_xi"))
        object.__setattr__(self, "dk_eta", nonneg(self.dk_eta, "dk_eta"))
        if self.breathing not in _BREATHING:
            raise ValueError(f"`breathing` must be 'switching' or 'cosine', got {self.breathing!r}")
        object.__setattr__(self, "speed", _law(self.speed))
        object.__setattr__(self, "phase", finite_float(self.phase, "phase"))

    def _spec(self) -> tuple:
        return (
            "crack", int(self.dof_x), int(self.dof_y), self.dk_xi, self.dk_eta, self.breathing,
            self.phase, self.speed._spec(),
        )  # fmt: skip

    def evaluate(
        self, position: ArrayLike, velocity: ArrayLike = (0.0, 0.0), t: float = 0.0
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """The crack's restoring force ``r`` (N) at the node's `position` (m) at time `t`
        and its tangents ``dr/dx`` (minus the open part of the loss matrix) and ``dr/dx'``
        (zero)."""
        from duhamel._engine.specs import element

        x = as_float_array(position, "position", shape=(2,))
        v = as_float_array(velocity, "velocity", shape=(2,))
        r, kx, cv = element(self._spec()).evaluate(x, v, finite_float(t, "t"))
        return np.asarray(r), np.asarray(kx).reshape(2, 2), np.asarray(cv).reshape(2, 2)
