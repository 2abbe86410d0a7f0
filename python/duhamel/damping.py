"""Damping made explicit: Rayleigh coefficients from two periods, damping restricted to a part
of the model, and each mode's resulting damping ratio.

The convention (docs/structural.md, "Damping conventions"): ``zeta`` is the damping ratio of
the modes of the *background* a run integrates. With ``Semianalytic(linear_parts="auto")``
and ``zeta`` given, the background is ``K`` alone, so a mode that exists only through the
elements' stiffness (an isolation mode on isolators given as elements) has ``omega = 0`` in
``K`` and gets no damping from ``zeta``; with ``linear_parts="background"`` (ETABS/FNA) the
modes are those of ``K`` plus the elements' initial stiffness, and every one of them, the
isolation mode included, is damped at ``zeta``. :func:`damping_summary` states which.
"""

from __future__ import annotations

import numbers
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.validate import as_square_matrix, finite_float, issparse, positive_float

__all__ = ["DampingSummary", "Rayleigh", "damping_spec", "damping_summary"]


@dataclass(frozen=True)
class Rayleigh:
    """Rayleigh damping ``C = alpha M + beta K``, optionally restricted to a part of the
    model: ``stiffness`` replaces ``K`` in the ``beta`` term (e.g. the superstructure's
    stiffness only, as an OpenSees model that damps the frame's elements and not the
    isolators), and ``dofs`` keeps both terms on those dofs only (their rows and columns).

    Pass it as ``System(M, K, rayleigh=...)``. Unrestricted it is classical damping (exact
    modal ratios ``(alpha / omega + beta omega) / 2``); restricted it is a damping matrix
    (:meth:`matrix`), non-classical in general, integrated exactly on the first-order route.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> r = duhamel.Rayleigh.from_periods(1.0, 0.2, 0.05)
    >>> w = 2 * np.pi / np.array([1.0, 0.2])
    >>> np.round((r.alpha / w + r.beta * w) / 2, 12).tolist()
    [0.05, 0.05]
    """

    alpha: float
    beta: float
    stiffness: Any = None
    dofs: Any = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "alpha", finite_float(self.alpha, "alpha"))
        object.__setattr__(self, "beta", finite_float(self.beta, "beta"))

    @classmethod
    def from_frequencies(
        cls,
        omega1: float,
        omega2: float,
        zeta: float | tuple[float, float],
        *,
        stiffness: Any = None,
        dofs: Sequence[int] | None = None,
    ) -> Rayleigh:
        """The coefficients that give the ratios `zeta` (one value, or one per frequency) at
        the circular frequencies `omega1` and `omega2` (rad/s, distinct).

        Examples
        --------
        >>> import duhamel
        >>> r = duhamel.Rayleigh.from_frequencies(2.0, 20.0, 0.05)
        >>> round(r.alpha, 6), round(r.beta, 6)
        (0.181818, 0.004545)
        """
        w1, w2 = positive_float(omega1, "omega1"), positive_float(omega2, "omega2")
        if w1 == w2:
            raise ValueError(f"`omega1` and `omega2` must differ, both are {w1}")
        z = np.broadcast_to(np.asarray(zeta, dtype=np.float64), (2,))
        # zeta_i = alpha / (2 w_i) + beta w_i / 2
        A = np.array([[1 / (2 * w1), w1 / 2], [1 / (2 * w2), w2 / 2]])
        alpha, beta = np.linalg.solve(A, z)
        return cls(float(alpha), float(beta), stiffness, dofs)

    @classmethod
    def from_periods(
        cls,
        T1: float,
        T2: float,
        zeta: float | tuple[float, float],
        *,
        stiffness: Any = None,
        dofs: Sequence[int] | None = None,
    ) -> Rayleigh:
        """The coefficients that give the ratios `zeta` at the periods `T1` and `T2` (s).

        Examples
        --------
        >>> import duhamel
        >>> duhamel.Rayleigh.from_periods(2.0, 0.5, 0.05).alpha > 0
        True
        """
        t1, t2 = positive_float(T1, "T1"), positive_float(T2, "T2")
        return cls.from_frequencies(
            2 * np.pi / t1, 2 * np.pi / t2, zeta, stiffness=stiffness, dofs=dofs
        )

    @property
    def restricted(self) -> bool:
        """Whether the damping acts on a part of the model only (a matrix, not ratios)."""
        return self.stiffness is not None or self.dofs is not None

    def matrix(self, M: Any, K: Any) -> Any:
        """``alpha M + beta K_s`` with ``K_s`` = `stiffness` (default `K`), kept on `dofs`
        only when given (sparse when `M` or ``K_s`` is)."""
        n = int(M.shape[0])
        Ks = K if self.stiffness is None else as_square_matrix(self.stiffness, "stiffness", n=n)
        sparse = issparse(M) or issparse(Ks)
        if sparse:
            import scipy.sparse as sp

            C = self.alpha * sp.csr_array(M) + self.beta * sp.csr_array(Ks)
        else:
            C = self.alpha * np.asarray(M) + self.beta * np.asarray(Ks)
        if self.dofs is not None:
            from duhamel._engine.validate import dof_list

            d = dof_list(self.dofs, "dofs", n)
            keep = np.zeros(n)
            keep[d] = 1.0
            if sparse:
                D = sp.diags_array(keep)
                C = sp.csr_array(D @ C @ D)
            else:
                C = C * np.outer(keep, keep)
        return C


@dataclass(frozen=True)
class DampingSummary:
    """Each mode's damping as a run integrates it.

    Attributes
    ----------
    omega : ndarray
        Undamped circular frequencies (rad/s) of the structure with the elements at their
        initial stiffness (their linear parts): the isolation mode of an isolated building.
    zeta : ndarray
        Their damping ratios: the modal ratios when the damping is diagonal on these modes,
        else those of the first-order (complex) modes, ``-Re(lambda) / |lambda|``, each
        paired with the undamped mode nearest in frequency.
    classical : bool
        Whether the damping is diagonal on these modes.
    background : str
        The modes a ``zeta`` is given on: ``"K"`` (``linear_parts="auto"`` with ``zeta``, or
        ``"pseudo-force"``) or ``"K + elements"`` (``"background"``, FNA's convention).
    massless : str
        What happens to damping at the massless dofs (empty without them): none reaches
        them (they are static), or it does and they are first-order coordinates with the
        time constants stated (docs/basis.md, "Massless dofs"); the ratios `zeta` are then
        those of the modes coupled with them.
    """

    omega: NDArray[np.float64]
    zeta: NDArray[np.float64]
    classical: bool
    background: str
    massless: str = ""

    def __str__(self) -> str:
        lines = [
            f"modes of {self.background}; damping "
            + ("classical" if self.classical else "non-classical"),
        ]
        if self.massless:
            lines.append(self.massless)
        lines.append(f"{'mode':>4} {'omega (rad/s)':>14} {'T (s)':>10} {'zeta':>8}")
        for i, (w, z) in enumerate(zip(self.omega, self.zeta, strict=True)):
            period = 2 * np.pi / w if w > 0 else np.inf
            lines.append(f"{i:>4} {w:>14.6g} {period:>10.4g} {z:>8.4f}")
        return "\n".join(lines)


def _ratios(
    omega: NDArray[np.float64], Cq: NDArray[np.float64], massless: tuple[Any, ...] | None = None
) -> tuple[NDArray, bool]:
    """Damping ratios of ``q'' + Cq q' + diag(omega^2) q = 0`` per mode (each undamped mode
    paired with the first-order eigenvalue nearest its frequency), and whether `Cq` is
    diagonal (classical). `massless`: ``(phi, C, Z, tau, s)``, the massless dofs `s`' first-
    order coordinates ``tau w' + w + Z^T C_s^T phi q' = 0`` coupled to the modes (their own
    real eigenvalues are not paired with a mode unless nearest)."""
    n = omega.size
    off = Cq - np.diag(np.diag(Cq))
    scale = max(float(np.abs(np.diag(Cq)).max(initial=0.0)), 1e-300)
    if massless is None and not np.any(np.abs(off) > 1e-8 * scale):
        return np.divide(np.diag(Cq), 2 * omega, out=np.zeros(n), where=omega > 0), True
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.diag(omega**2), -Cq]])
    if massless is not None:  # the state (q, q', w) of the relaxing directions
        phi, C, Z, tau, s = massless
        keep = tau > 0.0
        Dqw = np.asarray(phi.T @ np.asarray(C[:, s] @ Z[:, keep]))
        Ti = np.diag(1.0 / tau[keep])
        k = Ti.shape[0]
        rw = np.hstack([np.zeros((k, n)), -Ti @ Dqw.T, -Ti])
        rv = np.hstack([-np.diag(omega**2), -Cq, np.zeros((n, k))]) - Dqw @ rw
        A = np.vstack([np.hstack([np.zeros((n, n)), np.eye(n), np.zeros((n, k))]), rv, rw])
    lam = np.linalg.eigvals(A)
    lam = lam[np.imag(lam) >= 0]  # one of each conjugate pair (and the real ones)
    out, used = np.zeros(n), np.zeros(lam.size, bool)
    for i in np.argsort(omega, kind="stable"):
        cand = np.flatnonzero(~used)
        j = cand[np.argmin(np.abs(np.abs(lam[cand]) - omega[i]))]
        used[j] = True
        mag = abs(lam[j])
        out[i] = -np.real(lam[j]) / mag if mag > 0 else 0.0
    return out, False


def damping_summary(system: Any, linear_parts: str = "auto") -> DampingSummary:
    """Each mode's damping ratio as ``Semianalytic(linear_parts=...)`` integrates `system`
    (see :meth:`duhamel.System.damping_summary`): the modes of the structure linearised
    with the elements' linear parts (initial stiffness), and on them the damping of the
    equation of motion, whose ratios are those of its first-order modes when it is not
    diagonal there. ``zeta`` defines the damping on the modes of the background the run
    integrates (``K``, or ``K`` plus the elements' linear parts, as
    :mod:`duhamel._engine.background` chooses), which need not be those modes."""
    parts = [e._linear() for e in system.elements]
    law = system.mass_law
    linear = system
    if any(p is not None for p in parts):
        K = system.K.toarray() if issparse(system.K) else np.array(system.K, dtype=np.float64)
        for part in parts:
            if part is not None:
                idx = np.asarray(part[0])
                K[np.ix_(idx, idx)] += np.asarray(part[1], dtype=np.float64)
        linear = system._with_stiffness(K)
    into = linear_parts == "background" or (linear_parts == "auto" and system.damping != "zeta")
    if linear is system or not into or (law is not None and law.scale_stiffness):
        background, name = system, "K"
    else:
        background, name = linear, "K + elements"
    basis = linear.modal()
    phi, omega = np.asarray(basis.phi), np.asarray(basis.omega)
    if system.damping == "rayleigh":  # the equation's alpha M + beta K, on these modes
        alpha, beta = system.rayleigh
        Cq = alpha * np.eye(omega.size) + beta * phi.T @ np.asarray(system.K @ phi)
    elif system.damping == "matrix":
        Cq = phi.T @ np.asarray(system.C @ phi)
    elif system.damping == "zeta":  # M Phi_b diag(c_b) Phi_b^T M on the background's modes
        damped = background.modal()
        overlap = phi.T @ np.asarray(system.M @ np.asarray(damped.phi))
        Cq = (overlap * np.asarray(damped.c)) @ overlap.T
    else:
        Cq = np.zeros((omega.size, omega.size))
    text, relax = _massless(linear, system)
    if relax is None:
        zeta, classical = _ratios(omega, (Cq + Cq.T) / 2)
    else:
        zeta, classical = _ratios(omega, (Cq + Cq.T) / 2, (phi, *relax))[0], False
    return DampingSummary(omega, zeta, classical, name, text)


def _massless(linear: Any, system: Any) -> tuple[str, tuple[Any, ...] | None]:
    """What the summary says about damping at the massless dofs of `linear` (the structure
    with the elements' linear parts; `system`'s damping), and for a damping matrix coupling
    them to the modes ``(C, Z, tau)`` (:func:`duhamel._engine.massless.matrix_relaxation`)."""
    from duhamel._engine.massless import massless_damping, matrix_relaxation

    how = massless_damping(linear)
    if how is None:
        return "", None
    n = linear.massless_dofs.size
    if how.kind == "undamped":
        return (
            f"massless dofs: {n}, no damping reaches them: static (the static relation of "
            "K at every instant, elements' forces included)",
            None,
        )
    if how.kind == "rayleigh":
        return (
            f"massless dofs: {n}, damped by beta K: first-order, each relaxing with the time "
            f"constant beta = {how.tau[0]:.4g} s (uncoupled from the modes)",
            None,
        )
    tau, Z = matrix_relaxation(linear)
    damped = tau[tau > 0.0]
    text = (
        f"massless dofs: {n}, damped by C: first-order coordinates with time constants "
        f"{damped.min():.4g} .. {damped.max():.4g} s, coupled to the modes"
    )
    if damped.size < tau.size:
        text += f"; {tau.size - damped.size} directions without damping static"
    return text, (system.C, Z, tau, linear._condensation.s)


def damping_spec(C: Any, zeta: Any, rayleigh: Any, M: Any, K: Any) -> tuple[Any, Any, Any, str]:
    """A system's damping from its constructor's `C`, `zeta`, `rayleigh` (at most one given;
    checked, naming the parameter): ``(C, zeta, (alpha, beta), kind)``. A restricted
    :class:`Rayleigh` becomes the matrix ``C``; `zeta` may be a function of omega."""
    from duhamel._engine.validate import as_float_array, check_symmetric, warn_heavy_damping
    from duhamel.modal import frozen

    given = [
        f"`{k}`" for k, v in (("C", C), ("zeta", zeta), ("rayleigh", rayleigh)) if v is not None
    ]
    if len(given) > 1:
        raise ValueError(
            f"pass at most one damping specification (`C`, `zeta` or `rayleigh`), "
            f"got {' and '.join(given)}"
        )
    n = int(M.shape[0])
    if isinstance(rayleigh, Rayleigh):
        if not rayleigh.restricted:
            return None, None, (rayleigh.alpha, rayleigh.beta), "rayleigh"
        C = rayleigh.matrix(M, K)
    if C is not None:
        C = as_square_matrix(C, "C", n=n, ref="M")
        check_symmetric(C, "C")
        return (C if issparse(C) else frozen(C)), None, None, "matrix"
    if zeta is not None:
        if callable(zeta):
            return None, zeta, None, "zeta"
        if isinstance(zeta, numbers.Real | np.ndarray) and np.ndim(zeta) == 0:
            z: Any = finite_float(zeta, "zeta")
        else:
            z = as_float_array(zeta, "zeta", ndim=1)
            if not 1 <= z.size <= n:
                raise ValueError(
                    f"`zeta` must have one entry per mode (between 1 and n_dof={n}), got {z.size}"
                )
            z = frozen(z)
        warn_heavy_damping(z)
        return None, z, None, "zeta"
    if rayleigh is not None:
        alpha, beta = as_float_array(rayleigh, "rayleigh", shape=(2,)).tolist()
        return None, None, (alpha, beta), "rayleigh"
    return None, None, None, "none"
