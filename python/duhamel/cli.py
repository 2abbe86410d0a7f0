"""The ``duhamel`` command line (also ``python -m duhamel``)."""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import duhamel
from duhamel.errors import AccuracyWarning

__all__ = ["build_parser", "format_summary", "main"]


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``duhamel`` command.

    Returns
    -------
    argparse.ArgumentParser

    Examples
    --------
    >>> from duhamel.cli import build_parser
    >>> build_parser().parse_args(["demo", "--no-plot"]).out
    'results'
    """
    parser = argparse.ArgumentParser(
        prog="duhamel",
        description="Exact transient response of M x'' + C x' + K x = f(t) in modal "
        "coordinates (semi-analytic Duhamel method).",
    )
    parser.add_argument("--version", action="version", version=f"duhamel {duhamel.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    demo = sub.add_parser(
        "demo",
        help="10-storey shear building under a synthetic earthquake",
        description="Run the bundled example: a 10-storey shear building (T1 = 1.0 s, 5 % "
        "modal damping) under a synthetic 20 s ground-acceleration record scaled to "
        "PGA 0.3 g, integrated to 30 s with dt = 0.01 s. Prints a summary and writes "
        "OUT/demo.png and OUT/demo_summary.json.",
    )
    demo.add_argument(
        "--out", default="results", metavar="DIR", help="output directory (default: results)"
    )
    demo.add_argument("--no-plot", action="store_true", help="do not write demo.png")
    from duhamel.paper.report import NAMES

    reproduce = sub.add_parser(
        "reproduce",
        help="reproduce the paper's figures and check its claims (report.md)",
        description="Run the examples of Holl, Belyaev and Irschik (1999), sections 3 and "
        "4 (the rotor of section 4.4 included): write one PNG per figure and OUT/report.md, "
        "a table per example with our numbers, the paper's claim and whether it holds. See "
        "docs/paper.md.",
    )
    reproduce.add_argument(
        "--out", default="results", metavar="DIR", help="output directory (default: results)"
    )
    reproduce.add_argument(
        "--only",
        type=_names,
        metavar="LIST",
        help=f"comma-separated examples to run, from: {','.join(NAMES)} (default: all)",
    )
    reproduce.add_argument(
        "--quiet", action="store_true", help="no progress bar and no summary on stdout"
    )
    return parser


def _names(text: str) -> tuple[str, ...]:
    from duhamel.paper.report import parse_names

    try:
        return parse_names(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def format_summary(summary: dict[str, Any]) -> str:
    """Human-readable lines for a demo summary (see :meth:`duhamel.demo.DemoResult.summary`).

    Parameters
    ----------
    summary : dict
        The summary dictionary.

    Returns
    -------
    str

    Examples
    --------
    >>> from duhamel.cli import format_summary
    >>> from duhamel.demo import run_demo
    >>> print(format_summary(run_demo(t_end=1.0).summary()).splitlines()[1])
    natural periods     T1 = 1.000 s, T2 = 0.361 s, T3 = 0.222 s
    """
    s = summary
    periods = ", ".join(f"T{i + 1} = {p:.3f} s" for i, p in enumerate(s["periods_s"]))
    rate = s["mode_steps_per_second"]
    return "\n".join(
        [
            f"duhamel {s['version']} demo: 10-storey shear building, synthetic record "
            "(PGA 0.30 g, 20 s)",
            f"natural periods     {periods}",
            f"peak roof displ.    {100 * s['peak_roof_displacement_m']:+.2f} cm at "
            f"t = {s['peak_roof_displacement_time_s']:.2f} s (relative to the ground)",
            f"peak drift ratio    {100 * s['peak_drift_ratio']:.3f} % "
            f"(storey {s['peak_drift_storey']}, h = {s['storey_height_m']:g} m)",
            f"peak base shear     {s['peak_base_shear_N'] / 1e6:.2f} MN "
            f"({s['peak_base_shear_over_weight']:.3f} W)",
            f"run                 {s['steps']} steps x {s['modes']} modes in "
            f"{1e3 * s['wall_time_s']:.2f} ms ({rate:.3g} mode-steps/s)",
        ]
    )


def _demo(args: argparse.Namespace) -> int:
    from duhamel.demo import _figure_class, plot_demo, run_demo

    if not args.no_plot:
        try:
            _figure_class()  # fail before the run, not after it
        except ImportError as exc:
            return _fail(str(exc))
    out = Path(args.out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        return _fail(f"cannot create output directory '{out}': {exc.strerror or exc}")
    result = run_demo()
    summary = result.summary()
    print(format_summary(summary))
    written = []
    try:
        path = out / "demo_summary.json"
        path.write_text(json.dumps(summary, indent=2) + "\n")
        written.append(path)
        if not args.no_plot:
            written.append(plot_demo(result, out / "demo.png"))
    except ImportError as exc:
        return _fail(str(exc))
    except OSError as exc:
        return _fail(f"cannot write to '{out}': {exc.strerror or exc}")
    print(f"wrote               {', '.join(str(p) for p in written)}")
    return 0


def _reproduce(args: argparse.Namespace) -> int:
    from duhamel.paper.report import reproduce

    command = "duhamel reproduce --out " + str(args.out)
    if args.only:
        command += " --only " + ",".join(args.only)
    progress = not args.quiet and sys.stderr.isatty()
    try:
        with warnings.catch_warnings():
            # the paper's runs are at the paper's steps on purpose (the coarse ones show its
            # errors); the report measures each against its exact or converged reference
            warnings.simplefilter("ignore", AccuracyWarning)
            run = reproduce(args.out, args.only, progress=progress, command=command)
    except ImportError as exc:
        return _fail(str(exc))
    except OSError as exc:
        where = exc.filename if exc.filename is not None else args.out
        return _fail(f"cannot write to '{where}': {exc.strerror or exc}")
    if not args.quiet:
        for result in run.results:
            counts = [c.holds for c in result.claims]
            print(
                f"{result.example.key:9s} {counts.count(True)} hold, "
                f"{counts.count(False)} do not hold, {counts.count(None)} for information "
                f"({result.seconds:.1f} s)"
            )
        print(f"wrote {len(run.files)} files to {args.out} in {run.seconds:.1f} s: {run.report}")
    return 0


def _fail(message: str) -> int:
    print(f"duhamel: error: {message}", file=sys.stderr)
    return 1


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``duhamel`` command.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments without the program name; ``sys.argv[1:]`` by default.

    Returns
    -------
    int
        Exit status: 0 on success, 1 on a runtime error (e.g. an unwritable output
        directory), 2 on bad command-line input (argparse prints its message).

    Examples
    --------
    >>> from duhamel.cli import main
    >>> main(["--version"])  # doctest: +ELLIPSIS
    duhamel ...
    0
    """
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a usage error (code 2)
        return exc.code if isinstance(exc.code, int) else 1
    if args.command == "demo":
        return _demo(args)
    if args.command == "reproduce":
        return _reproduce(args)
    parser.error(f"unknown command {args.command!r}")  # pragma: no cover - argparse checks
    return 2  # pragma: no cover
