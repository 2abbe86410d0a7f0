"""Oil whirl: a run-up of a Jeffcott rotor on two short journal bearings through the linear
stability threshold.

A 10 kg disk at mid-span of a 0.6 m steel shaft (30 mm) carried by two short plain journal
bearings (D = 50 mm, L = 20 mm, radial clearance 50 um, 0.01 Pa s): Ocvirk's short-bearing
film with half-film cavitation, nonlinear (``duhamel.rotor.ShortJournalBearing``). The
linear stability threshold comes from the rotor's complex modes with the bearings linearised
at the static equilibrium of each speed (``rotor.modes(speed)``): the speed where the
damping ratio of the forward whirl mode crosses zero. The run-up (gravity, a small
unbalance, and a weak broadband force on the disk, as the flow and the machine excite every
real rotor) shows the subsynchronous whirl emerging near that speed at about half the
running speed, then growing into the limit cycle (oil whip) that the film's nonlinear
stiffening bounds.

    python examples/journal_whirl.py                       # prints, shows the spectrogram
    python examples/journal_whirl.py --save whirl.png      # writes the figure
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np
import scipy.optimize

import duhamel
from duhamel.rotor import (
    STEEL,
    Disk,
    Gravity,
    Rotor,
    Shaft,
    ShortJournalBearing,
    Unbalance,
    plot_spectrogram,
    spectrogram,
)

CLEARANCE = 5e-5


def jeffcott() -> Rotor:
    journal = lambda n: ShortJournalBearing(n, 0.05, 0.02, CLEARANCE, 0.01)  # noqa: E731
    shafts = [Shaft(0.3, 0.03, material=STEEL)] * 2
    return Rotor(shafts, [Disk(1, 10.0, 0.05, 0.025)], [journal(0), journal(2)], zeta=0.01)


def threshold(rotor: Rotor, lo: float = 300.0, hi: float = 1500.0) -> tuple[float, float]:
    """The speed where the least damped mode's damping ratio crosses zero, and that mode's
    frequency there (rad/s)."""
    least = lambda w: float(rotor.modes(w).damping_ratios.min())  # noqa: E731
    w = scipy.optimize.brentq(least, lo, hi, xtol=1e-8)
    modes = rotor.modes(w)
    return w, float(modes.frequencies[int(np.argmin(np.abs(modes.damping_ratios)))])


def onset(times: Any, speeds: Any, freqs: Any, amps: Any, w_th: float) -> dict[str, Any]:
    """The subsynchronous peak (0.3-0.7 x speed) along the run-up: the speed where it first
    exceeds ten times its level well below the threshold, and its frequency ratio there."""
    peak, ratio = np.zeros(speeds.size), np.zeros(speeds.size)
    for i, w in enumerate(speeds):
        band = (freqs > 0.3 * w) & (freqs < 0.7 * w)
        j = int(np.argmax(amps[band, i]))
        peak[i], ratio[i] = amps[band, i][j], freqs[band][j] / w
    base = float(np.median(peak[speeds < 0.9 * w_th]))
    k = int(np.argmax(peak > 10.0 * base))
    return {"speed": float(speeds[k]), "ratio": float(ratio[k]), "peak": peak, "base": base}


def run(w0: float, w1: float, seconds: float, dt: float, integrator: Any) -> dict[str, Any]:
    rotor = jeffcott()
    w_th, whirl = threshold(rotor)
    law = duhamel.speed.LinearRunUp(omega0=w0, omega1=w1, t1=seconds)
    system = rotor.system(law, [Unbalance(1, m_e=2e-6), Gravity()])
    rng = np.random.default_rng(1)
    tn = np.arange(0.0, seconds + 1e-3, 1e-3)
    for direction in ("x", "y"):  # weak broadband excitation, 2 N rms
        system.add_load(
            duhamel.loads.Tabulated(
                rotor.dof(1, direction), t=tn, values=2.0 * rng.normal(size=tn.size)
            )
        )
    x0 = rotor.static_equilibrium(w0)
    started = time.perf_counter()
    sol = duhamel.solve(system, integrator, t_end=seconds, dt=dt, x0=x0,
                        dofs=[rotor.dof(1, "x"), rotor.dof(0, "x"), rotor.dof(0, "y")])  # fmt: skip
    wall = time.perf_counter() - started
    times, speeds, freqs, amps = spectrogram(sol.t, sol.x[:, 0], law, window=0.2)
    found = onset(times, speeds, freqs, amps, w_th)
    return {
        "threshold": w_th,
        "whirl": whirl,
        "onset": found,
        "solution": sol,
        "law": law,
        "wall": wall,
        "eccentricity": float(np.hypot(*sol.x[:, 1:].T).max() / CLEARANCE),
    }


def main(argv: list[str] | None = None) -> dict[str, Any]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--save", help="write the figure to this file")
    parser.add_argument("--seconds", type=float, default=4.0, help="run-up duration (s)")
    parser.add_argument("--top", type=float, default=850.0, help="final speed (rad/s)")
    parser.add_argument("--integrator", choices=("semianalytic", "newmark"), default="semianalytic")
    args = parser.parse_args(argv)
    integ = duhamel.Semianalytic() if args.integrator == "semianalytic" else duhamel.Newmark()
    out = run(500.0, args.top, args.seconds, 1e-4, integ)
    o = out["onset"]
    print(
        f"linear stability threshold: {out['threshold']:.1f} rad/s, whirl at "
        f"{out['whirl']:.1f} rad/s ({out['whirl'] / out['threshold']:.3f} x speed)"
    )
    print(
        f"run-up: subsynchronous whirl from {o['speed']:.0f} rad/s "
        f"({o['speed'] / out['threshold']:.3f} x threshold) at {o['ratio']:.2f} x speed; "
        f"largest journal eccentricity ratio {out['eccentricity']:.2f}; {out['wall']:.1f} s"
    )
    if args.save or argv is None:
        import matplotlib.pyplot as plt

        ax = plot_spectrogram(out["solution"].t, out["solution"].x[:, 0], out["law"], window=0.2)
        ax.axvline(out["threshold"], color="r", lw=1)
        ax.annotate("linear threshold", (out["threshold"], 0.05 * ax.get_ylim()[1]), color="r",
                    rotation=90, ha="right", fontsize="small")  # fmt: skip
        ax.set_title("Jeffcott rotor on short journal bearings: run-up, disk x")
        plt.tight_layout()
        if args.save:
            plt.savefig(args.save, dpi=110)
        else:
            plt.show()
    return out


if __name__ == "__main__":
    main()
