"""The undamped critical speed map: critical speeds against the support stiffness, with the
bearings' direct stiffness against speed over it and the intersections (the critical speeds
the bearings give)."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array
from duhamel.rotor.bearing import TableRangeWarning

__all__ = ["CriticalSpeedMap", "Intersection", "undamped_critical_speeds"]

#: ``mu = 1 / omega^2`` below this fraction of the largest are massless (infinite) modes.
_MU_RTOL = 1e-12


@dataclass(frozen=True)
class Intersection:
    """Where a bearing's stiffness curve crosses a critical speed line of the map.

    Attributes
    ----------
    node : int
        The bearing's node.
    direction : str
        ``"kxx"`` or ``"kyy"``.
    mode : int
        The critical speed's index (0: the first).
    speed : float
        The critical speed there (rad/s): ``omega_mode(k_b(speed)) = speed``.
    stiffness : float
        The bearing stiffness there (N/m).
    """

    node: int
    direction: str
    mode: int
    speed: float
    stiffness: float


@dataclass(frozen=True, eq=False)
class CriticalSpeedMap:
    """Result of :meth:`Rotor.critical_speed_map <duhamel.rotor.Rotor.critical_speed_map>`.

    Attributes
    ----------
    stiffnesses : ndarray, shape (n_k,)
        Support stiffnesses (N/m), the same at every bearing, in x and y.
    critical_speeds : ndarray, shape (n_k, n_modes)
        Undamped critical speeds (rad/s) at each stiffness, ascending.
    gyroscopic : bool
        Synchronous forward whirl with the gyroscopic terms (else: the non-rotating rotor).
    speeds : ndarray
        The speeds (rad/s) at which the bearings' curves are drawn.
    curves : tuple of (node, direction, ndarray)
        Each bearing's ``kxx`` and ``kyy`` at `speeds`.
    intersections : tuple of Intersection
    """

    stiffnesses: NDArray[np.float64]
    critical_speeds: NDArray[np.float64]
    gyroscopic: bool
    speeds: NDArray[np.float64]
    curves: tuple[tuple[int, str, NDArray[np.float64]], ...]
    intersections: tuple[Intersection, ...]

    def plot(self, ax: Any = None) -> Any:
        """Critical speeds against stiffness (log-log), the bearings' curves over them and the
        intersections marked; returns the Axes."""
        import matplotlib.pyplot as plt

        ax = ax if ax is not None else plt.subplots()[1]
        for j in range(self.critical_speeds.shape[1]):
            ax.loglog(self.stiffnesses, self.critical_speeds[:, j], "k-", lw=1.5,
                      label="critical speeds" if j == 0 else None)  # fmt: skip
        for node, direction, k in self.curves:
            keep = self.speeds > 0
            ax.loglog(k[keep], self.speeds[keep], "--", label=f"bearing {node} {direction}")
        for p in self.intersections:
            ax.plot(p.stiffness, p.speed, "o", color="tab:red")
        ax.set_xlabel("support stiffness (N/m)")
        ax.set_ylabel("critical speed (rad/s)")
        ax.set_title("undamped critical speed map")
        ax.legend()
        return ax


def undamped_critical_speeds(
    M: NDArray[np.float64],
    K: NDArray[np.float64],
    G: NDArray[np.float64],
    *,
    gyroscopic: bool = True,
    length_scale: float = 1.0,
) -> NDArray[np.float64]:
    """Undamped critical speeds (rad/s, ascending) of ``M``, ``K`` (symmetric positive
    definite) and ``G`` (per unit speed), dofs node-wise ``(x, y, theta_x, theta_y)``.

    With `gyroscopic`: synchronous forward whirl, ``x = Re(X e^{i w t})`` at spin ``w``,
    ``(K - w^2 (M - i G)) X = 0``: the Hermitian pencil ``(M - i G) X = mu K X`` with
    ``w = 1 / sqrt(mu)`` for ``mu > 0``, of the solutions whose orbit turns forward (the
    signed orbit area, tilts weighted by `length_scale`, positive; the others are backward
    whirl at ``w = spin``, which an axisymmetric rotor's unbalance does not excite). Without
    it, the rotor at rest in the x-z plane: ``K X = w^2 M X`` on the dofs ``(x, theta_y)``
    (isotropic supports: the y-z plane has the same frequencies); so also with `gyroscopic`
    when ``G`` is zero (a forward orbit is then a degenerate pair of planar modes, which the
    orbit test cannot pick). Massless dofs give ``mu = 0`` and are dropped.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.rotor.critical_map import undamped_critical_speeds
    >>> M, K = np.diag([2.0, 2.0, 0.1, 0.1]), np.diag([800.0, 800.0, 90.0, 90.0])
    >>> undamped_critical_speeds(M, K, np.zeros((4, 4)), gyroscopic=False).tolist()
    [20.0, 30.0]
    """
    import scipy.linalg

    if gyroscopic and not np.any(G):  # no gyroscopic terms: forward whirl is the planar mode
        gyroscopic = False
    if gyroscopic:
        B, KK = M - 1j * G, K
    else:
        plane = np.sort(np.concatenate([np.arange(0, M.shape[0], 4), np.arange(3, M.shape[0], 4)]))
        B, KK = M[np.ix_(plane, plane)].astype(complex), K[np.ix_(plane, plane)]
    try:
        mu, vec = scipy.linalg.eigh(B, KK, check_finite=False)
    except np.linalg.LinAlgError:
        raise ValueError(
            "the stiffness is not positive definite: is every rigid-body motion supported?"
        ) from None
    keep = mu > _MU_RTOL * float(np.max(np.abs(mu)))
    if gyroscopic:
        X, Y, Tx, Ty = (vec[d::4] for d in range(4))
        area = np.sum(-np.imag(np.conj(X) * Y) + length_scale**2 * np.imag(np.conj(Ty) * Tx), 0)
        keep &= area > 0.0
    return np.sort(1.0 / np.sqrt(mu[keep]))


def critical_speed_map(
    M: NDArray[np.float64],
    K_structure: NDArray[np.float64],
    G: NDArray[np.float64],
    supports: Sequence[tuple[int, int]],
    bearings: Sequence[Any],
    stiffnesses: ArrayLike,
    *,
    n_modes: int,
    gyroscopic: bool,
    speeds: ArrayLike | None,
    length_scale: float = 1.0,
) -> CriticalSpeedMap:
    """The map: `supports` the ``(x, y)`` dof pairs that get the stiffness; `bearings`
    (with ``node`` and ``stiffness_at(speed)``) give the curves."""
    ks = as_float_array(stiffnesses, "stiffnesses", ndim=1)
    if ks.size == 0 or np.any(ks <= 0.0) or np.any(np.diff(ks) <= 0.0):
        raise ValueError("`stiffnesses` must be increasing positive stiffnesses (N/m)")
    if isinstance(n_modes, bool) or not isinstance(n_modes, int | np.integer) or n_modes < 1:
        raise ValueError(f"`n_modes` must be a positive integer, got {n_modes!r}")
    dofs = np.array([d for pair in supports for d in pair], dtype=np.intp)

    known: dict[float, NDArray[np.float64]] = {}

    def omegas(k: float) -> NDArray[np.float64]:
        # bearings alike (and kxx = kyy) share their curves: each stiffness solved once
        if k not in known:
            Kk = np.array(K_structure, dtype=float)
            Kk[dofs, dofs] += k
            known[k] = undamped_critical_speeds(
                M, Kk, G, gyroscopic=gyroscopic, length_scale=length_scale
            )
        return known[k]

    rows = [omegas(float(k)) for k in ks]
    m = min(n_modes, min(r.size for r in rows))
    if m == 0:
        raise ValueError(
            "no critical speed found at some stiffness (with `gyroscopic`, a rotor without "
            "gyroscopic terms has no distinct forward orbits: use gyroscopic=False)"
        )
    table = np.array([r[:m] for r in rows])
    if speeds is None:
        ws = np.linspace(0.0, 1.2 * float(table[-1, -1]), 241)
    else:
        ws = as_float_array(speeds, "speeds", ndim=1)
        if ws.size < 2 or np.any(ws < 0.0) or np.any(np.diff(ws) <= 0.0):
            raise ValueError(
                "`speeds` must be at least two increasing speeds >= 0 (rad/s), the bearings' "
                f"curves and where their intersections are searched; got {ws.size} values"
            )
    curves = []
    with warnings.catch_warnings():  # the curves hold a table's end values beyond it
        warnings.simplefilter("ignore", TableRangeWarning)
        for b in bearings:
            k = np.array([b.stiffness_at(float(w)) for w in ws])
            curves.append((int(b.node), "kxx", k[:, 0, 0]))
            curves.append((int(b.node), "kyy", k[:, 1, 1]))
        found = _intersections(curves, bearings, ws, omegas, m)
    return CriticalSpeedMap(ks, table, bool(gyroscopic), ws, tuple(curves), found)


def _intersections(
    curves: list, bearings: Sequence[Any], ws: NDArray, omegas: Any, m: int
) -> tuple[Intersection, ...]:
    """Brackets ``omega_j(k_b(w)) - w`` on the speeds `ws`, then Brent's method on the exact
    eigenproblem (1e-12 relative)."""
    from scipy.optimize import brentq

    by_node = {int(b.node): b for b in bearings}
    out = []
    for node, direction, k in curves:
        b = by_node[node]
        idx = 0 if direction == "kxx" else 1

        def stiffness(w: float, b: Any = b, idx: int = idx) -> float:
            return float(b.stiffness_at(w)[idx, idx])

        grid = np.array([omegas(float(kb))[:m] if kb > 0 else np.zeros(m) for kb in k])
        for j in range(m):

            def h(w: float, j: int = j, stiffness: Any = stiffness) -> float:
                kb = stiffness(w)
                return float(omegas(kb)[j]) - w if kb > 0 else -w

            g = grid[:, j] - ws
            for p in np.flatnonzero(g[:-1] * g[1:] < 0.0):
                a, c = float(ws[p]), float(ws[p + 1])
                w = float(brentq(h, a, c, xtol=1e-12 * max(c, 1.0), rtol=1e-14))
                out.append(Intersection(node, direction, j, w, stiffness(w)))
    return tuple(sorted(out, key=lambda p: (p.speed, p.node, p.direction)))
