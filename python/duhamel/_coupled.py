"""Exact integration of coupled linear systems in their first-order (complex) modes.

The retained modes of the symmetric background obey ``q'' + D q' + S q = p(t)`` with
``D = diag(c) + C_c`` and ``S = diag(omega^2) + K_c``: the couplings ``K_c``, ``C_c`` are the
modal projections of non-classical damping, gyroscopic (``speed * G``) and circulatory
(cross-coupled bearing) terms. In first order, with the scaled state
``y = (sigma q, q')`` (``sigma`` the natural frequencies, so that the eigenvalues of the
stiff modes do not swamp those of the soft ones),

    y' = A y + B p,   A = [[0, diag(sigma)], [-S diag(1/sigma), -D]],   B = [[0], [I]],

and ``A = V diag(lambda) V^-1``. The Rust engine (``duhamel-core::coupled``) advances each
first-order coordinate ``eta = V^-1 y`` exactly; only one of each complex-conjugate pair is
integrated (the other is its conjugate), so ``y = sum_k w_k Re(V_k eta_k)`` with ``w_k = 2``
for a pair and 1 for a real eigenvalue.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.solution import ModalHistory
from duhamel.system import ModalBasis

__all__ = [
    "CONDITION_LIMIT",
    "FirstOrderModes",
    "back_transform",
    "first_order_modes",
    "keep_finite_rows",
    "output_maps",
]

#: Largest eigenvector condition number ``kappa`` for which the first-order modes are used.
#: Near a defective (Jordan) block the eigenvalues themselves are only accurate to about
#: ``kappa * eps`` relative, and the error of the response grows like ``kappa^2 * eps``
#: (measured in tests/test_coupled_exact.py: about ``1e-17 kappa^2`` relative to the peak);
#: at this limit that is about 1e-9. Above it the couplings are integrated as pseudo-forces.
CONDITION_LIMIT = 1e4


@dataclass(frozen=True)
class FirstOrderModes:
    """The first-order modes kept for integration and the way back to ``(q, q')``.

    Attributes
    ----------
    lam : complex ndarray, shape (r,)
        Eigenvalues kept (``Im >= 0``; the conjugates are implied).
    inverse : complex ndarray, shape (r, 2m)
        Rows of ``V^-1``, for the initial state ``(sigma q0, v0)``.
    sigma : ndarray, shape (m,)
        State scaling.
    back : ndarray, shape (2r, 2m)
        ``[Re eta | Im eta] @ back = [q | q']``.
    condition : float
        1-norm condition number of the eigenvector matrix.
    """

    lam: NDArray[np.complex128]
    inverse: NDArray[np.complex128]
    sigma: NDArray[np.float64]
    back: NDArray[np.float64]
    condition: float

    @property
    def gain(self) -> NDArray[np.complex128]:
        """Rows of ``V^-1 B``, shape (r, m): the drive of each first-order coordinate by the
        modal loads (``B = [[0], [I]]``: the velocity columns of ``V^-1``)."""
        return self.inverse[:, self.sigma.size :]

    def initial(self, q0: NDArray[np.float64], v0: NDArray[np.float64]) -> NDArray[np.complex128]:
        """First-order coordinates of the modal state ``(q0, v0)``."""
        return self.inverse @ np.concatenate([self.sigma * q0, v0])


def first_order_modes(
    omega2: NDArray[np.float64],
    c: NDArray[np.float64],
    coupling_k: NDArray[np.float64] | None,
    coupling_c: NDArray[np.float64] | None,
) -> FirstOrderModes:
    """Eigen-decomposition of the coupled modal system (see the module docstring).

    The condition number is returned, not judged: the caller decides whether the
    decomposition is accurate enough (:data:`CONDITION_LIMIT`). A defective system (a
    Jordan block, e.g. exactly critical damping coupled to another mode) has an infinite or
    huge condition number.
    """
    m = omega2.size
    omega = np.sqrt(np.clip(omega2, 0.0, None))
    floor = 1e-6 * float(omega.max()) if m and omega.max() > 0.0 else 1.0
    sigma = np.maximum(omega, floor) if floor > 0.0 else np.ones(m)
    S = np.diag(omega2).astype(np.float64)
    D = np.diag(c).astype(np.float64)
    if coupling_k is not None:
        S = S + coupling_k
    if coupling_c is not None:
        D = D + coupling_c
    A = np.block([[np.zeros((m, m)), np.diag(sigma)], [-S / sigma, -D]])
    import scipy.linalg

    lam, V = scipy.linalg.eig(A, check_finite=False)
    try:
        with warnings.catch_warnings():
            # An ill-conditioned V is judged below by its condition number, not warned about.
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            W = scipy.linalg.inv(V, check_finite=False)
    except (np.linalg.LinAlgError, ValueError):
        W = np.full_like(V, np.nan)
    finite = bool(np.all(np.isfinite(W)))
    condition = float(np.linalg.norm(V, 1) * np.linalg.norm(W, 1)) if finite else float("inf")
    upper = lam.imag > 0.0
    real = lam.imag == 0.0
    if int(upper.sum()) != int((lam.imag < 0.0).sum()):  # pragma: no cover - LAPACK pairs
        condition = float("inf")
    keep = np.flatnonzero(upper | real)
    weight = np.where(real[keep], 1.0, 2.0)
    Vk = V[:, keep] * weight
    back = np.concatenate([Vk.real.T, -Vk.imag.T])
    back[:, :m] /= sigma
    Wk = W[keep, :]
    return FirstOrderModes(
        lam=lam[keep],
        inverse=Wk,
        sigma=sigma,
        back=np.ascontiguousarray(back),
        condition=condition,
    )


def keep_finite_rows(raw: dict[str, Any], n_out: int) -> None:
    """Cuts a diverged coupled run's history to its leading rows whose displacements and
    velocities are finite (accelerations may overflow, as on the other routes): the engine
    stops when the first-order coordinates overflow, but the outputs mapped from them can
    overflow a step or two earlier. The error message then names the new last instant."""
    finite = np.isfinite(raw["out"][:, : 2 * n_out]).all(axis=1)
    if finite.all():
        return
    keep = int(np.argmin(finite))
    old = float(raw["t"][-1])
    for key in ("t", "out", "eta", "load_values", "forcing", "pseudo"):
        if raw.get(key) is not None:
            raw[key] = raw[key][:keep]
    new = f"the history up to t = {float(raw['t'][-1])!r} is kept" if keep else "nothing is kept"
    err = raw["error"]
    err["message"] = err["message"].replace(f"the history up to t = {old!r} is kept", new)


def output_maps(
    basis: ModalBasis,
    phi_out: NDArray,
    specs: list,
    modes: FirstOrderModes,
    couplings: dict[str, Any],
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """The maps from ``[Re eta | Im eta]`` to ``[x | v]`` of the output dofs (``x = Phi q``,
    ``v = Phi q'``), applied by the engine during the run, and the maps from
    ``[Re eta | Im eta]`` and from the load values to their accelerations
    ``a = Phi (p - D q' - S q)``, applied on first access."""
    m = basis.omega2.size
    kc, cc = couplings["coupling_k"], couplings["coupling_c"]
    S = np.diag(basis.omega2) + (0.0 if kc is None else kc)
    D = np.diag(basis.c) + (0.0 if cc is None else cc)
    tq, tv = modes.back[:, :m], modes.back[:, m:]
    out_map = np.ascontiguousarray(np.concatenate([tq @ phi_out.T, tv @ phi_out.T], axis=1))
    out_loads = np.zeros((len(specs), out_map.shape[1]))
    acc_map = -(tq @ S.T + tv @ D.T) @ phi_out.T
    acc_loads = np.zeros((len(specs), phi_out.shape[0]))
    for i, spec in enumerate(specs):
        acc_loads[i] = phi_out @ spec[0]
    return out_map, out_loads, acc_map, acc_loads


def back_transform(
    raw: dict[str, Any],
    basis: ModalBasis,
    phi_out: NDArray,
    patterns: NDArray,
    modes: FirstOrderModes,
    couplings: dict[str, Any],
    acc_maps: tuple[NDArray, NDArray],
) -> tuple[NDArray, NDArray, Callable[[], NDArray], ModalHistory]:
    """``x``, ``v`` (the engine mapped them during the run), the accelerations as a function
    evaluated on first access (load and forcing terms included), and the modal history,
    whose ``q``, ``v`` are rebuilt from the first-order coordinates on demand."""
    n_out = phi_out.shape[0]
    out, eta = raw["out"], raw["eta"]
    values, forcing, pseudo = raw["load_values"], raw["forcing"], raw.get("pseudo")
    acc_map, acc_loads = acc_maps

    def acceleration() -> NDArray:
        a = eta @ acc_map + values @ acc_loads
        for extra in (forcing, pseudo):
            if extra is not None:
                a += extra @ phi_out.T
        return a

    modal = ModalHistory(
        q=None,
        v=None,
        omega=basis.omega,
        c=basis.c,
        load_values=values,
        patterns=patterns,
        forcing=forcing,
        pseudo=pseudo,
        first_order=(eta, modes.back),
        coupling=(couplings["coupling_k"], couplings["coupling_c"]),
    )
    return out[:, :n_out], out[:, n_out : 2 * n_out], acceleration, modal
