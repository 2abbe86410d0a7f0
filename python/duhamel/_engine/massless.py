"""Massless degrees of freedom: the exact static condensation of a positive semidefinite ``M``.

A dof whose row of ``M`` is zero (a rotation of a frame with lumped floor masses, an internal
node) carries no inertia: its equation is static, ``K_ss x_s + K_sm x_m = f_s``, at every
instant. With ``T = [I; -K_ss^-1 K_sm]`` the dofs with mass ``m`` obey the condensed model
``M_mm x_m'' + T^T C T x_m' + T^T K T x_m = T^T f``, and the massless ones follow from the static
relation ``x_s = K_ss^-1 (f_s - K_sm x_m)``.

The modes of the condensed model, expanded by ``T``, are the finite eigenpairs of
``K phi = omega^2 M phi`` (there are ``n_m`` of them, one per dof with mass); they are
M-orthonormal and K-orthogonal on the whole model, so the modal route needs nothing else for
loads at the dofs with mass: the response is ``Phi q``, massless dofs included. A load at a
massless dof projects on the modes exactly (``phi^T f = phi_m^T T^T f``), and adds its static
part ``K_ss^-1 f_s`` at the massless dofs, which no mode carries (:meth:`Condensation.static`).

A massless part whose stiffness ``K_ss`` is singular is a mechanism: refused, naming its dofs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.validate import SINGULAR_PIVOT_RTOL, issparse

__all__ = [
    "Condensation",
    "MasslessDamping",
    "load_terms",
    "massless_damping",
    "massless_dofs",
]

Array = NDArray[np.float64]


def massless_dofs(M: Any) -> NDArray[np.intp]:
    """The dofs whose diagonal entry of `M` is exactly zero (`M` checked semidefinite)."""
    return np.flatnonzero(np.asarray(M.diagonal(), dtype=np.float64) == 0.0)


def _mechanism(K_ss: Array, s: NDArray[np.intp]) -> ValueError:
    """The error naming the massless dofs that move in the null space of `K_ss` (dense)."""
    w, v = np.linalg.eigh((K_ss + K_ss.T) / 2)
    null = v[:, 0]
    dofs = s[np.abs(null) > 1e-3 * np.abs(null).max()].tolist()
    shown = ", ".join(str(d) for d in dofs[:12]) + (" ..." if len(dofs) > 12 else "")
    return ValueError(
        f"`M` has massless dofs whose stiffness is singular (a mechanism): the massless dofs "
        f"[{shown}] can move without mass and without stiffness (K_ss has the eigenvalue "
        f"{w[0]:.3g}); restrain them, give them stiffness, or give them mass"
    )


class Condensation:
    """The static condensation of the massless dofs `s` of ``(M, K)`` (see the module
    docstring); sparse `K` stays sparse (its ``K_ss`` factorised by SuperLU).

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel._engine.massless import Condensation
    >>> K = np.array([[2.0, -1.0], [-1.0, 2.0]])
    >>> c = Condensation(np.diag([1.0, 0.0]), K)
    >>> np.round(c.expand(np.array([[1.0]])).ravel(), 12).tolist()
    [1.0, 0.5]
    """

    def __init__(self, M: Any, K: Any) -> None:
        n = int(M.shape[0])
        self.n = n
        self.s = massless_dofs(M)
        mask = np.ones(n, dtype=bool)
        mask[self.s] = False
        self.m = np.flatnonzero(mask)
        self.sparse = issparse(K)
        if self.sparse:
            import scipy.sparse as sp

            Kc = sp.csr_array(K)
            self._K_ss = sp.csc_matrix(Kc[self.s][:, self.s])
            self._K_sm = sp.csr_array(Kc[self.s][:, self.m])
        else:
            Kd = np.asarray(K)
            self._K_ss = Kd[np.ix_(self.s, self.s)]
            self._K_sm = Kd[np.ix_(self.s, self.m)]
        self._factor = self._factorise()

    def _factorise(self) -> Any:
        """``K_ss`` factorised, or the mechanism error naming its dofs."""
        K_ss, s = self._K_ss, self.s
        diag = np.asarray(K_ss.diagonal(), dtype=np.float64)
        dense = K_ss.toarray() if self.sparse else K_ss
        if np.any(diag <= 0.0):
            if s.size <= 2000:
                raise _mechanism(dense if not self.sparse else K_ss.toarray(), s)
            raise ValueError(
                f"`M` has massless dofs whose stiffness is singular (a mechanism): massless "
                f"dof {int(s[np.argmax(diag <= 0.0)])} has K[i, i] = 0"
            )
        if self.sparse:
            from duhamel._engine.validate import symmetric_lu

            lu, n_bad = symmetric_lu(K_ss)
            pivots = None if lu is None else lu.U.diagonal()[lu.perm_r]
            if n_bad or pivots is None or np.min(pivots / diag) < SINGULAR_PIVOT_RTOL:
                if s.size <= 2000:
                    raise _mechanism(K_ss.toarray(), s)
                raise ValueError(
                    "`M` has massless dofs whose stiffness is singular (a mechanism): K_ss "
                    "has a non-positive pivot"
                )
            return lu
        import scipy.linalg

        try:
            chol = scipy.linalg.cho_factor(dense, lower=True, check_finite=False)
        except np.linalg.LinAlgError:
            raise _mechanism(dense, s) from None
        if np.min(np.diagonal(chol[0]) ** 2 / diag) < SINGULAR_PIVOT_RTOL:
            raise _mechanism(dense, s)
        return chol

    def solve_ss(self, b: Array) -> Array:
        """``K_ss^-1 b`` (`b` of shape ``(n_s,)`` or ``(n_s, k)``)."""
        if self.sparse:
            return np.asarray(self._factor.solve(np.asarray(b, dtype=np.float64)))
        import scipy.linalg

        return scipy.linalg.cho_solve(self._factor, b, check_finite=False)

    def expand(self, x_m: Array) -> Array:
        """Vectors of the dofs with mass (rows) completed by the static relation without
        load, ``x_s = -K_ss^-1 K_sm x_m``: shape ``(n, k)`` for `x_m` ``(n_m, k)``."""
        x_m = np.asarray(x_m, dtype=np.float64)
        out = np.empty((self.n, *x_m.shape[1:]))
        out[self.m] = x_m
        out[self.s] = -self.solve_ss(np.asarray(self._K_sm @ x_m))
        return out

    def condensed_stiffness(self, K: Any) -> Array:
        """``T^T K T = K_mm - K_ms K_ss^-1 K_sm`` (dense)."""
        m = self.m
        Kd = K.toarray() if issparse(K) else np.asarray(K)
        K_sm = Kd[np.ix_(self.s, m)]
        out = Kd[np.ix_(m, m)] - K_sm.T @ self.solve_ss(K_sm)
        return (out + out.T) / 2

    def transform(self) -> Array:
        """``T`` (dense, ``(n, n_m)``): the dofs with mass to every dof."""
        return self.expand(np.eye(self.m.size))

    def static(self, f: Array) -> Array:
        """The static part of loads `f` (rows: instants, columns: every dof) that no mode
        carries: ``K_ss^-1 f_s`` at the massless dofs, zero elsewhere (same shape)."""
        f = np.atleast_2d(np.asarray(f, dtype=np.float64))
        out = np.zeros_like(f)
        out[:, self.s] = self.solve_ss(f[:, self.s].T).T
        return out


@dataclass(frozen=True)
class MasslessDamping:
    """How the damping of a run's background reaches its massless dofs ``s``
    (:func:`massless_damping`; docs/basis.md, "Massless dofs").

    Attributes
    ----------
    kind : {"undamped", "rayleigh", "matrix"}
        ``"undamped"``: no damping there (``zeta``, none, or a ``C`` whose massless rows are
        zero): the massless dofs are quasi-static. ``"rayleigh"``: ``beta K`` there
        (``C_ss = beta K_ss``, ``Phi^T C E = 0``): every massless direction relaxes with the
        time constant ``beta``, uncoupled. ``"matrix"``: a damping matrix with entries
        there: first-order coordinates with the time constants of ``(C_ss, K_ss)``,
        coupled to the modes by ``Phi^T C E``.
    tau : ndarray
        The time constants: ``beta`` (rayleigh), the generalized eigenvalues of
        ``(C_ss, K_ss)`` (matrix, ascending), empty (undamped).
    """

    kind: str
    tau: Array


def massless_damping(system: Any) -> MasslessDamping | None:
    """How the damping of `system` (a run's background: its ``K`` with the elements' linear
    parts under FNA) reaches its massless dofs; None without massless dofs. The matrix case
    solves the generalized eigenproblem ``C_ss z = tau K_ss z`` (dense: refused above
    :data:`MAX_MATRIX_MASSLESS` massless dofs)."""
    c = system._condensation
    if c is None:
        return None
    kind = system.damping
    if kind == "rayleigh":
        beta = float(system.rayleigh[1])
        if beta == 0.0:
            return MasslessDamping("undamped", np.zeros(0))
        return MasslessDamping("rayleigh", np.full(c.s.size, beta))
    if kind != "matrix":
        return MasslessDamping("undamped", np.zeros(0))
    C = system.C
    cols = C[:, c.s] if issparse(C) else np.asarray(C)[:, c.s]
    if not (abs(cols).max() if cols.size else 0.0) > 0.0:
        return MasslessDamping("undamped", np.zeros(0))
    tau, _ = matrix_relaxation(system)
    return MasslessDamping("matrix", tau)


#: Most massless dofs a damping matrix with entries at them is analysed for (a dense
#: generalized eigenproblem of that size: their first-order coordinates).
MAX_MATRIX_MASSLESS = 3000


def matrix_relaxation(system: Any) -> tuple[Array, Array]:
    """``(tau, Z)``: ``C_ss Z = K_ss Z diag(tau)``, ``Z^T K_ss Z = I`` (dense), the time
    constants of the massless dofs of `system` under its damping matrix; values below
    ``1e-12`` of the largest are exactly 0 (those directions carry no damping). Refuses
    more than :data:`MAX_MATRIX_MASSLESS` massless dofs and a ``C`` negative there."""
    import scipy.linalg

    c = system._condensation
    s = c.s
    if s.size > MAX_MATRIX_MASSLESS:
        raise ValueError(
            f"the damping matrix `C` acts on {s.size} massless dofs (more than "
            f"{MAX_MATRIX_MASSLESS}): their first-order coordinates need a dense "
            "eigenproblem of that size; damp with `zeta` or `rayleigh`, give those dofs "
            "mass, or run duhamel.Newmark()"
        )
    C = system.C
    C_ss = C[s][:, s].toarray() if issparse(C) else np.asarray(C)[np.ix_(s, s)]
    K_ss = c._K_ss.toarray() if c.sparse else np.asarray(c._K_ss)
    tau, Z = scipy.linalg.eigh((C_ss + C_ss.T) / 2, (K_ss + K_ss.T) / 2, check_finite=False)
    top = float(np.abs(tau).max(initial=0.0))
    if tau.size and tau[0] < -1e-10 * top:
        d = int(s[np.argmax(np.abs(Z[:, 0]))])
        raise ValueError(
            f"the damping matrix `C` is negative at the massless dofs (a direction around "
            f"dof {d} has the time constant {tau[0]:.3g} s): a massless dof with negative "
            "damping has no stable motion; check `C`"
        )
    tau = np.where(tau <= 1e-12 * top, 0.0, tau)
    return tau, Z


def load_terms(
    system: Any,
    loads: Any,
    t: Array,
    dofs: NDArray[np.int64],
    dt: float,
    carried: Array | None = None,
) -> tuple[Array, Array, Array] | None:
    """The static response of the massless dofs to the loads acting on them, ``K_ss^-1
    f_s(t)`` (no mode carries it), at the saved instants `t` and output `dofs`: ``(x, v, a)``
    terms to add, or None when no load acts on a massless dof. The velocity and acceleration
    terms are central differences of the loads over ``h = 1e-3 dt``. `carried`: the
    K-orthonormal vectors the run's massless coordinates already carry
    (:func:`duhamel._engine.relaxation.massless_coordinates`), whose part is left out."""
    c = system._condensation
    if c is None or not loads:
        return None
    from duhamel.loads import Callable

    touches = False
    for load in loads:
        if isinstance(load, Callable):
            touches = True
            break
        for pattern in (term.pattern for term in load._terms(system)):
            if np.any(np.asarray(pattern)[c.s]):
                touches = True
    if not touches:
        return None

    def forces(times: Array) -> Array:
        f = np.zeros((times.size, system.n_dof))
        for load in loads:
            f += np.asarray(load.evaluate(system, times)).reshape(times.size, -1)
        return f

    if (
        not np.any(forces(t)[:, c.s])
        and t.size > 1
        and not any(isinstance(load, Callable) for load in loads)
    ):
        return None
    h = 1e-3 * dt

    def static(f: Array) -> Array:  # the part the massless coordinates do not carry
        out = c.static(f)
        if carried is not None and carried.shape[1]:
            out -= (f @ carried) @ carried.T
        return out[:, dofs]

    f0, fp, fm = forces(t), forces(t + h), forces(t - h)
    x = static(f0)
    v = static((fp - fm) / (2 * h))
    a = static((fp - 2 * f0 + fm) / (h * h))
    return x, v, a
