"""Run the paper's examples, draw their figures and write ``report.md``.

:func:`reproduce` is what ``duhamel reproduce`` runs. Each example (:data:`EXAMPLES`) computes
its data once, draws the figures asked for and returns its claims (:class:`Claim`): the
paper's statement, our numbers and whether the statement holds. :func:`render_report` turns
them into markdown tables.
"""

from __future__ import annotations

import os
import platform
import sys
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import duhamel
from duhamel.paper import bessel as _bessel
from duhamel.paper import duffing as _duffing
from duhamel.paper import figures as _figures
from duhamel.paper import pendulum as _pendulum
from duhamel.paper import rotor as _rotor
from duhamel.paper import stability as _stability
from duhamel.paper._common import Claim

__all__ = [
    "EXAMPLES",
    "NAMES",
    "Example",
    "ExampleResult",
    "Reproduction",
    "parse_names",
    "render_report",
    "reproduce",
]


@dataclass(frozen=True)
class Example:
    """One example of the paper: how to compute it and which figures it draws.

    Attributes
    ----------
    key : str
        Identifier (``"fig1"``, ``"duffing"``, ...).
    title : str
        Section title in the report.
    setup : str
        One paragraph: the model, parameters and references.
    figures : tuple of str
        The figure names (:data:`duhamel.paper.figures.FIGURES`) drawn from its data.
    names : tuple of str
        The names under which ``--only`` selects it (its figures, or e.g. ``"cpu"``). Its
        `key`, when listed, selects it with all its figures.
    compute : callable
        ``compute(**options)`` returns the data (with a ``claims()`` method).
    """

    key: str
    title: str
    setup: str
    figures: tuple[str, ...]
    names: tuple[str, ...]
    compute: Callable[..., Any]


EXAMPLES: tuple[Example, ...] = (
    Example(
        "fig1",
        "Fig. 1: stability of schemes (a), (b), (c), damping as a pseudo-force (section 3)",
        "X'' + omega^2 X = -2 zeta omega X' with zeta = 0.1: undamped exact background, the "
        "damping a pseudo-force along the three approximations of eq. 20; spectral radius of "
        "the measured amplification matrix for dt/T from 1e-3 to 1e3 (1201 points; the "
        "maxima and the ends of the unstable intervals refined by root finding). "
        "`duhamel.paper.fig1`, docs/analysis.md.",
        ("fig1",),
        ("fig1",),
        _stability.fig1,
    ),
    Example(
        "fig2",
        "Fig. 2: eq. 25, scheme (b) against Newmark (section 3)",
        "X'' + 2 zeta omega X' + omega^2 X = s alpha omega^2 X, alpha = 0.3, zeta = 0.1: the "
        "damping in the exact background, the alpha term a pseudo-force; scheme (b) against "
        "`duhamel.Newmark(1/2, 1/4)`, 601 points. The printed eq. 25 has s = -1; eqs. 26 and "
        "27 hold for s = +1 (NOTES.md section 2), so both are drawn (+ solid, - dashed). "
        "`duhamel.paper.fig2`.",
        ("fig2",),
        ("fig2",),
        _stability.fig2,
    ),
    Example(
        "fig3",
        "Fig. 3: Duffing oscillator, error phase plane (section 4.1)",
        "X'' + omega^2 X + b X^3 = 0, b X0^2 = 4 omega^2, X0' = 0, omega dt = 2 pi/100, "
        "10 background periods (1000 steps); reference: Jacobi cn (`duhamel.exact.duffing`). "
        "Methods: `Semianalytic()` (scheme b, trapezoidal pseudo-force, the default), "
        "`Semianalytic(quadrature='parabolic')` (the paper's parabolic load interpolation), "
        "`Newmark(1/2, 1/4)` and `CubicHermite()` (a reconstruction of Argyris' cubic "
        "Hermitian method). `duhamel.paper.fig3`.",
        ("fig3",),
        ("fig3",),
        _duffing.fig3,
    ),
    Example(
        "cpu",
        "CPU time against Newmark (section 4.1)",
        "The Duffing case of Fig. 3 at the paper's step, run for 1e5 steps (1000 periods) so "
        "that a run's fixed cost does not count; the methods are interleaved and timed by the "
        "Rust loop's own clock (`SolveStats.wall_time`, every step saved); best of 5. "
        "Machine-dependent: the numbers below are from this run. `duhamel.paper.cpu_ratios`.",
        (),
        ("cpu",),
        _duffing.cpu_ratios,
    ),
    Example(
        "fig4",
        "Fig. 4: pendulum with decaying mass (section 4.2)",
        "(m w')' + m omega^2 w = f_step, m = m0 exp(-a omega t), a = 1/10, "
        "w0'/(w0 omega) = 2, f_step/(omega^2 w0 m0) = 1, omega dt = 2 pi/10, five periods; "
        "reference: eq. 31 with its sine coefficient corrected "
        "(`duhamel.exact.decaying_mass_pendulum`). Eq. 30 route: negative damping -a/2 in "
        "the exact background, load f/m; eq. 32 route: mass change as a pseudo-force, scheme "
        "(b), the acceleration eliminated (default) or estimated as (v1 - v0)/dt. "
        "`duhamel.paper.fig4`, docs/mass.md.",
        ("fig4",),
        ("fig4",),
        _pendulum.fig4,
    ),
    Example(
        "figs5to7",
        "Figs. 5-7: exponentially varying mass, exact solution (section 4.3)",
        "(m x')' + m0 omega^2 x = 0, m/m0 = K exp(-2 a omega t), a = 1/20, K = 1 (the paper's "
        "'c = a = 1/20', NOTES.md section 3), x0 = 1, x0' = 0, omega t in [0, 20] (the paper "
        "gives no span); exact: eq. 44 (`duhamel.exact.bessel_mass`); drawn with the "
        "semi-analytic run at omega dt = 2 pi/40. `duhamel.paper.figs5to7`.",
        ("fig5", "fig6", "fig7"),
        ("fig5", "fig6", "fig7"),
        _bessel.figs5to7,
    ),
    Example(
        "fig8",
        "Fig. 8: convergence for several steps (section 4.3)",
        "The case of Figs. 5-7 with dt = T/10 ... T/320, maximum displacement error over "
        "omega t in [0, 20] against eq. 44; order = least-squares slope over T/40 ... T/320 "
        "(from T/10 the first halvings are pre-asymptotic). `duhamel.paper.fig8`.",
        ("fig8",),
        ("fig8",),
        _bessel.fig8,
    ),
    Example(
        "rotor",
        "Figs. 9-13: nonlinear rotor with variable mass, orbits (section 4.4)",
        "5 nodes, 4 Timoshenko elements, 3 disks, 20 dofs (`duhamel.rotor`); the paper's dof "
        "j is our node (j - 1) // 4, so its bearing dofs 1, 2, 13, 14 are x, y of nodes 0 "
        "and 3; disks at nodes 1 (left rotor), 2 (right rotor) and 4 (overhung). Our "
        "geometry (the paper gives none): steel shaft 200 mm, bearing span 2.0 m, overhang "
        "0.5 m, disks 552, 552 and 193 kg, 1911 kg in all; Rayleigh damping 2 % at the first "
        "two bending frequencies. Bearings k11 = k22 = 1e9 N/m, k12 = -k21 = 1e7 N/m, cubic "
        "law beta = 0 and 0.1 (x_stat: each bearing's static deflection under the weight). "
        "1500 rpm; from rest, gravity and a sudden unbalance on node 2 whose force is 5e4 N; "
        "M(t) = M0 [1 + xi sin(Omega t)] (acceleration form), xi = 0, 0.05, 0.1. "
        "`Semianalytic()` (20 modes), dt = 1e-4 s (400 steps per revolution), 0.5 s. Orbits "
        "scaled by each position's static deflection under the weight (beta = 0). "
        "`duhamel.paper.rotor_orbits`, docs/paper.md.",
        ("fig9", "fig10", "fig11", "fig12", "fig13"),
        ("rotor", "fig9", "fig10", "fig11", "fig12", "fig13"),
        _rotor.rotor_orbits,
    ),
    Example(
        "table1",
        "Table 1: modal reduction and Newmark on the rotor (section 4.4)",
        "The case beta = 0.1, xi = 0.1 of Figs. 10-13 with `Semianalytic(modes=m, "
        "static_correction=False)` (the paper's modal truncation), m = 20 (full), 15, 10, 5, "
        "3, then with the static correction, and `Newmark()` at the same step (dt = 1e-4 s, "
        "5000 steps), "
        "interleaved, best of 7, the Rust loop's own clock. Error of a reduced model: "
        "max_t |r_m - r_full| / max_t |r_full| of the (x, y) vector r at each position of "
        "Figs. 10-13 (also for the linear rotor, beta = 0, xi = 0). Accuracy against a "
        "converged run: the full model at dt/16. Machine-dependent: the times are from this "
        "run. `duhamel.paper.table1`.",
        (),
        ("table1",),
        _rotor.table1,
    ),
)

#: Every name ``--only`` accepts, in report order.
NAMES: tuple[str, ...] = tuple(n for e in EXAMPLES for n in e.names)

_PLOTS: dict[str, Callable[[Any], Any]] = {
    "fig1": _figures.plot_fig1,
    "fig2": _figures.plot_fig2,
    "fig3": _figures.plot_fig3,
    "fig4": _figures.plot_fig4,
    "fig5": _figures.plot_fig5,
    "fig6": _figures.plot_fig6,
    "fig7": _figures.plot_fig7,
    "fig8": _figures.plot_fig8,
    "fig9": _figures.plot_fig9,
    "fig10": _figures.plot_fig10,
    "fig11": _figures.plot_fig11,
    "fig12": _figures.plot_fig12,
    "fig13": _figures.plot_fig13,
}


def parse_names(text: str) -> tuple[str, ...]:
    """Split a comma-separated selection (``"fig3,fig4"``) and check every name.

    Parameters
    ----------
    text : str
        Names from :data:`NAMES`, separated by commas (spaces allowed).

    Returns
    -------
    tuple of str
        The names, in report order, without duplicates.

    Raises
    ------
    ValueError
        An unknown or empty name.

    Examples
    --------
    >>> from duhamel.paper.report import parse_names
    >>> parse_names("fig4, fig3,fig3")
    ('fig3', 'fig4')
    """
    names = [n.strip() for n in text.split(",")]
    unknown = [n for n in names if n not in NAMES]
    if unknown:
        raise ValueError(
            f"unknown example {', '.join(repr(n) for n in unknown)} "
            f"(choose from {', '.join(NAMES)})"
        )
    return tuple(n for n in NAMES if n in names)


@dataclass(frozen=True, eq=False)
class ExampleResult:
    """What one example produced.

    Attributes
    ----------
    example : Example
    data : object
        The example's data (e.g. :class:`~duhamel.paper.Fig3Data`).
    claims : list of Claim
    figures : dict of str to Path
        Figure name to the PNG written.
    seconds : float
        Time to compute the data and draw the figures.
    """

    example: Example
    data: Any
    claims: list[Claim]
    figures: dict[str, Path]
    seconds: float


@dataclass(frozen=True, eq=False)
class Reproduction:
    """The result of :func:`reproduce`.

    Attributes
    ----------
    results : list of ExampleResult
    report : Path
        The ``report.md`` written.
    seconds : float
        Total time.
    """

    results: list[ExampleResult]
    report: Path
    seconds: float
    command: str = field(default="duhamel reproduce")

    @property
    def claims(self) -> list[Claim]:
        """Every claim of every example, in report order."""
        return [c for r in self.results for c in r.claims]

    @property
    def files(self) -> list[Path]:
        """The PNGs and the report, in the order written."""
        return [p for r in self.results for p in r.figures.values()] + [self.report]


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def render_report(
    results: Sequence[ExampleResult], *, seconds: float, command: str = "duhamel reproduce"
) -> str:
    """The markdown report: one table of claims per example, with the figures.

    Parameters
    ----------
    results : sequence of ExampleResult
    seconds : float
        Total run time, stated in the header.
    command : str
        The command line stated in the header.

    Returns
    -------
    str

    Examples
    --------
    >>> from duhamel.paper.report import render_report
    >>> print(render_report([], seconds=0.0).splitlines()[0])
    # Holl, Belyaev and Irschik (1999), reproduced
    """
    claims = [c for r in results for c in r.claims]
    held = sum(c.holds is True for c in claims)
    failed = sum(c.holds is False for c in claims)
    lines = [
        "# Holl, Belyaev and Irschik (1999), reproduced",
        "",
        "H. J. Holl, A. K. Belyaev, H. Irschik, *A numerical algorithm for nonlinear dynamic "
        "problems based on BEM*, Engineering Analysis with Boundary Elements 23 (1999) "
        "503-513: sections 3 and 4.",
        "",
        f"Made by `{command}` with duhamel {duhamel.__version__}, Python "
        f"{platform.python_version()}, {platform.machine()}, {os.cpu_count()} cores, in "
        f"{seconds:.1f} s. Every number below is computed by this run; 'paper' quotes the "
        "paper (OCR text: its figures are not available to us, so the figures reproduce the "
        "stated axes and quantities) or, where marked, the verified notes of "
        "`shared/method/NOTES.md`.",
        "",
        f"**{len(claims)} statements checked: {held} hold, {failed} do not hold, "
        f"{len(claims) - held - failed} measurements for information.**",
        "",
    ]
    if failed:
        lines += ["Statements that do not hold:", ""]
        for r in results:
            for c in r.claims:
                if c.holds is False:
                    lines.append(f"- {r.example.title.split(':')[0]}: {c.claim} ({c.ours}).")
        lines.append("")
    for r in results:
        lines += [f"## {r.example.title}", "", r.example.setup, ""]
        for name, path in r.figures.items():
            lines += [f"![{name}]({path.name})", ""]
        lines += ["| claim | paper | ours | verdict | note |", "|---|---|---|---|---|"]
        for c in r.claims:
            verdict = f"**{c.verdict}**" if c.holds is False else c.verdict
            cells = (c.claim, c.paper, c.ours, verdict, c.note)
            lines.append("| " + " | ".join(_cell(x) for x in cells) + " |")
        lines += ["", f"Computed and drawn in {r.seconds:.2f} s.", ""]
    return "\n".join(lines)


def _selected(only: Iterable[str] | None) -> list[tuple[Example, tuple[str, ...]]]:
    names = set(NAMES if only is None else only)
    unknown = names - set(NAMES)
    if unknown:
        raise ValueError(
            f"unknown example {', '.join(sorted(unknown))} (choose from {', '.join(NAMES)})"
        )
    out = []
    for ex in EXAMPLES:
        if names & set(ex.names):
            every = ex.key in names and ex.key in ex.names
            out.append((ex, tuple(f for f in ex.figures if every or f in names)))
    return out


def reproduce(
    out: str | os.PathLike[str],
    only: Iterable[str] | None = None,
    *,
    progress: bool = False,
    options: Mapping[str, Mapping[str, Any]] | None = None,
    command: str = "duhamel reproduce",
) -> Reproduction:
    """Run the examples, write one PNG per figure and ``report.md`` into `out`.

    Parameters
    ----------
    out : path
        Output directory (created with its parents).
    only : iterable of str, optional
        Names from :data:`NAMES` (``"fig1"`` ... ``"fig13"``, ``"cpu"``, ``"rotor"``,
        ``"table1"``); all by default. Figs. 5-7 share one computation, and so do Figs.
        9-13; only the figures named are drawn (``"rotor"``: all of Figs. 9-13).
    progress : bool
        Show a tqdm progress bar across the examples (on stderr).
    options : mapping, optional
        Keyword arguments per example key (``"fig1"``, ``"fig3"``, ``"cpu"``, ``"figs5to7"``,
        ``"rotor"``, ``"table1"``, ...) passed to its function, e.g.
        ``{"cpu": {"repeats": 1}}`` for a quick run.
    command : str
        The command line stated in the report.

    Returns
    -------
    Reproduction

    Raises
    ------
    ValueError
        An unknown name in `only`.
    ImportError
        matplotlib is missing and a figure was asked for.

    Examples
    --------
    >>> import tempfile
    >>> from duhamel.paper import reproduce
    >>> with tempfile.TemporaryDirectory() as d:
    ...     run = reproduce(d, only=["fig3"])
    ...     sorted(p.name for p in run.files)
    ['fig3_duffing_error_phase_plane.png', 'report.md']
    >>> [c.verdict for c in run.claims]
    ['holds', 'does not hold', 'does not hold', 'holds']
    """
    from tqdm import tqdm

    start = time.perf_counter()
    selected = _selected(only)
    if any(figs for _, figs in selected):
        _figures.figure_class()  # fail before computing anything
    directory = Path(out)
    directory.mkdir(parents=True, exist_ok=True)
    options = options or {}
    results = []
    with tqdm(
        total=len(selected),
        desc="reproduce",
        unit="example",
        disable=not progress,
        file=sys.stderr,
        leave=False,
    ) as bar:
        for example, figs in selected:
            bar.set_postfix_str(example.key)
            t0 = time.perf_counter()
            data = example.compute(**dict(options.get(example.key, {})))
            written = {}
            for name in figs:
                fig = _PLOTS[name](data)
                path = directory / _figures.FIGURES[name]
                fig.savefig(path, dpi=_figures.DPI)
                written[name] = path
            results.append(
                ExampleResult(example, data, data.claims(), written, time.perf_counter() - t0)
            )
            bar.update()
    seconds = time.perf_counter() - start
    report = directory / "report.md"
    report.write_text(render_report(results, seconds=seconds, command=command))
    return Reproduction(results, report, seconds, command)
