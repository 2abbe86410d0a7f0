"""Free vibration of the undamped Duffing oscillator (Jacobi elliptic functions): the
paper's section 4.1."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import scipy.special as sc
from numpy.typing import ArrayLike

from duhamel._engine.validate import finite_float, nonneg_float
from duhamel.exact._common import Array
from duhamel.exact._common import times as _times

__all__ = ["duffing", "duffing_period"]


def _duffing_params(omega: Any, b: Any, x0: Any) -> tuple[float, float, str]:
    """Return ``(rate, m, kind)`` with x = x0 * f(rate t | m) (see :func:`duffing`).

    Computed on the scale ``s = max(omega, sqrt|b| |x0|)`` so that ``b x0^2`` may lie
    beyond the double range; a ValueError names the parameters when the rate or the
    velocity amplitude ``x0 rate`` does."""
    omega = nonneg_float(omega, "omega")
    b = finite_float(b, "b")
    x0 = finite_float(x0, "x0")
    if x0 == 0.0 or (b == 0.0 and omega == 0.0):
        return 0.0, 0.0, "rest"  # at rest at the origin
    cubic = math.sqrt(abs(b)) * abs(x0)  # sqrt|b x0^2|
    if not math.isfinite(cubic):
        if b < 0.0:
            raise ValueError(
                "the motion is unbounded: a softening spring (`b` < 0) released beyond the "
                "separatrix (`x0`^2 must be below omega^2 / |b|)"
            )
        raise ValueError(_too_fast(omega, b, x0))
    scale = max(omega, cubic)
    w, c2 = omega / scale, math.copysign((cubic / scale) ** 2, b)  # omega/s, b x0^2/s^2
    big2 = w * w + c2  # Omega^2 / s^2
    if big2 == 0.0:
        # At the top of the potential barrier: b x0^2 = -omega^2.
        return 0.0, 0.0, "rest"
    if big2 < 0.0:
        raise ValueError(
            "the motion is unbounded: a softening spring (`b` < 0) released beyond the "
            f"separatrix, omega^2 + b x0^2 = {big2 * scale * scale:.6g} < 0 (`x0`^2 must be "
            "below omega^2 / |b|)"
        )
    if c2 >= 0.0:
        # x = x0 cn(Omega t | m), Omega^2 = omega^2 + b x0^2, m = b x0^2 / (2 Omega^2) in [0, 1/2]
        rate, m, kind = scale * math.sqrt(big2), c2 / (2.0 * big2), "cn"
    else:
        # Softening, bounded: m < 0. cn(u | -mu) = cd(u sqrt(1 + mu) | mu / (1 + mu)), so
        # x = x0 cd(lam t | k2), lam^2 = omega^2 + b x0^2 / 2, k2 = -b x0^2 / (2 lam^2) in (0, 1).
        lam2 = w * w + 0.5 * c2
        rate, m, kind = scale * math.sqrt(lam2), -c2 / (2.0 * lam2), "cd"
    if not (math.isfinite(rate) and math.isfinite(abs(x0) * rate)):
        raise ValueError(_too_fast(omega, b, x0))
    return rate, m, kind


def _too_fast(omega: float, b: float, x0: float) -> str:
    return (
        f"`b` = {b:g} and `x0` = {x0:g} (with `omega` = {omega:g}): the motion's frequency "
        "sqrt(omega^2 + b x0^2) or its velocity amplitude beyond the double range"
    )


def _reduce(u: Array, quarter: float) -> Array:
    """Reduce the argument modulo the real period ``4 K`` (keeps ellipj accurate for large u)."""
    period = 4.0 * quarter
    return u - period * np.round(u / period)


def duffing(t: ArrayLike, omega: float, b: float, x0: float) -> tuple[Array, Array]:
    """Free vibration of the undamped Duffing oscillator released from rest.

    Solves ``x'' + omega^2 x + b x^3 = 0`` with ``x(0) = x0``, ``x'(0) = 0``:

    - ``b x0^2 >= 0`` (hardening or linear): ``x = x0 cn(Omega t | m)`` with
      ``Omega^2 = omega^2 + b x0^2`` and parameter ``m = b x0^2 / (2 Omega^2)`` in ``[0, 1/2]``;
      ``x' = -x0 Omega sn dn``.
    - ``-omega^2 < b x0^2 < 0`` (softening, bounded): the same formula with ``m < 0``, evaluated
      through the negative-parameter transformation ``cn(u | -mu) = cd(u sqrt(1 + mu) |
      mu / (1 + mu))``, i.e. ``x = x0 cd(lam t | k2)`` with ``lam^2 = omega^2 + b x0^2 / 2`` and
      ``k2 = -b x0^2 / (2 lam^2)`` in ``(0, 1)``; ``x' = -x0 lam (1 - k2) sn / dn^2``.
    - ``b x0^2 = -omega^2``: the oscillator sits at the top of the potential barrier (an
      unstable equilibrium), ``x = x0``.
    - ``b x0^2 < -omega^2``: released beyond the separatrix; the motion is unbounded and a
      ValueError is raised.

    Parameters
    ----------
    t : array_like
        Times (>= 0), any shape.
    omega : float
        Linear natural frequency (rad/s), ``>= 0`` (``0`` gives the pure cubic oscillator).
    b : float
        Cubic stiffness per unit mass; any sign (``b < 0`` is a softening spring).
    x0 : float
        Initial displacement (the initial velocity is zero).

    Returns
    -------
    x, v : ndarray
        Displacement and velocity, shaped like `t`.

    Raises
    ------
    ValueError
        If the softening motion is unbounded (``omega^2 + b x0^2 < 0``), if `t` is negative
        or not finite, or if `omega` is negative.

    See Also
    --------
    duffing_period : The period of this motion.

    Examples
    --------
    The paper's case ``b x0^2 = 4 omega^2`` returns to ``x0`` after one period:

    >>> import numpy as np
    >>> from duhamel import exact
    >>> period = exact.duffing_period(omega=1.0, b=4.0, x0=1.0)
    >>> round(period, 6)
    3.179723
    >>> x, v = exact.duffing([0.0, period / 2, period], omega=1.0, b=4.0, x0=1.0)
    >>> np.round(x, 12).tolist(), bool(np.abs(v).max() < 1e-12)
    ([1.0, -1.0, 1.0], True)
    """
    t = _times(t)
    rate, m, kind = _duffing_params(omega, b, x0)
    x0 = float(x0)
    if kind == "rest":
        return np.full_like(t, x0), np.zeros_like(t)
    quarter = float(sc.ellipk(m))
    cycles = rate * float(np.max(t, initial=0.0)) / (4.0 * quarter)
    if not cycles < 2.0**52:
        raise ValueError(
            f"`t`: {cycles:.3g} periods of the motion (`b` = {b:g}, `x0` = {x0:g}) elapse by "
            "the last time, beyond what a double resolves: the phase would be meaningless"
        )
    u = _reduce(rate * t, quarter)
    sn, cn, dn, _ = sc.ellipj(u, m)
    if kind == "cn":
        return x0 * cn, -x0 * rate * sn * dn
    return x0 * cn / dn, -x0 * rate * (1.0 - m) * sn / (dn * dn)


def duffing_period(omega: float, b: float, x0: float) -> float:
    """Period of the motion returned by :func:`duffing`.

    ``4 K(m) / Omega`` for ``b x0^2 >= 0`` and ``4 K(k2) / lam`` for bounded softening (see
    :func:`duffing` for the symbols); ``inf`` when the oscillator rests at an equilibrium
    (``x0 = 0`` with ``omega = 0``, or ``b x0^2 = -omega^2``). For ``x0 = 0`` and
    ``omega > 0`` this is the linear period ``2 pi / omega``.

    Parameters
    ----------
    omega, b, x0 : float
        As in :func:`duffing`.

    Returns
    -------
    float
        The period (s).

    Examples
    --------
    A softening spring lengthens the period, a hardening one shortens it:

    >>> from duhamel import exact
    >>> [round(exact.duffing_period(omega=1.0, b=b, x0=1.0), 6) for b in (-0.5, 0.0, 4.0)]
    [8.008619, 6.283185, 3.179723]
    """
    rate, m, kind = _duffing_params(omega, b, x0)
    if kind == "rest":
        w = float(omega)
        return 2.0 * math.pi / w if float(x0) == 0.0 and w > 0.0 else math.inf
    return 4.0 * float(sc.ellipk(m)) / rate
