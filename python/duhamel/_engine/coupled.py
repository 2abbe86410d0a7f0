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

import hashlib
import threading
import warnings
from collections import OrderedDict
from dataclasses import dataclass
from typing import cast

import numpy as np
from numpy.typing import NDArray

__all__ = ["CONDITION_LIMIT", "FirstOrderModes", "first_order_modes"]

#: Largest eigenvector condition number ``kappa`` for which the first-order modes are used.
#: Near a defective (Jordan) block the eigenvalues themselves are only accurate to about
#: ``kappa * eps`` relative, and the error of the response grows like ``kappa^2 * eps``
#: (measured in tests/engine/test_coupled_exact.py: about ``1e-17 kappa^2`` relative to the peak);
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
    def n_states(self) -> int:
        """Feedback states beyond ``(sigma q, q')`` (``duhamel.feedback.Feedback``)."""
        return int(self.inverse.shape[1] - 2 * self.sigma.size)

    @property
    def gain(self) -> NDArray[np.complex128]:
        """Rows of ``V^-1 B``, shape (r, m): the drive of each first-order coordinate by the
        modal loads (``B = [[0], [I], [0]]``: the velocity columns of ``V^-1``)."""
        m = self.sigma.size
        return self.inverse[:, m : 2 * m]

    def initial(self, q0: NDArray[np.float64], v0: NDArray[np.float64]) -> NDArray[np.complex128]:
        """First-order coordinates of the modal state ``(q0, v0)`` (feedback states zero)."""
        out = self.inverse @ np.concatenate([self.sigma * q0, v0, np.zeros(self.n_states)])
        return cast(NDArray[np.complex128], out)


#: First-order modes kept per process, by a digest of their inputs (at most this many): a
#: model rebuilt for every run (a study, ``solve_many``) decomposes its coupled modal system
#: once. The same inputs give the same modes, bit for bit.
KEPT = 16
_KNOWN: OrderedDict[bytes, FirstOrderModes] = OrderedDict()
_LOCK = threading.Lock()


def _digest(*arrays: NDArray[np.float64] | None) -> bytes:
    h = hashlib.blake2b(digest_size=20)
    for a in arrays:
        if a is None:
            h.update(b"none")
        else:
            a = np.ascontiguousarray(a, dtype=np.float64)
            h.update(repr(a.shape).encode())
            h.update(a.data)
    return h.digest()


#: Feedback states in modal form: ``(A, B Phi, Phi^T F)`` of ``z' = A z + B x`` pushing the
#: dofs with ``-F z`` (``duhamel.feedback.Feedback.modal_states``).
States = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]


def first_order_modes(
    omega2: NDArray[np.float64],
    c: NDArray[np.float64],
    coupling_k: NDArray[np.float64] | None,
    coupling_c: NDArray[np.float64] | None,
    states: States | None = None,
) -> FirstOrderModes:
    """Eigen-decomposition of the coupled modal system (see the module docstring), with the
    feedback `states` when given, taken from an earlier identical system's when there is
    one (:data:`KEPT`)."""
    key = _digest(omega2, c, coupling_k, coupling_c, *(states or ()))
    with _LOCK:
        known = _KNOWN.get(key)
        if known is not None:
            _KNOWN.move_to_end(key)
            return known
    modes = _decompose(omega2, c, coupling_k, coupling_c, states)
    with _LOCK:
        _KNOWN[key] = modes
        while len(_KNOWN) > KEPT:
            _KNOWN.popitem(last=False)
    return modes


def _decompose(
    omega2: NDArray[np.float64],
    c: NDArray[np.float64],
    coupling_k: NDArray[np.float64] | None,
    coupling_c: NDArray[np.float64] | None,
    states: States | None = None,
) -> FirstOrderModes:
    """Eigen-decomposition of the coupled modal system (see the module docstring), extended
    by feedback `states` ``z``: the state ``(sigma q, q', z)`` with ``z' = A z + (B Phi)
    diag(1/sigma) (sigma q)`` and ``-(Phi^T F) z`` in the velocity rows; `back` maps to
    ``(q, q')`` only, and the loads drive the velocity rows.

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
    if states is not None:
        Az, Bz, Fz = states
        nz = Az.shape[0]
        A = np.block(
            [
                [A, np.concatenate([np.zeros((m, nz)), -Fz])],
                [np.concatenate([Bz / sigma, np.zeros((nz, m))], axis=1), Az],
            ]
        )
    import scipy.linalg

    scale = None
    if states is not None:  # the feedback states' own units: balanced (V = T V_b)
        _, (scale, _) = scipy.linalg.matrix_balance(A, permute=False, separate=True)
        A = A * scale[None, :] / scale[:, None]
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
    if scale is not None:
        V, W = V * scale[:, None], W / scale[None, :]
    upper = lam.imag > 0.0
    real = lam.imag == 0.0
    if int(upper.sum()) != int((lam.imag < 0.0).sum()):  # pragma: no cover - LAPACK pairs
        condition = float("inf")
    keep = np.flatnonzero(upper | real)
    weight = np.where(real[keep], 1.0, 2.0)
    Vk = V[: 2 * m, keep] * weight
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
