"""Linear time-invariant systems under polynomial or harmonic loads, exactly: the matrix
exponential of an augmented first-order system."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike

from duhamel._engine.validate import as_float_array, finite_float, issparse
from duhamel.exact._common import Array
from duhamel.exact._common import times as _times
from duhamel.system import System

__all__ = ["linear"]

#: Largest number of float64 entries held at once by the stacked matrix exponentials of
#: :func:`linear` (about 32 MB).
_EXPM_BATCH_ENTRIES = 4_000_000


def _dense(mat: Any) -> Array:
    return np.asarray(mat.toarray() if issparse(mat) else mat, dtype=np.float64)


def _damping_matrix(system: System) -> Array:
    if system.C is not None:
        return _dense(system.C)
    if system.rayleigh is not None:
        alpha, beta = system.rayleigh
        return alpha * _dense(system.M) + beta * _dense(system.K)
    basis = system.modal(None)
    mphi = _dense(system.M) @ basis.phi
    return (mphi * basis.c) @ mphi.T


def _load_block(load: Any, n_dof: int) -> tuple[Array, Array, Array]:
    """Return ``(B, N, w0)``: f(t) = B w(t) with w' = N w, w(0) = w0."""
    if load is None:
        return np.zeros((n_dof, 0)), np.zeros((0, 0)), np.zeros(0)
    if not isinstance(load, tuple) or not load or not isinstance(load[0], str):
        raise TypeError(
            "`load` must be None, ('polynomial', coeffs) or "
            f"('harmonic', amplitude, Omega, phase), got {type(load).__name__}"
        )
    kind = load[0]
    if kind == "polynomial":
        if len(load) != 2:
            raise ValueError(f"`load` ('polynomial', coeffs) must have 2 entries, got {len(load)}")
        coeffs = as_float_array(load[1], "coeffs", ndim=2)
        if coeffs.shape[0] < 1 or coeffs.shape[1] != n_dof:
            raise ValueError(
                f"`coeffs` must have shape (n_terms, n_dof) = (>= 1, {n_dof}), got {coeffs.shape}"
            )
        p = coeffs.shape[0]
        # w_k = t^k / k!, w_k' = w_{k-1}; f = sum_k coeffs[k] k! w_k
        factorials = np.array([math.factorial(k) for k in range(p)], dtype=np.float64)
        shift = np.eye(p, k=-1)
        w0 = np.zeros(p)
        w0[0] = 1.0
        return (coeffs * factorials[:, None]).T, shift, w0
    if kind == "harmonic":
        if len(load) != 4:
            raise ValueError(
                f"`load` ('harmonic', amplitude, Omega, phase) must have 4 entries, got {len(load)}"
            )
        amplitude = as_float_array(load[1], "amplitude", shape=(n_dof,))
        big = finite_float(load[2], "Omega")
        phase = finite_float(load[3], "phase")
        # w = (sin(Omega t + phase), cos(Omega t + phase))
        rot = np.array([[0.0, big], [-big, 0.0]])
        block = np.zeros((n_dof, 2))
        block[:, 0] = amplitude
        return block, rot, np.array([math.sin(phase), math.cos(phase)])
    raise ValueError(f"`load` kind must be 'polynomial' or 'harmonic', got {kind!r}")


def linear(
    system: System,
    t: ArrayLike,
    x0: ArrayLike,
    v0: ArrayLike,
    load: tuple[Any, ...] | None = None,
) -> tuple[Array, Array]:
    """Exact response of a linear time-invariant system (a reference, not a solver).

    Solves ``M x'' + C x' + K x = f(t)`` with ``x(0) = x0``, ``x'(0) = v0``, writing the load
    as ``f = B w`` with ``w' = N w`` (polynomial: ``w_k = t^k / k!``; harmonic:
    ``w = (sin(Omega t + phase), cos(Omega t + phase))``) and evaluating
    ``[z; w](t) = expm(t [[F, G B], [0, N]]) [z0; w0]`` for the state ``z = (x, x')`` with
    ``F = [[0, I], [-M^-1 K, -M^-1 C]]`` and ``G = [0; M^-1]``, separately at every time (no
    error accumulates over steps). The damping matrix is `system.C` when given,
    ``alpha M + beta K`` for Rayleigh damping, and ``M Phi diag(c) Phi^T M`` (the modal
    damping of ``system.modal()``) for damping ratios. Everything is dense: meant for small
    systems (up to a few hundred degrees of freedom).

    Parameters
    ----------
    system : System
        The model; its `loads` are ignored (the load is given by `load`).
    t : array_like, shape (n_t,)
        Times (>= 0).
    x0, v0 : array_like, shape (n_dof,)
        Initial displacements and velocities.
    load : tuple or None, optional
        ``None`` (free vibration), ``("polynomial", coeffs)`` with `coeffs` of shape
        ``(n_terms, n_dof)`` for ``f(t) = sum_k coeffs[k] t^k``, or
        ``("harmonic", amplitude, Omega, phase)`` with `amplitude` of shape ``(n_dof,)`` for
        ``f(t) = amplitude sin(Omega t + phase)``.

    Returns
    -------
    x, v : ndarray, shape (n_t, n_dof)
        Displacements and velocities.

    Raises
    ------
    TypeError
        If `system` is not a :class:`~duhamel.System` or `load` is not a tuple or None.
    ValueError
        If shapes do not match, values are not finite, `t` is negative, the load kind is
        unknown, or the damping is not defined for the full system (damping ratios `zeta`
        given for fewer modes than ``n_dof``).

    Examples
    --------
    A unit mass on a unit spring under a unit step force (a polynomial of degree 0):

    >>> import numpy as np
    >>> import duhamel
    >>> from duhamel import exact
    >>> system = duhamel.System([[1.0]], [[1.0]])
    >>> x, v = exact.linear(system, [0.0, np.pi], [0.0], [0.0], ("polynomial", [[1.0]]))
    >>> np.round(x[:, 0], 12).tolist()
    [0.0, 2.0]
    """
    if not isinstance(system, System):
        raise TypeError(f"`system` must be a duhamel.System, got {type(system).__name__}")
    times = _times(t)
    if times.ndim != 1:
        raise ValueError(f"`t` must be a 1-D array, got shape {times.shape}")
    n = system.n_dof
    x0 = as_float_array(x0, "x0", shape=(n,))
    v0 = as_float_array(v0, "v0", shape=(n,))
    block, shift, w0 = _load_block(load, n)
    m = _dense(system.M)
    k = _dense(system.K)
    c = _damping_matrix(system)
    minv_k, minv_c, minv_b = np.split(np.linalg.solve(m, np.hstack([k, c, block])), [n, 2 * n], 1)
    p = w0.size
    size = 2 * n + p
    aug = np.zeros((size, size))
    aug[:n, n : 2 * n] = np.eye(n)
    aug[n : 2 * n, :n] = -minv_k
    aug[n : 2 * n, n : 2 * n] = -minv_c
    aug[n : 2 * n, 2 * n :] = minv_b
    aug[2 * n :, 2 * n :] = shift
    start = np.concatenate([x0, v0, w0])
    out = np.empty((times.size, 2 * n))
    batch = max(1, _EXPM_BATCH_ENTRIES // (size * size))
    for lo in range(0, times.size, batch):
        chunk = times[lo : lo + batch]
        expo = scipy.linalg.expm(chunk[:, None, None] * aug)
        out[lo : lo + batch] = (expo @ start)[:, : 2 * n]
    return out[:, :n].copy(), out[:, n:].copy()
