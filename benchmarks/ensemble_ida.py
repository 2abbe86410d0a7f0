"""A study of 1,000+ runs of a frame: an IDA of the 3-storey hinged frame on one process, on
2 threads and on a Dask LocalCluster of 2 single-threaded worker processes (issue 42,
"Studies that scale").

The frame, damping, records and collapse criterion are tests/_support/_collapse_frame.py's
(examples/collapse_ida.py's frame: ``ModIMKPeakOriented`` storey hinges, a leaning column,
Rayleigh 3 % on the initial stiffness; collapse at 10 % storey drift, the example's terminal
event, or no convergence). ``--records`` of the example's synthetic records (12-20 s at
0.01 s) x ``--intensities`` Sa(T1) from 0.05 g to 3 g, every run made by ``ida`` with
``Semianalytic()``; the model built once (``--form prepared``: the factory returns the one
System with the scaled record as its loads, prepared once per process) or per run
(``--form fresh``).

Configurations, interleaved (the order turned each repeat), each timed on the whole ``ida``
call: ``workers=1``; ``workers=2``; ``client=`` a LocalCluster (2 processes, 1 thread each,
started once and warmed by a small IDA). Every configuration's measures, collapse times and
failures are checked identical (bit for bit) to the one-process run. The 1-min load average is
recorded before and after every measurement; best and median per configuration.

Usage::

    python benchmarks/ensemble_ida.py [--repeats 3] [--records 4] [--intensities 250]
    python benchmarks/ensemble_ida.py --quick   # 2 records x 20 intensities, once
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import functools  # noqa: E402
import importlib.util  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from datetime import UTC, datetime  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = ("1 process", "2 threads", "Dask, 2 processes")
sys.path.insert(0, str(ROOT / "tests" / "_support"))
# the Dask workers import the frame's module by name, and duhamel from this tree
os.environ["PYTHONPATH"] = os.pathsep.join(
    [str(ROOT / "tests" / "_support"), *filter(None, [os.environ.get("PYTHONPATH")])]
)


def _frame_module():
    path = ROOT / "tests" / "_support" / "_collapse_frame.py"
    spec = importlib.util.spec_from_file_location("_collapse_frame", path)
    assert spec is not None and spec.loader is not None
    cf = importlib.util.module_from_spec(spec)
    sys.modules["_collapse_frame"] = cf  # picklable by reference on the workers
    spec.loader.exec_module(cf)
    return cf


cf = _frame_module()
MODEL = cf.frame()  # the frame without loads: one model under every scaled record


def prepared(motion):
    """The one frame under `motion` (prepared once per process by solve_many)."""
    return MODEL, {"loads": [motion.as_load(np.ones(3))]}


def study(form: str, motions, grid, **where):
    import duhamel
    from duhamel.ensemble import ida

    factory = prepared if form == "prepared" else functools.partial(cf.frame)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", duhamel.errors.AccuracyWarning)
        return ida(factory, motions, grid, cf.ex.peak_drift_ratio, duhamel.Semianalytic(),
                   period=cf.T1, damping=0.05, collapse=cf.ex.collapse_event(),
                   solver_error="collapse", **where)  # fmt: skip


def gil_free_share(motion, grid, n: int = 40) -> float:
    """The share `f` of one process's run time spent in the core's loop (the GIL released):
    2 threads run at most ``min(2, 1 / (1 - f))`` times as many runs per second (the GIL-held
    rest of the runs, one at a time; the estimate's passes, also without the GIL, are not
    counted in `f`)."""
    import duhamel

    unit = cf.sa1(motion)
    loop, started = 0.0, time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", duhamel.errors.AccuracyWarning)
        for im in grid[:n]:
            model, opts = prepared(motion.scaled(im / unit))
            sol = duhamel.solve(model, duhamel.Semianalytic(), t_end=motion.duration,
                                dt=motion.dt, threads=1, events=[cf.ex.collapse_event()],
                                **opts)  # fmt: skip
            cf.ex.peak_drift_ratio(sol)
            loop += sol.stats.loop_time
    return loop / (time.perf_counter() - started)


def _cpu(client) -> float:
    """CPU seconds of this process and of the cluster's workers so far."""
    return time.process_time() + sum(client.run(time.process_time).values())


def _busy(tasks: list[dict], wall: float) -> tuple[float, float, int]:
    """From Dask's task stream: the share of the study's wall time its workers spent in
    tasks, the time between the first and the last worker's last task, and the tasks."""
    spans: dict[str, list[tuple[float, float]]] = {}
    for task in tasks:
        for s in task["startstops"]:
            if s["action"] == "compute":
                spans.setdefault(task["worker"], []).append((s["start"], s["stop"]))
    total = sum(stop - start for spans_ in spans.values() for start, stop in spans_)
    ends = [max(stop for _, stop in spans_) for spans_ in spans.values()]
    return total / (len(spans) * wall), max(ends) - min(ends), len(tasks)


def same(a, b) -> bool:
    """Bit for bit the same IDA (measures, collapse times, failures)."""
    return (
        np.array_equal(a.measures, b.measures)
        and np.array_equal(a.collapse_times, b.collapse_times, equal_nan=True)
        and np.array_equal(a.failed, b.failed)
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--records", type=int, default=4)
    parser.add_argument("--intensities", type=int, default=250)
    parser.add_argument("--form", choices=("prepared", "fresh"), default="prepared")
    parser.add_argument("--quick", action="store_true", help="2 records x 20 intensities")
    parser.add_argument("--append", help="append the section to this markdown file")
    args = parser.parse_args(argv)
    import distributed

    from duhamel.records import G

    n_rec, n_im = (2, 20) if args.quick else (args.records, args.intensities)
    repeats = 1 if args.quick else args.repeats
    motions = cf.records(n_rec)
    grid = G * np.linspace(0.05, 3.0, n_im)
    times: dict[str, list[float]] = {c: [] for c in CONFIGS}
    cpu: dict[str, list[float]] = {c: [] for c in CONFIGS}
    busy: list[tuple[float, float, int]] = []
    loads: list[float] = []
    results = {}
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        import duhamel

        # the records' step is coarse for the accuracy check: not its warning on each run
        client.run(warnings.simplefilter, "ignore", duhamel.errors.AccuracyWarning)
        where = {"1 process": {"workers": 1}, "2 threads": {"workers": 2},
                 "Dask, 2 processes": {"client": client}}  # fmt: skip
        for w in where.values():  # warm-up: imports, the workers' first models
            study(args.form, motions[:1], grid[:4], **w)
        for r in range(repeats):
            for name in CONFIGS if r % 2 == 0 else CONFIGS[::-1]:
                before = os.getloadavg()[0]
                c0, t0 = _cpu(client), time.perf_counter()
                with distributed.get_task_stream(client) as stream:
                    res = study(args.form, motions, grid, **where[name])
                times[name].append(time.perf_counter() - t0)
                if name.startswith("Dask"):
                    busy.append(_busy(stream.data, times[name][-1]))
                cpu[name].append(_cpu(client) - c0)
                after = os.getloadavg()[0]
                loads += [before, after]
                results.setdefault(name, res)
                assert same(res, results["1 process"] if "1 process" in results else res), name
                print(f"{name}: {times[name][-1]:.2f} s (CPU {cpu[name][-1]:.2f} s), load "
                      f"{before:.2f} -> {after:.2f}", file=sys.stderr)  # fmt: skip
        share = gil_free_share(motions[0], grid)
    for name in CONFIGS:
        assert same(results[name], results["1 process"]), name
    ref = results["1 process"]
    rev = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                         capture_output=True, text=True).stdout.strip()  # fmt: skip
    when = datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC")
    runs = n_rec * n_im
    hit = int((~np.isfinite(ref.measures)).sum())
    cmd = "python benchmarks/ensemble_ida.py" + (" --quick" if args.quick else
                                                f" --repeats {repeats}")  # fmt: skip
    lines = [
        f"`{cmd}` · {when} · `{rev}` · load {min(loads):.2f} to {max(loads):.2f}"
        + (" · **under load**" if max(loads) > 2 else "")
        + f". {n_rec} records x {n_im} Sa(T1) = {grid[0] / G:.2f}-{grid[-1] / G:.2f} g on the "
        f"3-storey hinged frame, {runs} runs ({hit} collapse), model {args.form}; "
        f"{repeats} interleaved repeat(s), every configuration bit for bit the same.",
        "",
        "| where | best [s] | median [s] | x 1 process (best, median) | runs/s (best) | CPU "
        "[s] (median) |",
        "|---|---:|---:|---|---:|---:|",
    ]
    b1, m1 = min(times["1 process"]), float(np.median(times["1 process"]))
    for name in CONFIGS:
        best, med = min(times[name]), float(np.median(times[name]))
        lines.append(f"| {name} | {best:.2f} | {med:.2f} | {b1 / best:.2f}x, {m1 / med:.2f}x "
                     f"| {runs / best:.0f} | {float(np.median(cpu[name])):.2f} |")  # fmt: skip
    lines.append("")
    lines.append(f"Core loop (GIL released) {100 * share:.0f} % of a run in one process: "
                 f"2 threads at most {min(2.0, 1 / (1 - share)):.2f}x. CPU: this process and the "
                 "Dask workers (process time).")  # fmt: skip
    share, gap, n_tasks = (float(np.median(x)) for x in zip(*busy, strict=True))
    lines.append(
        f"Dask (median): the workers in tasks {100 * share:.0f} % of the study's wall "
        f"time, the last finishing {gap:.2f} s after the first; {n_tasks:.0f} tasks."
    )
    lines.append("Load before -> after each: " + ", ".join(
        f"{a:.2f}->{b:.2f}" for a, b in zip(loads[::2], loads[1::2], strict=True)))  # fmt: skip
    text = "\n".join(lines) + "\n"
    print(text)
    if args.append:
        with open(args.append, "a", encoding="utf-8") as f:
            f.write("\n" + text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
