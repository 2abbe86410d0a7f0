"""Records and spectra: a two-component record written in the PEER .AT2 format, read back,
its intensity measures, elastic spectra at several dampings, RotD50/RotD100 and
constant-ductility spectra, in one figure.

The record is synthetic (filtered noise with a build-up and a decay, 40 s at 200 Hz), so that
nothing is downloaded; with a real record, pass its .AT2 files instead.

    python examples/spectra.py                    # prints the numbers, shows the figure
    python examples/spectra.py --save fig.png     # writes the figure instead
"""

from __future__ import annotations

import argparse
import pathlib
import tempfile

import numpy as np
import scipy.signal

from duhamel.records import G, read_at2
from duhamel.spectra import ductility_spectrum, response_spectrum, rotd

DT, N = 0.005, 8000


def synthetic(seed: int, pga_g: float) -> np.ndarray:
    """Acceleration in g: band-passed noise, 2 s build-up, decay after 10 s."""
    rng = np.random.default_rng(seed)
    t = DT * np.arange(N)
    b, a = scipy.signal.butter(4, [0.3, 10.0], btype="band", fs=1 / DT)
    env = np.minimum(t / 2.0, 1.0) * np.exp(-np.maximum(t - 10.0, 0.0) / 5.0)
    x = env * scipy.signal.lfilter(b, a, rng.normal(size=N))
    return pga_g * x / np.abs(x).max()


def write_at2(path: pathlib.Path, acc_g: np.ndarray, component: str) -> None:
    """The NGA-West2 layout: four header lines, five E15.7 values per line."""
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        f"Synthetic event, 1/1/2026, Example station, {component}",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {acc_g.size:6d}, DT= {DT:.4f} SEC",
    ]
    for i in range(0, acc_g.size, 5):
        lines.append("".join(f"{v:15.7E}" for v in acc_g[i : i + 5]))
    path.write_text("\n".join(lines) + "\n")


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--save", help="write the figure to this file")
    args = parser.parse_args(argv)
    folder = pathlib.Path(tempfile.mkdtemp())
    for comp, seed, pga in (("000", 1, 0.35), ("090", 2, 0.28)):
        write_at2(folder / f"SYN{comp}.AT2", synthetic(seed, pga), comp)
    h1, h2 = read_at2(folder / "SYN000.AT2"), read_at2(folder / "SYN090.AT2")
    for gm in (h1, h2):
        print(
            f"{gm.name}: PGA {gm.pga / G:.3f} g, PGV {gm.pgv:.3f} m/s, PGD {gm.pgd:.3f} m, "
            f"Arias {gm.arias_intensity:.2f} m/s, D5-95 {gm.significant_duration():.1f} s"
        )
    periods = np.geomspace(0.02, 10.0, 120)
    el = response_spectrum([h1, h2], periods, damping=[0.02, 0.05, 0.10])
    rd = rotd(h1, h2, periods, percentiles=(50, 100))
    duct = ductility_spectrum(h1, periods, ductility=[1, 2, 4, 6], alpha=0.02)
    k1 = int(np.argmin(np.abs(periods - 1.0)))
    print(
        f"T = {periods[k1]:.2f} s, 5 %: PSA {el.psa[0, 1, k1] / G:.3f} g ({h1.name}), "
        f"RotD50 {rd.psa[0, 0, k1] / G:.3f} g, RotD100 {rd.psa[0, 1, k1] / G:.3f} g; "
        f"Cy for ductility 4: {duct.cy[0, 2, k1]:.3f}"
    )
    import matplotlib

    if args.save:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    axes[0, 0].plot(h1.t, h1.a / G, lw=0.6, label=h1.name)
    axes[0, 0].plot(h2.t, h2.a / G, lw=0.6, label=h2.name, alpha=0.8)
    axes[0, 0].set(xlabel="t [s]", ylabel="a [g]", title="record (read from .AT2)")
    axes[0, 0].legend(fontsize="small")
    el.plot("psa", ax=axes[0, 1])
    axes[0, 1].set_title("elastic spectra, 2/5/10 % damping")
    ax = axes[1, 0]
    for q, label in zip(rd.percentiles, ("RotD50", "RotD100"), strict=True):
        ax.loglog(periods, rd.psa[0, list(rd.percentiles).index(q)] / G, label=label)
    ax.loglog(periods, el.psa[0, 1] / G, "--", lw=0.8, label=f"{h1.name} 5 %")
    ax.loglog(periods, el.psa[1, 1] / G, "--", lw=0.8, label=f"{h2.name} 5 %")
    ax.set(xlabel="Period [s]", ylabel="PSA [g]", title="orientation-independent (5 %)")
    ax.legend(fontsize="small")
    ax.grid(True, which="both", alpha=0.3)
    ax = axes[1, 1]
    for m, mu in enumerate(duct.ductility):
        ax.loglog(periods, duct.cy[0, m], label=f"ductility {mu:g}")
    ax.set(xlabel="Period [s]", ylabel="Cy = Fy / (m g)", title="constant-ductility (bilinear)")
    ax.legend(fontsize="small")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    if args.save:
        fig.savefig(args.save, dpi=100)
    else:
        plt.show()
    return {"el": el, "rotd": rd, "ductility": duct, "motions": (h1, h2)}


if __name__ == "__main__":
    main()
