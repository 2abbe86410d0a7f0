"""A rotordynamics engineer's next analyses on one compressor-like rotor: frequency response
(Bode, Nyquist, speed-frequency map), API 684 Level I stability and the undamped critical
speed map.

A 1.5 m steel shaft (12 Timoshenko elements, 60 mm) with three impellers, on two
fluid-film bearings whose coefficients are tabulated against speed (stiffening and
cross-coupled with speed, as a tilting-pad or plain journal bearing's).

    python examples/rotor_analyses.py                        # prints the numbers
    python examples/rotor_analyses.py --save docs/figures     # writes the four figures
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, Stage, anticipated_cross_coupling

SPEEDS = [0.0, 500.0, 1000.0, 1500.0]  # rad/s, the bearing table
MCS = 1100.0  # rad/s, maximum continuous speed


def rotor() -> Rotor:
    bearings = [
        Bearing(n, kxx=[5e6, 7e6, 9e6, 1.1e7], kyy=[4e6, 6e6, 8e6, 1e7],
                kxy=[0.0, 2e5, 4e5, 6e5], kyx=[0.0, -2e5, -4e5, -6e5],
                cxx=[6e4, 7e4, 8e4, 9e4], cyy=[6e4, 7e4, 8e4, 9e4], speeds=SPEEDS)
        for n in (1, 11)
    ]  # fmt: skip
    disks = [Disk.from_geometry(n, width=0.06, outer_diameter=0.4, inner_diameter=0.06,
                                material=STEEL) for n in (4, 6, 8)]  # fmt: skip
    return Rotor([Shaft(0.125, 0.06, material=STEEL)] * 12, disks, bearings, zeta=0.005)


def run() -> dict:
    model = rotor()
    freqs = np.linspace(20.0, 2500.0, 1000)
    frf = model.frequency_response(MCS, freqs, inputs=[(6, "x")], outputs=[(6, "x"), (6, "y")])
    coarse = np.linspace(20.0, 2500.0, 250)
    fmap = model.frequency_response_map(np.linspace(0.0, 1500.0, 31), coarse, (6, "x"), (6, "x"))
    stages = [Stage(power=0.3e6, diameter=0.4, width=0.02, density_ratio=1.3)] * 3
    q_a = anticipated_cross_coupling(stages, MCS)
    level1 = model.level1_stability(MCS, location=6, q_range=np.linspace(0.0, 4e6, 21), q_a=q_a)
    ucs = model.critical_speed_map(np.logspace(5.5, 9, 60), n_modes=3)
    return {"model": model, "frf": frf, "map": fmap, "level1": level1, "ucs": ucs}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--save", help="directory for the figures")
    args = parser.parse_args()
    out = run()
    frf, level1, ucs = out["frf"], out["level1"], out["ucs"]
    k = int(np.argmax(frf.magnitude(0, 0)))
    print(f"peak receptance x6/x6 at {MCS:g} rad/s: {frf.magnitude(0, 0)[k]:.3g} m/N at "
          f"{frf.frequencies[k]:.1f} rad/s")  # fmt: skip
    print(
        f"Level I at {MCS:g} rad/s: log dec {level1.log_dec[0]:.3f} at q = 0, "
        f"Q_0 = {level1.threshold:.4g} N/m, Q_A = {level1.q_a:.4g} N/m, "
        f"Q_0/Q_A = {level1.ratio:.2f}, Level II required: {level1.requires_level2}"
    )
    for p in ucs.intersections:
        print(f"bearing {p.node} {p.direction} meets critical speed {p.mode} at "
              f"{p.speed:.1f} rad/s ({p.stiffness:.3g} N/m)")  # fmt: skip
    if args.save:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        target = Path(args.save)
        fig = plt.figure(figsize=(11, 4.8))
        grid = fig.add_gridspec(2, 2)
        mag = fig.add_subplot(grid[0, 0])
        frf.plot_bode(0, 0, axes=(mag, fig.add_subplot(grid[1, 0], sharex=mag)))
        frf.plot_nyquist(1, 0, ax=fig.add_subplot(grid[:, 1]))
        fig.tight_layout()
        fig.savefig(target / "rotor_frf.png", dpi=90)
        for name, draw in (("rotor_frf_map", out["map"].plot_map), ("rotor_level1", level1.plot),
                           ("rotor_ucs_map", ucs.plot)):  # fmt: skip
            fig, ax = plt.subplots(figsize=(6.5, 4.5))
            draw(ax=ax)
            fig.tight_layout()
            fig.savefig(target / f"{name}.png", dpi=90)


if __name__ == "__main__":
    main()
