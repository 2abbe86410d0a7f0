"""The linear model behind an analysis: linearity checks, load-free copies, modal matrices."""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from duhamel.system import System

Array = NDArray[np.float64]


def check_system(system: Any) -> System:
    """Return `system` if it is a linear :class:`~duhamel.System` with constant coefficients.

    Linear elements are allowed (``Damper``, ``LinearCoupling``, ``Spring`` and ``Cubic``
    with ``k3 == 0``, ``Polynomial`` of degree <= 1 without a constant term); anything
    nonlinear, a constant force, or a time-varying mass raises ValueError naming `system`.
    """
    if not isinstance(system, System):
        raise TypeError(f"`system` must be a duhamel.System, got {type(system).__name__}")
    if system.mass_law is not None:
        raise ValueError(
            "`system` must have constant coefficients for an amplification matrix, but it has "
            "a time-varying mass law"
        )
    for coupling in system.couplings:
        if coupling.constant_factor() is None:
            raise ValueError(
                f"`system` must be linear for an amplification matrix, but its coupling "
                f"{coupling!r} has a time-varying scale (a speed law): the coefficients are "
                "not constant"
            )
    for element in system.elements:
        reason = _nonlinear_reason(element)
        if reason is not None:
            raise ValueError(
                f"`system` must be linear for an amplification matrix, but its element "
                f"{element!r} {reason}"
            )
    return system


def _nonlinear_reason(element: Any) -> str | None:
    try:
        element._linear_matrices()
    except ValueError as exc:
        return str(exc)
    return None


def unloaded(system: System) -> System:
    """A shallow copy of `system` without loads (matrices, elements and caches are shared)."""
    free = copy.copy(system)
    free.loads = []
    return free


@dataclass(frozen=True, eq=False)
class ModalModel:
    """``q'' + C_q q' + K_q q = 0`` in the mass-normalised undamped modes ``x = Phi q``.

    `K_q` holds ``diag(omega^2)`` plus the projected stiffness of the elements, `C_q` the
    modal damping, the non-classical remainder of a damping matrix and the projected element
    damping. With all modes, ``P = blockdiag(Phi^T M, Phi^T M)`` and ``Q = blockdiag(Phi,
    Phi)`` are inverse to each other; with fewer modes ``Q S P`` is the Galerkin-reduced
    model in physical coordinates.
    """

    phi: Array
    phi_t_m: Array
    k_q: Array
    c_q: Array

    @property
    def n_modes(self) -> int:
        return int(self.k_q.shape[0])

    def state_matrix(self) -> Array:
        """The first-order matrix ``[[0, I], [-K_q, -C_q]]`` of the modal state ``(q, q')``."""
        m = self.n_modes
        s = np.zeros((2 * m, 2 * m))
        s[:m, m:] = np.eye(m)
        s[m:, :m] = -self.k_q
        s[m:, m:] = -self.c_q
        return s

    def transition(self, dt: float) -> Array:
        """Exact modal transition matrix ``expm(S dt)`` (any sign of `dt`)."""
        return np.asarray(scipy.linalg.expm(self.state_matrix() * dt), dtype=np.float64)

    def to_physical(self, a_q: Array) -> Array:
        """``Q a_q P``: a modal state map as a map of the physical state ``(x, v)``."""
        phi, pm = self.phi, self.phi_t_m
        m = self.n_modes
        top = np.vstack([phi @ a_q[:m, :m] @ pm, phi @ a_q[m:, :m] @ pm])
        bottom = np.vstack([phi @ a_q[:m, m:] @ pm, phi @ a_q[m:, m:] @ pm])
        return np.hstack([top, bottom])

    def project(self, w: Any) -> Any:
        """``P w``: physical state vectors (columns ``(x, v)``) in modal coordinates."""
        n = self.phi.shape[0]
        return np.vstack([self.phi_t_m @ w[:n], self.phi_t_m @ w[n:]])

    def to_modal(self, a: Array) -> Array:
        """``P a Q``: a physical state map restricted to the modal coordinates."""
        n = self.phi.shape[0]
        phi, pm = self.phi, self.phi_t_m
        blocks = [
            [pm @ a[i * n : (i + 1) * n, j * n : (j + 1) * n] @ phi for j in (0, 1)] for i in (0, 1)
        ]
        return np.block(blocks)


def modal_model(system: System, modes: int | None = None) -> ModalModel:
    """The :class:`ModalModel` of a linear `system` on ``system.modal(modes)``."""
    basis = system.modal(modes)
    phi = np.asarray(basis.phi)
    k_q = np.diag(np.asarray(basis.omega2, dtype=np.float64)).copy()
    c_q = np.diag(np.asarray(basis.c, dtype=np.float64)).copy()
    if basis.c_coupling is not None:
        c_q += basis.c_coupling
    for coupling in system.couplings:
        kk, cc = coupling.modal(phi)
        factor = coupling.constant_factor()  # not None: checked by check_system
        if kk is not None:
            k_q += factor * kk
        if cc is not None:
            c_q += factor * cc
    for element in system.elements:
        dofs, k_e, c_e = element._linear_matrices()  # linear: checked by check_system
        local = phi[np.asarray(dofs)]
        k_q += local.T @ k_e @ local
        c_q += local.T @ c_e @ local
    phi_t_m = np.asarray(system.M @ phi, dtype=np.float64).T  # M is symmetric
    return ModalModel(phi=phi, phi_t_m=np.ascontiguousarray(phi_t_m), k_q=k_q, c_q=c_q)
