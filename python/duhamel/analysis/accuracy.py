"""Accuracy measures: period and damping errors, local truncation errors, convergence orders."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, positive_float
from duhamel.analysis._linear import check_system, modal_model
from duhamel.analysis.convergence import Convergence, ReferenceProblem, convergence_order
from duhamel.analysis.matrices import _spectrum, amplification_matrix
from duhamel.system import System

__all__ = [
    "Convergence",
    "ModalErrors",
    "ReferenceProblem",
    "convergence_order",
    "damping_error",
    "local_truncation_error",
    "modal_errors",
    "one_step_error",
    "period_error",
]

Array = NDArray[np.float64]

#: An exact eigenvalue ``s`` with ``Im(s) > OSCILLATORY_RTOL |s|`` belongs to an oscillatory
#: mode (critically damped, overdamped and rigid-body modes are left out).
OSCILLATORY_RTOL = 1e-7
#: A mode with ``|zeta| <= ZERO_ZETA`` is undamped: its damping error is absolute.
ZERO_ZETA = 1e-12


@dataclass(frozen=True)
class ModalErrors:
    """Period and damping errors of every oscillatory mode (see :func:`modal_errors`).

    All arrays have shape ``(n_osc,)``, one entry per oscillatory mode of the exact system,
    ordered by ``omega``.

    Attributes
    ----------
    omega : ndarray
        ``|s|`` of the exact eigenvalue ``s`` (the undamped natural frequency of a
        classically damped mode).
    zeta, period : ndarray
        Exact damping ratio ``-Re(s)/|s|`` and damped period ``2 pi / Im(s)``.
    eigenvalue, exact_eigenvalue : ndarray of complex
        The principal eigenvalue of the amplification matrix and ``exp(s dt)``.
    zeta_num, period_num : ndarray
        The same measures of ``s_num = log(eigenvalue) / dt`` (on the branch nearest the
        exact ``s dt``; ``period_num`` is inf for a real positive eigenvalue).
    period_error : ndarray
        ``(period_num - period) / period``.
    damping_error : ndarray
        ``(zeta_num - zeta) / zeta``, or ``zeta_num`` (absolute) where ``|zeta| <= 1e-12``.
    """

    omega: Array
    zeta: Array
    period: Array
    eigenvalue: NDArray[np.complex128]
    exact_eigenvalue: NDArray[np.complex128]
    zeta_num: Array
    period_num: Array
    period_error: Array
    damping_error: Array


def _ratios(s: NDArray[np.complex128]) -> tuple[Array, Array]:
    """Damping ratio ``-Re(s)/|s|`` and period ``2 pi/Im(s)`` (inf for ``Im(s) == 0``)."""
    mag = np.abs(s)
    zeta = np.divide(-s.real, mag, out=np.zeros(s.shape), where=mag > 0)
    with np.errstate(divide="ignore"):
        period = np.where(s.imag != 0.0, 2.0 * np.pi / np.abs(s.imag), np.inf)
    return zeta, period


def _principal(pair: NDArray[np.complex128], s: complex, dt: float) -> tuple[complex, complex]:
    """The principal eigenvalue of the two assigned to an exact pair, and its ``s_num``.

    Of the complex candidates and the branches of their logarithms, the phase nearest the
    exact ``Im(s) dt``; with no complex candidate, the real one of larger modulus on the
    principal branch.
    """
    pair = pair[np.isfinite(pair)]
    if pair.size == 0:  # the realization did not reveal this mode
        return complex(np.nan, np.nan), complex(np.nan, np.nan)
    complex_ones = pair[pair.imag != 0.0]
    if complex_ones.size == 0:
        lam = complex(pair[np.argmax(np.abs(pair))])
        with np.errstate(divide="ignore"):
            return lam, complex(np.log(lam)) / dt
    logs = np.log(complex_ones)
    turns = np.round((s.imag * dt - logs.imag) / (2.0 * np.pi))
    logs = logs + 2j * np.pi * turns
    best = int(np.argmin(np.abs(logs.imag - s.imag * dt)))
    return complex(complex_ones[best]), complex(logs[best]) / dt


def modal_errors(system: System, integrator: Any, dt: float) -> ModalErrors:
    """Period elongation and algorithmic damping of each mode, from the principal eigenvalues.

    The exact eigenvalues ``s`` of the linear system (all linear elements included, as in
    :func:`~duhamel.analysis.exact_transition_matrix`) and the eigenvalues of the step
    (:func:`~duhamel.analysis.amplification_eigenvalues`: of the amplification matrix, or
    of the realized step of an integrator that carries its acceleration, whose spurious
    eigenvalues then take part in the assignment) are computed in the modal coordinates of
    ``system.modal(integrator.modes)`` (all modes for integrators without ``modes``). Each
    numerical eigenvalue is assigned to one exact eigenvalue by maximising the total cosine
    similarity of the eigenvectors (``scipy.optimize.linear_sum_assignment``), so the modes
    are told apart by shape, not by frequency. For every oscillatory exact pair
    ``(s, conj(s))`` with ``Im(s) > 0``, the principal numerical eigenvalue ``lambda`` is the
    one of the two assigned to the pair, and ``log(lambda)`` the branch of the logarithm,
    whose phase is nearest the exact phase ``Im(s) dt`` (for ``dt`` below half a period and
    a phase error below half a turn: the eigenvalue in the upper half-plane and the principal
    logarithm); if both are real, the larger in modulus on the principal branch
    (``period_num`` inf if it is positive, ``2 dt`` if negative). Then
    ``s_num = log(lambda) / dt`` and, following NOTES.md section 2 (the convention under
    which the paper's eqs. 24a and 24b hold),

        period = 2 pi / Im(s)            (the damped period)
        zeta   = -Re(s) / |s|            (the same for s_num)

    An exact step thus reports zero errors at any ``dt``; beyond ``dt ~ period / 2`` the
    phase of one step is ambiguous modulo a turn and the period error of an approximate
    step means little. Modes that are not oscillatory (rigid-body, critically or
    over-damped) are left out.

    Parameters
    ----------
    system : System
        Linear model (as for :func:`~duhamel.analysis.amplification_matrix`).
    integrator : object
        Any integrator :func:`duhamel.solve` accepts, or
        :class:`~duhamel.analysis.ClosedFormNewmark`.
    dt : float
        Step, > 0.

    Returns
    -------
    ModalErrors

    Examples
    --------
    Scheme (b) with damping as a pseudo-force against the paper's eqs. 24a and 24b:

    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import modal_errors
    >>> w, z, dt = 1.0, 0.1, 0.01
    >>> oscillator = duhamel.System([[1.0]], [[w * w]]).add(duhamel.elements.Damper(0, c=2 * z * w))
    >>> errors = modal_errors(oscillator, duhamel.Semianalytic(scheme="b"), dt)
    >>> eq24a = -(3 - 4 * z**2) * z**2 * (w * dt) ** 2 / (12 * (1 - z**2))
    >>> eq24b = -(1 - 2 * z**2) * (w * dt) ** 2 / 12
    >>> ratios = errors.period_error[0] / eq24a, errors.damping_error[0] / eq24b
    >>> [round(float(r), 4) for r in ratios]
    [1.0, 1.0]
    """
    system = check_system(system)
    dt = positive_float(dt, "dt")
    model = modal_model(system, getattr(integrator, "modes", None))
    s, vec = np.linalg.eig(model.state_matrix())
    spectrum = _spectrum(system, integrator, dt)
    lam, wec = spectrum.eigenvalues, model.project(spectrum.vectors)
    cosine = np.abs(vec.conj().T @ wec)
    cosine /= np.linalg.norm(vec, axis=0)[:, None] * np.linalg.norm(wec, axis=0)[None, :]
    from scipy.optimize import linear_sum_assignment  # 0.4 s to import: only here

    rows, cols = linear_sum_assignment(-cosine)
    assigned = np.full(s.size, np.nan, dtype=complex)  # numerical eigenvalue of each exact one
    assigned[rows] = lam[cols]
    scale = np.abs(s)
    osc = np.flatnonzero(s.imag > OSCILLATORY_RTOL * scale)
    principal = np.empty(osc.size, dtype=complex)
    s_num = np.empty(osc.size, dtype=complex)
    for out, k in enumerate(osc):
        distance = np.abs(s - np.conj(s[k]))
        distance[k] = np.inf
        pair = assigned[[k, int(np.argmin(distance))]]
        principal[out], s_num[out] = _principal(pair, s[k], dt)
    order = np.lexsort((s[osc].imag, scale[osc]))
    s_exact, principal, s_num = s[osc][order], principal[order], s_num[order]
    zeta, period = _ratios(s_exact)
    zeta_num, period_num = _ratios(s_num)
    damped = np.abs(zeta) > ZERO_ZETA
    with np.errstate(invalid="ignore"):
        period_error = (period_num - period) / period
        damping_error = np.where(damped, (zeta_num - zeta) / np.where(damped, zeta, 1.0), zeta_num)
    return ModalErrors(
        omega=scale[osc][order],
        zeta=zeta,
        period=period,
        eigenvalue=principal,
        exact_eigenvalue=np.exp(s_exact * dt),
        zeta_num=zeta_num,
        period_num=period_num,
        period_error=period_error,
        damping_error=damping_error,
    )


def period_error(system: System, integrator: Any, dt: float) -> Array:
    """Relative period elongation ``(T_num - T) / T`` of each oscillatory mode.

    ``T`` is the exact damped period ``2 pi / Im(s)`` and ``T_num`` that of
    ``s_num = log(lambda) / dt`` for the principal eigenvalue ``lambda`` of the
    amplification matrix; see :func:`modal_errors` for how modes are matched.

    Returns
    -------
    ndarray, shape (n_osc,)
        One entry per oscillatory mode, by increasing frequency (one for a 1-dof oscillator).

    Examples
    --------
    >>> import duhamel
    >>> from duhamel.analysis import ClosedFormNewmark, period_error
    >>> oscillator = duhamel.System([[1.0]], [[1.0]])
    >>> dt = 0.01
    >>> round(float(period_error(oscillator, ClosedFormNewmark(), dt)[0]) / (dt**2 / 12), 4)
    1.0
    """
    return modal_errors(system, integrator, dt).period_error


def damping_error(system: System, integrator: Any, dt: float) -> Array:
    """Algorithmic damping ``(zeta_num - zeta) / zeta`` of each oscillatory mode.

    ``zeta = -Re(s)/|s|`` for the exact eigenvalue and ``zeta_num`` the same for
    ``s_num = log(lambda) / dt``. For an undamped mode (``|zeta| <= 1e-12``) the relative
    error is undefined and the absolute algorithmic damping ratio ``zeta_num`` is returned
    instead. See :func:`modal_errors`.

    Returns
    -------
    ndarray, shape (n_osc,)

    Examples
    --------
    The exact semi-analytic step on a classically damped background has no algorithmic
    damping:

    >>> import duhamel
    >>> from duhamel.analysis import damping_error
    >>> oscillator = duhamel.System([[1.0]], [[1.0]], zeta=0.05)
    >>> abs(float(damping_error(oscillator, duhamel.Semianalytic(), dt=0.3)[0])) < 1e-12
    True
    """
    return modal_errors(system, integrator, dt).damping_error


def _state(value: ArrayLike, name: str, n: int) -> Array:
    arr = as_float_array(value, name)
    if arr.ndim == 0 and n == 1:
        arr = arr.reshape(1)
    if arr.shape != (n,):
        raise ValueError(f"`{name}` must have shape ({n},), got {arr.shape}")
    return arr


def local_truncation_error(
    system: System, integrator: Any, dt: float, x0: ArrayLike, v0: ArrayLike
) -> float:
    """Hughes' local truncation error ``tau`` of a 1-dof linear oscillator (the paper's eq. 23).

    Eliminating the velocity from ``y_{k+1} = A y_k`` (Cayley-Hamilton) gives the two-step
    displacement recurrence ``x_{k+1} - 2 A1 x_k + A2 x_{k-1} = 0`` with ``A1 = tr(A)/2``
    and ``A2 = det(A)``. The local truncation error is what the exact solution leaves in it,

        tau = [x(t0 + dt) - 2 A1 x(t0) + A2 x(t0 - dt)] / dt^2,

    where ``x(t)`` is the exact free vibration with ``x(t0) = x0``, ``x'(t0) = v0``: the
    error of one step of the recurrence started from exact values, divided by ``dt^2``
    (T. J. R. Hughes, *The Finite Element Method*, 1987, section 9.1). An algorithm is of
    order ``k`` when ``tau = O(dt^k)``. This is the measure of the paper's eqs. 23, 26, 27.
    For an integrator that carries more state (e.g. HHT-alpha: ``m = 3`` eigenvalues, see
    :func:`~duhamel.analysis.amplification_eigenvalues`) the recurrence is the
    characteristic polynomial ``sum_k c_k lambda^(m-k)`` of its step, and
    ``tau = sum_k c_k x(t0 + (1 - k) dt) / dt^2``, Hughes' form for such methods.

    Parameters
    ----------
    system : System
        A linear 1-dof model (as for :func:`~duhamel.analysis.amplification_matrix`); use
        :func:`one_step_error` for more degrees of freedom.
    integrator : object
        Any integrator :func:`duhamel.solve` accepts, or
        :class:`~duhamel.analysis.ClosedFormNewmark`.
    dt : float
        Step, > 0.
    x0, v0 : float or array_like of shape (1,)
        The exact state at ``t0``.

    Returns
    -------
    float

    Examples
    --------
    Scheme (b) against the paper's eq. 23b,
    ``tau = [zeta x0 - (1 - 4 zeta^2) v0 / (2 omega)] zeta omega^4 dt^2 / 3``:

    >>> import duhamel
    >>> from duhamel.analysis import local_truncation_error
    >>> w, z, dt = 1.0, 0.1, 0.01
    >>> oscillator = duhamel.System([[1.0]], [[w * w]]).add(duhamel.elements.Damper(0, c=2 * z * w))
    >>> tau = local_truncation_error(oscillator, duhamel.Semianalytic(scheme="b"), dt, 0.0, 1.0)
    >>> eq23b = -(1 - 4 * z**2) / (2 * w) * z * w**4 * dt**2 / 3
    >>> round(tau / eq23b, 3)
    0.999
    """
    system = check_system(system)
    if system.n_dof != 1:
        raise ValueError(
            f"`system` must have one degree of freedom for Hughes' local truncation error, "
            f"got {system.n_dof} (use one_step_error)"
        )
    dt = positive_float(dt, "dt")
    y0 = np.concatenate([_state(x0, "x0", 1), _state(v0, "v0", 1)])
    spectrum = _spectrum(system, integrator, dt)
    if spectrum.one_step:  # tr and det of the matrix itself: no round-off of eigenvalues
        a = amplification_matrix(system, integrator, dt, check=False)
        coeffs = np.array([1.0, -np.trace(a), np.linalg.det(a)])
    else:
        coeffs = np.real(np.poly(spectrum.eigenvalues))
    model = modal_model(system, None)
    x = [(model.to_physical(model.transition((1 - k) * dt)) @ y0)[0] for k in range(coeffs.size)]
    return float(np.dot(coeffs, x) / (dt * dt))


def one_step_error(
    system: System, integrator: Any, dt: float, x0: ArrayLike, v0: ArrayLike
) -> Array:
    """The error of one step started from an exact state: ``expm(S dt) y0 - A y0``.

    ``y0 = (x0, v0)``, ``A`` the map of the first step (:func:`amplification_matrix` with
    ``check=False``: for an integrator that carries its own acceleration, the step that
    starts from the equilibrium acceleration), ``expm(S dt)`` the exact transition matrix
    (on the integrator's modal basis, see
    :func:`~duhamel.analysis.exact_transition_matrix`). For an algorithm of order ``k`` it
    is ``O(dt^(k+1))``. Works for any number of degrees of freedom.

    Returns
    -------
    ndarray, shape (2 n,)
        Displacement errors, then velocity errors.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import ClosedFormNewmark, one_step_error
    >>> two_dof = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 2.0]])
    >>> e = [one_step_error(two_dof, ClosedFormNewmark(), h, [1.0, 0.0], [0.0, 0.0])
    ...      for h in (0.02, 0.01)]
    >>> round(float(np.log2(np.abs(e[0]).max() / np.abs(e[1]).max())), 2)   # order 2 + 1
    3.0
    """
    system = check_system(system)
    dt = positive_float(dt, "dt")
    n = system.n_dof
    y0 = np.concatenate([_state(x0, "x0", n), _state(v0, "v0", n)])
    a = amplification_matrix(system, integrator, dt, check=False)
    model = modal_model(system, getattr(integrator, "modes", None))
    return np.asarray(model.to_physical(model.transition(dt)) @ y0 - a @ y0)
