"""Response spectra: duhamel against dvars, pyrotd and eqsig, in one run (issue 13).

One record of 8,000 samples (dt = 0.005 s, filtered noise with a build-up and decay, PGA
about 0.3 g), 100 periods from 0.01 s to 20 s (the frequencies dvars itself chooses between
0.05 and 100 Hz, used by every contender), 5 % damping, one core. Timed per call as a user
makes it (dvars converts the record to float32 through ctypes inside its call), contenders
interleaved, best and median of the repeats. Accuracy: the largest error over the periods,
relative to each period's value, against ``scipy.signal.lsim`` (first-order hold: exact for
the piecewise-linear record) of the quantity each returns (dvars: absolute acceleration;
pyrotd, eqsig: pseudo-acceleration). Then a batch of 1,000 records (8,000 samples, 100
periods) on one core and on all cores: throughput in records per second.

Usage::

    python benchmarks/spectra.py                          # print the tables
    python benchmarks/spectra.py --append BENCHMARKS.md   # as a section of BENCHMARKS.md
    python benchmarks/spectra.py --quick                  # smoke test

dvars, pyrotd and eqsig are benchmark-only dependencies (``pip install dvars pyrotd eqsig``);
a contender that is not installed is reported as such.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

from collections.abc import Callable  # noqa: E402

import _section  # noqa: E402
import numpy as np  # noqa: E402
import scipy.signal  # noqa: E402

from duhamel.records import G, GroundMotion  # noqa: E402
from duhamel.spectra import response_spectrum  # noqa: E402

DT, N, ZETA = 0.005, 8000, 0.05


def record(n: int = N, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = DT * np.arange(n)
    b, a = scipy.signal.butter(4, [0.2, 12.0], btype="band", fs=1 / DT)
    env = np.minimum(t / 2.0, 1.0) * np.exp(-np.maximum(t - 10.0, 0.0) / 6.0)
    x = env * scipy.signal.lfilter(b, a, rng.normal(size=n))
    return 0.3 * G * x / np.abs(x).max()


def lsim_reference(acc: np.ndarray, periods: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(absolute acceleration, pseudo-acceleration) peaks from lsim, per period."""
    sa, psa = [], []
    t = DT * np.arange(acc.size)
    for p in periods:
        w = 2 * np.pi / p
        A = np.array([[0.0, 1.0], [-w * w, -2 * ZETA * w]])
        sys = scipy.signal.StateSpace(A, [[0.0], [-1.0]], np.eye(2), np.zeros((2, 1)))
        y = scipy.signal.lsim(sys, acc, t, interp=True)[1]
        sa.append(np.abs(w * w * y[:, 0] + 2 * ZETA * w * y[:, 1]).max())
        psa.append(w * w * np.abs(y[:, 0]).max())
    return np.array(sa), np.array(psa)


def contenders(acc: np.ndarray, freqs: np.ndarray) -> dict[str, tuple[Callable, str]]:
    """name -> (call returning the spectrum on `freqs`, which reference it matches)."""
    periods = 1.0 / freqs
    gm = GroundMotion(acc, DT)
    out: dict[str, tuple[Callable, str]] = {
        "duhamel": (lambda: response_spectrum(gm, periods, ZETA, threads=1).sa[0, 0], "sa"),
    }
    try:
        from dvars import dars

        def run_dvars() -> np.ndarray:
            _, _, saa = dars(
                acc, 1 / DT, damp=ZETA, nfreq=freqs.size, freq1=freqs[0], freq2=freqs[-1]
            )
            return np.asarray(saa)

        out["dvars (C, float32)"] = (run_dvars, "sa")
    except ImportError:
        pass
    try:
        import pyrotd

        pyrotd.processes = 1
        out["pyrotd (frequency domain)"] = (
            lambda: np.asarray(pyrotd.calc_spec_accels(DT, acc, freqs, ZETA).spec_accel),
            "psa",
        )
    except ImportError:
        pass
    try:
        import eqsig.sdof

        out["eqsig (numpy Nigam-Jennings)"] = (
            lambda: eqsig.sdof.pseudo_response_spectra(acc, DT, periods, ZETA)[2],
            "psa",
        )
    except ImportError:
        pass
    return out


def measure(quick: bool) -> dict:
    load0 = os.getloadavg()[0]
    acc = record()
    try:  # the frequencies dvars picks (log-spaced), so that it needs no interpolation
        from dvars import dars

        freqs = np.asarray(dars(acc, 1 / DT, damp=ZETA, nfreq=100, freq1=0.05, freq2=100.0)[0])
    except ImportError:
        freqs = np.geomspace(0.05, 100.0, 100)
    periods = 1.0 / freqs
    ref = dict(zip(("sa", "psa"), lsim_reference(acc, periods), strict=True))
    cs = contenders(acc, freqs)
    errors = {}
    long = periods >= 0.05
    for name, (f, kind) in cs.items():
        rel = np.abs(f() - ref[kind]) / ref[kind]
        worst = int(np.argmax(rel))
        errors[name] = (float(rel[worst]), float(periods[worst]), float(rel[long].max()))
    repeats = 3 if quick else 15
    times: dict[str, list[float]] = {name: [] for name in cs}
    for _ in range(repeats):  # interleaved
        for name, (f, _) in cs.items():
            times[name].append(_section.timed(f))
    n_batch = 20 if quick else 1000
    batch = [GroundMotion(record(seed=s), DT) for s in range(n_batch)]
    batch_times = {}
    for threads in (1, None):
        best = min(
            _section.timed(lambda t=threads: response_spectrum(batch, periods, ZETA, threads=t))
            for _ in range(1 if quick else 2)
        )
        batch_times["1 core" if threads == 1 else f"all cores ({os.cpu_count()})"] = best
    return {
        "errors": errors,
        "times": times,
        "batch": batch_times,
        "n_batch": n_batch,
        "periods": (periods.min(), periods.max()),
        "load": (load0, os.getloadavg()[0]),
    }


def markdown(r: dict) -> list[str]:
    best = {k: min(v) for k, v in r["times"].items()}
    base = best["duhamel"]
    out = [
        "## Response spectra (issue 13)",
        "",
        "Generated by `benchmarks/spectra.py --append BENCHMARKS.md`. One record of 8,000 "
        f"samples (dt = 0.005 s), 100 periods {r['periods'][0]:.3g}..{r['periods'][1]:.3g} s "
        "(dvars' log-spaced frequencies, used by all), 5 % damping, one core, contenders "
        f"interleaved, {len(r['times']['duhamel'])} repeats. Error: largest relative error over "
        "the periods against `scipy.signal.lsim` (first-order hold, exact for the record) of "
        "the quantity returned (dvars: Sa; pyrotd, eqsig: PSA). 1-min load average before "
        f"{r['load'][0]:.2f}, after {r['load'][1]:.2f}.",
        "",
        "| contender | best [ms] | median [ms] | x duhamel (best) | max rel. error (at T) | "
        "max rel. error, T >= 0.05 s |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for name, ts in r["times"].items():
        out.append(
            f"| {name} | {1e3 * min(ts):.2f} | {1e3 * float(np.median(ts)):.2f} | "
            f"{min(ts) / base:.1f} | {r['errors'][name][0]:.1e} ({r['errors'][name][1]:.3g} s) | "
            f"{r['errors'][name][2]:.1e} |"
        )
    out += [
        "",
        f"Batch of {r['n_batch']} records (8,000 samples each, 100 periods, 5 %):",
        "",
        "| threads | time [s] | records/s |",
        "|---|---:|---:|",
    ]
    for k, v in r["batch"].items():
        out.append(f"| {k} | {v:.2f} | {r['n_batch'] / v:.0f} |")
    return out


def main(argv: list[str] | None = None) -> int:
    return _section.main(
        __doc__, lambda quick: markdown(measure(quick)), "few repeats, a small batch", argv
    )


if __name__ == "__main__":
    raise SystemExit(main())
