"""Exact reference solutions for verifying time integrators.

Each function evaluates a closed-form (or matrix-exponential) solution at the given times,
so that any integrator, in this package or elsewhere, can be checked against it to
round-off. The nonlinear and time-varying cases are the examples of Holl, Belyaev and
Irschik (1999), sections 4.1 to 4.3:

- :func:`duffing`: free vibration of the undamped Duffing oscillator (Jacobi ``cn``).
- :func:`duffing_period`: its period.
- :func:`decaying_mass_pendulum`: linearised pendulum whose mass decays exponentially,
  under a step load (the paper's eq. 31, with its sine coefficient corrected).
- :func:`bessel_mass`: free vibration with mass ``m0 K exp(-2 a omega t)`` (Bessel
  functions of order one, the paper's eq. 44).
- :func:`linear`: any linear time-invariant :class:`~duhamel.System` under a polynomial or
  harmonic load, by the matrix exponential of an augmented first-order system.

All times are measured from the initial instant ``t = 0`` and must be non-negative.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.special as sc
from numpy.typing import ArrayLike, NDArray

from duhamel._validate import as_float_array, finite_float, nonneg_float, positive_float
from duhamel.system import System

__all__ = ["bessel_mass", "decaying_mass_pendulum", "duffing", "duffing_period", "linear"]

#: Largest number of float64 entries held at once by the stacked matrix exponentials of
#: :func:`linear` (about 32 MB).
_EXPM_BATCH_ENTRIES = 4_000_000

Array = NDArray[np.float64]


def _times(t: ArrayLike) -> Array:
    arr = as_float_array(t, "t")
    if np.any(arr < 0.0):
        raise ValueError("`t` must be non-negative (times since the initial instant t = 0)")
    return arr


# --------------------------------------------------------------------------------------------
# Duffing oscillator
# --------------------------------------------------------------------------------------------


def _duffing_params(omega: Any, b: Any, x0: Any) -> tuple[float, float, str]:
    """Return ``(rate, m, kind)`` with x = x0 * f(rate t | m) (see :func:`duffing`)."""
    omega = nonneg_float(omega, "omega")
    b = finite_float(b, "b")
    x0 = finite_float(x0, "x0")
    bx2 = b * x0 * x0
    omega2 = omega * omega
    big2 = omega2 + bx2  # Omega^2
    if x0 == 0.0 or big2 == 0.0:
        # At rest at an equilibrium: the origin, or the top of the potential barrier.
        return 0.0, 0.0, "rest"
    if big2 < 0.0:
        raise ValueError(
            "the motion is unbounded: a softening spring (`b` < 0) released beyond the "
            f"separatrix, omega^2 + b x0^2 = {big2:.6g} < 0 (`x0`^2 must be below "
            "omega^2 / |b|)"
        )
    if bx2 >= 0.0:
        # x = x0 cn(Omega t | m), Omega^2 = omega^2 + b x0^2, m = b x0^2 / (2 Omega^2) in [0, 1/2]
        return math.sqrt(big2), bx2 / (2.0 * big2), "cn"
    # Softening, bounded: m < 0. cn(u | -mu) = cd(u sqrt(1 + mu) | mu / (1 + mu)), so
    # x = x0 cd(lam t | k2), lam^2 = omega^2 + b x0^2 / 2, k2 = -b x0^2 / (2 lam^2) in (0, 1).
    lam2 = omega2 + 0.5 * bx2
    return math.sqrt(lam2), -bx2 / (2.0 * lam2), "cd"


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


# --------------------------------------------------------------------------------------------
# Pendulum with exponentially decaying mass (section 4.2)
# --------------------------------------------------------------------------------------------


def decaying_mass_pendulum(
    t: ArrayLike,
    a: float,
    omega: float,
    w0: float,
    v0: float,
    f_step: float,
    m0: float = 1.0,
) -> tuple[Array, Array]:
    """Linearised pendulum with exponentially decaying mass under a step load.

    Solves ``(m w')' + m omega^2 w = f_step`` for ``t >= 0`` with ``m = m0 exp(-a omega t)``,
    ``w(0) = w0``, ``w'(0) = v0``. Dividing by ``m`` gives the paper's eq. 30,
    ``w'' - a omega w' + omega^2 w = (f_step / m0) exp(a omega t)``: an oscillator with
    negative damping ratio ``-a/2``. With ``wd = omega sqrt(1 - (a/2)^2)`` and the static
    deflection ``ws = f_step / (m0 omega^2)``, the solution is

    ``w = exp(a omega t / 2) (A cos(wd t) + B sin(wd t)) + ws exp(a omega t)``

    with ``A = w0 - ws`` and ``B = (v0 - a omega (w0 + ws) / 2) / wd``. (The particular
    solution ``C exp(a omega t)`` gives ``(a^2 - a^2 + 1) omega^2 C = f_step / m0``.) Divided by
    ``w0`` this is the paper's eq. 31, whose free-vibration sine coefficient must read
    ``(v0 / (w0 omega) - a/2) / sqrt(1 - (a/2)^2)``; the form used here also holds for
    ``w0 = 0``.

    Parameters
    ----------
    t : array_like
        Times (>= 0), any shape. The step is applied at ``t = 0``.
    a : float
        Mass decay rate (dimensionless, per radian of the linear oscillator), ``|a| < 2``.
        Negative values describe a growing mass (positive damping).
    omega : float
        Natural frequency of the linearised constant-mass pendulum (rad/s), ``> 0``.
    w0, v0 : float
        Initial angle and angular velocity.
    f_step : float
        Amplitude of the step load (a generalised force, like ``m omega^2 w``).
    m0 : float, optional
        Initial mass, ``> 0``.

    Returns
    -------
    w, wdot : ndarray
        Angle and angular velocity, shaped like `t`.

    Raises
    ------
    ValueError
        If ``|a| >= 2`` (not oscillatory), `omega` or `m0` is not positive, or `t` is
        negative.

    Examples
    --------
    The paper's case (``a = 1/10``, ``v0 / (w0 omega) = 2``, ``f_step / (m0 omega^2 w0) = 1``):

    >>> import numpy as np
    >>> from duhamel import exact
    >>> w, wdot = exact.decaying_mass_pendulum(
    ...     [0.0, 2 * np.pi], a=0.1, omega=1.0, w0=1.0, v0=2.0, f_step=1.0
    ... )
    >>> np.round(w, 6).tolist(), np.round(wdot, 6).tolist()
    ([1.0, 1.853987], [2.0, 2.787647])
    """
    t = _times(t)
    a = finite_float(a, "a")
    if not abs(a) < 2.0:
        raise ValueError(
            f"`a` must satisfy |a| < 2 (an oscillatory response, damping ratio -a/2), got {a!r}"
        )
    omega = positive_float(omega, "omega")
    w0 = finite_float(w0, "w0")
    v0 = finite_float(v0, "v0")
    f_step = finite_float(f_step, "f_step")
    m0 = positive_float(m0, "m0")
    wd = omega * math.sqrt(1.0 - 0.25 * a * a)
    sigma = 0.5 * a * omega  # growth rate of the free vibration
    ws = f_step / (m0 * omega * omega)
    c_amp = w0 - ws
    s_amp = (v0 - sigma * (w0 + ws)) / wd
    envelope = np.exp(sigma * t)
    cos, sin = np.cos(wd * t), np.sin(wd * t)
    forced = ws * envelope * envelope
    w = envelope * (c_amp * cos + s_amp * sin) + forced
    wdot = (
        envelope * ((sigma * c_amp + wd * s_amp) * cos + (sigma * s_amp - wd * c_amp) * sin)
        + 2.0 * sigma * forced
    )
    return w, wdot


# --------------------------------------------------------------------------------------------
# Exponentially varying mass, Bessel solution (section 4.3)
# --------------------------------------------------------------------------------------------


def bessel_mass(
    t: ArrayLike, a: float, K: float, omega: float, x0: float, v0: float
) -> tuple[Array, Array]:
    """Free vibration with exponentially varying mass, in Bessel functions of order one.

    Solves ``(m x')' + m0 omega^2 x = 0`` with ``m = m0 K exp(-2 a omega t)``, ``x(0) = x0``,
    ``x'(0) = v0``, i.e. ``x'' - 2 a omega x' + (omega^2 / K) exp(2 a omega t) x = 0``. With
    ``xi = exp(a omega t)`` this becomes ``xi^2 x_xixi - xi x_xi + (xi / chi)^2 x = 0``,
    ``chi = |a| sqrt(K)``, whose solution is (the paper's eq. 44)

    ``x = xi (C1 J1(xi / chi) + C2 Y1(xi / chi))``,
    ``x' = (a omega / chi) xi^2 (C1 J0(xi / chi) + C2 Y0(xi / chi))``

    (from ``d/dz (z J1(z)) = z J0(z)``). At ``t = 0`` (``xi = 1``, ``z0 = 1 / chi``) the
    Wronskian ``J1 Y0 - J0 Y1 = 2 / (pi z)`` gives, with ``u0 = chi v0 / (a omega)``,

    ``C1 = (pi / (2 chi)) (x0 Y0(z0) - u0 Y1(z0))``,
    ``C2 = (pi / (2 chi)) (u0 J1(z0) - x0 J0(z0))``.

    For ``a = 0`` the mass is constant and ``x = x0 cos(w t) + (v0 / w) sin(w t)``,
    ``w = omega / sqrt(K)``.

    Parameters
    ----------
    t : array_like
        Times (>= 0), any shape.
    a : float
        Mass decay rate (dimensionless): the mass decays for ``a > 0``, grows for ``a < 0``.
    K : float
        Initial mass ratio ``m(0) / m0``, ``> 0``.
    omega : float
        Reference natural frequency ``sqrt(k / m0)`` (rad/s), ``> 0``.
    x0, v0 : float
        Initial displacement and velocity.

    Returns
    -------
    x, v : ndarray
        Displacement and velocity, shaped like `t`.

    Raises
    ------
    ValueError
        If `K` or `omega` is not positive, or `t` is negative.

    Examples
    --------
    The paper's case ``a = 1/20``, ``K = 1`` (``chi = 1/20``): as the mass decays, the
    frequency grows and the amplitude shrinks.

    >>> import numpy as np
    >>> from duhamel import exact
    >>> x, v = exact.bessel_mass([0.0, 10.0, 20.0], a=0.05, K=1.0, omega=1.0, x0=1.0, v0=0.0)
    >>> np.round(x, 6).tolist(), np.round(v, 6).tolist()
    ([1.0, 1.169464, -1.622304], [0.0, -0.844662, -0.837189])
    """
    t = _times(t)
    a = finite_float(a, "a")
    K = positive_float(K, "K")
    omega = positive_float(omega, "omega")
    x0 = finite_float(x0, "x0")
    v0 = finite_float(v0, "v0")
    if a == 0.0:
        w = omega / math.sqrt(K)
        cos, sin = np.cos(w * t), np.sin(w * t)
        return x0 * cos + (v0 / w) * sin, v0 * cos - x0 * w * sin
    chi = abs(a) * math.sqrt(K)
    rate = a * omega
    z0 = 1.0 / chi
    u0 = chi * v0 / rate
    c1 = (math.pi / (2.0 * chi)) * (x0 * sc.y0(z0) - u0 * sc.y1(z0))
    c2 = (math.pi / (2.0 * chi)) * (u0 * sc.j1(z0) - x0 * sc.j0(z0))
    xi = np.exp(rate * t)
    z = xi / chi
    x = xi * (c1 * sc.j1(z) + c2 * sc.y1(z))
    v = (rate / chi) * xi * xi * (c1 * sc.j0(z) + c2 * sc.y0(z))
    return x, v


# --------------------------------------------------------------------------------------------
# Linear time-invariant systems (matrix exponential)
# --------------------------------------------------------------------------------------------


def _dense(mat: Any) -> Array:
    return np.asarray(mat.toarray() if sp.issparse(mat) else mat, dtype=np.float64)


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
