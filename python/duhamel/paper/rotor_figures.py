"""The rotordynamic figures of the paper (section 4.4): the model (Fig. 9) and the orbits
(Figs. 10 to 13), drawn with matplotlib; re-exported by :mod:`duhamel.paper.figures`."""

from __future__ import annotations

from typing import Any

import numpy as np

from duhamel.paper import rotor as _rotor
from duhamel.paper._canvas import figure_class
from duhamel.paper.rotor import RotorOrbits

__all__ = ["plot_fig9", "plot_fig10", "plot_fig11", "plot_fig12", "plot_fig13"]


def plot_fig9(data: RotorOrbits) -> Any:
    """Fig. 9: the rotordynamic model, as we laid it out (the paper gives no dimensions).

    Parameters
    ----------
    data : RotorOrbits
        From :func:`duhamel.paper.rotor_orbits` (for the eccentricity drawn).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import rotor_orbits
    >>> from duhamel.paper.figures import plot_fig9
    >>> plot_fig9(rotor_orbits(betas=(0.0,), xis=(0.0,), t_end=0.002)).axes[0].get_xlabel()
    'z (m)'
    """
    from matplotlib.patches import Polygon, Rectangle

    rotor = _rotor.paper_rotor(0.0)
    z = rotor.nodes_z
    radius = _rotor.SHAFT_DIAMETER / 2.0
    fig = figure_class()(figsize=(10.0, 5.2), layout="constrained")
    ax = fig.subplots()
    ax.add_patch(
        Rectangle((0.0, -radius), z[-1], 2 * radius, facecolor="0.8", edgecolor="k", lw=0.8)
    )
    for (node, width, outer), disk in zip(_rotor.DISKS, rotor.disks, strict=True):
        ax.add_patch(
            Rectangle(
                (z[node] - width / 2, -outer / 2),
                width,
                outer,
                facecolor="C0",
                alpha=0.55,
                edgecolor="k",
                lw=0.8,
            )
        )
        ax.annotate(
            f"{disk.mass:.0f} kg\n$\\varnothing$ {1e3 * outer:.0f} mm",
            (z[node], outer / 2),
            xytext=(0, 4),
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=8,
        )
    for node in _rotor.BEARING_NODES:
        h = 0.16
        ax.add_patch(
            Polygon(
                [
                    (z[node], -radius),
                    (z[node] - h / 2, -radius - h),
                    (z[node] + h / 2, -radius - h),
                ],
                closed=True,
                facecolor="C2",
                edgecolor="k",
                lw=0.8,
            )
        )
    j = 1
    for node in range(rotor.n_nodes):
        ax.plot(z[node], 0.0, "ko", ms=4)
        ax.annotate(
            f"node {node}\ndofs {j}-{j + 3}",
            (z[node], -0.58),
            ha="center",
            va="top",
            fontsize=7.5,
            color="0.25",
        )
        j += 4
    labels = {0: "left bearing", 3: "right bearing", 1: "left rotor", 2: "right rotor"}
    for node, label in labels.items():
        ax.annotate(label, (z[node], 0.62), ha="center", fontsize=8.5, weight="bold")
    force = "unbalance, turning" if data.eccentricity == "rotating" else "fixed along x"
    ax.annotate(
        f"F = {_rotor.FORCE:.0e} N\n({force})",
        (z[_rotor.FORCE_NODE] + 0.08, -0.3),
        xytext=(z[_rotor.FORCE_NODE] + 0.35, -0.45),
        arrowprops={"arrowstyle": "->", "color": "C3"},
        fontsize=8,
        color="C3",
    )
    ax.annotate(
        "", (z[-1] + 0.25, -0.3), xytext=(z[-1] + 0.25, 0.1), arrowprops={"arrowstyle": "->"}
    )
    ax.annotate("g", (z[-1] + 0.28, -0.12), fontsize=9)
    ax.text(
        -0.1,
        -0.86,
        rf"bearings at dofs 1, 2, 13, 14: $k_{{11}} = k_{{22}}$ = {_rotor.K_DIRECT:.0e} N/m, "
        rf"$k_{{12}} = -k_{{21}}$ = {_rotor.K_CROSS:.0e} N/m, cubic law $\beta$ = 0, 0.1"
        "\n"
        rf"steel shaft $\varnothing$ {1e3 * _rotor.SHAFT_DIAMETER:.0f} mm, "
        f"{rotor.mass:.0f} kg in all, 1500 rpm",
        fontsize=8,
        va="top",
    )
    ax.set(
        xlim=(-0.2, z[-1] + 0.45),
        ylim=(-1.1, 0.8),
        xlabel="z (m)",
        ylabel="radius (m)",
        title="Fig. 9: rotordynamic model, our layout\n(5 nodes, 4 Timoshenko elements, "
        "3 disks, 20 dofs; the paper gives no dimensions)",
    )
    ax.set_aspect("equal")
    return fig


def _plot_orbit(data: RotorOrbits, index: int, number: int) -> Any:
    """Orbits of one position of :data:`duhamel.paper.rotor.POSITIONS`, one panel per beta."""
    label, node = _rotor.POSITIONS[index]
    betas = data.betas
    fig = figure_class()(figsize=(4.4 * len(betas) + 0.6, 4.9), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(betas), sharex=True, sharey=True))
    styles = ["k", "C0", "C3", "C2", "C1"]
    widths = [1.3, 0.8, 0.8, 0.8, 0.8]
    lim = 1.08 * max(float(np.abs(o[:, index]).max()) for o in data.orbits.values())
    for ax, beta in zip(axes, betas, strict=True):
        for i, xi in enumerate(data.xis):
            r = data.orbits[(beta, xi)][:, index]
            ax.plot(
                r[:, 0],
                r[:, 1],
                color=styles[i % len(styles)],
                lw=widths[i % len(widths)],
                alpha=0.9 if i == 0 else 0.75,
                label=rf"$\xi$ = {xi:g}",
            )
        ax.plot(0.0, 0.0, "o", color="0.3", ms=4, mfc="none", label="start (rest)")
        ax.plot(0.0, -1.0, "+", color="0.3", ms=8, mew=1.2, label="static, weight")
        ax.set(
            xlabel=r"$x\,/\,x_{stat}$",
            title=rf"$\beta$ = {beta:g}",
            xlim=(-lim, lim),
            ylim=(-lim, lim),
        )
        ax.set_aspect("equal", adjustable="box")
        ax.grid(True, alpha=0.3)
        ax.axhline(0.0, color="0.6", lw=0.5)
        ax.axvline(0.0, color="0.6", lw=0.5)
    axes[0].set_ylabel(r"$y\,/\,x_{stat}$")
    axes[-1].legend(fontsize=7.5, loc="upper right")
    what = "unbalance" if data.eccentricity == "rotating" else "force along x"
    fig.suptitle(
        f"Fig. {number}: motion of the center at the {label} (node {node}), "
        f"$x_{{stat}}$ = {1e6 * data.x_stat[index]:.2f} $\\mu$m\n"
        f"1500 rpm, sudden {what} 5e4 N at t = 0, "
        rf"$M(t) = M_0 [1 + \xi \sin(\Omega t)]$, $0 \leq t \leq$ {data.t_end:g} s",
        fontsize=10,
    )
    return fig


def plot_fig10(data: RotorOrbits) -> Any:
    """Fig. 10: motion of the centre of the journal at the left bearing, ``(x, y) / x_stat``.

    Parameters
    ----------
    data : RotorOrbits
        From :func:`duhamel.paper.rotor_orbits`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import rotor_orbits
    >>> from duhamel.paper.figures import plot_fig10
    >>> fig = plot_fig10(rotor_orbits(xis=(0.0, 0.1), t_end=0.002))
    >>> len(fig.axes), fig.axes[0].get_ylabel()
    (2, '$y\\\\,/\\\\,x_{stat}$')
    """
    return _plot_orbit(data, 0, 10)


def plot_fig11(data: RotorOrbits) -> Any:
    """Fig. 11: motion of the centre of the journal at the right bearing (as :func:`plot_fig10`).

    Parameters
    ----------
    data : RotorOrbits
        From :func:`duhamel.paper.rotor_orbits`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import rotor_orbits
    >>> from duhamel.paper.figures import plot_fig11
    >>> len(plot_fig11(rotor_orbits(xis=(0.0,), t_end=0.002)).axes)
    2
    """
    return _plot_orbit(data, 1, 11)


def plot_fig12(data: RotorOrbits) -> Any:
    """Fig. 12: motion of the centre of the left rotor (disk at node 1; as :func:`plot_fig10`).

    Parameters
    ----------
    data : RotorOrbits
        From :func:`duhamel.paper.rotor_orbits`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import rotor_orbits
    >>> from duhamel.paper.figures import plot_fig12
    >>> len(plot_fig12(rotor_orbits(betas=(0.1,), xis=(0.0,), t_end=0.002)).axes)
    1
    """
    return _plot_orbit(data, 2, 12)


def plot_fig13(data: RotorOrbits) -> Any:
    """Fig. 13: motion of the centre of the right rotor (disk at node 2; as :func:`plot_fig10`).

    Parameters
    ----------
    data : RotorOrbits
        From :func:`duhamel.paper.rotor_orbits`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import rotor_orbits
    >>> from duhamel.paper.figures import plot_fig13
    >>> len(plot_fig13(rotor_orbits(xis=(0.0,), t_end=0.002)).axes)
    2
    """
    return _plot_orbit(data, 3, 13)
