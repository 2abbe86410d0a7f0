"""A 10-storey building on friction pendulum isolators under a bidirectional record.

The building is a shear frame in each horizontal direction (10 floors of 4e5 kg, storey
stiffness 6e8 N/m: fixed-base first period about 1.0 s), on a base mat (6e5 kg) that rests
on a single-friction-pendulum system (radius 2.5 m: isolated period 2 pi sqrt(R / g) =
3.2 s; friction 5 %) carrying the whole weight. The ground motion is a synthetic,
seeded, bidirectional record (filtered noise with a build-up and decay envelope, PGA
0.4 g and 0.3 g). The fixed-base building (the mat fixed to the ground) is run for
comparison.

Outputs (docs/structural.md): roof displacement relative to the ground, inter-storey drift
ratios, absolute roof accelerations, and the isolator's hysteresis loop, in
``docs/figures/isolated_building.png``.

The plane variant (``--plane``): one frame line along x (the mat, dof 0, and the 10
floors) on uniaxial ``FrictionPendulum(0, dof_y=None, ...)`` with velocity-dependent friction
(``mu`` 6 % sliding fast, 3 % at rest, rate 20 s/m) under the record's x component, run for
the nominal isolator and for its lower- and upper-bound properties
(``duhamel.ensemble.solve_bounds`` with lambda factors 0.8 and 1.3 on the friction). Per
model: the isolator displacement, the base shear (``sol.base_shear()``), the peak drift
ratio, the energy balance (``sol.energy``) and the roof's floor spectrum
(``sol.floor_spectra``); figure ``docs/figures/isolated_plane.png`` (the nominal run's
energy, the three floor spectra, the isolator loops). The pendulums' axial force is constant
(their weight): duhamel does not couple the friction pendulum with a vertical dof yet.

Usage::

    python examples/isolated_building.py            # prints the peaks, writes the figure
    python examples/isolated_building.py --no-plot
    python examples/isolated_building.py --plane    # the 2-D variant
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import duhamel
from duhamel import elements as E
from duhamel import loads as L
from duhamel.ensemble import solve_bounds

G = duhamel.STANDARD_GRAVITY
FLOORS, M_FLOOR, K_STOREY, M_MAT, H_STOREY = 10, 4e5, 6e8, 6e5, 3.5
RADIUS, MU = 2.5, 0.05


def record(seed: int, pga: float, dt: float = 0.01, duration: float = 30.0):
    """A synthetic accelerogram: band-limited noise (0.3-8 Hz) with a Saragoni-Hart-like
    envelope, scaled to `pga` (m/s^2)."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration, dt)
    noise = rng.standard_normal(t.size)
    spectrum = np.fft.rfft(noise)
    f = np.fft.rfftfreq(t.size, dt)
    spectrum[(f < 0.3) | (f > 8.0)] = 0.0
    a = np.fft.irfft(spectrum, t.size)
    envelope = (t / 4.0) ** 2 * np.exp(2.0 * (1.0 - t / 4.0))
    a *= np.minimum(envelope, 1.0) * np.exp(-np.maximum(t - 15.0, 0.0) / 6.0)
    return t, pga * a / np.abs(a).max()


def shear_frame(levels: int, masses: np.ndarray, fixed: bool) -> tuple[np.ndarray, np.ndarray]:
    """Mass and stiffness of a shear frame in one direction: level 0 is the mat (on the
    ground when `fixed`, free otherwise), levels 1.. the floors."""
    k = np.zeros((levels, levels))
    for s in range(1, levels):
        k[s - 1 : s + 1, s - 1 : s + 1] += K_STOREY * np.array([[1.0, -1.0], [-1.0, 1.0]])
    if fixed:
        k[0, 0] += 1e3 * K_STOREY  # the mat tied to the ground
    return np.diag(masses), k


def building(isolated: bool, motions) -> duhamel.System:
    """Both horizontal directions: dofs 0..10 along x (0 the mat), 11..21 along y."""
    n = FLOORS + 1
    masses = np.array([M_MAT] + [M_FLOOR] * FLOORS)
    m1, k1 = shear_frame(n, masses, fixed=not isolated)
    m = np.zeros((2 * n, 2 * n))
    k = np.zeros((2 * n, 2 * n))
    for d in range(2):
        m[d * n : (d + 1) * n, d * n : (d + 1) * n] = m1
        k[d * n : (d + 1) * n, d * n : (d + 1) * n] = k1
    system = duhamel.System(m, k, zeta=0.05)
    if isolated:
        weight = masses.sum() * G
        system.add(E.FrictionPendulum((0, n), radius=RADIUS, mu=MU, weight=weight))
    for d, (t, a) in enumerate(motions):
        r = np.zeros(2 * n)
        r[d * n : (d + 1) * n] = 1.0
        system.add_load(L.BaseAcceleration(r, t=t, values=a))
    return system


# The plane (2-D) variant: one frame line along x on uniaxial pendulums.
MU_FAST, MU_SLOW, RATE = 0.06, 0.03, 20.0
LAMBDAS = {"mu": (0.8, 1.3), "mu_slow": (0.8, 1.3)}
PERIODS = np.linspace(0.05, 4.0, 80)


def plane() -> duhamel.System:
    """The frame line along x on uniaxial pendulums, under the record's x component."""
    n = FLOORS + 1
    masses = np.array([M_MAT] + [M_FLOOR] * FLOORS)
    m, k = shear_frame(n, masses, fixed=False)
    system = duhamel.System(m, k, zeta=0.05)
    weight = masses.sum() * G
    system.add(
        E.FrictionPendulum(
            0,
            radius=RADIUS,
            mu=MU_FAST,
            mu_slow=MU_SLOW,
            rate=RATE,
            weight=weight,
        )
    )
    t, a = record(1, 0.4 * G, duration=32.0)  # outlasts the 30-s run
    system.add_load(L.BaseAcceleration(np.ones(n), t=t, values=a))
    return system


def summary(sol: duhamel.Solution) -> dict:
    weight = (M_MAT + FLOORS * M_FLOOR) * G
    drift = sol.drifts(list(range(FLOORS + 1)), heights=[1.0] + [H_STOREY] * FLOORS)[:, 1:]
    energy = sol.energy
    return {
        "isolator": float(np.abs(sol.x[:, 0]).max()),
        "base_shear": float(np.abs(sol.base_shear()).max() / weight),
        "drift": float(np.abs(drift).max()),
        "dissipated": float(energy.hysteretic[-1] / energy.input[-1]),
        "damping": float(energy.damping[-1] / energy.input[-1]),
        "balance": float(abs(energy.error[-1]) / energy.input[-1]),
        "roof_sa": sol.floor_spectra([FLOORS], PERIODS).sa[0, 0],
        "solution": sol,
    }


def main_plane(no_plot: bool, path: str) -> dict:
    """The plane variant: nominal, lower- and upper-bound runs, printed and plotted."""
    system = plane()
    run = {"t_end": 30.0, "dt": 0.005}
    out = {"nominal": summary(duhamel.solve(system, duhamel.Semianalytic(), **run))}
    bounds = solve_bounds(system, duhamel.Semianalytic(), LAMBDAS, **run)
    for name, sol in zip(bounds.params, bounds.results, strict=True):
        out[name] = summary(sol)
    for name in ("lower", "nominal", "upper"):
        r = out[name]
        print(
            f"{name:8s} isolator {r['isolator']:.3f} m, base shear {r['base_shear']:.3f} W, "
            f"drift ratio {100 * r['drift']:.2f} %, isolator dissipates "
            f"{100 * r['dissipated']:.0f} % of the input, damping {100 * r['damping']:.0f} %, "
            f"balance error {r['balance']:.1e}"
        )
    if not no_plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 3, figsize=(14, 4))
        out["nominal"]["solution"].plot_energy(ax=axes[0])
        axes[0].set_title("energy (nominal)")
        for name, style in (("lower", "C0"), ("nominal", "k"), ("upper", "C3")):
            axes[1].plot(PERIODS, out[name]["roof_sa"] / G, style, label=name)
            iso = out[name]["solution"].elements[0]
            axes[2].plot(iso.x[:, 0], iso.force[:, 0] / 1e6, style, lw=0.6, label=name)
        axes[1].set(xlabel="period [s]", ylabel="roof spectral acceleration [g] (5 %)")
        axes[2].set(xlabel="isolator displacement [m]", ylabel="isolator force [MN]")
        for ax in axes[1:]:
            ax.grid(alpha=0.3)
            ax.legend()
        fig.suptitle("plane frame on uniaxial friction pendulums: bounds, energy, floor spectra")
        fig.tight_layout()
        fig.savefig(path, dpi=90)
        print(f"figure: {path}")
    return out


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--no-plot", action="store_true")
    parser.add_argument("--plane", action="store_true", help="the 2-D variant")
    parser.add_argument("--out", default=None)
    args = parser.parse_args(argv)
    if args.plane:
        return main_plane(args.no_plot, args.out or "docs/figures/isolated_plane.png")
    args.out = args.out or "docs/figures/isolated_building.png"
    motions = [record(1, 0.4 * G), record(2, 0.3 * G)]
    n = FLOORS + 1
    floors = list(range(1, n))
    out = {}
    for name, isolated in (("fixed", False), ("isolated", True)):
        started = time.perf_counter()
        sol = duhamel.solve(
            building(isolated, motions), duhamel.Semianalytic(), t_end=30.0, dt=0.005
        )
        wall = time.perf_counter() - started
        drifts = sol.drifts([0, *floors], heights=[1.0] + [H_STOREY] * FLOORS)[:, 1:]
        masses = np.array([M_MAT] + [M_FLOOR] * FLOORS)
        # base shear along x: the floors' inertia forces (the isolator's force, isolated)
        shear = np.abs(sol.a_absolute[:, :n] @ masses).max() / (masses.sum() * G)
        out[name] = {
            "base_shear": shear,
            "solution": sol,
            "roof": np.abs(sol.x[:, n - 1]).max(),
            "mat": np.abs(sol.x[:, 0]).max(),
            "drift": np.abs(drifts).max(),
            "roof_acc": np.abs(sol.a_absolute[:, n - 1]).max() / G,
            "seconds": wall,
        }
        print(
            f"{name:9s} roof {out[name]['roof']:.3f} m, mat {out[name]['mat']:.3f} m, "
            f"max drift ratio {100 * out[name]['drift']:.2f} %, roof abs. acc. "
            f"{out[name]['roof_acc']:.2f} g, base shear {out[name]['base_shear']:.3f} W "
            f"({sol.stats.steps} steps in {wall:.2f} s, "
            f"{sol.stats.subdivided_steps} subdivided)"
        )
    if not args.no_plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(2, 2, figsize=(11, 7))
        for name, style in (("fixed", "C3"), ("isolated", "C0")):
            sol = out[name]["solution"]
            axes[0, 0].plot(sol.t, sol.x[:, n - 1], style, lw=0.8, label=name)
            axes[0, 1].plot(sol.t, sol.a_absolute[:, n - 1] / G, style, lw=0.6, label=name)
            d = sol.drifts([0, *floors], heights=[1.0] + [H_STOREY] * FLOORS)[:, 1:]
            axes[1, 0].plot(100 * np.abs(d).max(axis=0), floors, style + "o-", label=name)
        iso = out["isolated"]["solution"].elements[0]
        axes[1, 1].plot(iso.x[:, 0], iso.force[:, 0] / 1e6, "C0", lw=0.7)
        axes[0, 0].set(xlabel="t [s]", ylabel="roof displacement x [m]")
        axes[0, 1].set(xlabel="t [s]", ylabel="roof absolute acceleration x [g]")
        axes[1, 0].set(xlabel="peak drift ratio x [%]", ylabel="storey")
        axes[1, 1].set(xlabel="isolator displacement x [m]", ylabel="isolator force x [MN]")
        for ax in axes.flat:
            ax.grid(alpha=0.3)
        axes[0, 0].legend()
        fig.suptitle("10-storey building on friction pendulum isolators (duhamel)")
        fig.tight_layout()
        fig.savefig(args.out, dpi=90)
        print(f"figure: {args.out}")
    return out


if __name__ == "__main__":
    main()
