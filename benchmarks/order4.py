"""The fourth-order semi-analytic step against explicit Runge-Kutta codes (issue 41's
"Order 4" speed acceptance).

The Duffing oscillator ``x'' + x + 4 x^3 = 0``, ``x(0) = 1``, ``x'(0) = 0``, over 100 periods
of its linear background (``t_end = 200 pi``); error = ``max |x - x_exact|`` over 2,001
equally spaced instants against the exact ``cn`` solution (:func:`duhamel.exact.duffing`).

Contenders, each at the cheapest setting of a sweep whose error is at most the target
(1e-6, 1e-9):

* duhamel ``Semianalytic(scheme="hermite")`` (fourth order) and ``Semianalytic()``
  (second order), ``steps`` internal steps per output interval (``dt = t_end / (2000 steps)``,
  ``save_every = steps``), through ``duhamel.solve`` on a fresh ``System`` (the whole call);
* pydiffsol's Tsit5 (``tsit45``, diffsol's JIT-compiled right-hand side, nalgebra dense),
  ``rtol`` swept, ``atol = rtol / 100``, dense output at the instants (``solve_dense``);
* scipy ``solve_ivp`` DOP853, ``rtol`` swept, ``atol = rtol / 100``, ``t_eval`` the instants.

Each case is timed as the best of ``--repeats`` calls, the contenders interleaved in each
round; the 1-min load average is printed before and after. pydiffsol's JIT compilation is
done once, outside the timing (its ``Ode`` is made once and re-solved).

Run: ``python benchmarks/order4.py [--repeats 7]``
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

import duhamel  # noqa: E402
from duhamel.exact import duffing  # noqa: E402

T_END = 100 * 2 * np.pi
N_OUT = 2000
T_OUT = np.linspace(0.0, T_END, N_OUT + 1)
EXACT = duffing(T_OUT, 1.0, 4.0, 1.0)[0]
TARGETS = (1e-6, 1e-9)


def run_duhamel(scheme: str, steps: int) -> np.ndarray:
    system = duhamel.System(np.eye(1), np.array([[1.0]]))
    system.add(duhamel.elements.Cubic(0, k3=4.0))
    integrator = duhamel.Semianalytic(scheme=scheme, error_warning=None)
    dt = T_END / (N_OUT * steps)
    sol = duhamel.solve(system, integrator, t_end=T_END, dt=dt, x0=[1.0], save_every=steps)
    return sol.x[:, 0]


def _pydiffsol() -> Callable[[float], np.ndarray] | None:
    try:
        import pydiffsol as ds
    except ImportError:  # pragma: no cover - optional contender
        return None
    code = "u_i { x = 1.0, v = 0.0 }\nF_i { v, -x - 4.0 * x * x * x }\n"
    ode = ds.Ode(code, matrix_type=ds.nalgebra_dense, ode_solver=ds.tsit45)

    def run(rtol: float) -> np.ndarray:
        ode.rtol, ode.atol = rtol, rtol / 100
        return np.asarray(ode.solve_dense(np.array([]), T_OUT).ys)[0]

    return run


def run_dop853(rtol: float) -> np.ndarray:
    def f(t: float, y: np.ndarray) -> list[float]:
        return [y[1], -y[0] - 4.0 * y[0] ** 3]

    sol = solve_ivp(f, (0.0, T_END), [1.0, 0.0], "DOP853", T_OUT, rtol=rtol, atol=rtol / 100)
    return sol.y[0]


def error(x: np.ndarray) -> float:
    return float(np.max(np.abs(x - EXACT)))


def cheapest(run: Callable[[float], np.ndarray], settings: list, target: float):
    """The first of `settings` (cheapest first) whose error is at most `target`."""
    for s in settings:
        e = error(run(s))
        if e <= target:
            return s, e
    return None, None


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args(argv)
    print(f"1-min load average before: {os.getloadavg()[0]:.2f}")
    steps = [1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512]
    rtols = [10.0**-k for k in np.arange(3, 14.5, 0.5)]
    contenders: dict[str, tuple[Callable[[float], np.ndarray], list]] = {
        "duhamel Semianalytic(scheme='hermite')": (lambda s: run_duhamel("hermite", s), steps),
        "duhamel Semianalytic() (second order)": (lambda s: run_duhamel("b", s), steps),
        "scipy solve_ivp DOP853": (run_dop853, rtols),
    }
    tsit = _pydiffsol()
    if tsit is not None:
        contenders["pydiffsol Tsit5 (tsit45)"] = (tsit, rtols)
    for target in TARGETS:
        chosen = {}
        for name, (run, settings) in contenders.items():
            s, e = cheapest(run, settings, target)
            if s is not None:
                chosen[name] = (run, s, e)
        best = {name: float("inf") for name in chosen}
        for _ in range(args.repeats):  # interleaved rounds
            for name, (run, s, _e) in chosen.items():
                t0 = time.perf_counter()
                run(s)
                best[name] = min(best[name], time.perf_counter() - t0)
        ref = best.get("duhamel Semianalytic(scheme='hermite')")
        print(f"\nmax error <= {target:g} (100 periods, 2,001 instants):")
        print("| contender | setting | error | best time [ms] | x hermite |")
        print("|---|---|---:|---:|---:|")
        for name, (_run, s, e) in chosen.items():
            setting = f"{s} steps per interval" if name.startswith("duhamel") else f"rtol {s:.0e}"
            ratio = best[name] / ref if ref else float("nan")
            print(f"| {name} | {setting} | {e:.1e} | {1e3 * best[name]:.2f} | {ratio:.2f} |")
        for name in contenders:
            if name not in chosen:
                print(f"| {name} | none of the sweep reaches it | | | |")
    print(f"\n1-min load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
