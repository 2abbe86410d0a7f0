"""Amplification matrices: by stepping unit states with any integrator, exact, and Newmark's."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float, positive_float
from duhamel.analysis._linear import ModalModel, check_system, modal_model, unloaded
from duhamel.errors import AccuracyWarning
from duhamel.prepared import solve
from duhamel.system import System

__all__ = [
    "ClosedFormNewmark",
    "amplification_eigenvalues",
    "amplification_matrix",
    "exact_transition_matrix",
    "newmark_amplification",
    "spectral_radius",
]

Array = NDArray[np.float64]

#: Relative tolerance of the one-step check of :func:`amplification_matrix`: two steps must
#: equal the square of one step to this fraction of its squared largest entry (in the
#: state ``(x, v / omega)``; round-off is ~1e-15).
ONE_STEP_RTOL = 1e-8


@dataclass(frozen=True)
class ClosedFormNewmark:
    """Newmark's method as a closed-form amplification matrix (not a solver).

    Accepted by the functions of :mod:`duhamel.analysis` in place of an integrator: the
    amplification matrix is computed from the system's matrices by the textbook formula
    (see :func:`newmark_amplification`), not by stepping. It is a reference that does not
    depend on any time-stepping implementation; :func:`duhamel.solve` does not accept it.

    Parameters
    ----------
    gamma, beta : float
        Newmark's parameters; the default ``(1/2, 1/4)`` is the average-acceleration
        (trapezoidal) rule.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import ClosedFormNewmark, spectral_radius
    >>> oscillator = duhamel.System([[1.0]], [[1.0]])
    >>> round(spectral_radius(oscillator, ClosedFormNewmark(), dt=100.0), 12)
    1.0
    """

    gamma: float = 0.5
    beta: float = 0.25

    def __post_init__(self) -> None:
        object.__setattr__(self, "gamma", finite_float(self.gamma, "gamma"))
        object.__setattr__(self, "beta", finite_float(self.beta, "beta"))


def _newmark_blocks(
    k: Any, c: Any, dt: Any, gamma: float, beta: float, eye: Any = 1.0
) -> tuple[Any, Any]:
    """``L`` and ``R`` of Newmark's step ``L (x1, v1) = R (x0, v0)`` for ``x'' + c x' + k x = 0``.

    Blocks as nested lists (scalars/arrays broadcast, or matrices with ``eye`` the identity).
    """
    h2 = dt * dt
    lhs = [[eye + beta * h2 * k, beta * h2 * c], [gamma * dt * k, eye + gamma * dt * c]]
    rhs = [
        [eye - (0.5 - beta) * h2 * k, dt * eye - (0.5 - beta) * h2 * c],
        [-(1.0 - gamma) * dt * k, eye - (1.0 - gamma) * dt * c],
    ]
    return lhs, rhs


def _newmark_modal(model: ModalModel, dt: float, gamma: float, beta: float) -> Array:
    eye = np.eye(model.n_modes)
    lhs, rhs = _newmark_blocks(model.k_q, model.c_q, dt, gamma, beta, eye)
    return np.asarray(np.linalg.solve(np.block(lhs), np.block(rhs)), dtype=np.float64)


def _alpha_sign(value: Any) -> int:
    if isinstance(value, bool | np.bool_) or value not in (1, -1):
        raise ValueError(f"`alpha_sign` must be +1 or -1, got {value!r}")
    return int(value)


def newmark_amplification(
    omega: ArrayLike,
    zeta: ArrayLike,
    dt: ArrayLike,
    gamma: float,
    beta: float,
    alpha: float = 0.0,
    *,
    alpha_sign: int = 1,
) -> Array:
    """Newmark's amplification matrix of ``x'' + 2 zeta omega x' + omega^2 x = s alpha omega^2 x``.

    With ``k = (1 - s alpha) omega^2`` (``s`` = `alpha_sign`) and ``c = 2 zeta omega``, the
    accelerations satisfy the equation of motion at both ends of the step,
    ``a_i = -(c v_i + k x_i)``, and Newmark's updates

        x1 = x0 + dt v0 + dt^2 ((1/2 - beta) a0 + beta a1),
        v1 = v0 + dt ((1 - gamma) a0 + gamma a1)

    give ``L (x1, v1) = R (x0, v0)`` with ``L = [[1 + beta dt^2 k, beta dt^2 c], [gamma dt k,
    1 + gamma dt c]]`` and ``R = [[1 - (1/2 - beta) dt^2 k, dt - (1/2 - beta) dt^2 c],
    [-(1 - gamma) dt k, 1 - (1 - gamma) dt c]]``; the result is ``L^-1 R``, evaluated in
    closed form (``det L = 1 + gamma dt c + beta dt^2 k``). The whole right-hand side
    ``s alpha omega^2 x`` is treated implicitly, as a direct integrator does.

    Parameters
    ----------
    omega, zeta, dt : array_like
        Natural frequency (rad/s, >= 0), damping ratio and step (> 0); broadcast together.
    gamma, beta : float
        Newmark's parameters (``1/2, 1/4``: average acceleration).
    alpha : float
        The extra stiffness term of the paper's eq. 25 (0: a plain damped oscillator).
    alpha_sign : {+1, -1}
        Sign ``s`` of the right-hand side ``s alpha omega^2 x``: +1 is the form consistent
        with the paper's eqs. 26 and 27, -1 the form printed in its eq. 25 (see
        ``docs/analysis.md``).

    Returns
    -------
    ndarray, shape (..., 2, 2)
        Maps ``(x, v)`` at ``t`` to ``t + dt``; the leading shape is that of the broadcast
        inputs.

    Examples
    --------
    Average acceleration conserves energy (spectral radius 1) for any step:

    >>> import numpy as np
    >>> from duhamel.analysis import newmark_amplification
    >>> A = newmark_amplification(1.0, 0.0, [0.1, 10.0, 1e3], 0.5, 0.25)
    >>> A.shape
    (3, 2, 2)
    >>> np.round(np.abs(np.linalg.eigvals(A)).max(axis=1), 12).tolist()
    [1.0, 1.0, 1.0]
    """
    w = as_float_array(omega, "omega")
    z = as_float_array(zeta, "zeta")
    h = as_float_array(dt, "dt")
    if np.any(w < 0.0):
        raise ValueError("`omega` must be non-negative")
    if np.any(h <= 0.0):
        raise ValueError("`dt` must be positive")
    gamma = finite_float(gamma, "gamma")
    beta = finite_float(beta, "beta")
    alpha = finite_float(alpha, "alpha")
    sign = _alpha_sign(alpha_sign)
    w, z, h = np.broadcast_arrays(w, z, h)
    k = (1.0 - sign * alpha) * w * w
    c = 2.0 * z * w
    (l11, l12), (l21, l22) = _newmark_blocks(k, c, h, gamma, beta)[0]
    (r11, r12), (r21, r22) = _newmark_blocks(k, c, h, gamma, beta)[1]
    det = l11 * l22 - l12 * l21
    out = np.empty((*w.shape, 2, 2))
    out[..., 0, 0] = (l22 * r11 - l12 * r21) / det
    out[..., 0, 1] = (l22 * r12 - l12 * r22) / det
    out[..., 1, 0] = (l11 * r21 - l21 * r11) / det
    out[..., 1, 1] = (l11 * r22 - l21 * r12) / det
    return out


def _unit_responses(system: System, integrator: Any, dt: float, steps: int) -> Array:
    """``Y[k]``: the state after ``k`` steps from each unit state (columns), k = 0..steps."""
    free = unloaded(system)
    n = system.n_dof
    out = np.empty((steps + 1, 2 * n, 2 * n))
    for j in range(2 * n):
        start = np.zeros(2 * n)
        start[j] = 1.0
        with warnings.catch_warnings():  # a few steps from a unit state: not a result
            warnings.simplefilter("ignore", AccuracyWarning)
            sol = solve(free, integrator, t_end=steps * dt, dt=dt, x0=start[:n], v0=start[n:])
        out[:, :n, j] = sol.x[: steps + 1]
        out[:, n:, j] = sol.v[: steps + 1]
    return out


def _velocity_scale(system: System, integrator: Any, dt: float) -> tuple[Array, float]:
    """Scale ``(1, .., 1/omega_ref, ..)`` of the state ``(x, v)`` and ``h = omega_ref dt``.

    ``omega_ref`` is the highest natural frequency of the modes used (``1/dt`` if there is
    none): in ``(x, v / omega_ref)`` the entries of a step are O(1) whatever the units.
    """
    omega = np.asarray(system.modal(getattr(integrator, "modes", None)).omega)
    ref = float(omega.max()) if omega.size and omega.max() > 0.0 else 1.0 / dt
    n = system.n_dof
    return np.concatenate([np.ones(n), np.full(n, 1.0 / ref)]), ref * dt


def _scaled(a: Array, scale: Array) -> Array:
    return a * scale[..., :, None] / scale[..., None, :]


def _one_step_excess(ys: Array, scale: Array) -> float:
    """How far two steps are from the first step applied twice (relative, scaled state)."""
    a, b = _scaled(ys[1], scale), _scaled(ys[2], scale)
    return float(np.max(np.abs(b - a @ a))) / max(1.0, float(np.max(np.abs(a)))) ** 2


@dataclass(frozen=True, eq=False)
class _Spectrum:
    """Eigenvalues of the step and the ``(x, v)`` parts of their eigenvectors (columns)."""

    eigenvalues: NDArray[np.complex128]
    vectors: NDArray[np.complex128]
    one_step: bool


def _realize(ys: Array, scale: Array, h: float) -> _Spectrum:
    """Eigenvalues of an integrator that carries more state than ``(x, v)``.

    With ``z`` its full state (e.g. ``(x, v, a)``), ``z_{k+1} = G z_k`` and ``y = C z``, the
    unit responses are ``Y_k = C G^k E``. The block Hankel matrices ``H0 = [[Y0, Y1], [Y1,
    Y2]] = O R`` and ``H1 = [[Y1, Y2], [Y2, Y3]] = O G R`` (``O = [C; C G]``,
    ``R = [E, G E]``) give ``G`` in a minimal basis (the eigensystem realization algorithm):
    ``G_r = S^-1/2 U^T H1 V S^-1/2`` from the SVD ``H0 = U S V^T`` truncated to its numerical
    rank. Exact for states of dimension up to ``2 (2 n)`` that ``(x, v)`` reveals within two
    steps (``(x, v, a)``: ``3 n``).
    """
    y = _scaled(ys, scale)
    h0 = np.block([[y[0], y[1]], [y[1], y[2]]])
    h1 = np.block([[y[1], y[2]], [y[2], y[3]]])
    u, sv, vt = np.linalg.svd(h0)
    # round-off of the step is ~eps (1 + h^2) relative (terms of size dt^2 omega^2 cancel)
    rank = int(np.sum(sv > max(1e-13, 1e-14 * (1.0 + h * h)) * sv[0]))
    root = 1.0 / np.sqrt(sv[:rank])
    g = (root[:, None] * u[:, :rank].T) @ h1 @ (vt[:rank].T * root[None, :])
    lam, q = np.linalg.eig(g)
    m = y.shape[1]
    outputs = (u[:m, :rank] * np.sqrt(sv[:rank])[None, :]) @ q
    return _Spectrum(lam, outputs / scale[:, None], one_step=False)


def _spectrum(system: System, integrator: Any, dt: float) -> _Spectrum:
    """The step's eigenvalues: of the amplification matrix, or of a realization."""
    if isinstance(integrator, ClosedFormNewmark):
        lam, vec = np.linalg.eig(amplification_matrix(system, integrator, dt))
        return _Spectrum(lam, vec, one_step=True)
    ys = _unit_responses(system, integrator, dt, 3)
    scale, h = _velocity_scale(system, integrator, dt)
    if _one_step_excess(ys, scale) <= ONE_STEP_RTOL:
        lam, vec = np.linalg.eig(ys[1])
        return _Spectrum(lam, vec, one_step=True)
    return _realize(ys, scale, h)


def amplification_eigenvalues(system: System, integrator: Any, dt: float) -> NDArray[np.complex128]:
    """Eigenvalues of the step of any integrator on a linear system.

    For a one-step map of ``(x, v)`` (the check of :func:`amplification_matrix` passes),
    the eigenvalues of :func:`amplification_matrix`. For an integrator that carries more
    state from step to step (HHT-alpha and generalized-alpha carry the acceleration), the
    eigenvalues of its full step ``z_{k+1} = G z_k``, recovered from three steps of the
    unit states by a minimal realization (block Hankel matrices of the responses, the
    eigensystem realization algorithm): ``3 n`` eigenvalues for ``(x, v, a)``, the spurious
    ones included. An eigenvalue that the responses barely reveal is inaccurate or left
    out (the spurious root of HHT-alpha at ``dt/T <= 1e-4``, below 1e-8; the principal
    ones are unaffected), and when every eigenvalue is tiny (generalized-alpha with
    ``rho_inf = 0`` at ``dt/T = 1e3``) the moduli are at round-off level. Dense: meant for
    models of up to a few hundred degrees of freedom (``2 n`` runs of three steps).

    Parameters
    ----------
    system, integrator, dt
        As for :func:`amplification_matrix`.

    Returns
    -------
    ndarray of complex, shape (m,)

    Examples
    --------
    The exact step of an undamped oscillator rotates by ``omega dt``:

    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import amplification_eigenvalues
    >>> oscillator = duhamel.System([[1.0]], [[4.0]])
    >>> lam = amplification_eigenvalues(oscillator, duhamel.Semianalytic(), dt=0.1)
    >>> np.round(np.sort_complex(lam), 12).tolist(), round(float(np.angle(lam).max()), 12)
    ([(0.980066577841-0.198669330795j), (0.980066577841+0.198669330795j)], 0.2)

    (HHT-alpha carries its acceleration: three eigenvalues per degree of freedom, see
    ``docs/analysis.md``.)
    """
    system = check_system(system)
    dt = positive_float(dt, "dt")
    return _spectrum(system, integrator, dt).eigenvalues


def amplification_matrix(
    system: System, integrator: Any, dt: float, *, check: bool = True
) -> Array:
    """The matrix that maps the state ``(x, v)`` at ``t`` to ``t + dt`` for a linear system.

    Column ``j`` is the state after one step of ``duhamel.solve(system, integrator,
    dt=dt, x0=..., v0=...)`` started from the ``j``-th unit state (``x0 = e_j`` for
    ``j < n``, ``v0 = e_{j-n}`` after), so it works for every integrator that
    :func:`duhamel.solve` accepts, including the semi-analytic schemes whose pseudo-forces
    (``Damper``, ``LinearCoupling``, non-classical damping) make the step approximate. The
    system's loads are ignored (the matrix belongs to the homogeneous system).
    :class:`ClosedFormNewmark` is evaluated by its formula instead of stepping.

    Parameters
    ----------
    system : System
        A linear model with constant coefficients: elements must be linear (``Damper``,
        ``LinearCoupling``, ``Spring``/``Cubic`` with ``k3 == 0``, ``Polynomial`` of degree
        1), no mass law.
    integrator : object
        Anything :func:`duhamel.solve` accepts (e.g. ``duhamel.Semianalytic(scheme="a")``),
        or :class:`ClosedFormNewmark`.
    dt : float
        Step, > 0.
    check : bool
        Also take a second step and verify that it equals the first one applied twice (to
        :data:`ONE_STEP_RTOL` of the squared largest entry, in the state
        ``(x, v / omega_max)``; one extra step per unit state, no extra call). This fails for
        an integrator whose step depends on more than ``(x, v)`` (HHT-alpha and
        generalized-alpha carry their own acceleration from step to step): its one-step map
        of ``(x, v)`` is then not an amplification matrix, and ValueError says so. Their
        eigenvalues are available from :func:`amplification_eigenvalues` (and
        :func:`spectral_radius`, :func:`~duhamel.analysis.modal_errors`). With
        ``check=False`` the first step's map is returned whatever the integrator.

    Returns
    -------
    ndarray, shape (2 n, 2 n)
        Rows and columns ordered ``(x_0..x_{n-1}, v_0..v_{n-1})``.

    Raises
    ------
    TypeError, ValueError
        A non-System `system`, a nonlinear or time-varying one, a bad `dt`, or a failed
        one-step check; :func:`duhamel.solve` rejects unknown integrators.

    Examples
    --------
    The paper's eq. 22: damping ``2 zeta omega x'`` moved to the right-hand side of an
    undamped oscillator and integrated along scheme (b):

    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import amplification_matrix
    >>> oscillator = duhamel.System([[1.0]], [[1.0]]).add(duhamel.elements.Damper(0, c=0.2))
    >>> A = amplification_matrix(oscillator, duhamel.Semianalytic(scheme="b"), dt=0.5)
    >>> h, z = 0.5, 0.1
    >>> eq22 = np.array([[2 * z + (h - 2 * z) * np.cos(h), h * np.sin(h)],
    ...                  [-h * np.sin(h), -2 * z + (h + 2 * z) * np.cos(h)]])
    >>> bool(np.allclose(A, eq22 / (h + 2 * z * (1 - np.cos(h))), rtol=0, atol=1e-14))
    True
    """
    system = check_system(system)
    dt = positive_float(dt, "dt")
    if not isinstance(check, bool | np.bool_):
        raise TypeError(f"`check` must be a bool, got {type(check).__name__}")
    if isinstance(integrator, ClosedFormNewmark):
        model = modal_model(system, None)
        return model.to_physical(_newmark_modal(model, dt, integrator.gamma, integrator.beta))
    ys = _unit_responses(system, integrator, dt, 2 if check else 1)
    if check:
        excess = _one_step_excess(ys, _velocity_scale(system, integrator, dt)[0])
        if excess > ONE_STEP_RTOL:
            raise ValueError(
                f"`integrator` ({type(integrator).__name__}) is not a one-step map of (x, v): "
                f"two steps differ from the first step applied twice by {excess:.3g} "
                "(relative), so it carries more state than (x, v) and has no (x, v) "
                "amplification matrix; amplification_eigenvalues gives its eigenvalues "
                "(check=False returns the first step's map anyway)"
            )
    return ys[1].copy()


def exact_transition_matrix(system: System, dt: float, *, modes: int | None = None) -> Array:
    """The exact transition matrix ``expm(S dt)`` of a linear system, in physical ``(x, v)``.

    ``S = [[0, I], [-M^-1 K_tot, -M^-1 C_tot]]`` with every linear element included in
    ``K_tot`` and ``C_tot`` (so a ``Damper`` counts as damping, whatever integrator treats it
    as a pseudo-force). It is evaluated in the mass-normalised modes of
    ``system.modal(modes)``; with ``modes < n_dof`` it is the transition matrix of the
    Galerkin-reduced model ``Q expm(S_q dt) P`` (zero outside the retained modes), the
    reference for an integrator with the same modal reduction. Loads are ignored.

    Parameters
    ----------
    system : System
        A linear model with constant coefficients (as for :func:`amplification_matrix`).
    dt : float
        Time span, > 0.
    modes : int, optional
        Number of retained modes (default all).

    Returns
    -------
    ndarray, shape (2 n, 2 n)

    Raises
    ------
    ValueError
        `dt` not positive, or a matrix beyond the double range (a mode that grows
        by more than 1e308 over `dt`).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import exact_transition_matrix
    >>> E = exact_transition_matrix(duhamel.System([[1.0]], [[4.0]]), dt=np.pi / 4)
    >>> np.round(E, 12).tolist()   # a quarter period of omega = 2
    [[0.0, 0.5], [-2.0, 0.0]]
    """
    system = check_system(system)
    dt = positive_float(dt, "dt")
    model = modal_model(system, modes)
    with np.errstate(all="ignore"):
        out = model.to_physical(model.transition(dt))
    if not np.all(np.isfinite(out)):
        raise ValueError(
            f"`dt` = {dt!r}: the exact transition matrix overflows the double range (a mode "
            "growing by more than 1e308 over the step: negative damping or a negative "
            "stiffness over a long span); take a shorter `dt`"
        )
    return out


def spectral_radius(system: System, integrator: Any, dt: float) -> float:
    """Largest eigenvalue modulus of the step (:func:`amplification_eigenvalues`).

    Parameters
    ----------
    system, integrator, dt
        As for :func:`amplification_matrix`.

    Returns
    -------
    float

    Examples
    --------
    Scheme (a) with damping as a pseudo-force is unstable at ``dt/T = 3/4``, where its
    spectral radius is ``sqrt((1 + zeta) / (1 - zeta))``:

    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import spectral_radius
    >>> oscillator = duhamel.System([[1.0]], [[1.0]]).add(duhamel.elements.Damper(0, c=0.2))
    >>> rho = spectral_radius(oscillator, duhamel.Semianalytic(scheme="a"), dt=0.75 * 2 * np.pi)
    >>> round(rho, 10), round(float(np.sqrt(1.1 / 0.9)), 10)
    (1.1055415968, 1.1055415968)
    """
    return float(np.max(np.abs(amplification_eigenvalues(system, integrator, dt))))
