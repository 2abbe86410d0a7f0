"""A rotor with a misaligned flexible coupling in a slow run-up: the misalignment's
signature, a force at twice the running speed (2x) that excites the first critical speed at
half of it, seen in the order amplitudes and in a spectrogram.

A 1 m shaft (four Timoshenko elements, 50 mm) with a 30 kg disk at mid-span on two stiff
bearings, 2 % modal damping (first critical speed 265 rad/s), a small unbalance for the 1x
reference, and at shaft element 0 (next to the bearing) a flexible coupling with the
parallel and angular misalignment of ROSS's example (0.2 mm / 0.2 mm offsets, 5 degrees;
ROSS's ``MisalignmentFlex``), run up from 40 to 320 rad/s in 8 s.

    python examples/misaligned_rotor.py                       # prints the peaks
    python examples/misaligned_rotor.py --save docs/figures    # writes rotor_misalignment.png
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import duhamel
from duhamel.rotor import STEEL, Bearing, CouplingMisalignment, Disk, Rotor, Shaft, Unbalance
from duhamel.speed import LinearRunUp

LAW = LinearRunUp(omega0=40.0, omega1=320.0, t1=8.0)
DT = 2.5e-4
ROTOR = Rotor(
    [Shaft(0.25, 0.05, material=STEEL)] * 4,
    [Disk(2, 30.0, 0.6, 0.3)],
    [Bearing(0, 1e7, 1e7), Bearing(4, 1e7, 1e7)],
    zeta=0.02,
)
FAULT = CouplingMisalignment(0, "combined", mis_distance_x=2e-4, mis_distance_y=2e-4,
                             mis_angle=np.radians(5), radial_stiffness=4e5,
                             bending_stiffness=4e5)  # fmt: skip


def run() -> dict:
    system = ROTOR.system(LAW, [FAULT, Unbalance(2, m_e=5e-5)])
    res = duhamel.solve(system, duhamel.Semianalytic(), t_end=LAW.t1, dt=DT)
    t = np.asarray(res.t)
    x = np.asarray(res.x)[:, ROTOR.dof(2, "x")]  # the disk's horizontal displacement
    theta = LAW.theta(t)
    # order tracking: the h-th order's amplitude over windows of 4 revolutions
    turns = np.floor(theta / (8 * np.pi)).astype(int)
    speeds, orders = [], {h: [] for h in (1, 2, 3)}
    for k in range(turns.max()):
        sel = turns == k
        speeds.append(float(LAW.omega(t[sel]).mean()))
        for h in orders:
            orders[h].append(2 * abs(np.mean(x[sel] * np.exp(-1j * h * theta[sel]))))
    critical = float(ROTOR.natural_frequencies(0.0)[0])
    return {"t": t, "x": x, "speeds": np.array(speeds), "critical": critical,
            "orders": {h: np.array(v) for h, v in orders.items()}}  # fmt: skip


def peak_speed(out: dict, h: int, lo: float, hi: float) -> float:
    """The speed of the largest `h`-th order amplitude between `lo` and `hi` rad/s."""
    sel = (out["speeds"] > lo) & (out["speeds"] < hi)
    return float(out["speeds"][sel][np.argmax(out["orders"][h][sel])])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--save", type=Path, help="directory for rotor_misalignment.png")
    args = parser.parse_args()
    force = FAULT.harmonics(np.arange(4), ROTOR)[:, 0]
    amp = np.abs(force) * [1, 2, 2, 2]
    print("coupling force F_x: static {:.3f} N, 1x {:.3f} N, 2x {:.3f} N, 3x {:.3f} N".format(*amp))
    out = run()
    wc = out["critical"]
    p1 = peak_speed(out, 1, 0.8 * wc, 1.2 * wc)
    p2 = peak_speed(out, 2, 0.4 * wc, 0.6 * wc)
    p3 = peak_speed(out, 3, 0.25 * wc, 0.4 * wc)
    print(f"first critical {wc:.1f} rad/s; 1x peak at {p1:.1f} rad/s ({p1 / wc:.3f} wc), "
          f"2x peak at {p2:.1f} rad/s ({p2 / wc:.3f} wc), "
          f"3x peak at {p3:.1f} rad/s ({p3 / wc:.3f} wc)")  # fmt: skip
    if args.save:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from duhamel.rotor import plot_spectrogram

        fig, (a, b, c) = plt.subplots(1, 3, figsize=(15, 4.5),
                                      gridspec_kw={"width_ratios": [0.7, 1.2, 1.2]})  # fmt: skip
        a.bar(range(4), amp, color=["0.6", "C0", "C1", "C2"])
        a.set_xticks(range(4), ["static", "1x", "2x", "3x"])
        a.set_ylabel("coupling force F_x (N)")
        a.set_title("misalignment force (closed form)")
        for h, color in ((1, "C0"), (2, "C1"), (3, "C2")):
            b.semilogy(out["speeds"], out["orders"][h] * 1e6, color=color, label=f"{h}x")
        for frac in (1 / 3, 1 / 2, 1.0):
            b.axvline(frac * wc, color="0.6", lw=0.8)
        b.set_xlabel("speed (rad/s)")
        b.set_ylabel("order amplitude of the disk's x (um)")
        b.set_title("run-up: 2x peak at half the critical speed")
        b.legend(fontsize=8)
        plot_spectrogram(out["t"], out["x"], LAW, orders=(1.0, 2.0, 3.0), window=0.5, ax=c)
        c.set_title("spectrogram of the disk's x")
        fig.tight_layout()
        args.save.mkdir(parents=True, exist_ok=True)
        fig.savefig(args.save / "rotor_misalignment.png", dpi=110)
        print(f"wrote {args.save / 'rotor_misalignment.png'}")


if __name__ == "__main__":
    main()
