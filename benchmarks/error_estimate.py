"""The error estimate of semi-analytic runs (issue 41): its cost against the run itself, and
(``--table``) the table of docs/accuracy.md, estimate against true error.

Each case is solved repeatedly; the time of the run's estimate (``_core.Estimator.estimate``,
made by ``duhamel._engine.accuracy.estimator``, timed around the call) is compared with the
whole ``duhamel.solve`` call, both in process CPU time (``time.process_time``: less
sensitive to other processes than wall time), the minimum over the repeats. Run:
``python benchmarks/error_estimate.py [--table | --jumps]`` (record the load average with
the numbers; ``--jumps``: the force-jump family). The references of the table: the exact
``cn`` solution (Duffing), DOP853 at ``rtol = 1e-12`` restarted at every record sample
(cubic SDOF), the same run at ``dt / 64`` (the others).
"""

from __future__ import annotations

import os
import sys
import time
import warnings

import numpy as np

import duhamel
import duhamel._engine.accuracy as accuracy

_SPENT: list[float] = []
_ESTIMATOR = accuracy.estimator


class _Timed:
    """The core's estimator, its estimate timed."""

    def __init__(self, core):
        self.core = core

    def estimate(self, *args):
        t0 = time.process_time()
        got = self.core.estimate(*args)
        _SPENT.append(time.process_time() - t0)
        return got


def _timed(*args, **kwargs):
    return _Timed(_ESTIMATOR(*args, **kwargs))


def _duffing() -> duhamel.System:
    system = duhamel.System(np.eye(1), np.array([[1.0]]))
    system.add(duhamel.elements.Cubic(0, k3=4.0))
    return system


def _minmax() -> duhamel.System:
    """The materials' SDOF of issue 37 with a ``MinMax`` that fails under the record
    (tests/_support/_materials_system.py): the estimate's jump term at work."""
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "_support"))
    from _materials_system import sdof

    return sdof("MinMax")


def _frame(n: int = 60) -> duhamel.System:
    """A shear frame of `n` storeys (unit masses, storey stiffness 400, 3 % modal damping)
    with a yielding first storey and a cubic spring at mid-height under 20 s of sinusoidal
    base motion."""
    k = 400.0 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    k[-1, -1] = 400.0
    t = np.arange(0.0, 20.0 + 0.005, 0.01)
    system = duhamel.System(np.eye(n), k, zeta=0.03)
    system.add(duhamel.elements.Bilinear(0, k=300.0, fy=3.0, alpha=0.1))
    system.add(duhamel.elements.Cubic(n // 2, k3=2e3))
    system.add_load(duhamel.loads.BaseAcceleration(np.ones(n), t=t, values=np.sin(5.0 * t)))
    return system


def main(repeats: int = 7) -> None:
    accuracy.estimator = _timed
    warnings.simplefilter("ignore", duhamel.AccuracyWarning)
    cases = (
        ("Duffing, 100 periods, 200 steps a period", _duffing, dict(
            t_end=200 * np.pi, dt=2 * np.pi / 200, x0=[1.0])),
        ("60-dof frame, bilinear + cubic, 2,000 steps", _frame, dict(t_end=20.0, dt=0.01)),
        ("MinMax SDOF failing (a force jump), 4,800 steps", _minmax, dict(
            t_end=12.0, dt=0.0025)),
    )  # fmt: skip
    print(f"load average {os.getloadavg()}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    for name, make, kw in cases:
        runs, spent = [], []
        for _ in range(repeats):
            _SPENT.clear()
            t0 = time.process_time()
            duhamel.solve(make(), duhamel.Semianalytic(), **kw)
            runs.append(time.process_time() - t0)
            spent.append(_SPENT[0])
        run, est = min(runs), min(spent)
        print(f"{name}: solve {run * 1e3:.2f} ms, estimate {est * 1e3:.2f} ms "
              f"({100 * est / run:.1f} % of the call)")  # fmt: skip


def _row(name: str, error: float, sol: duhamel.Solution, element: float | None = None) -> None:
    st = sol.stats
    est, bound = st.error_estimate, st.error_bound
    line = f"| {name} | {error:.2e} | {est:.2e} | {est / error:.2f} | {bound / error:.1f} |"
    if element is None:
        line += " |"
    else:
        worst, top = max(st.element_error_estimate), max(st.element_error_bound)
        line += f" {element:.2e} / {worst:.2e} ({worst / element:.2f}; bound {top / element:.1f}) |"
    print(line + f" {st.subdivided_steps} |")


def table() -> None:
    """The rows of docs/accuracy.md's table."""
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "engine"))
    from test_accuracy_estimate import (  # the test family
        B3,
        _cubic_reference,
        _duffing,
        _record,
        _sdof,
        _stiff,
    )

    warnings.simplefilter("ignore", duhamel.AccuracyWarning)
    print("| case | true error | estimate | ratio | bound ratio | elements: true / estimate "
          "(ratio; bound ratio) | subdivided steps |\n|---|---|---|---|---|---|---|")  # fmt: skip
    for n in (50, 100, 200, 400):
        error, sol = _duffing(n)
        _row(f"Duffing, 10 periods, {n} steps a period", error, sol)
    t_rec, ag = _record()
    x_ref = _cubic_reference(t_rec, ag)

    def scaled(x: np.ndarray, ref: np.ndarray) -> float:
        return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))

    def make_cubic():
        return _sdof(t_rec, ag, duhamel.elements.Cubic(0, k3=B3))

    def make_bilinear():
        k0 = 3 * (2 * np.pi) ** 2
        return _sdof(t_rec, ag, duhamel.elements.Bilinear(0, k=k0, fy=0.015 * k0, alpha=0.05))

    for k in (1, 2, 4, 8):
        sol = duhamel.solve(make_cubic(), duhamel.Semianalytic(), t_end=t_rec[-1], dt=0.02 / k)
        _row(f"cubic SDOF, record, dt = 0.02/{k}", scaled(sol.x[::k, 0], x_ref), sol)
    cases = (
        ("bilinear SDOF, record", make_bilinear, 0.02, t_rec[-1], {}, {}),
        ("5-dof frame, bilinear + cubic, record", _frame5, 0.02, 8.0, {}, {}),
        ("stiff cubic (omega_c dt = 1 at dt = 0.01)", _stiff, 0.01, 2.0, {"x0": [1.0]}, {}),
        ("60-dof frame reduced to 10 modes + correction, record", lambda: _frame(60), 0.02,
         8.0, {}, {"modes": 10}),
    )  # fmt: skip
    for name, make, dt, t_end, kw, integ in cases:
        ref = duhamel.solve(make(), duhamel.Semianalytic(**integ), t_end=t_end, dt=dt / 64, **kw)
        for k in (1, 2, 4, 8, 16):
            sol = duhamel.solve(make(), duhamel.Semianalytic(**integ), t_end=t_end, dt=dt / k, **kw)
            step = 64 // k
            element = max(
                scaled(a.deformation, b.deformation[::step])
                for a, b in zip(sol.elements, ref.elements, strict=True)
            )
            _row(f"{name}, dt = {dt}/{k}", scaled(sol.x, ref.x[::step]), sol, element)


def _frame5() -> duhamel.System:
    n = 5
    t = np.arange(0.0, 8.0 + 0.01, 0.02)
    rng = np.random.default_rng(7)
    ag = 3.0 * np.sin(5.0 * t) * np.exp(-0.3 * t) + rng.normal(0.0, 0.8, t.size)
    ag[0] = 0.0
    k = 400.0 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    k[-1, -1] = 400.0
    system = duhamel.System(np.eye(n), k, zeta=0.03)
    system.add(duhamel.elements.Bilinear(0, k=300.0, fy=3.0, alpha=0.1))
    system.add(duhamel.elements.Cubic(3, k3=2e3))
    system.add_load(duhamel.loads.BaseAcceleration(np.ones(n), t=t, values=ag))
    return system


def jumps() -> None:
    """The force-jump family of docs/accuracy.md ("Force jumps (measured)"): the materials'
    SDOF with a failing ``MinMax``, a ``Steel02``, a ``Bilinear``, a ``FrictionPendulum``
    and a ``Gap``, at the record's step / k saved at every step and at the record's
    instants, against the same run at the record's step / 1024."""
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "_support"))
    import _materials_system as m

    from duhamel import elements as e

    def sdof(element: e.Element, k0: float = 0.0) -> duhamel.System:
        t, a = m.record()
        s = duhamel.System(np.eye(1), k0 * np.eye(1), (m.A0 + m.A1 * m.K0) * np.eye(1))
        s.add(element)
        s.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=a))
        return s

    cases = {
        "MinMax": lambda: m.sdof("MinMax"),
        "Steel02": lambda: m.sdof("Steel02"),
        "Bilinear": lambda: sdof(e.Bilinear(0, k=m.K0, fy=m.FY, alpha=0.05)),
        "FrictionPendulum": lambda: sdof(e.FrictionPendulum(0, radius=2.0, mu=0.06, weight=9.81)),
        "Gap": lambda: sdof(e.Gap(0, gap=0.02, k=10 * m.K0), k0=m.K0),
    }

    def run(system: duhamel.System, k: int, save: int) -> duhamel.Solution:
        return duhamel.solve(
            system, duhamel.Semianalytic(), t_end=m.SECONDS, dt=m.DT / k, save_every=save
        )

    warnings.simplefilter("ignore", duhamel.AccuracyWarning)
    print(f"load average {os.getloadavg()}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print("| case | k | save | true error | estimate | ratio | bound ratio |\n"
          "|---|---|---|---|---|---|---|")  # fmt: skip
    for name, make in cases.items():
        system = make()
        ref = run(system, 1024, 1024).x[:, 0]
        for k in (1, 2, 4, 8, 16):
            for save in sorted({1, k}):
                sol = run(system, k, save)
                x = sol.x[::k, 0] if save == 1 else sol.x[:, 0]
                error = float(np.abs(x - ref).max() / np.abs(ref).max())
                est, bound = sol.stats.error_estimate, sol.stats.error_bound
                print(f"| {name} | {k} | {save} | {error:.2e} | {est:.2e} | {est / error:.2f} | "
                      f"{bound / error:.1f} |")  # fmt: skip


if __name__ == "__main__":
    if "--table" in sys.argv:
        table()
    elif "--jumps" in sys.argv:
        jumps()
    else:
        main()
