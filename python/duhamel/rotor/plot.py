"""Matplotlib plots: Campbell diagram and orbits."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from duhamel.results.solution import Solution
    from duhamel.rotor._protocols import CampbellData, DofNumbering

__all__ = ["plot_campbell", "plot_orbit"]

_UNITS = {
    "rad/s": (1.0, "rad/s", "rad/s"),
    "Hz": (0.5 / np.pi, "Hz", "Hz"),
    "rpm": (30.0 / np.pi, "rpm", "cpm"),
}
_STYLE = {
    "forward": {"marker": "^", "color": "tab:red", "label": "forward whirl"},
    "backward": {"marker": "v", "color": "tab:blue", "label": "backward whirl"},
    "mixed": {"marker": "o", "color": "tab:gray", "label": "mixed whirl"},
    "planar": {"marker": "s", "color": "tab:green", "label": "planar (no whirl)"},
}


def _axes(ax: Any) -> Any:
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    return plt.subplots()[1]


def plot_campbell(
    campbell: CampbellData,
    *,
    ax: Any = None,
    units: str = "rad/s",
    harmonics: tuple[float, ...] = (1.0,),
) -> Any:
    """Campbell diagram: damped natural frequencies against speed, with the ``kX`` lines.

    Each column of the Campbell is joined by a thin line: a tracked branch
    (``campbell.tracked``, the default of :meth:`duhamel.rotor.Rotor.campbell`), or the
    ``j``-th lowest frequency at each speed (``track=False``, whose lines jump between
    branches at crossings); lines break where a column is NaN. Markers show the whirl
    (forward ▲ red, backward ▼ blue). Speed and frequency share `units`
    (``"rad/s"``, ``"Hz"``, or ``"rpm"`` with frequencies in cycles per minute), so the 1X
    line has slope 1; critical speeds are its crossings with forward-whirl branches.

    Parameters
    ----------
    campbell : Campbell
        From :meth:`duhamel.rotor.Rotor.campbell`.
    ax : matplotlib Axes, optional
        Axes to draw on (default: a new figure).
    units : {"rad/s", "Hz", "rpm"}
    harmonics : tuple of float
        Multiples of the speed to draw (``1`` is the 1X line); ``()`` for none.

    Returns
    -------
    matplotlib Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, plot_campbell
    >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.3, 0.16)],
    ...               [Bearing(0, 1e7, 1e7), Bearing(4, 1e7, 1e7)])
    >>> ax = plot_campbell(rotor.campbell(np.linspace(0, 2000, 21), n_modes=4), units="Hz")
    >>> [line.get_label() for line in ax.get_lines() if line.get_label() == "1X"]
    ['1X']
    """
    if units not in _UNITS:
        raise ValueError(f"`units` must be one of {list(_UNITS)}, got {units!r}")
    factor, speed_unit, freq_unit = _UNITS[units]
    ax = _axes(ax)
    x = campbell.speeds * factor
    f = campbell.frequencies * factor
    for j in range(f.shape[1]):
        ax.plot(x, f[:, j], color="0.75", lw=0.8, zorder=1)
    for kind, style in _STYLE.items():
        hit = campbell.whirl == kind
        if hit.any():
            ax.scatter(
                np.broadcast_to(x[:, None], f.shape)[hit],
                f[hit],
                s=14,
                zorder=2,
                marker=style["marker"],
                color=style["color"],
                label=style["label"],
            )
    top = float(np.nanmax(f)) if np.isfinite(f).any() else 1.0
    for h in harmonics:
        ax.plot(x, h * x, "k--", lw=1.0, label=f"{h:g}X", zorder=3)
    ax.set_ylim(0.0, 1.05 * top)
    ax.set_xlabel(f"speed ({speed_unit})")
    ax.set_ylabel(f"damped natural frequency ({freq_unit})")
    ax.set_title("Campbell diagram")
    ax.legend(loc="best", fontsize="small")
    return ax


def plot_orbit(
    solution: Solution,
    rotor: DofNumbering,
    node: int,
    *,
    scale: float = 1.0,
    ax: Any = None,
    **kwargs: Any,
) -> Any:
    """Orbit of a node's centre, ``(x, y) / scale``, from a :class:`duhamel.Solution`.

    Parameters
    ----------
    solution : Solution
        Must hold the node's x and y (``dofs`` of :func:`duhamel.solve`).
    rotor : Rotor
        The model the solution belongs to (for the dof numbering).
    node : int
        The node.
    scale : float
        Divide the displacements by this (e.g. the static deflection, as the paper does).
    ax : matplotlib Axes, optional
    **kwargs
        Passed to ``ax.plot``.

    Returns
    -------
    matplotlib Axes
    """
    cols = []
    for direction in ("x", "y"):
        dof = rotor.dof(node, direction)
        hit = np.flatnonzero(solution.dofs == dof)
        if hit.size == 0:
            raise ValueError(
                f"the solution does not hold dof {dof} (node {node}, {direction}); solve with "
                "dofs including it"
            )
        cols.append(int(hit[0]))
    ax = _axes(ax)
    ax.plot(solution.x[:, cols[0]] / scale, solution.x[:, cols[1]] / scale, **kwargs)
    ax.set_aspect("equal", adjustable="datalim")
    unit = "m" if scale == 1.0 else "scaled"
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    ax.set_title(f"orbit of node {node}")
    return ax
