"""The coordinates of massless dofs: static, or first-order where damping reaches them
(docs/basis.md, "Massless dofs").

Every displacement splits exactly into ``x = Phi q + E y``: ``Phi`` the modes of the
background ``(K_b, M)`` (condensed: they satisfy the static relation of the massless dofs
``s``) and ``E = [0; I_s]``, ``y`` the massless dofs' deviation from that relation. ``Phi`` is
K_b-orthogonal to ``E`` and ``M E = 0``, so with ``D = [Phi E]^T C_b [Phi E]``

    q'' + D_qq q' + D_qy y' + Omega^2 q = Phi^T (f - r)
          D_yq q' + C_ss y' + K_ss y   = f_s - r_s.

With ``C_ss Z = K_ss Z diag(tau)``, ``Z^T K_ss Z = I``, ``y = Z w``:
``tau_i w_i' + w_i + (Z^T D_yq q')_i = z_i^T (f_s - r_s)``, each ``w_i`` relaxing with the time
constant ``tau_i``, or static (``tau_i = 0``; then ``C z_i = 0`` for a semidefinite ``C``).

* No damping at the massless dofs (``zeta``, none, a ``C`` zero there): every ``w`` is
  static. Only the directions the elements drive leave the static relation of the loads
  (``K_ss^-1 d_s``, K-orthonormalised); the loads' own static part is added after the run
  (:func:`duhamel._engine.massless.load_terms`).
* Rayleigh damping ``alpha M + beta K_b``: ``D_qy = beta Phi^T K_b E = 0`` and
  ``C_ss = beta K_ss``: every ``w`` relaxes with ``tau = beta``, uncoupled. The directions the
  elements and the loads drive, ``K_ss^-1 [d_s, f_s]`` (every massless direction when a
  Python load, whose pattern is unknown, acts).
* A damping matrix with entries at the massless dofs: every massless direction, coupled to
  the modes by ``D_qy`` (a coupling the pseudo-force route integrates).

Each coordinate enters the modal engine on its K-orthonormal vector ``psi`` with the modal
stiffness ``omega2 = +inf`` (no mass) and ``c = tau``: the core steps ``tau w' + w = p``
exactly (``crates/duhamel-core/src/kernel/relaxation.rs``), also its velocity.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.massless import massless_damping, matrix_relaxation
from duhamel._engine.validate import issparse

__all__ = ["Massless", "check_loads", "check_state", "massless_coordinates"]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Massless:
    """The coordinates a run adds for its massless dofs (:func:`massless_coordinates`).

    Attributes
    ----------
    basis : ModalBasis
        The basis with them appended (columns ``psi``, ``omega2 = inf``, ``c = tau``).
    carried : ndarray, shape (n_dof, k)
        Their K-orthonormal vectors ``psi`` (what :func:`~duhamel._engine.massless.
        load_terms` leaves out of the static part of loads).
    tau : ndarray
        Their time constants (0: static).
    initial : ndarray, shape (k, n_dof)
        The coordinates of a physical state ``x``: ``psi^T K_b x``.
    kind : str
        ``"undamped"``, ``"rayleigh"`` or ``"matrix"`` (see
        :class:`~duhamel._engine.massless.MasslessDamping`).
    complete : bool
        Whether they span every massless direction (no static remainder of any load).
    condensation : Condensation
        The background's (its ``K_ss`` factorised), for the checks of a run's initial state
        and loads.
    """

    basis: Any
    carried: Array
    tau: Array
    initial: Array
    kind: str
    complete: bool = False
    condensation: Any = field(default=None, compare=False, repr=False)

    @property
    def first_order(self) -> bool:
        """Whether any coordinate relaxes (``tau > 0``)."""
        return bool(np.any(self.tau > 0.0))


def _directions(system: Any, loads: bool) -> tuple[list[Array], bool]:
    """The massless parts of the elements' directions (and, with `loads`, of the loads'
    patterns), and whether a Python load (pattern unknown) is among the loads."""
    from duhamel.couplings import LinearCoupling
    from duhamel.loads import Callable

    c = system._condensation
    n = system.n_dof
    cols: list[Array] = []
    for element in system.elements:
        if isinstance(element, LinearCoupling):
            continue
        for i, j in element._directions():
            d = np.zeros(n)
            d[i] = 1.0
            if j is not None:
                d[j] = -1.0
            if np.any(d[c.s]):
                cols.append(d[c.s])
    unknown = False
    for load in system.loads if loads else ():
        if isinstance(load, Callable):
            unknown = True
            continue
        for pattern in (term.pattern for term in load._terms(system)):
            part = np.asarray(pattern, dtype=np.float64)[c.s]
            if np.any(part):
                cols.append(part)
    return cols, unknown


def _k_orthonormal(c: Any, cols: list[Array]) -> Array:
    """``K_ss^-1 [cols]`` K_ss-orthonormalised, dependent directions dropped."""
    ys = c.solve_ss(np.stack(cols, axis=1))
    K_ss = c._K_ss.toarray() if c.sparse else c._K_ss
    g = ys.T @ K_ss @ ys
    w, u = np.linalg.eigh((g + g.T) / 2)
    keep = w > 1e-10 * w.max()
    return np.asarray(ys @ (u[:, keep] / np.sqrt(w[keep])))


def _all_directions(c: Any) -> Array:
    """A K_ss-orthonormal basis of every massless direction (``L^-T``, ``K_ss = L L^T``)."""
    import scipy.linalg

    K_ss = c._K_ss.toarray() if c.sparse else np.asarray(c._K_ss)
    L = scipy.linalg.cholesky((K_ss + K_ss.T) / 2, lower=True, check_finite=False)
    return np.asarray(scipy.linalg.solve_triangular(L, np.eye(L.shape[0]), lower=True).T)


def massless_coordinates(system: Any, basis: Any) -> Massless | None:
    """The coordinates of the massless dofs of `system` (a run's background, with its
    elements and loads) appended to `basis`; None without massless dofs or when nothing
    moves them off the static relation of the loads (see the module docstring)."""
    how = massless_damping(system)
    if how is None:
        return None
    c = system._condensation
    coupling_qy = None
    if how.kind == "undamped":
        cols, _ = _directions(system, loads=False)
        if not cols:
            return None
        psi_s, complete = _k_orthonormal(c, cols), False
        tau = np.zeros(psi_s.shape[1])
    elif how.kind == "rayleigh":
        beta = float(how.tau[0])
        if beta < 0.0:
            raise ValueError(
                f"`rayleigh`: beta = {beta:.3g} < 0 damps the massless dofs negatively (their "
                "first-order motion grows as exp(t / |beta|)): give beta >= 0"
            )
        cols, unknown = _directions(system, loads=True)
        if unknown:
            psi_s, complete = _all_directions(c), True
        elif cols:
            psi_s, complete = _k_orthonormal(c, cols), False
        else:
            return None
        tau = np.full(psi_s.shape[1], beta)
    else:
        tau, psi_s = matrix_relaxation(system)
        complete = True
        C = system.C
        C_s = C[:, c.s] if issparse(C) else np.asarray(C)[:, c.s]
        coupling_qy = np.asarray(np.asarray(basis.phi).T @ np.asarray(C_s @ psi_s))
        cols, unknown = _directions(system, loads=True)
        scale = float(np.abs(basis.c).max(initial=0.0)) * float(np.abs(psi_s).max())
        if not cols and not unknown and np.abs(coupling_qy).max(initial=0.0) <= 1e-12 * scale:
            return None  # nothing moves them off the static relation: they stay on it
    psi = np.zeros((system.n_dof, psi_s.shape[1]))
    psi[c.s] = psi_s
    return Massless(
        _extend(basis, psi, tau, coupling_qy),
        psi,
        tau,
        _initial(system, psi),
        how.kind,
        complete,
        c,
    )


def _extend(basis: Any, psi: Array, tau: Array, coupling_qy: Array | None) -> Any:
    """`basis` with the massless coordinates `psi` (time constants `tau`) appended; the modal
    damping coupling of the modes with them, `coupling_qy` (None: none)."""
    from duhamel.modal import CLASSICAL_RTOL, ModalBasis, frozen

    m, k = basis.n_modes, psi.shape[1]
    coupling = basis.c_coupling
    full = None if coupling is None else np.pad(np.asarray(coupling), ((0, k), (0, k)))
    if coupling_qy is not None:
        ref = float(np.abs(basis.c).max(initial=0.0)) * float(np.abs(psi).max(initial=0.0))
        if float(np.abs(coupling_qy).max(initial=0.0)) > CLASSICAL_RTOL * max(ref, 1e-300):
            if full is None:
                full = np.zeros((m + k, m + k))
            full[:m, m:] = coupling_qy
            full[m:, :m] = coupling_qy.T
    omega = np.concatenate([np.asarray(basis.omega), np.full(k, np.inf)])
    return ModalBasis(
        phi=frozen(np.ascontiguousarray(np.hstack([np.asarray(basis.phi), psi]))),
        omega2=frozen(omega * omega),
        omega=frozen(omega),
        c=frozen(np.concatenate([np.asarray(basis.c), tau])),
        zeta=frozen(np.concatenate([np.asarray(basis.zeta), np.zeros(k)])),
        c_coupling=None if full is None else frozen(full),
        mass=basis.mass,
        labels=basis.labels,
    )


def _initial(system: Any, psi: Array) -> Array:
    """``psi^T K_b`` (rows): the massless coordinates of a physical state."""
    K = system.K
    rows = np.asarray(K @ psi).T if issparse(K) else (np.asarray(K) @ psi).T
    return np.ascontiguousarray(rows)


def _outside(massless: Massless, y: Array) -> float:
    """The largest entry of the part of massless deviations `y` (columns) outside the
    coordinates' span (K_ss-orthogonal projection)."""
    c = massless.condensation
    psi_s = massless.carried[c.s]
    rest = y - psi_s @ (psi_s.T @ np.asarray(c._K_ss @ y))
    return float(np.abs(rest).max(initial=0.0))


def check_state(massless: Massless | None, x: Array, name: str) -> None:
    """Refuses an initial state whose massless dofs leave the static relation in a direction
    the run's first-order coordinates do not hold (it would relax unseen)."""
    if massless is None or massless.complete or not massless.first_order:
        return
    c = massless.condensation
    y = x[c.s] + c.solve_ss(np.asarray(c._K_sm @ x[c.m]))  # the deviation from the relation
    if _outside(massless, y) > 1e-9 * max(float(np.abs(x).max(initial=0.0)), 1e-300):
        raise ValueError(
            f"`{name}` moves the massless dofs off their static relation in a direction no "
            "element or load of the system drives; with damping there (a first-order motion) "
            "the run holds only those directions: start them on the static relation, or add "
            "the load that holds them to the system"
        )


def check_loads(massless: Massless | None, system: Any, loads: list[Any]) -> None:
    """Refuses a run's own loads that act at damped massless dofs in a direction the
    prepared run does not hold (their response there is not static)."""
    if massless is None or massless.complete or not massless.first_order:
        return
    from duhamel.loads import Callable

    c = massless.condensation
    for load in loads:
        if isinstance(load, Callable):
            raise ValueError(
                "`loads`: a Python load on a model with damped massless dofs must be among "
                "the system's loads when it is prepared (its pattern decides which massless "
                "directions are first-order coordinates)"
            )
        for pattern in (term.pattern for term in load._terms(system)):
            f_s = np.asarray(pattern, dtype=np.float64)[c.s]
            if not np.any(f_s):
                continue
            y = c.solve_ss(f_s)[:, None]
            if _outside(massless, y) > 1e-9 * float(np.abs(y).max()):
                raise ValueError(
                    f"`loads`: {type(load).__name__} acts at damped massless dofs in a "
                    "direction the prepared run does not hold; add it to the system before "
                    "preparing (its massless part is then a first-order coordinate)"
                )
