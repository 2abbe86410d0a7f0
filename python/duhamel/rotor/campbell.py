"""Campbell diagram: damped natural frequencies against speed, modes tracked by shape."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array
from duhamel.rotor.modes import CLUSTER_RTOL, Modes, _mac_columns

__all__ = ["Campbell", "campbell"]

#: Campbell mode tracking: weight of the relative eigenvalue distance added to ``1 - MAC`` in
#: the assignment cost, so that it only breaks ties between equally similar shapes.
TRACK_TIE_WEIGHT = 1e-6

#: The modes at a constant speed (rad/s), the lowest `n` (all when None).
ModesAt = Callable[[float, int | None], Modes]


@dataclass(frozen=True, eq=False)
class Campbell:
    """Damped natural frequencies against speed, from :meth:`Rotor.campbell`.

    Tracked (``tracked=True``): column ``j`` follows one branch (one physical mode) through
    crossings. Untracked: column ``j`` is the ``j``-th lowest frequency at each speed. Rows are
    in the order of `speeds` as given. Missing entries (fewer oscillatory modes at a speed, or,
    tracked, a branch that is not among the lowest ``n_modes`` there) are NaN, whirl ``""``.

    Attributes
    ----------
    speeds : ndarray, shape (n_speeds,)
        rad/s.
    frequencies, damping_ratios : ndarray, shape (n_speeds, n_columns)
        rad/s, and ``-Re(lambda)/|lambda|``.
    whirl : ndarray of str, shape (n_speeds, n_columns)
        As :attr:`Modes.whirl`.
    mac : ndarray, shape (n_speeds, n_columns), optional
        :meth:`Modes.mac` between the shape in each cell and the shape of the same column at
        the next lower speed of `speeds` (tracked: the matched pair); NaN at the lowest speed
        and where either is missing. Near 1 along a well-resolved branch; a low value flags a
        crossing or veering that the speed grid does not resolve (refine it there).
    tracked : bool
        Whether the columns are tracked branches.
    """

    speeds: NDArray[np.float64]
    frequencies: NDArray[np.float64]
    damping_ratios: NDArray[np.float64]
    whirl: NDArray[np.str_]
    mac: NDArray[np.float64] | None = None
    tracked: bool = False

    @property
    def log_dec(self) -> NDArray[np.float64]:
        """Logarithmic decrements ``2 pi zeta / sqrt(1 - zeta^2)`` of the cells (NaN where
        missing; negative: unstable)."""
        z = self.damping_ratios
        with np.errstate(invalid="ignore", divide="ignore"):
            return 2.0 * np.pi * z / np.sqrt(1.0 - z**2)

    def plot(self, **kwargs: Any) -> Any:
        """Plot with :func:`duhamel.rotor.plot_campbell` (same keywords); returns the Axes."""
        from duhamel.rotor.plot import plot_campbell

        return plot_campbell(self, **kwargs)


def campbell(
    modes_at: ModesAt,
    speeds: ArrayLike,
    n_modes: int | None = None,
    *,
    track: bool = True,
    window: int | None = None,
) -> Campbell:
    """The Campbell diagram of the modes `modes_at` gives at each of `speeds` (rad/s).

    The algorithm of :meth:`duhamel.rotor.Rotor.campbell` (see there), for any model whose
    modes at a speed are :class:`~duhamel.rotor.Modes`.

    Parameters
    ----------
    modes_at : callable
        ``modes_at(speed, n)``: the lowest `n` modes (all for ``None``) at constant `speed`.
    speeds : array_like
        Spin speeds (rad/s), in any order.
    n_modes : int, optional
        Show the lowest `n_modes` modes at each speed (default: all oscillatory modes).
    track : bool
        Keyword only. Track modes through crossings (default) or sort them by frequency.
    window : int, optional
        Keyword only. Track among the lowest `window` modes at each speed (default: all
        oscillatory modes; large models take a window so that their modes come from the
        shift-invert path, :mod:`duhamel.rotor._sparse_modes`).

    Returns
    -------
    Campbell

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
    >>> from duhamel.rotor.campbell import campbell
    >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
    ...               [Bearing(0, 1e7, 1e7), Bearing(4, 1e7, 1e7)])
    >>> diagram = campbell(rotor.modes, [0.0, 1000.0], n_modes=2)
    >>> diagram.frequencies.shape, diagram.whirl[1].tolist()
    ((2, 2), ['backward', 'forward'])
    """
    ws = as_float_array(speeds, "speeds", ndim=1)
    if n_modes is not None and (
        isinstance(n_modes, bool) or not isinstance(n_modes, int | np.integer) or n_modes < 1
    ):
        raise ValueError(f"`n_modes` must be a positive integer, got {n_modes!r}")
    if not isinstance(track, bool | np.bool_):
        raise TypeError(f"`track` must be a bool, got {type(track).__name__}")
    order = np.argsort(ws, kind="stable")  # the path the tracking walks
    if track:
        return _tracked(modes_at, ws, order, n_modes, window)
    found = [modes_at(float(w), n_modes) for w in ws]
    m = max((f.n_modes for f in found), default=0) if n_modes is None else int(n_modes)
    freq = np.full((ws.size, m), np.nan)
    zeta = np.full((ws.size, m), np.nan)
    whirl = np.full((ws.size, m), "", dtype="<U8")
    mac = np.full((ws.size, m), np.nan)
    for i, f in enumerate(found):
        k = min(f.n_modes, m)
        freq[i, :k] = f.frequencies[:k]
        zeta[i, :k] = f.damping_ratios[:k]
        whirl[i, :k] = f.whirl[:k]
    for p in range(1, ws.size):
        prev, cur = found[order[p - 1]], found[order[p]]
        k = min(prev.n_modes, cur.n_modes, m)
        mac[order[p], :k] = _mac_columns(
            prev.shapes[:, :k], cur.shapes[:, :k], cur.length_scale, cur.layout
        )
    return Campbell(ws, freq, zeta, whirl, mac=mac, tracked=False)


def _tracked(
    modes_at: ModesAt,
    ws: NDArray[np.float64],
    order: NDArray[np.intp],
    n_modes: int | None,
    window: int | None = None,
) -> Campbell:
    from scipy.optimize import linear_sum_assignment  # 0.4 s to import: only when tracking

    path = [modes_at(float(ws[i]), window) for i in order]
    # branch[p][k]: the branch of mode k at the p-th lowest speed; pair[p][k]: its MAC
    # with its predecessor on the branch (NaN for a branch that starts there)
    branch: list[NDArray[np.intp]] = []
    pair: list[NDArray[np.float64]] = []
    n_branches = 0
    for p, cur in enumerate(path):
        ids = np.full(cur.n_modes, -1, dtype=np.intp)
        macs = np.full(cur.n_modes, np.nan)
        if p > 0 and path[p - 1].n_modes and cur.n_modes:
            prev = path[p - 1]
            mac = prev.mac(cur)
            lp, lc = prev.eigenvalues[:, None], cur.eigenvalues[None, :]
            dist = np.abs(lp - lc) / np.maximum(np.abs(lp), np.abs(lc))
            rows, cols = linear_sum_assignment(1.0 - mac + TRACK_TIE_WEIGHT * dist)
            ids[cols] = branch[p - 1][rows]
            macs[cols] = mac[rows, cols]
        new = ids < 0  # modes without a predecessor start branches
        ids[new] = n_branches + np.arange(int(new.sum()))
        n_branches += int(new.sum())
        branch.append(ids)
        pair.append(macs)
    # the columns: branches among the lowest n_modes somewhere, in order of entry: by
    # speed, then frequency, equal frequencies (a degenerate pair) by the next speed's
    entry: dict[int, tuple[int, int, float]] = {}
    for p, (f, ids) in enumerate(zip(path, branch, strict=True)):
        freqs = f.frequencies
        cluster = np.concatenate(
            [[0], np.cumsum(np.diff(freqs) > CLUSTER_RTOL * np.abs(freqs[1:]))]
        )
        for k, b in enumerate(ids[:n_modes] if n_modes is not None else ids):
            if int(b) not in entry:
                later = np.flatnonzero(branch[p + 1] == b) if p + 1 < len(path) else []
                after = float(path[p + 1].frequencies[later[0]]) if len(later) else np.inf
                entry[int(b)] = (p, int(cluster[k]), after)
    column = {b: j for j, b in enumerate(sorted(entry, key=entry.__getitem__))}
    m = len(column)
    freq = np.full((ws.size, m), np.nan)
    zeta = np.full((ws.size, m), np.nan)
    whirl = np.full((ws.size, m), "", dtype="<U8")
    mac = np.full((ws.size, m), np.nan)
    for p, (f, ids, macs) in enumerate(zip(path, branch, pair, strict=True)):
        k = f.n_modes if n_modes is None else min(f.n_modes, int(n_modes))
        row = order[p]
        cols = [column[int(b)] for b in ids[:k]]
        freq[row, cols] = f.frequencies[:k]
        zeta[row, cols] = f.damping_ratios[:k]
        whirl[row, cols] = f.whirl[:k]
        mac[row, cols] = macs[:k]
    return Campbell(ws, freq, zeta, whirl, mac=mac, tracked=True)
