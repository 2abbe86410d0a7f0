"""A fast run-up of ROSS's compressor (200 -> 1000 rad/s in 10 ms; two bearings and twelve
seals whose coefficients follow the speed) through ``from_ross``, against ROSS's own run-up
(``run_time_response`` with a speed array), and with the coefficients frozen at the initial
speed (the route a user had to take before).

Needs ROSS (``pip install ross-rotordynamics``).

    python examples/ross_runup.py                       # prints the differences
    python examples/ross_runup.py --save docs/figures    # writes ross_runup.png
"""

from __future__ import annotations

import argparse
import contextlib
import io
import warnings
from pathlib import Path

import numpy as np

import duhamel
from duhamel.rotor import from_ross

W0, W1, T1, NODE, M_E = 200.0, 1000.0, 0.01, 25, 1e-4
ALPHA = (W1 - W0) / T1


def force(rr, t):
    """The unbalance's force on ROSS's dofs, faded in over 2 ms."""
    theta, w = W0 * t + 0.5 * ALPHA * t**2, W0 + ALPHA * t
    F = np.zeros((t.size, rr.ndof))
    fade = np.minimum(t / 0.002, 1.0)
    F[:, rr.number_dof * NODE] = M_E * (w**2 * np.cos(theta) + ALPHA * np.sin(theta)) * fade
    F[:, rr.number_dof * NODE + 1] = M_E * (w**2 * np.sin(theta) - ALPHA * np.cos(theta)) * fade
    return F


def run(dt: float = 5e-5) -> dict:
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency, the file's ROSS version
        import ross

        rr = ross.compressor_example()
    t = np.arange(round(T1 / dt) + 1) * dt
    out = {"t": t}
    for name, speed in (("duhamel", duhamel.speed.LinearRunUp(W0, W1, T1)), ("frozen", W0)):
        model = from_ross(rr, speed)
        for load in model.dofs.loads(force(rr, t), t):
            model.system.add_load(load)
        if name == "duhamel":
            K = ALPHA * model.acceleration_stiffness()  # ROSS's alpha Ksdt, as ROSS has it
            model.system.add(duhamel.elements.LinearCoupling(K=K))
        sol = duhamel.solve(model.system, duhamel.Semianalytic(), t_end=t[-1], dt=dt)
        out[name] = sol.x[:, model.dofs(NODE, "x")]
    with contextlib.redirect_stdout(io.StringIO()):
        yout = rr.run_time_response(W0 + ALPHA * t, force(rr, t), t).yout
    out["ross"] = model.dofs.from_ross(yout)[:, model.dofs(NODE, "x")]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--save", help="directory for the figure")
    args = parser.parse_args()
    r = run()
    peak = np.abs(r["duhamel"]).max()
    for name in ("ross", "frozen"):
        print(
            f"{name} vs duhamel at node {NODE} x: {np.abs(r[name] - r['duhamel']).max() / peak:.2e}"
        )
    if args.save:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, (a, b) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
        ms = r["t"] * 1e3
        a.plot(ms, r["duhamel"] * 1e6, label="duhamel (coefficients follow the speed)")
        a.plot(ms, r["ross"] * 1e6, "--", label="ROSS run_time_response (speed array)")
        a.plot(ms, r["frozen"] * 1e6, ":", label="coefficients frozen at 200 rad/s")
        a.set_ylabel(f"x at node {NODE} (um)")
        a.set_title("ROSS compressor, 200 -> 1000 rad/s in 10 ms (dt = 50 us)")
        a.legend(fontsize=8)
        b.plot(ms, (r["ross"] - r["duhamel"]) / peak, label="ROSS - duhamel")
        b.set_xlabel("t (ms)")
        b.set_ylabel("difference / peak")
        b.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(Path(args.save) / "ross_runup.png", dpi=90)


if __name__ == "__main__":
    main()
