"""Steady-state unbalance response in the frequency domain, its peaks, amplification factors
and API 684 separation margins.

At constant speed ``Omega`` an unbalance ``(node, m_e, phase)`` forces the node with
``m_e Omega^2 (cos(Omega t + phase), sin(Omega t + phase))`` on ``(x, y)`` (the force of
:class:`duhamel.rotor.Unbalance`), i.e. ``Re(F e^{i Omega t})`` with ``F_x = m_e Omega^2
e^{i phase}``, ``F_y = -i F_x``. The steady state is ``x(t) = Re(X e^{i Omega t})`` with

    (K(Omega) - Omega^2 M + i Omega (C(Omega) + Omega G)) X = F,

one complex solve per speed: exact, with the bearings' coefficients at each speed (dense
and batched for small models, banded LU for long rotors, :mod:`duhamel.rotor._banded`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float, positive_float
from duhamel.rotor._banded import banded_responses, bandwidths, worth_banding
from duhamel.rotor._orbit import circular_parts

__all__ = ["Peak", "UnbalanceResponse", "unbalance_response"]

#: Speeds solved together (a batch of dense complex systems).
_BATCH = 64


@dataclass(frozen=True)
class Peak:
    """A resonance peak of an unbalance response curve (API 684 vocabulary).

    Attributes
    ----------
    speed : float
        Critical speed ``N_c`` (rad/s): the speed of the peak (the largest sample, refined by
        a parabola through it and its neighbours).
    amplitude : float
        Peak amplitude (m).
    half_power : (float, float)
        Speeds ``N_1 < N_c < N_2`` where the amplitude is ``peak / sqrt(2)`` (linear
        interpolation between samples); NaN where the curve does not fall that low.
    amplification_factor : float
        ``AF = N_c / (N_2 - N_1)`` (NaN when a half-power point is missing).
    required_margin : float
        API 684 / API 617 separation margin (a fraction) required of this critical speed:
        0 when ``AF < 2.5``; else, below the minimum operating speed,
        ``min(0.16, 0.17 (1 - 1 / (AF - 1.5)))``, above the maximum continuous speed,
        ``min(0.26, 0.10 + 0.17 (1 - 1 / (AF - 1.5)))`` (NaN without an operating range,
        or inside it).
    margin : float
        Actual separation margin from the operating range: ``(N_min - N_c) / N_c`` below it,
        ``(N_c - N_max) / N_max`` above it, negative inside it (NaN without a range).
    """

    speed: float
    amplitude: float
    half_power: tuple[float, float]
    amplification_factor: float
    required_margin: float
    margin: float

    @property
    def meets_margin(self) -> bool:
        """Whether the actual margin is at least the required one (False inside the range)."""
        if np.isnan(self.margin):
            return True
        return bool(self.margin >= 0.0 and self.margin >= np.nan_to_num(self.required_margin))


def _half_power(w: NDArray, amp: NDArray, k: int) -> tuple[float, float]:
    level = amp[k] / np.sqrt(2.0)
    sides = []
    for step in (-1, 1):
        i = k
        while 0 <= i + step < w.size and amp[i + step] > level:
            i += step
        j = i + step
        if not 0 <= j < w.size:
            sides.append(np.nan)
            continue
        s = (amp[i] - level) / (amp[i] - amp[j])
        sides.append(float(w[i] + s * (w[j] - w[i])))
    return sides[0], sides[1]


def _vertex(w: NDArray, a: NDArray) -> tuple[float, float]:
    """Speed and value of the vertex of the parabola through three samples around a peak."""
    h0, h1 = w[1] - w[0], w[2] - w[1]
    d0, d2 = a[0] - a[1], a[2] - a[1]
    c = (h0 * d2 + h1 * d0) / (h0 * h1 * (h0 + h1))
    b = (h0**2 * d2 - h1**2 * d0) / (h0 * h1 * (h0 + h1))
    if c >= 0.0:  # flat or not a maximum: the sample itself
        return float(w[1]), float(a[1])
    x = float(np.clip(-b / (2.0 * c), -h0, h1))
    return float(w[1] + x), float(a[1] + b * x + c * x**2)


def _margins(nc: float, af: float, operating: tuple[float, float] | None) -> tuple[float, float]:
    if operating is None:
        return np.nan, np.nan
    lo, hi = operating
    if lo <= nc <= hi:
        return np.nan, -min(nc - lo, hi - nc) / nc
    below = nc < lo
    margin = (lo - nc) / nc if below else (nc - hi) / hi
    if not np.isfinite(af):
        return np.nan, margin
    if af < 2.5:
        return 0.0, margin
    base = 0.17 * (1.0 - 1.0 / (af - 1.5))
    return (min(0.16, base) if below else min(0.26, 0.10 + base)), margin


@dataclass(frozen=True, eq=False)
class UnbalanceResponse:
    """Steady-state unbalance response: ``x(t) = Re(response[k] e^{i speeds[k] t})``.

    Attributes
    ----------
    speeds : ndarray, shape (n_speeds,)
        rad/s.
    response : ndarray of complex, shape (n_speeds, n_dof)
        Complex amplitudes (m, rad).
    dof : callable
        ``(node, direction) -> dof index`` of the model.
    unbalances : tuple
        The ``(node, m_e, phase)`` given.
    """

    speeds: NDArray[np.float64]
    response: NDArray[np.complex128]
    dof: Callable[[int, str], int]
    unbalances: tuple[tuple[int, float, float], ...]

    def _at(self, node: int, direction: str) -> NDArray[np.complex128]:
        return self.response[:, int(self.dof(node, direction))]

    def amplitude(self, node: int, direction: str = "x") -> NDArray[np.float64]:
        """``|X|`` of one dof (m or rad) at each speed."""
        return np.abs(self._at(node, direction))

    def phase(self, node: int, direction: str = "x") -> NDArray[np.float64]:
        """Phase ``angle(X)`` (rad): ``x(t) = |X| cos(Omega t + phase)``."""
        return np.angle(self._at(node, direction))

    def _forward_backward(self, node: int) -> tuple[NDArray, NDArray]:
        return circular_parts(self._at(node, "x"), self._at(node, "y"))

    def major_axis(self, node: int) -> NDArray[np.float64]:
        """Major semi-axis of the node's elliptical orbit (m): ``|F| + |B|`` with the forward
        and backward circular parts ``F = (X + i Y) / 2``, ``B = (conj X + i conj Y) / 2``."""
        f, b = self._forward_backward(node)
        return f + b

    def minor_axis(self, node: int) -> NDArray[np.float64]:
        """Minor semi-axis of the orbit (m), ``||F| - |B||``."""
        f, b = self._forward_backward(node)
        return np.abs(f - b)

    def whirl(self, node: int) -> NDArray[np.str_]:
        """``"forward"`` where the orbit turns with the spin (``|F| > |B|``), else
        ``"backward"`` (``"planar"`` for a straight line)."""
        f, b = self._forward_backward(node)
        tol = 1e-12 * np.maximum(f, b)
        return np.where(f > b + tol, "forward", np.where(b > f + tol, "backward", "planar"))

    def peaks(
        self,
        node: int,
        direction: str | None = None,
        *,
        operating: tuple[float, float] | None = None,
    ) -> list[Peak]:
        """The resonance peaks of one response curve, with their amplification factors and
        API 684 separation margins.

        Parameters
        ----------
        node : int
            The node.
        direction : str, optional
            A dof direction (``"x"``, ``"y"``...); default the orbit's major semi-axis.
        operating : (float, float), optional
            Keyword only. Minimum operating and maximum continuous speeds (rad/s), for the
            margins.

        Returns
        -------
        list of Peak
            Local maxima of the sampled curve, ascending in speed. Their accuracy is that of
            the speed grid: sample finely around them.
        """
        amp = self.major_axis(node) if direction is None else self.amplitude(node, direction)
        w = self.speeds
        span = None
        if operating is not None:
            lo, hi = (finite_float(v, "operating") for v in operating)
            if not 0.0 <= lo <= hi:
                raise ValueError(
                    f"`operating` must be (min, max) with 0 <= min <= max, got {operating}"
                )
            span = (lo, hi)
        out = []
        for k in range(1, w.size - 1):
            if not (amp[k] > amp[k - 1] and amp[k] >= amp[k + 1]):
                continue
            nc, top = _vertex(w[k - 1 : k + 2], amp[k - 1 : k + 2])
            n1, n2 = _half_power(w, amp, k)
            af = nc / (n2 - n1) if np.isfinite(n1) and np.isfinite(n2) else np.nan
            required, margin = _margins(nc, af, span)
            out.append(Peak(nc, top, (n1, n2), float(af), float(required), float(margin)))
        return out

    def plot_bode(self, node: int, direction: str | None = None, **kwargs: Any) -> Any:
        """Amplitude and phase against speed (:func:`duhamel.rotor.plot_bode`)."""
        from duhamel.rotor._plot_response import plot_bode

        return plot_bode(self, node, direction, **kwargs)

    def plot_polar(self, node: int, direction: str = "x", **kwargs: Any) -> Any:
        """The complex amplitude ``X`` traced over the speeds (a polar / Nyquist plot)."""
        from duhamel.rotor._plot_response import plot_polar

        return plot_polar(self, node, direction, **kwargs)


def _dynamic_stiffness(mats: tuple, w: NDArray) -> NDArray[np.complex128]:
    """``K - w^2 M + i w (C + w G)`` for each speed of `w`, shape ``(w.size, n, n)``."""
    M, K, C, G = mats
    w3 = w[:, None, None]
    return K[None] - w3**2 * M[None] + 1j * w3 * (C[None] + w3 * G[None])


def _direct(matrices: Any, w: NDArray, F0: NDArray) -> NDArray[np.complex128]:
    """One LU solve per speed (a batch); `matrices` fixed or ``speed -> (M, K, C, G)``."""
    if callable(matrices):
        A = np.stack([_dynamic_stiffness(tuple(np.asarray(a) for a in matrices(float(wi))),
                                         np.array([wi]))[0] for wi in w])  # fmt: skip
    else:
        A = _dynamic_stiffness(matrices, w)
    try:
        return np.linalg.solve(A, ((w**2)[:, None] * F0[None, :])[..., None])[..., 0]
    except np.linalg.LinAlgError:
        raise ValueError(
            "the dynamic stiffness is singular at a speed in "
            f"[{w[0]:g}, {w[-1]:g}] rad/s (an undamped resonance, or a rigid-body mode at "
            "speed 0): add damping or move the speeds off it"
        ) from None


def _unbalances(value: Any) -> tuple[tuple[int, float, float], ...]:
    try:
        items = list(value)
    except TypeError:
        raise TypeError("`unbalances` must be a list of (node, m_e, phase)") from None
    if not items:
        raise ValueError("`unbalances` is empty")
    out = []
    for item in items:
        if all(hasattr(item, a) for a in ("node", "m_e", "phase")):  # a rotor Unbalance
            item = (item.node, item.m_e, item.phase)
        parts = tuple(item) if not isinstance(item, str) else ()
        if len(parts) not in (2, 3):
            raise ValueError(f"each unbalance must be (node, m_e[, phase]), got {item!r}")
        node = parts[0]
        if isinstance(node, bool) or not isinstance(node, int | np.integer) or node < 0:
            raise ValueError(f"an unbalance's node must be an integer >= 0, got {node!r}")
        m_e = positive_float(parts[1], "m_e")
        phase = finite_float(parts[2], "phase") if len(parts) == 3 else 0.0
        out.append((int(node), m_e, phase))
    return tuple(out)


def unbalance_response(
    matrices: Any,
    speeds: ArrayLike,
    unbalances: Sequence[tuple[int, float, float]],
    *,
    dof: Callable[[int, str], int],
) -> UnbalanceResponse:
    """Steady-state response to unbalances at each speed, one complex solve per speed.

    Parameters
    ----------
    matrices : RotorMatrices or callable
        ``(M, K, C, G)`` of ``M x'' + (C + speed G) x' + K x = f``, or ``speed ->`` those
        (speed-dependent bearings).
    speeds : array_like
        Spin speeds (rad/s).
    unbalances : list of (node, m_e, phase)
        Unbalance (kg m) and its angle at ``t = 0`` (rad) at each node (or
        :class:`duhamel.rotor.Unbalance` loads; their speeds are not used).
    dof : callable
        Keyword only. ``(node, direction) -> dof`` (``Rotor.dof``, or ``from_ross``'s
        ``dofs``).

    Returns
    -------
    UnbalanceResponse

    Examples
    --------
    A Jeffcott rotor: a 10 kg disk on a massless shaft and stiff bearings (1e6 N/m), 2 %
    damping. At resonance the amplitude is ``m_e / (2 zeta m)``.

    >>> import numpy as np
    >>> from duhamel.rotor.assembly import RotorMatrices
    >>> from duhamel.rotor.unbalance import unbalance_response
    >>> m, k = 10.0, 1e6
    >>> c = 2 * 0.02 * np.sqrt(k * m)
    >>> mats = RotorMatrices(np.diag([m, m]), np.diag([k, k]), np.diag([c, c]), np.zeros((2, 2)))
    >>> res = unbalance_response(mats, [np.sqrt(k / m)], [(0, 1e-4, 0.0)],
    ...                          dof=lambda node, d: {"x": 0, "y": 1}[d])
    >>> round(float(res.amplitude(0, "x")[0]) / (1e-4 / (2 * 0.02 * m)), 12)
    1.0
    """
    ws = as_float_array(speeds, "speeds", ndim=1)
    if ws.size == 0:
        raise ValueError("`speeds` is empty")
    cases = _unbalances(unbalances)
    fixed = None if callable(matrices) else matrices
    first = tuple(np.asarray(a) for a in (fixed if fixed is not None else matrices(float(ws[0]))))
    M0 = first[0]
    n = M0.shape[0]
    F0 = np.zeros(n, dtype=complex)  # per unit Omega^2
    for node, m_e, phase in cases:
        fx = m_e * np.exp(1j * phase)
        F0[int(dof(node, "x"))] += fx
        F0[int(dof(node, "y"))] += -1j * fx
    mats = matrices if fixed is None else tuple(np.asarray(a) for a in fixed)
    out = np.empty((ws.size, n), dtype=complex)
    band = bandwidths(first)
    if fixed is not None and worth_banding(n, *band):
        out[:] = banded_responses(mats, ws, F0, *band)
    elif fixed is None and worth_banding(n, *band):
        for s, w in enumerate(ws):  # speed-dependent matrices, each speed's band
            at = tuple(np.asarray(a) for a in matrices(float(w)))
            out[s] = banded_responses(at, ws[s : s + 1], F0, *bandwidths(at))[0]
    else:
        for start in range(0, ws.size, _BATCH):
            out[start : start + _BATCH] = _direct(mats, ws[start : start + _BATCH], F0)
    if not np.all(np.isfinite(out)):
        raise ValueError("the unbalance response is not finite (an undamped resonance?)")
    return UnbalanceResponse(ws, out, dof, cases)
