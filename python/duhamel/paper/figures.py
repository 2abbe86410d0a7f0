"""The figures of the paper (sections 3 and 4), drawn with matplotlib.

Every function takes the data of one example (:mod:`duhamel.paper`) and returns a
``matplotlib.figure.Figure`` (no pyplot state, no global backend): save it with
``fig.savefig(path)``. :data:`FIGURES` maps each figure name (``"fig1"`` ... ``"fig13"``) to
its file name. Figs. 1 to 8 are drawn here, the rotor's (9 to 13) in
:mod:`duhamel.paper.rotor_figures`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from duhamel.analysis import plot_stability_chart
from duhamel.paper import bessel as _bessel
from duhamel.paper import duffing as _duffing
from duhamel.paper import pendulum as _pendulum
from duhamel.paper._canvas import DPI, FIGURES, figure_class
from duhamel.paper._common import OMEGA, PERIOD
from duhamel.paper.bessel import BesselData, Fig8Data
from duhamel.paper.duffing import Fig3Data
from duhamel.paper.pendulum import Fig4Data
from duhamel.paper.rotor_figures import plot_fig9, plot_fig10, plot_fig11, plot_fig12, plot_fig13
from duhamel.paper.stability import Fig1Data, Fig2Data

__all__ = [
    "DPI",
    "FIGURES",
    "figure_class",
    "plot_fig1",
    "plot_fig2",
    "plot_fig3",
    "plot_fig4",
    "plot_fig5",
    "plot_fig6",
    "plot_fig7",
    "plot_fig8",
    "plot_fig9",
    "plot_fig10",
    "plot_fig11",
    "plot_fig12",
    "plot_fig13",
]


def plot_fig1(data: Fig1Data) -> Any:
    """Fig. 1: ``|lambda|`` against ``dt/T`` for schemes (a), (b), (c), damping as pseudo-force.

    Parameters
    ----------
    data : Fig1Data
        From :func:`duhamel.paper.fig1`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import fig1
    >>> from duhamel.paper.figures import plot_fig1
    >>> len(plot_fig1(fig1(n_points=31)).axes)
    3
    """
    fig = figure_class()(figsize=(10.5, 3.4), layout="constrained")
    axes = list(fig.subplots(1, 3, sharey=True))
    plot_stability_chart(data.chart, axes)
    for ax, s in zip(axes, "abc", strict=True):
        ax.set_title(f"({s}) scheme of eq. 20{s}", fontsize=10)
        ax.set_xlim(data.chart.dt_over_T[0], data.chart.dt_over_T[-1])
    fig.suptitle(
        rf"Fig. 1: spectral radius, damping as pseudo-force, $\zeta$ = {data.chart.zeta:g}",
        fontsize=11,
    )
    return fig


def plot_fig2(data: Fig2Data) -> Any:
    """Fig. 2: ``|lambda|`` for eq. 25, scheme (b) and Newmark; both signs of the alpha term.

    Parameters
    ----------
    data : Fig2Data
        From :func:`duhamel.paper.fig2`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import fig2
    >>> from duhamel.paper.figures import plot_fig2
    >>> len(plot_fig2(fig2(n_points=21)).axes[0].get_lines())
    6
    """
    fig = figure_class()(figsize=(6.4, 4.2), layout="constrained")
    ax = fig.subplots()
    plus, minus = data.charts[1], data.charts[-1]
    x = plus.dt_over_T
    for i, label in enumerate(plus.labels):
        ax.semilogx(x, plus.curve(label), color=f"C{i}", lw=1.4, label=rf"{label}, $+\alpha$")
        ax.semilogx(
            x, minus.curve(label), color=f"C{i}", lw=1.0, ls="--", label=rf"{label}, $-\alpha$"
        )
    ax.semilogx(x, plus.exact, color="0.4", lw=1.0, ls=":", label="exact")
    ax.axhline(1.0, color="0.75", lw=0.6)
    ax.set(
        xlabel=r"$\Delta t\,/\,T$",
        ylabel=r"$|\lambda|$",
        xlim=(x[0], x[-1]),
        ylim=(0.0, 1.05),
    )
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    ax.set_title(
        rf"Fig. 2: eq. 25, $\alpha$ = {data.alpha:g}, $\zeta$ = {data.zeta:g} "
        r"($\pm\alpha\,\omega^2 X$ on the right-hand side)",
        fontsize=10,
    )
    return fig


def plot_fig3(data: Fig3Data) -> Any:
    """Fig. 3 (a)-(c): error phase planes of the Duffing oscillator.

    Normalised displacement error ``(w_calc - w_exact) / w0`` (horizontal) against
    normalised velocity error ``(w'_calc - w'_exact) / (w0 omega)`` (vertical).

    Parameters
    ----------
    data : Fig3Data
        From :func:`duhamel.paper.fig3`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import fig3
    >>> from duhamel.paper.figures import plot_fig3
    >>> len(plot_fig3(fig3(periods=1)).axes)
    3
    """
    fig = figure_class()(figsize=(11.5, 4.0), layout="constrained")
    axes = fig.subplots(1, 3)
    panels = [
        ("(a) present method, scheme (b)", [_duffing.DEFAULT, _duffing.PARABOLIC]),
        ("(b) Newmark, average acceleration", [_duffing.NEWMARK]),
        ("(c) cubic Hermite", [_duffing.HERMITE]),
    ]
    names = list(data.runs)
    for ax, (title, keys) in zip(axes, panels, strict=True):
        for key in keys:
            run = data.runs[key]
            ax.plot(
                run.eps,
                run.sigma,
                lw=0.8,
                color=f"C{names.index(key)}",
                label=f"{key}: max $|\\epsilon|$ = {run.max_eps:.3g}",
            )
            ax.plot(run.eps[-1], run.sigma[-1], "o", ms=3.5, color=f"C{names.index(key)}")
        ax.axhline(0.0, color="0.7", lw=0.5)
        ax.axvline(0.0, color="0.7", lw=0.5)
        ax.set_xlabel(r"$\epsilon = (w_{calc} - w_{exact})\,/\,w_0$")
        ax.set_title(title, fontsize=10)
        ax.legend(fontsize=7, loc="upper left")
        ax.ticklabel_format(style="sci", scilimits=(-3, 3))
        ax.margins(x=0.05, y=0.22)  # room for the legend above the spiral
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel(r"$\sigma = (\dot w_{calc} - \dot w_{exact})\,/\,(w_0\,\omega)$")
    steps = round(PERIOD / data.dt)
    fig.suptitle(
        rf"Fig. 3: Duffing oscillator, $b w_0^2 = 4\omega^2$, $\omega\Delta t = 2\pi/{steps}$, "
        f"{data.periods:g} periods (dot: end of the run)",
        fontsize=11,
    )
    return fig


def plot_fig4(data: Fig4Data) -> Any:
    """Fig. 4: (a) motion ``w / w0`` and (b) error ``(w_calc - w_exact) / w0`` against ``t/T``.

    Parameters
    ----------
    data : Fig4Data
        From :func:`duhamel.paper.fig4`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import fig4
    >>> from duhamel.paper.figures import plot_fig4
    >>> len(plot_fig4(fig4(convergence_steps=(10, 20))).axes)
    2
    """
    fig = figure_class()(figsize=(7.5, 7.0), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    tau = data.t / PERIOD
    ax1.plot(data.t_fine / PERIOD, data.exact_fine, color="k", lw=1.2, label="exact (eq. 31)")
    styles = {
        _pendulum.ELIMINATE: ("C0", "o"),
        _pendulum.ESTIMATE: ("C3", "s"),
        _pendulum.EQ30: ("C2", "+"),
        _pendulum.NEWMARK: ("C1", "^"),
    }
    for name, (color, marker) in styles.items():
        ax1.plot(tau, data.w[name], marker, ms=3.5, color=color, mfc="none", lw=0, label=name)
        err = data.error(name)
        ax2.plot(
            tau,
            err,
            "-" + marker,
            ms=3.0,
            lw=0.8,
            color=color,
            mfc="none",
            label=f"{name}: max {np.abs(err).max():.3g}",
        )
    ax1.set(ylabel=r"$w\,/\,w_0$", title="(a) resulting motion")
    ax2.set(
        xlabel=r"$t\,/\,T$",
        ylabel=r"$\epsilon = (w_{calc} - w_{exact})\,/\,w_0$",
        title="(b) error",
    )
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7.5, loc="upper left")
    fig.suptitle(
        rf"Fig. 4: pendulum with decaying mass, $a$ = {_pendulum.A:g}, "
        rf"$\Delta t / T$ = 1/{data.steps_per_period}",
        fontsize=11,
    )
    return fig


def plot_fig5(data: BesselData) -> Any:
    """Fig. 5: the dimensionless mass ratio ``m(t) / m0`` against ``omega t``.

    Parameters
    ----------
    data : BesselData
        From :func:`duhamel.paper.figs5to7`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import figs5to7
    >>> from duhamel.paper.figures import plot_fig5
    >>> plot_fig5(figs5to7(n_fine=51)).axes[0].get_ylabel()
    '$m(t)\\\\,/\\\\,m_0$'
    """
    fig = figure_class()(figsize=(6.0, 3.6), layout="constrained")
    ax = fig.subplots()
    ax.plot(OMEGA * data.t, data.mass_ratio, color="k", lw=1.3)
    ax.set(
        xlabel=r"$\omega t$",
        ylabel=r"$m(t)\,/\,m_0$",
        xlim=(0.0, OMEGA * data.t[-1]),
        ylim=(0.0, 1.05 * data.mass_ratio.max()),
        title=rf"Fig. 5: mass ratio $K e^{{-2 a \omega t}}$, $a$ = 1/{1 / _bessel.A:g}, "
        f"$K$ = {_bessel.K:g}",
    )
    ax.grid(True, alpha=0.3)
    return fig


def plot_fig6(data: BesselData) -> Any:
    """Fig. 6: displacement ``x / x0`` and velocity ``x' / (x0 omega)`` against ``omega t``.

    Parameters
    ----------
    data : BesselData
        From :func:`duhamel.paper.figs5to7`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import figs5to7
    >>> from duhamel.paper.figures import plot_fig6
    >>> len(plot_fig6(figs5to7(n_fine=51)).axes)
    2
    """
    fig = figure_class()(figsize=(7.0, 5.6), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    label = rf"semi-analytic, $\omega\Delta t = 2\pi/{data.steps_per_period}$"
    for ax, exact, num, ylabel in (
        (ax1, data.x, data.x_num, r"$x\,/\,x_0$"),
        (ax2, data.v, data.v_num, r"$\dot x\,/\,(x_0\,\omega)$"),
    ):
        ax.plot(OMEGA * data.t, exact, color="k", lw=1.2, label="exact (eq. 44)")
        ax.plot(OMEGA * data.t_num, num, "o", ms=3.0, mfc="none", color="C0", label=label)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="lower left")
    ax1.set_title("(a) displacement", fontsize=10)
    ax2.set_title("(b) velocity", fontsize=10)
    ax2.set_xlabel(r"$\omega t$")
    ax2.set_xlim(0.0, OMEGA * data.t[-1])
    fig.suptitle("Fig. 6: displacement and velocity for the mass ratio of Fig. 5", fontsize=11)
    return fig


def plot_fig7(data: BesselData) -> Any:
    """Fig. 7: the solution of Figs. 5-6 in the phase plane.

    Parameters
    ----------
    data : BesselData
        From :func:`duhamel.paper.figs5to7`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import figs5to7
    >>> from duhamel.paper.figures import plot_fig7
    >>> plot_fig7(figs5to7(n_fine=51)).axes[0].get_xlabel()
    '$x\\\\,/\\\\,x_0$'
    """
    fig = figure_class()(figsize=(5.6, 5.2), layout="constrained")
    ax = fig.subplots()
    ax.plot(data.x, data.v, color="k", lw=1.1, label="exact (eq. 44)")
    ax.plot(
        data.x_num,
        data.v_num,
        "o",
        ms=2.8,
        mfc="none",
        color="C0",
        label=rf"semi-analytic, $\omega\Delta t = 2\pi/{data.steps_per_period}$",
    )
    ax.plot(data.x[0], data.v[0], "s", color="C3", ms=5, label=r"start, $x_0 = 1$, $\dot x_0 = 0$")
    ax.set(
        xlabel=r"$x\,/\,x_0$",
        ylabel=r"$\dot x\,/\,(x_0\,\omega)$",
        title="Fig. 7: solution of Fig. 6 in the phase plane",
    )
    ax.axhline(0.0, color="0.7", lw=0.5)
    ax.axvline(0.0, color="0.7", lw=0.5)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    return fig


def plot_fig8(data: Fig8Data) -> Any:
    """Fig. 8: (a) solutions for several steps, (b) error against the step, with the order.

    Parameters
    ----------
    data : Fig8Data
        From :func:`duhamel.paper.fig8`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from duhamel.paper import fig8
    >>> from duhamel.paper.figures import plot_fig8
    >>> len(plot_fig8(fig8(steps=(20, 40, 80))).axes)
    2
    """
    fig = figure_class()(figsize=(11.0, 4.3), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2, width_ratios=(1.5, 1.0))
    ax1.plot(OMEGA * data.t, data.x, color="k", lw=1.4, label="exact (eq. 44)")
    for i, n in enumerate(data.steps[:4]):
        t, x = data.solutions[n]
        ax1.plot(OMEGA * t, x, "-o", ms=2.5, lw=0.8, color=f"C{i}", label=rf"$\Delta t = T/{n}$")
    ax1.set(xlabel=r"$\omega t$", ylabel=r"$x\,/\,x_0$", title="(a) solutions with different steps")
    ax1.set_xlim(0.0, OMEGA * data.t[-1])
    ax1.legend(fontsize=8, loc="lower left")
    ax1.grid(True, alpha=0.3)
    h = np.array([1.0 / n for n in data.steps])
    e = np.array([data.errors[n] for n in data.steps])
    e_nm = np.array([data.newmark_errors[n] for n in data.steps])
    ax2.loglog(h, e, "o-", color="C0", label=f"semi-analytic (order {data.order:.2f})")
    ax2.loglog(
        h, e_nm, "^--", color="C1", mfc="none", label=f"Newmark (order {data.newmark_order:.2f})"
    )
    ref = e[-1] * (h / h[-1]) ** 2
    ax2.loglog(h, ref, ":", color="0.4", label=r"slope 2")
    ax2.set(
        xlabel=r"$\Delta t\,/\,T$",
        ylabel=r"$\max\,|x_{calc} - x_{exact}|\,/\,x_0$",
        title="(b) error against the step",
    )
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend(fontsize=8, loc="upper left")
    fig.suptitle(
        r"Fig. 8: exponentially varying mass, $0 \leq \omega t \leq$ "
        f"{OMEGA * data.t[-1]:g}, solutions with different time steps",
        fontsize=11,
    )
    return fig
