"""Oscillators with a time-varying mass: the pendulum with exponentially decaying mass
(section 4.2) and the Bessel solution for an exponentially varying mass (section 4.3)."""

from __future__ import annotations

import math

import numpy as np
import scipy.special as sc
from numpy.typing import ArrayLike

from duhamel._engine.validate import finite_float, positive_float
from duhamel.exact._common import Array
from duhamel.exact._common import times as _times

__all__ = ["bessel_mass", "decaying_mass_pendulum"]


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
