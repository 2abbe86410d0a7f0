"""Static correction of a reduced modal basis (load-dependent Ritz vectors, as FNA uses).

Free-interface modes cannot represent the local response at a stiff nonlinear link or under
a concentrated load: that is what the truncated modes would have carried, quasi-statically.
The basis is enriched with the static responses ``K^-1 f`` to unit forces along each
element's deformations (``e_i - e_j`` for a two-node element, ``e_d`` at each dof of the
others) and to the load patterns, made mass-orthogonal to the kept modes and among
themselves (dependent vectors dropped), and rotated by a Rayleigh-Ritz solve in their span.
As the kept modes are eigenvectors, ``K`` stays diagonal on the whole enriched basis: every
coordinate is still an uncoupled oscillator, stepped with its exact transition matrices.

A static load whose pattern is one of those vectors is then represented exactly: its static
response lies in the basis.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.eigen import SHIFT_RTOL
from duhamel._engine.validate import issparse
from duhamel.couplings import LinearCoupling
from duhamel.loads import Callable
from duhamel.modal import ModalBasis, damped
from duhamel.system import System

__all__ = ["corrected", "enriched", "force_directions", "resolved", "stiffness_ratios", "substeps"]

Array = NDArray[np.float64]

#: The internal step resolves every correction coordinate whose ``omega dt`` would fall in
#: ``(RESOLVED, STIFF)`` down to ``omega dt <= RESOLVED`` (see :func:`substeps`).
RESOLVED = 1.0
STIFF = 4.0
#: At most this many internal steps per step.
MAX_SUBSTEPS = 64
#: A correction coordinate whose elements' tangent stiffness on it stays within
#: ``SAFE_RATIO * zeta`` of its own ``omega^2`` (``zeta`` its damping ratio) is stable at any
#: ``omega dt`` and is not resolved in time (see :func:`resolved`).
SAFE_RATIO = 2.0

#: Correction vectors whose M-norm falls below this fraction of their size after the kept
#: modes are removed are dependent (already in the basis) and dropped.
DEPENDENT_RTOL = 1e-8


def force_directions(system: System) -> Array:
    """Unit force patterns along the elements' deformations and the load patterns of
    `system`, as columns (Python load functions have none)."""
    n = system.n_dof
    cols: list[Array] = []
    for element in system.elements:
        if isinstance(element, LinearCoupling):
            continue
        for i, j in element._directions():
            f = np.zeros(n)
            f[i] = 1.0
            if j is not None:
                f[j] = -1.0
            cols.append(f)
    for load in system.loads:
        if isinstance(load, Callable):
            continue
        for pattern in (term.pattern for term in load._terms(system)):
            p = np.asarray(pattern, dtype=np.float64)
            if np.any(p):
                cols.append(p / np.abs(p).max())
    return np.stack(cols, axis=1) if cols else np.zeros((n, 0))


def _static(system: System, basis: ModalBasis, f: Array) -> Array:
    """``K^-1 f`` for the forces `f` with their components on the rigid-body modes of `basis`
    removed first (forces that had nothing else are dropped), by iterative refinement on the
    factorisation of ``K - sigma M`` (shared with the modal analysis for a sparse model)."""
    M = system.M
    scale = max(float(np.max(np.abs(basis.omega2))), system._modes._ratio)
    rigid = basis.omega2 <= 1e-10 * scale if scale > 0.0 else np.ones(basis.n_modes, bool)
    if np.any(rigid):
        phi0 = basis.phi[:, rigid]
        size = np.abs(f).max(axis=0)
        f = f - np.asarray(M @ phi0) @ (phi0.T @ f)
        f = f[:, np.abs(f).max(axis=0) > 1e-10 * size]
    if f.shape[1] == 0:
        return f
    if issparse(system.M) or issparse(system.K):
        lu, sigma, Mc, _ = system._modes._factorisation()
        solve = lu.solve
        mass = Mc
    else:
        import scipy.linalg

        K, Md = np.asarray(system.K), np.asarray(M)
        mass = np.diag(Md)  # massless dofs (zero diagonal) left out of the scale
        ratio = float(np.max(np.abs(np.diag(K))[mass > 0] / mass[mass > 0]))
        sigma = -SHIFT_RTOL * (ratio if ratio > 0.0 else 1.0)
        factor = scipy.linalg.lu_factor(K - sigma * Md, check_finite=False)
        solve = lambda b: scipy.linalg.lu_solve(factor, b, check_finite=False)  # noqa: E731
        mass = Md
    with np.errstate(all="ignore"):  # overflow in extreme units: such columns are dropped
        x = np.asarray(solve(f))
        for _ in range(3):  # (K - sigma M) x_{k+1} = f - sigma M x_k converges to K^-1 f
            step = np.asarray(solve(f - sigma * np.asarray(mass @ x)))
            if not np.all(np.isfinite(step)):
                break  # keep the last finite iterate
            x = step
    c = system._condensation
    if c is not None:  # K^-1 f = T K_c^-1 T^T f + E K_ss^-1 f_s: the condensed part only
        x[c.s] -= c.solve_ss(f[c.s])  # (the massless part is the massless coordinates')
    return x


def _m_orthonormal(system: System, phi: Array, x: Array) -> Array:
    """The part of the columns of `x` M-orthogonal to `phi`, M-orthonormalised, dependent
    directions dropped. Computed with M scaled to unit diagonal (models in any units)."""
    scale = float(np.max(system.M.diagonal()))
    Ms = system.M / scale  # phi is Ms-orthogonal with phi.T Ms phi = I / scale
    x = x[:, np.all(np.isfinite(x), axis=0) & (np.abs(x).max(axis=0) > 0)]
    if x.shape[1] == 0:
        return x
    x = x / np.abs(x).max(axis=0)
    x = x / np.sqrt(np.einsum("ij,ij->j", x, np.asarray(Ms @ x)))

    def project(y: Array) -> Array:
        return y - phi @ ((phi.T @ np.asarray(Ms @ y)) * scale)

    x = project(project(x))  # twice: orthogonal to working precision
    g = x.T @ np.asarray(Ms @ x)
    s, u = np.linalg.eigh((g + g.T) / 2)
    keep = s > DEPENDENT_RTOL**2  # the columns had unit norm before the projection
    if not np.any(keep):
        return x[:, :0]
    y = project(x @ (u[:, keep] / np.sqrt(s[keep])))
    g = y.T @ np.asarray(Ms @ y)
    c = np.linalg.cholesky((g + g.T) / 2)
    return np.linalg.solve(c, y.T).T / np.sqrt(scale)  # M-orthonormal


@dataclass(frozen=True)
class _Damping:
    """The damping of a system as :func:`duhamel.modal.damped` reads it."""

    damping: str
    zeta: Any
    rayleigh: tuple[float, float] | None
    C: Any
    K: Any
    M: Any


def _damping(system: System, n_modes: int, order: NDArray[np.intp]) -> _Damping:
    """`system`'s damping for :func:`duhamel.modal.damped` on the enriched basis (columns in
    `order`): per-mode ratios extended to the correction vectors with the last mode's."""
    z = system.zeta
    if system.damping == "zeta" and isinstance(z, np.ndarray):
        extra = np.full(order.size - n_modes, z[min(n_modes, z.size) - 1])
        z = np.concatenate([z[:n_modes], extra])[order]
    return _Damping(system.damping, z, system.rayleigh, system.C, system.K, system.M)


def corrected(system: System, basis: ModalBasis) -> ModalBasis:
    """`basis` (the lowest modes of `system`) enriched with the static responses to its
    elements' deformation forces and load patterns; cached on `system` per basis size and
    force patterns."""
    return enriched(system, basis)[0]


def substeps(omega: Array, dt: float) -> int:
    """Internal steps per step `dt` for a run whose static-correction coordinates have the
    circular frequencies `omega` and carry nonlinear elements as pseudo-forces.

    The pseudo-force step (scheme b) is only conditionally stable on a coordinate with
    ``1 <~ omega dt <~ 4`` once an element's tangent stiffness on it, ``k_t phi_d^2``,
    exceeds about its own ``omega^2`` (measured on one oscillator, zeta = 0.05: spectral
    radius 1.22 at ``omega dt = 2.5`` with the ratio 1, 2.15 at 1.5 with 10; below 1 for
    ``omega dt <= 1`` up to the ratio 10 and for ``omega dt >= 4`` at any ratio). A
    correction coordinate holds the whole residual flexibility ``R_dd`` of the truncated
    modes at an element's dof, so that ratio is ``k_t R_dd``, while the full model spreads
    the same flexibility over many modes, each with a small share, the stiff local ones at
    ``omega dt >> 4``. The reduced model stays cheap, so its correction coordinates are
    resolved in time instead: the smallest count of internal steps that leaves none of them
    in ``(RESOLVED, STIFF)``.

    A run passes only the coordinates :func:`resolved` keeps (those whose elements' bounded
    tangent can exceed ``SAFE_RATIO * zeta`` of their ``omega^2``; all of them under an
    element with an unbounded tangent). The count is the cheapest that clears the band: a
    count between two tried ones would leave the largest coordinate in the band in it."""
    if len(omega) == 0:  # no correction coordinate: the common case, at once
        return 1
    h = np.asarray(omega, dtype=np.float64) * dt
    n = 1
    while n < MAX_SUBSTEPS:
        band = h[(h / n > RESOLVED) & (h / n < STIFF)]
        if band.size == 0:
            break
        n = min(MAX_SUBSTEPS, max(n + 1, int(np.ceil(float(band.max()) / RESOLVED))))
    return n


def enriched(system: System, basis: ModalBasis) -> tuple[ModalBasis, Array]:
    """:func:`corrected` with the circular frequencies of the correction coordinates (their
    Ritz values' roots; empty when nothing was added)."""
    f = force_directions(system)
    key = (basis.n_modes, f.shape[1], f.tobytes())
    cache = system.__dict__.setdefault("_corrected", {})
    if key in cache:
        return cache[key]
    n = basis.n_modes
    if f.shape[1] == 0 or n == system.n_mass:
        return basis, np.zeros(0)
    try:
        y = _m_orthonormal(system, basis.phi, _static(system, basis, f))
    except np.linalg.LinAlgError:  # vectors dependent to round-off: nothing to add
        y = np.zeros((system.n_dof, 0))
    if y.shape[1]:
        ky = y.T @ np.asarray(system.K @ y)
        theta, w = np.linalg.eigh((ky + ky.T) / 2)
        y = y @ w
        theta = np.maximum(theta, 0.0)
        lam = np.concatenate([basis.omega2, theta])
        phi = np.hstack([basis.phi, y])
    else:
        theta = np.zeros(0)
        lam, phi = np.asarray(basis.omega2), np.asarray(basis.phi)
    order = np.argsort(lam, kind="stable")
    lam, phi = lam[order], np.ascontiguousarray(phi[:, order])
    result = damped(lam, phi, _damping(system, n, order)), np.sqrt(theta)
    cache[key] = result
    return result


def stiffness_ratios(system: System, basis: ModalBasis, columns: NDArray[np.intp]) -> Array:
    """Per column of `basis` in `columns`, an upper bound on the ratio ``a`` of the elements'
    tangent stiffness projected on that coordinate to its own ``omega^2``, less the margin
    its damping leaves: ``(sum_e k_e |phi_e|^2) / omega^2 - SAFE_RATIO * zeta_eff`` where
    ``zeta_eff`` is its damping ratio less what the elements' damping could take away (the
    off-diagonal modal damping of a non-proportional ``C``, dissipative as a whole, is not
    counted); ``inf`` where an element with an unbounded tangent loads it. The coordinate is
    stable at any ``omega dt`` when the value is <= 0 (see :func:`resolved`)."""
    phi = basis.phi[:, columns]
    w2 = np.asarray(basis.omega2, dtype=np.float64)[columns]
    w = np.sqrt(np.maximum(w2, 0.0))
    k = np.zeros(columns.size)
    c = np.zeros(columns.size)
    scale = np.abs(phi).max(axis=0) if phi.size else np.zeros(0)
    for element in system.elements:
        if isinstance(element, LinearCoupling):
            continue
        share = np.zeros(columns.size)
        for i, j in element._directions():
            d = phi[i] if j is None else phi[i] - phi[j]
            share += d * d
        loaded = share > (1e-12 * scale) ** 2
        bound = element._tangent_bound()
        if bound is None:
            k[loaded] = np.inf
            continue
        k += bound[0] * share
        c += bound[1] * share
    zeta = np.asarray(basis.zeta, dtype=np.float64)[columns].copy()
    with np.errstate(divide="ignore", invalid="ignore"):
        zeta = np.where(w > 0.0, zeta - c / (2.0 * np.where(w > 0, w, 1.0)), 0.0)
        ratio = np.where(w2 > 0.0, k / np.where(w2 > 0, w2, 1.0), np.inf)
        out = ratio - SAFE_RATIO * np.maximum(zeta, 0.0)
    return np.where(np.isnan(out), np.inf, out)


def resolved(system: System, basis: ModalBasis, omega: Array) -> Array:
    """The circular frequencies among `omega` (the static-correction coordinates of the
    enriched `basis`) that a run must resolve in time (:func:`substeps`): those the
    elements' tangent can make unstable.

    Measured on one oscillator (the pseudo-force step, scheme b, with a linear element of
    ``a`` times its stiffness as a pseudo-force; spectral radius over ``omega dt`` from 0.05
    to 60): stable at every ``omega dt`` for ``|a| <= 0.02`` at zeta = 0.005 and 0.01,
    ``|a| <= 0.05`` at 0.02, ``|a| <= 0.2`` at 0.05, and unstable near ``omega dt = pi``
    just beyond (1 + 1.5e-2 at zeta = 0.005, a = 0.05; 1 + 2.2e-3 at 0.02, a = -0.1;
    1 + 5.9e-2 at 0.05, a = -0.3). A positive damping pseudo-force is stable. The rule
    keeps a coordinate out of the band check when ``|a| <= SAFE_RATIO * zeta`` with ``a``
    from the elements' largest tangent (:func:`stiffness_ratios`); a coordinate loaded by
    an element whose tangent has no bound (``Cubic``, a ``Spring`` with ``k3``, a Python
    element) is always resolved, since the core's stiffness watch only sees elements at
    least twice the background's stiffness and the band is unstable from ``a`` ~ 2 zeta
    up to there."""
    omega = np.asarray(omega, dtype=np.float64)
    if omega.size == 0:
        return omega
    w = np.sqrt(np.maximum(np.asarray(basis.omega2, dtype=np.float64), 0.0))
    columns = []
    for value in omega:
        match = np.flatnonzero(w == value)
        if match.size != 1:  # not identified (ambiguous): resolved, as before
            return omega
        columns.append(int(match[0]))
    ratio = stiffness_ratios(system, basis, np.asarray(columns, dtype=np.intp))
    return omega[ratio > 0.0]
