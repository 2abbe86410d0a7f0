"""The lowest modes of a large rotor by shift-invert Arnoldi on the first-order pencil.

``lambda^2 M + lambda D + K`` linearised as ``A z = lambda B z``, ``A = [[0, I], [-K, -D]]``,
``B = [[I, 0], [0, M]]``, ``z = (x, lambda x)``. ARPACK (``scipy.sparse.linalg.eigs``) finds
the eigenvalues nearest the shift ``sigma = 0`` from the operator ``(A - sigma B)^-1 B``,
whose application is one solve with the banded ``T(sigma) = K + sigma D + sigma^2 M`` (its
sparse LU made once; a singular ``K``, rigid-body modes, takes the dense path):

    z_1 = -T^-1 (M y_2 + (D + sigma M) y_1),   z_2 = y_1 + sigma z_1.

It asks for ``k = 3 n + 8`` eigenvalues and grows ``k`` by half until the ``n`` lowest
oscillatory modes (as :func:`duhamel.rotor.modes.split_eigenvalues` classifies them) are
found *and* every eigenvalue within :data:`COVER` times the ``n``-th frequency of the shift
is: ARPACK's eigenvalues are the ``k`` nearest the shift, so a mode below the ``n``-th
frequency can be missing only if its ``|lambda|`` exceeds that radius, i.e. if its damping
ratio exceeds ``sqrt(1 - 1 / COVER^2) = 0.866`` (a heavily damped mode, AF below 0.6; the
dense path, ``n=None``, lists every mode). The eigenvalues agree with the dense QZ's to about
1e-11 (tolerance ``eps``). ``overdamped`` then lists only the non-oscillatory eigenvalues
found.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["COVER", "SPARSE_DOFS", "lowest_modes", "sparse_worth"]

#: Models with at least this many dofs take the shift-invert path when a few modes are asked.
SPARSE_DOFS = 96
#: The radius of the eigenvalues found, in multiples of the highest frequency returned.
COVER = 2.0


def sparse_worth(n_dof: int, n: int | None) -> bool:
    """Whether the lowest `n` modes of `n_dof` dofs go through the shift-invert path."""
    return n is not None and n_dof >= SPARSE_DOFS and 0 < 4 * n <= n_dof


def _scale(M: Any, K: Any) -> float:
    """``sqrt(max K_ii / M_ii)``, an estimate of the largest natural frequency: the
    reference of the rigid-body test (``Im > 1e-6 max|lambda|``), standing for the dense
    path's largest ``|lambda|`` (only eigenvalues within a millionth of it differ)."""
    ratio = np.asarray(K.diagonal(), dtype=float) / np.asarray(M.diagonal(), dtype=float)
    top = float(np.max(ratio)) if ratio.size else 0.0
    return float(np.sqrt(top)) if top > 0.0 else 1.0


def _csc(a: NDArray[np.float64], rows: NDArray[np.intp], cols: NDArray[np.intp]) -> Any:
    """``scipy.sparse.csc_matrix(a)`` (the same arrays) from the nonzero entries of `a` among
    those at ``(rows, cols)`` (row-major, a superset of its nonzeros)."""
    import scipy.sparse as sp

    v = a[rows, cols]
    keep = v != 0.0
    return sp.csc_matrix((v[keep], (rows[keep], cols[keep])), shape=a.shape)


def lowest_modes(
    M: NDArray[np.float64],
    D: NDArray[np.float64],
    K: NDArray[np.float64],
    n: int,
    oscillatory: Callable[[NDArray[np.complex128], float], NDArray[np.bool_]],
) -> tuple[NDArray[np.complex128], NDArray[np.complex128], float] | None:
    """The eigenvalues nearest zero, enough to hold the lowest `n` of those `oscillatory`
    tells (with the reference scale it takes) and every eigenvalue within :data:`COVER`
    times the `n`-th one's frequency: ``(lambda, shapes, scale)``, or None when the sparse
    path does not apply (a massless dof, a singular ``T``, no convergence, not enough
    modes below ``2 n_dof``)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    nd = M.shape[0]
    if np.any(np.diag(M) <= 0.0):
        return None  # massless dofs: infinite eigenvalues, the dense QZ path
    rows, cols = np.nonzero((M != 0.0) | (D != 0.0) | (K != 0.0))  # one scan of the band
    Ms, Ds, Ks = (_csc(a, rows, cols) for a in (M, D, K))
    scale = _scale(Ms, Ks)
    sigma = 0.0
    try:
        lu = spla.splu(sp.csc_matrix(Ks))
    except RuntimeError:  # singular: rigid-body modes at zero (often defective): dense QZ
        return None
    if not np.all(np.isfinite(lu.U.diagonal())) or np.min(np.abs(lu.U.diagonal())) <= (
        1e-13 * np.max(np.abs(lu.U.diagonal()))
    ):
        return None  # numerically singular: the same
    DsM = sp.csr_matrix(Ds + sigma * Ms)
    Mr = sp.csr_matrix(Ms)

    def apply(y: NDArray) -> NDArray:
        z1 = -lu.solve(np.asarray(Mr @ y[nd:] + DsM @ y[:nd]))
        return np.concatenate([z1, y[:nd] + sigma * z1])

    op = spla.LinearOperator((2 * nd, 2 * nd), matvec=apply, dtype=float)
    k = 3 * n + 8  # about the eigenvalues within COVER times the n-th frequency
    v0 = np.ones(2 * nd)
    while k < 2 * nd - 1:  # (ARPACK needs k < N - 1)
        try:
            mu, Z = spla.eigs(op, k=k, which="LM", tol=0.0, v0=v0)
        except spla.ArpackNoConvergence:
            return None
        with np.errstate(divide="ignore"):
            lam = sigma + 1.0 / mu
        keep = np.isfinite(lam)
        lam, Z = lam[keep], Z[:nd, keep]
        good = oscillatory(lam, scale)
        freqs = np.sort(lam.imag[good])
        if freqs.size >= n and float(np.max(np.abs(lam - sigma))) >= COVER * freqs[n - 1]:
            return lam, Z, scale
        k = (3 * k) // 2
    return None


def modes_near(
    M: NDArray[np.float64],
    D: NDArray[np.float64],
    K: NDArray[np.float64],
    sigma: complex,
    k: int,
) -> tuple[NDArray[np.complex128], NDArray[np.complex128]] | None:
    """The `k` eigenvalues of ``lambda^2 M + lambda D + K`` nearest the complex shift
    `sigma` and their shapes (the dofs' rows), by shift-invert Arnoldi with the complex
    ``T(sigma) = K + sigma D + sigma^2 M`` (one LU, a few dozen solves): how a critical
    speed's refinement follows one branch without the whole window of modes. None when it
    does not apply (massless dofs, ``T(sigma)`` singular, no convergence)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    nd = M.shape[0]
    if np.any(np.diag(M) <= 0.0) or not 0 < k < 2 * nd - 1:
        return None
    s = complex(sigma)
    rows, cols = np.nonzero((M != 0.0) | (D != 0.0) | (K != 0.0))  # one banded pattern

    Mv, Dv, Kv = M[rows, cols], D[rows, cols], K[rows, cols]
    T = sp.csc_matrix((Kv + s * Dv + (s * s) * Mv, (rows, cols)), shape=(nd, nd))
    if not np.all(np.isfinite(T.data)):
        return None
    try:
        lu = spla.splu(T)
    except RuntimeError:  # exactly singular
        return None
    if not np.all(np.isfinite(lu.U.diagonal())):
        return None  # (nearly singular is what a shift near an eigenvalue gives)
    DsM = sp.csr_matrix((Dv + s * Mv, (rows, cols)), shape=(nd, nd))
    Mr = sp.csr_matrix((Mv, (rows, cols)), shape=(nd, nd))

    def apply(y: NDArray) -> NDArray:
        z1 = -lu.solve(np.asarray(Mr @ y[nd:] + DsM @ y[:nd]))
        return np.concatenate([z1, y[:nd] + s * z1])

    op = spla.LinearOperator((2 * nd, 2 * nd), matvec=apply, dtype=complex)
    try:
        mu, Z = spla.eigs(op, k=k, which="LM", tol=0.0, v0=np.ones(2 * nd, dtype=complex))
    except spla.ArpackNoConvergence:
        return None
    with np.errstate(divide="ignore"):
        lam = s + 1.0 / mu
    keep = np.isfinite(lam)
    return lam[keep], Z[:nd, keep]
