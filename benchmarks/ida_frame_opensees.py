"""A collapse IDA of the 3-storey hinged frame end to end: duhamel against OpenSees on the same
frame (issue 37's speed acceptance).

The frame, damping, records, scaling and collapse criterion are those of
tests/_support/_collapse_frame.py (examples/collapse_ida.py's frame with Rayleigh 3 % as one
constant matrix in both programs; ``ModIMKPeakOriented`` storey hinges, leaning column; collapse
at a storey drift ratio of 10 % or when a step finds no equilibrium): 11 records x 15 intensities
Sa(T1) = 0.2 g ... 3.0 g, every one of the 165 runs made (as ``ida`` makes them), each run
stopped at its collapse. ``--damping initial`` (the default): Rayleigh on the mass and the
initial stiffness (OpenSees' ``betaKinit``), classical in duhamel's modes; ``--damping
storeys``: on the storeys' stiffness without the geometric one (OpenSees: storey dashpots),
not classical in duhamel's modes (its first-order route).

* duhamel: ``ida(..., workers=1)`` with ``Semianalytic()`` and with ``Newmark()`` at the
  records' step (the collapse event located inside the step); timed: the whole call (the
  records' Sa, a model built per run, the runs).
* OpenSees (openseespy): per run a model built from scratch, Newmark average acceleration at
  the records' step, Newton, ``NormDispIncr`` 1e-8 m, ``BandGeneral``; ``analyze(1)`` and the
  storey drifts read after every step (the collapse check); timed: the records' Sa (duhamel's
  spectrum, as the scaling is shared) and the 165 runs.

Each contender runs in its own fresh process (one thread), the contenders interleaved,
``--repeats`` times; best and median per contender, the 1-min load average before and after
each run. The first collapse on the grid per record is compared between the programs.

Usage::

    python benchmarks/ida_frame_opensees.py [--repeats 3] [--damping storeys] [--append FILE]
    python benchmarks/ida_frame_opensees.py --quick  # 3 records x 4 intensities (1 g to 2.5 g)
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import functools  # noqa: E402
import importlib.util  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from datetime import UTC, datetime  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CONTENDERS = ("duhamel Semianalytic", "duhamel Newmark", "OpenSees")


def _frame_module():
    path = ROOT / "tests" / "_support" / "_collapse_frame.py"
    spec = importlib.util.spec_from_file_location("_collapse_frame", path)
    assert spec is not None and spec.loader is not None
    cf = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(cf)
    return cf


def _grid(quick: bool) -> tuple[int, np.ndarray]:
    from duhamel.records import G

    if quick:
        return 3, G * np.linspace(1.0, 2.5, 4)
    return 11, G * np.linspace(0.2, 3.0, 15)


def _first(hit: np.ndarray, grid: np.ndarray) -> list[float]:
    return [float(grid[row.argmax()]) if row.any() else float("inf") for row in hit]


def contender(name: str, quick: bool, damping: str) -> dict:
    """One contender's IDA in this process: its time, runs, collapses and first collapses."""
    cf = _frame_module()
    n, grid = _grid(quick)
    motions = cf.records(n)
    started = time.perf_counter()
    if name.startswith("duhamel"):
        import duhamel
        from duhamel.ensemble import ida

        scheme = duhamel.Newmark() if name.endswith("Newmark") else duhamel.Semianalytic()
        warnings.simplefilter("ignore", duhamel.errors.AccuracyWarning)  # at the record step
        factory = functools.partial(cf.frame, damping=damping)
        res = ida(factory, motions, grid, cf.ex.peak_drift_ratio, scheme, period=cf.T1,
                  damping=0.05, collapse=cf.ex.collapse_event(), solver_error="collapse",
                  workers=1)  # fmt: skip
        seconds = time.perf_counter() - started
        hit = ~np.isfinite(res.measures)
        kinds = {"collapse": int(hit.sum() - res.failed.sum()), "failed": int(res.failed.sum())}
    else:
        import openseespy.opensees as ops

        hit = np.zeros((n, grid.size), dtype=bool)
        kinds = {"collapse": 0, "failed": 0}
        for i, m in enumerate(motions):
            unit = cf.sa1(m)
            for j, im in enumerate(grid):
                kind, _ = cf.opensees_run(ops, m.scaled(im / unit).a, m.dt, damping)
                hit[i, j] = kind != "none"
                kinds["collapse" if kind == "drift" else "failed"] += kind != "none"
        seconds = time.perf_counter() - started
        ops.wipe()
    return {"seconds": seconds, "runs": int(hit.size), "first": _first(hit, grid), **kinds}


def _spawn(name: str, quick: bool, damping: str) -> tuple[dict, float, float]:
    before = os.getloadavg()[0]
    cmd = [sys.executable, __file__, "--contender", name, "--damping", damping]
    cmd += ["--quick"] if quick else []
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    line = [x for x in out.splitlines() if x.startswith("{")][-1]
    return json.loads(line), before, os.getloadavg()[0]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--append", help="append the section to this markdown file")
    parser.add_argument("--quick", action="store_true", help="3 records x 4 intensities, once")
    parser.add_argument("--damping", choices=("initial", "storeys"), default="initial",
                        help="the Rayleigh stiffness term (see tests/_support)")  # fmt: skip
    parser.add_argument("--contender", choices=CONTENDERS, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.contender:
        print(json.dumps(contender(args.contender, args.quick, args.damping)))
        return 0
    repeats = 1 if args.quick else args.repeats
    times: dict[str, list[float]] = {c: [] for c in CONTENDERS}
    loads, results = [], {}
    for r in range(repeats):  # interleaved, the order turned each repeat
        order = CONTENDERS if r % 2 == 0 else CONTENDERS[::-1]
        for name in order:
            res, before, after = _spawn(name, args.quick, args.damping)
            times[name].append(res["seconds"])
            loads += [before, after]
            results[name] = res
            print(f"{name}: {res['seconds']:.2f} s, load {before:.2f} -> {after:.2f}",
                  file=sys.stderr)  # fmt: skip
    from duhamel.records import G

    ref = np.array(results["OpenSees"]["first"])
    rev = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                         capture_output=True, text=True).stdout.strip()  # fmt: skip
    when = datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC")
    n, grid = _grid(args.quick)
    cmd = "python benchmarks/ida_frame_opensees.py" + (" --quick" if args.quick else
                                                      f" --repeats {repeats}")  # fmt: skip
    cmd += " --damping storeys" if args.damping == "storeys" else ""
    lines = [
        f"`{cmd}` · {when} · `{rev}` · load {min(loads):.2f} to {max(loads):.2f}"
        + (" · **under load**" if max(loads) > 2 else "")
        + f". {n} records x {grid.size} Sa(T1) intensities ({grid[0] / G:.2f} g to "
        f"{grid[-1] / G:.2f} g), {n * grid.size} runs each, each contender in its own process "
        f"(one thread), {repeats} interleaved repeat(s); first collapse on the grid per record "
        "[g], OpenSees: " + ", ".join(f"{x / G:.2f}" for x in ref) + ".",
        "",
        "| contender | best [s] | median [s] | OpenSees / it (best, median) | collapses "
        "(drift, no convergence) | first collapses as OpenSees' |",
        "|---|---:|---:|---|---|---|",
    ]
    os_best, os_med = min(times["OpenSees"]), float(np.median(times["OpenSees"]))
    for name in CONTENDERS:
        best, med = min(times[name]), float(np.median(times[name]))
        res = results[name]
        first = np.array(res["first"])
        same = int(np.sum(first == ref))
        if same == n:
            within = ""
        elif np.array_equal(np.isinf(first), np.isinf(ref)):
            off = np.abs(first - ref)[np.isfinite(ref)].max() / float(grid[1] - grid[0])
            within = f" (the others within {off:.0f} steps)"
        else:
            within = " (a record collapses in one program only)"
        lines.append(f"| {name} | {best:.2f} | {med:.2f} | {os_best / best:.1f}x, "
                     f"{os_med / med:.1f}x | {res['collapse']}, {res['failed']} | "
                     f"{same} of {n}{within} |")  # fmt: skip
    text = "\n".join(lines) + "\n"
    print(text)
    if args.append:
        with open(args.append, "a", encoding="utf-8") as f:
            f.write("\n" + text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
