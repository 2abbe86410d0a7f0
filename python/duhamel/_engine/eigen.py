"""The undamped modes ``K phi = omega^2 M phi`` of one system: computed, grown, or supplied.

A :class:`Modes` keeps the lowest modes known so far (mass-normalised, ascending) and
computes more only when more are asked for:

* dense (and sparse when nearly every mode is wanted): ``scipy.linalg.eigh``;
* sparse: shift-invert Lanczos (``eigsh``) about a small negative shift ``sigma``, on one
  symmetric SuperLU factorisation of ``K - sigma M`` made once per system and kept. Its
  inertia proves ``K - sigma M`` positive definite (so no eigenvalue lies below ``sigma``,
  where the iteration could miss it); it serves every later growth; and it answers the
  stiffness's own semidefiniteness check (:func:`~duhamel._engine.validate.check_semidefinite`)
  whenever ``|sigma| |M| <= tau``, so a free-free model needs no second factorisation.

Growth: with ``m`` modes known, ``k`` more are the lowest ``k`` of the problem restricted to
the M-orthogonal complement of the known ones. Sparse: ``eigsh`` on the deflated operator
``P (K - sigma M)^-1 M P``, ``P = I - Phi Phi^T M`` (the known modes become eigenvalue 0 of
the operator, which is never wanted), on the kept factorisation. Dense: ``eigh`` of the
complement's projected problem. The known modes stay as they are, so a basis of ``n`` modes
is always the first ``n`` of a larger one.

Modes supplied by the user (:meth:`duhamel.System.use_basis`) start the store; they are
extended the same way when allowed.
"""

from __future__ import annotations

from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.memory import SMALL_ALLOCATION, check_fits
from duhamel._engine.validate import check_semidefinite, issparse, symmetric_lu

__all__ = ["DENSE_EIGH_ARRAYS", "NEG_EIG_RTOL", "SHIFT_RTOL", "ZERO_EIG_RTOL", "Modes"]

#: Eigenvalues below ``-NEG_EIG_RTOL * scale`` mean K is not positive semidefinite.
NEG_EIG_RTOL = 1e-9
#: Eigenvalues with ``omega2 <= ZERO_EIG_RTOL * scale`` are rigid-body modes, set to exactly 0.
ZERO_EIG_RTOL = 1e-12
#: Sparse shift-invert uses sigma = -SHIFT_RTOL * max(diag(K) / diag(M)): far enough below 0
#: for a reliable inertia check of K - sigma M, close enough for fast convergence.
SHIFT_RTOL = 1e-10
#: Dense ``n x n`` float64 arrays a full dense eigendecomposition holds at its peak: K and M
#: densified, LAPACK's copies of them, the eigenvectors and the workspace (the peak resident
#: memory measured 3.3 and 5.1 of them at n = 1,500 and 3,000).
DENSE_EIGH_ARRAYS = 6
#: Seed of the Lanczos start vector: the same model gives the same modes, run after run.
_SEED = 12

Array = NDArray[np.float64]


def _sym(a: Array) -> Array:
    return (a + a.T) / 2


class Modes:
    """The lowest undamped modes of ``(K, M)`` known so far (see the module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel._engine.eigen import Modes
    >>> modes = Modes(np.eye(3), np.diag([3.0, 1.0, 2.0]))
    >>> lam, phi = modes.lowest(2)
    >>> lam.tolist(), modes.lowest(3)[0].tolist()
    ([1.0, 2.0], [1.0, 2.0, 3.0])
    """

    def __init__(self, M: Any, K: Any, condensation: Any = None) -> None:
        self._M, self._K = M, K
        #: The static condensation of massless dofs (:mod:`duhamel._engine.massless`) or None.
        self._condensation = condensation
        self._sparse = issparse(M) or issparse(K)
        n = int(M.shape[0])
        self.lam: Array = np.zeros(0)
        self.phi: Array = np.zeros((n, 0))
        #: Whether the modes were supplied, and whether more may then be computed.
        self.supplied = False
        self.extend = True
        #: ``(lu, sigma, M, K)`` of the sparse shift-invert, made once (CSC matrices).
        self._factor: tuple[Any, float, Any, Any] | None = None
        self._semidefinite = False
        mass = np.asarray(M.diagonal())
        ratio = np.abs(np.asarray(K.diagonal()))[mass > 0] / mass[mass > 0]
        self._ratio = float(np.max(ratio))
        #: Number of finite modes: one per dof with mass.
        self.n_finite = int(np.count_nonzero(mass > 0))

    @property
    def count(self) -> int:
        """Number of modes known."""
        return int(self.lam.size)

    def supply(self, lam: Array, phi: Array, *, extend: bool) -> None:
        """Start from the given modes (checked by the caller); `extend`: compute more when
        more are asked for, rather than raise."""
        self.lam, self.phi = lam, phi
        self.supplied, self.extend = True, extend

    def lowest(self, n: int) -> tuple[Array, Array]:
        """The lowest `n` modes ``(omega2, phi)``, computing the ones not yet known."""
        m = self.count
        if n > m:
            if self.supplied and not self.extend:
                every = " (every mode)" if n == self.phi.shape[0] else ""
                raise ValueError(
                    f"`modes` = {n}{every} asks for more modes than the basis given to "
                    f"use_basis holds ({m}): pass modes <= {m} (e.g. Semianalytic(modes={m})), "
                    "or let the system compute the others with use_basis(basis, extend=True)"
                )
            lam, phi = self._more(n - m)
            phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, np.asarray(self._M @ phi)))
            lam = self._checked(lam)
            lam, phi = np.concatenate([self.lam, lam]), np.hstack([self.phi, phi])
            order = np.argsort(lam, kind="stable")  # known modes first among equals
            if np.any(order != np.arange(n)):
                lam, phi = lam[order], phi[:, order]
            self.lam, self.phi = lam, np.ascontiguousarray(phi)
        return self.lam[:n], self.phi[:, :n]

    # ------------------------------------------------------------------ computing
    def _more(self, k: int) -> tuple[Array, Array]:
        if self._sparse and self.count + k < self.n_finite - 1:
            return self._sparse_more(k)
        return self._dense_more(k)

    def _factorisation(self) -> tuple[Any, float, Any, Any]:
        if self._factor is None:
            import scipy.sparse as sp

            M, K = sp.csc_matrix(self._M), sp.csc_matrix(self._K)
            sigma = -SHIFT_RTOL * (self._ratio if self._ratio > 0.0 else 1.0)
            # A negative pivot of K - sigma M means K has an eigenvalue below sigma < 0, which
            # the shift-invert iteration (eigenvalues nearest sigma) could otherwise miss.
            lu, n_bad = symmetric_lu(K - sigma * M)
            if n_bad:
                raise ValueError(
                    f"`K` must be positive semidefinite, but K - sigma M (sigma = {sigma:.3g}) "
                    "has a non-positive pivot, so K has an eigenvalue below sigma"
                )
            self._factor = (lu, sigma, M, K)
        return self._factor

    def _sparse_more(self, k: int) -> tuple[Array, Array]:
        import scipy.linalg
        import scipy.sparse.linalg as spla

        lu, sigma, M, K = self._factorisation()
        known, n_dof, m = self.phi, self.phi.shape[0], self.count
        m_known = np.asarray(M @ known)

        def deflate(x: Array) -> Array:  # P x: the M-orthogonal part off the known modes
            return x - known @ (m_known.T @ x) if m else x

        def op_inv(b: Array) -> Array:  # b = M x; P (K - sigma M)^-1 M P x
            return deflate(lu.solve(b - m_known @ (known.T @ b) if m else b))

        op = spla.LinearOperator((n_dof, n_dof), matvec=op_inv, dtype=np.float64)
        v0 = deflate(np.random.default_rng(_SEED).standard_normal(n_dof))  # type: ignore[arg-type]
        ncv = min(n_dof - m, max(2 * k + 1, 20))
        _, x = spla.eigsh(K, k=k, M=M, sigma=sigma, which="LM", OPinv=op, v0=v0, ncv=ncv)
        x = deflate(deflate(x))  # twice: exactly M-orthogonal to the known modes
        # Rayleigh-Ritz on the converged subspace: exact M-orthonormality, sorted output.
        lam, y = scipy.linalg.eigh(_sym(x.T @ (K @ x)), _sym(x.T @ (M @ x)))
        return lam, x @ y

    def _dense_more(self, k: int) -> tuple[Array, Array]:
        import scipy.linalg as la

        n = int(self._M.shape[0])
        need = DENSE_EIGH_ARRAYS * 8.0 * n * n
        if need > SMALL_ALLOCATION:  # the messages only where the check may refuse
            advice = (
                "ask for the lowest modes only (`duhamel.Semianalytic(modes=...)`), which a "
                "sparse model (scipy.sparse M and K) computes by shift-invert Lanczos"
            )
            if self._sparse:
                advice += (
                    "; with modal damping (`zeta`) on a direct integrator use Rayleigh damping "
                    "(`rayleigh=(alpha, beta)`), which keeps the model sparse"
                )
            wanted = self.count + k
            check_fits(
                need,
                f"`modes` = {wanted:,} of the {n:,}-dof model asks for a full dense "
                f"eigendecomposition (scipy.linalg.eigh of {n:,} x {n:,} matrices), which",
                advice,
            )

        def dense(a: Any) -> Array:
            return a.toarray() if issparse(a) else np.asarray(a)

        K, M, m = dense(self._K), dense(self._M), self.count
        c = self._condensation
        if c is not None:  # the condensed model's modes, expanded: every finite one
            idx = np.ix_(c.m, c.m)
            lam, y = la.eigh(c.condensed_stiffness(K), M[idx], check_finite=False)
            if m:  # continue the known ones: the complement's modes in the known span's order
                x = c.expand(y)
                x = x - self.phi @ (self.phi.T @ (M @ x))
                g = x.T @ M @ x
                s, u = la.eigh(_sym(g))
                x = x @ (u[:, s > 1e-10 * s.max()] / np.sqrt(s[s > 1e-10 * s.max()]))
                lam, y2 = la.eigh(_sym(x.T @ K @ x), _sym(x.T @ M @ x), check_finite=False)
                return lam[:k], (x @ y2)[:, :k]
            return lam[:k], c.expand(y[:, :k])
        if m == 0:
            return cast(
                tuple[Array, Array], la.eigh(K, M, subset_by_index=[0, k - 1], check_finite=False)
            )
        # With M = L L^T and y = L^T x the problem is standard, A = L^-1 K L^-T, and the known
        # modes are orthonormal columns L^T phi; Q spans their orthogonal complement.
        L = la.cholesky(M, lower=True, check_finite=False)
        A = la.solve_triangular(L, la.solve_triangular(L, K, lower=True).T, lower=True)
        q = la.qr(L.T @ self.phi, mode="full", check_finite=False)[0][:, m:]
        lam, y = la.eigh(_sym(q.T @ A @ q), subset_by_index=[0, k - 1], check_finite=False)
        return lam, la.solve_triangular(L.T, q @ y, lower=False)

    def _checked(self, lam: Array) -> Array:
        """Refuses a negative eigenvalue; sets rigid-body modes' to exactly 0 once K is known
        to be semidefinite (a test of K alone: an ill-conditioned M inflates `scale` and could
        hide a negative eigenvalue, by Sylvester's law of inertia)."""
        scale = max(float(np.max(np.abs(lam))), self._ratio)
        if lam[0] < -NEG_EIG_RTOL * scale:
            raise ValueError(
                f"`K` must be positive semidefinite, but the modal analysis found "
                f"omega^2 = {lam[0]:.6g} < 0 (tolerance {NEG_EIG_RTOL:g} * {scale:.6g})"
            )
        zero = lam <= ZERO_EIG_RTOL * scale
        if zero.any() and not self._semidefinite:
            shifted = None
            if self._factor is not None:  # K - sigma M > 0: its inertia may answer
                _, sigma, M, _ = self._factor
                shifted = (-sigma, float(abs(M).sum(axis=1).max()))
            check_semidefinite(self._K, NEG_EIG_RTOL, shifted=shifted)
            self._semidefinite = True
        return np.where(zero, 0.0, lam)
