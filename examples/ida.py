"""Incremental dynamic analysis of a yielding 3-storey frame: 20 synthetic records x 15
intensities (Sa(T1) from 0.2 g to 3 g), peak inter-storey drift ratio, with the 16/50/84 %
fractiles.

Each storey is an elastic column pair (70 % of the storey stiffness) in parallel with a
yielding brace (``Bilinear``, 30 %, yield at 0.4 % drift, 2 % hardening); 5 % modal damping.
The records are synthetic (band-passed noise with random duration and corner frequencies),
so nothing is downloaded.

    python examples/ida.py                    # prints the fractiles, shows the figure
    python examples/ida.py --save ida.png     # writes the figure
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.signal

import duhamel
from duhamel.ensemble import ida
from duhamel.records import G, GroundMotion

H = 3.5  # storey height, m
MASS = 2e5  # kg per floor
K_STOREY = np.array([3.0e8, 2.5e8, 2.0e8])  # N/m
DT = 0.01


def records(n: int = 20, seed: int = 7) -> list[GroundMotion]:
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        seconds = rng.uniform(12.0, 20.0)
        t = np.arange(0.0, seconds, DT)
        lo, hi = rng.uniform(0.2, 0.6), rng.uniform(5.0, 12.0)
        b, a = scipy.signal.butter(2, [lo, hi], btype="band", fs=1 / DT)
        env = np.minimum(t / 1.5, 1.0) * np.exp(-np.maximum(t - 0.4 * seconds, 0.0) / 3.0)
        x = env * scipy.signal.lfilter(b, a, rng.normal(size=t.size))
        out.append(GroundMotion(0.3 * x / np.abs(x).max(), DT, units="g", name=f"syn{i:02d}"))
    return out


def frame(motion: GroundMotion) -> duhamel.System:
    """Three storeys: elastic part in K, a yielding brace per storey, the record as load."""
    k = 0.7 * K_STOREY
    K = np.diag(k + np.r_[k[1:], 0.0]) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
    s = duhamel.System(MASS * np.eye(3), K, zeta=0.05)
    for storey in range(3):
        kb = 0.3 * K_STOREY[storey]
        j = None if storey == 0 else storey - 1
        s.add(duhamel.elements.Bilinear(storey, j, k=kb, fy=kb * 0.004 * H, alpha=0.02))
    return s.add_load(motion.as_load(np.ones(3)))


def peak_drift_ratio(sol: duhamel.Solution) -> float:
    x = np.hstack([np.zeros((sol.x.shape[0], 1)), sol.x])
    return float(np.abs(np.diff(x, axis=1)).max() / H)


def first_period() -> float:
    k = K_STOREY  # the braces' initial stiffness included
    K = np.diag(k + np.r_[k[1:], 0.0]) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
    w2 = np.linalg.eigvalsh(K / MASS)
    return float(2 * np.pi / np.sqrt(w2[0]))


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--save", help="write the figure to this file")
    parser.add_argument("--records", type=int, default=20)
    args = parser.parse_args(argv)
    t1 = first_period()
    intensities = G * np.linspace(0.2, 3.0, 15)
    started = time.perf_counter()
    res = ida(frame, records(args.records), intensities, peak_drift_ratio, period=t1, damping=0.05)
    seconds = time.perf_counter() - started
    print(f"T1 = {t1:.3f} s; {res.measures.size} runs in {seconds:.1f} s")
    print("Sa(T1) [g]   16 %     50 %     84 %   (peak drift ratio, %)")
    for im, row in zip(intensities, res.fractiles().T, strict=True):
        print(f"{im / G:8.2f}  " + "  ".join(f"{100 * v:7.3f}" for v in row))
    import matplotlib

    if args.save:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ax = res.plot()
    ax.set_xlabel("peak inter-storey drift ratio")
    ax.set_ylabel(f"Sa(T1 = {t1:.2f} s) [m/s^2]")
    ax.set_title(f"IDA, {len(res.names)} records x {intensities.size} intensities")
    if args.save:
        ax.figure.savefig(args.save, dpi=100, bbox_inches="tight")
    else:
        plt.show()
    return {"ida": res, "t1": t1, "seconds": seconds}


if __name__ == "__main__":
    main()
