"""Controller blocks of an active magnetic bearing, each a single-input single-output linear
state-space system ``z' = A z + B u``, ``y = C z + D u`` with its transfer function in closed
form: :class:`PID`, :class:`LowPass` (first or second order), :class:`Notch`,
:class:`Sensor` and :class:`Amplifier` dynamics, any :class:`StateSpace`, and
:class:`Series` (the signal through several blocks in turn, ``C(s) = C_1(s) C_2(s) ...``;
also ``block_1 * block_2``).

A :class:`~duhamel.rotor.magnetic.MagneticBearing` takes one block or a sequence of them
(the measured displacement in, the coil current out); their states join the closed loop's
first-order state, so closed-loop transients, modes and frequency responses stay exact.
Second-order blocks are realised in the scaled states ``(y, y' / omega)`` so that a filter at
``omega`` contributes entries of order ``omega``, not ``omega^2``, to the augmented matrix.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import finite_float, nonneg_float, positive_float

__all__ = [
    "PID",
    "Amplifier",
    "ControllerBlock",
    "LowPass",
    "Notch",
    "Sensor",
    "Series",
    "StateSpace",
    "realization_response",
]

Realization = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], float]


class ControllerBlock:
    """A SISO linear block: :meth:`state_space` and its transfer function ``block(s)``."""

    def state_space(self) -> Realization:  # pragma: no cover - every block overrides it
        """``(A, B, C, D)``: ``A`` (n, n), ``B`` and ``C`` (n,), ``D`` a float."""
        raise NotImplementedError

    def __call__(self, s: Any) -> Any:  # pragma: no cover - every block overrides it
        """The transfer function at the complex frequencies `s`, in closed form."""
        raise NotImplementedError

    @property
    def n_states(self) -> int:
        """Number of states the block adds to the closed loop."""
        return int(self.state_space()[0].shape[0])

    def __mul__(self, other: ControllerBlock) -> Series:
        if not isinstance(other, ControllerBlock):
            return NotImplemented
        return Series(self, other)


def realization_response(block: ControllerBlock, s: ArrayLike) -> NDArray[np.complex128]:
    """``C (s I - A)^-1 B + D`` of `block`'s realization at the complex frequencies `s`.

    Examples
    --------
    >>> from duhamel.rotor.controllers import LowPass, realization_response
    >>> f = LowPass(100.0)
    >>> bool(abs(realization_response(f, [100j])[0] - f(100j)) < 1e-15)
    True
    """
    A, B, C, D = block.state_space()
    ss = np.atleast_1d(np.asarray(s, dtype=complex))
    n = A.shape[0]
    out = np.full(ss.shape, D, dtype=complex)
    if n:
        for k, sk in enumerate(ss):
            out[k] += C @ np.linalg.solve(sk * np.eye(n) - A, B)
    return out


def _first_order(gain: float, bandwidth: float | None) -> Realization:
    if bandwidth is None:
        return np.zeros((0, 0)), np.zeros(0), np.zeros(0), gain
    return np.array([[-bandwidth]]), np.array([bandwidth]), np.array([gain]), 0.0


def _bandwidth(value: Any, name: str) -> float | None:
    if value is None or (isinstance(value, float) and np.isinf(value) and value > 0):
        return None
    return positive_float(value, name)


@dataclass(frozen=True)
class PID(ControllerBlock):
    """``C(s) = kp + ki / s + kd s / (1 + tau s)`` (A/m, A/(m s), A s/m, s).

    Examples
    --------
    >>> from duhamel.rotor import PID
    >>> PID(3e4, 1e5, 30.0, 1e-4).n_states
    2
    """

    kp: float
    ki: float = 0.0
    kd: float = 0.0
    tau: float = 0.0

    def __post_init__(self) -> None:
        for name in ("kp", "ki", "kd"):
            object.__setattr__(self, name, finite_float(getattr(self, name), name))
        object.__setattr__(self, "tau", nonneg_float(self.tau, "tau"))
        if self.kd != 0.0 and self.tau <= 0.0:
            raise ValueError("`tau` must be > 0 with a derivative gain `kd` (a proper C(s))")

    def __call__(self, s: Any) -> Any:
        """``C(s)``."""
        out = self.kp + (self.ki / s if self.ki else 0.0)
        return out + (self.kd * s / (1.0 + self.tau * s) if self.kd else 0.0)

    def state_space(self) -> Realization:
        """States: the integral of the input (``ki != 0``), the derivative's filter
        ``z' = (u - z) / tau`` (``kd != 0``: ``kd s / (1 + tau s) u = (kd / tau)(u - z)``)."""
        a, b, c = [], [], []
        if self.ki:
            a.append(0.0)
            b.append(1.0)
            c.append(self.ki)
        d = self.kp
        if self.kd:
            a.append(-1.0 / self.tau)
            b.append(1.0 / self.tau)
            c.append(-self.kd / self.tau)
            d += self.kd / self.tau
        return np.diag(a), np.array(b), np.array(c), d


@dataclass(frozen=True)
class LowPass(ControllerBlock):
    """Low-pass filter of unit DC gain at the corner `cutoff` (rad/s): first order
    ``w / (s + w)``, or second order ``w^2 / (s^2 + 2 damping w s + w^2)`` (`damping`
    ``1/sqrt(2)``: Butterworth).

    Examples
    --------
    >>> from duhamel.rotor import LowPass
    >>> round(abs(LowPass(1000.0, order=2)(1000j)), 12)
    0.707106781187
    """

    cutoff: float
    order: int = 1
    damping: float = float(np.sqrt(0.5))

    def __post_init__(self) -> None:
        object.__setattr__(self, "cutoff", positive_float(self.cutoff, "cutoff"))
        if self.order not in (1, 2) or isinstance(self.order, bool):
            raise ValueError(f"`order` must be 1 or 2, got {self.order!r}")
        object.__setattr__(self, "damping", positive_float(self.damping, "damping"))

    def __call__(self, s: Any) -> Any:
        w = self.cutoff
        if self.order == 1:
            return w / (s + w)
        return w * w / (s * s + 2.0 * self.damping * w * s + w * w)

    def state_space(self) -> Realization:
        w = self.cutoff
        if self.order == 1:
            return _first_order(1.0, w)
        A = w * np.array([[0.0, 1.0], [-1.0, -2.0 * self.damping]])
        return A, np.array([0.0, w]), np.array([1.0, 0.0]), 0.0


@dataclass(frozen=True)
class Notch(ControllerBlock):
    """Notch filter at `frequency` (rad/s):
    ``(s^2 + 2 depth zeta w s + w^2) / (s^2 + 2 zeta w s + w^2)``; `zeta` sets its width
    (the -3 dB band is about ``2 zeta w`` wide for a deep notch), `depth` its gain at ``w``
    (0: a zero there), unit gain far from it.

    Examples
    --------
    >>> from duhamel.rotor import Notch
    >>> round(abs(Notch(500.0, zeta=0.1, depth=0.05)(500j)), 12)
    0.05
    """

    frequency: float
    zeta: float = 0.1
    depth: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "frequency", positive_float(self.frequency, "frequency"))
        object.__setattr__(self, "zeta", positive_float(self.zeta, "zeta"))
        object.__setattr__(self, "depth", nonneg_float(self.depth, "depth"))

    def __call__(self, s: Any) -> Any:
        w, z = self.frequency, self.zeta
        den = s * s + 2.0 * z * w * s + w * w
        return (s * s + 2.0 * self.depth * z * w * s + w * w) / den

    def state_space(self) -> Realization:
        w, z = self.frequency, self.zeta
        A = w * np.array([[0.0, 1.0], [-1.0, -2.0 * z]])
        C = np.array([0.0, 2.0 * z * (self.depth - 1.0)])
        return A, np.array([0.0, w]), C, 1.0


@dataclass(frozen=True)
class Sensor(ControllerBlock):
    """A displacement sensor: `gain` (V/m, or 1 to keep the controller's gains in A/m) with a
    first-order `bandwidth` (rad/s; None: ideal), ``gain w / (s + w)``.

    Examples
    --------
    >>> from duhamel.rotor import Sensor
    >>> Sensor(bandwidth=2e4).n_states
    1
    """

    gain: float = 1.0
    bandwidth: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "gain", finite_float(self.gain, "gain"))
        object.__setattr__(self, "bandwidth", _bandwidth(self.bandwidth, "bandwidth"))

    def __call__(self, s: Any) -> Any:
        w = self.bandwidth
        return self.gain * (1.0 if w is None else w / (s + w))

    def state_space(self) -> Realization:
        return _first_order(self.gain, self.bandwidth)


@dataclass(frozen=True)
class Amplifier(Sensor):
    """A power amplifier: `gain` (A/V, or 1) with a first-order current `bandwidth`
    (rad/s; None: ideal), ``gain w / (s + w)``.

    Examples
    --------
    >>> from duhamel.rotor import Amplifier
    >>> round(abs(Amplifier(bandwidth=1e4)(1e4j)), 12)
    0.707106781187
    """


@dataclass(frozen=True, eq=False)
class StateSpace(ControllerBlock):
    """Any SISO block ``z' = A z + B u``, ``y = C z + D u`` (``A`` (n, n), ``B``, ``C``
    (n,), ``D`` a number).

    Examples
    --------
    >>> from duhamel.rotor import StateSpace
    >>> lag = StateSpace([[-50.0]], [50.0], [1.0], 0.0)   # 50 / (s + 50)
    >>> complex(lag(50j))
    (0.5-0.5j)
    """

    A: Any
    B: Any
    C: Any
    D: float = 0.0

    def __post_init__(self) -> None:
        A = np.atleast_2d(np.asarray(self.A, dtype=float)) if np.size(self.A) else np.zeros((0, 0))
        n = A.shape[0]
        if A.ndim != 2 or A.shape != (n, n):
            raise ValueError(f"`A` must be square, got shape {np.shape(self.A)}")
        B = np.asarray(self.B, dtype=float).reshape(-1)
        C = np.asarray(self.C, dtype=float).reshape(-1)
        for name, v in (("B", B), ("C", C)):
            if v.size != n:
                raise ValueError(f"`{name}` must have {n} entries (A is {n}x{n}), got {v.size}")
        if not (np.all(np.isfinite(A)) and np.all(np.isfinite(B)) and np.all(np.isfinite(C))):
            raise ValueError("`A`, `B` and `C` must be finite")
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "B", B)
        object.__setattr__(self, "C", C)
        object.__setattr__(self, "D", finite_float(self.D, "D"))

    def __call__(self, s: Any) -> Any:
        out = realization_response(self, np.ravel(s))
        return out.reshape(np.shape(s)) if np.ndim(s) else out[0]

    def state_space(self) -> Realization:
        return self.A, self.B, self.C, float(self.D)


class Series(ControllerBlock):
    """Blocks in series, the signal through `blocks` in turn: ``C(s) = prod C_k(s)``.

    Examples
    --------
    >>> from duhamel.rotor import PID, LowPass, Notch, Sensor, Series
    >>> c = Series(Sensor(bandwidth=3e4), PID(3e4, 1e5, 30.0, 1e-4), LowPass(5e3), Notch(800.0))
    >>> c.n_states
    6
    """

    def __init__(self, *blocks: ControllerBlock | Sequence[ControllerBlock]) -> None:
        flat: list[ControllerBlock] = []
        for b in blocks:
            if isinstance(b, Series):
                flat += b.blocks
            elif isinstance(b, ControllerBlock):
                flat.append(b)
            else:
                raise TypeError(
                    f"a controller must be a block (PID, LowPass, Notch, Sensor, Amplifier, "
                    f"StateSpace), got {type(b).__name__}"
                )
        if not flat:
            raise ValueError("a controller needs at least one block")
        self.blocks: tuple[ControllerBlock, ...] = tuple(flat)

    def __call__(self, s: Any) -> Any:
        out: Any = 1.0
        for b in self.blocks:
            out = out * b(s)
        return out

    def state_space(self) -> Realization:
        """``u -> (A1, B1, C1, D1) -> (A2, B2, C2, D2) -> y``:
        ``A = [[A1, 0], [B2 C1, A2]]``, ``B = [B1; B2 D1]``, ``C = [D2 C1, C2]``,
        ``D = D2 D1``, block by block."""
        A, B, C, D = self.blocks[0].state_space()
        for block in self.blocks[1:]:
            A2, B2, C2, D2 = block.state_space()
            n1, n2 = A.shape[0], A2.shape[0]
            big = np.zeros((n1 + n2, n1 + n2))
            big[:n1, :n1] = A
            big[n1:, :n1] = np.outer(B2, C)
            big[n1:, n1:] = A2
            A, B, C, D = (
                big,
                np.concatenate([B, B2 * D]),
                np.concatenate([D2 * C, C2]),
                D2 * D,
            )
        return A, B, C, float(D)

    def __repr__(self) -> str:
        return f"Series({', '.join(map(repr, self.blocks))})"
