"""Exact step matrices of one modal oscillator ``x'' + 2 zeta omega x' + omega^2 x = p(t)``.

Over a step ``dt`` the state ``y = (x, x')`` obeys Duhamel's integral
``y(dt) = A y(0) + B (p0, Dp, DDp)`` for a load that is the parabola
``p(t + s dt) = p0 + Dp s + 4 DDp s (1 - s)``, ``s`` in ``[0, 1]`` (``Dp = p1 - p0``,
``DDp = p(dt/2) - (p0 + p1)/2``). The matrices are computed in Rust to round-off in every
damping regime (negative, zero, light, critical, heavy damping, rigid-body modes
``omega = 0``) for ``omega * dt`` from 1e-8 to beyond 1e3.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._engine.validate import positive_float

__all__ = ["transfer_matrices", "transfer_moments"]


def _prepare(omega: ArrayLike, zeta: ArrayLike, dt: float) -> tuple[NDArray, NDArray, float, bool]:
    arrays = []
    for name, value in (("omega", omega), ("zeta", zeta)):
        try:
            arrays.append(np.asarray(value))
        except (ValueError, TypeError, OverflowError) as exc:
            raise ValueError(f"`{name}` could not be converted to an array: {exc}") from None
    w, z = arrays
    for name, arr in (("omega", w), ("zeta", z)):
        if arr.dtype.kind not in "iuf":
            raise TypeError(f"`{name}` must be real numbers, got dtype {arr.dtype}")
        if arr.ndim > 1:
            raise ValueError(f"`{name}` must be a scalar or a 1-D array, got shape {arr.shape}")
    scalar = w.ndim == 0 and z.ndim == 0
    try:
        w, z = np.broadcast_arrays(np.atleast_1d(w), np.atleast_1d(z))
    except ValueError:
        raise ValueError(
            f"`omega` and `zeta` must have the same length, got {w.size} and {z.size}"
        ) from None
    w = np.ascontiguousarray(w, dtype=np.float64)
    z = np.ascontiguousarray(z, dtype=np.float64)
    if not np.all(np.isfinite(w)) or np.any(w < 0):
        raise ValueError("`omega` must be finite and >= 0 (rad/s)")
    if not np.all(np.isfinite(z)):
        raise ValueError("`zeta` must be finite")
    dt = positive_float(dt, "dt")
    return w, z, dt, scalar


def transfer_matrices(
    omega: ArrayLike, zeta: ArrayLike, dt: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Exact transition matrix ``A`` and load-transfer matrix ``B`` of a modal oscillator.

    Parameters
    ----------
    omega : float or array_like
        Undamped natural frequency (rad/s), ``>= 0``; ``0`` is a rigid-body mode.
    zeta : float or array_like
        Damping ratio; any real value (negative: self-excited, ``> 1``: overdamped).
        Broadcast against `omega`.
    dt : float
        Step length, ``> 0``.

    Returns
    -------
    A : ndarray, shape (2, 2) or (n, 2, 2)
        ``(x, x')`` at the end of the step from ``(x, x')`` at its start, without load.
    B : ndarray, shape (2, 3) or (n, 2, 3)
        Response to the load basis ``(p0, Dp, DDp)`` (parabola through the load at the start,
        middle and end of the step), per unit modal mass.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.oscillator import transfer_matrices
    >>> A, B = transfer_matrices(2.0, 0.0, 0.1)
    >>> bool(np.isclose(A[0, 0], np.cos(0.2)))
    True
    >>> A, B = transfer_matrices([0.0, 1.0, 10.0], 1.0, 0.5)
    >>> A.shape, B.shape
    ((3, 2, 2), (3, 2, 3))
    """
    w, z, dt, scalar = _prepare(omega, zeta, dt)
    a, b = _core.transfer(w, z, dt, False)
    return (a[0], b[0]) if scalar else (a, b)


def transfer_moments(
    omega: ArrayLike, zeta: ArrayLike, dt: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Transition matrix and the Duhamel moments of ``(t/dt)^k``, ``k = 0..3``.

    ``M[:, k]`` is the state at the end of the step, from rest, under the load
    ``(t/dt)^k``; any load that is a cubic polynomial in time over the step is integrated
    exactly by ``A y0 + M @ coefficients``.

    Parameters
    ----------
    omega, zeta, dt
        As in :func:`transfer_matrices`.

    Returns
    -------
    A : ndarray, shape (2, 2) or (n, 2, 2)
    M : ndarray, shape (2, 4) or (n, 2, 4)

    Examples
    --------
    >>> from duhamel.oscillator import transfer_moments
    >>> A, M = transfer_moments(0.0, 0.0, 1.0)   # rigid body: M[0, k] = 1/((k+1)(k+2))
    >>> [round(float(m), 12) for m in M[0]]
    [0.5, 0.166666666667, 0.083333333333, 0.05]
    """
    w, z, dt, scalar = _prepare(omega, zeta, dt)
    a, m = _core.transfer(w, z, dt, True)
    return (a[0], m[0]) if scalar else (a, m)
