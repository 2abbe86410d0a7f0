"""The bundled example: a 10-storey shear building under a synthetic earthquake.

Used by ``duhamel demo`` (see :mod:`duhamel.cli`); the model and the record are reusable.
The ground acceleration is piecewise linear between its samples, and the run's step equals
the record's sampling interval, so the semi-analytic method integrates it exactly.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import scipy.linalg
import scipy.signal
from numpy.typing import NDArray

import duhamel
from duhamel.constants import STANDARD_GRAVITY

__all__ = ["DemoResult", "G", "plot_demo", "run_demo", "shear_building", "synthetic_record"]

#: Standard gravity (m/s^2): :data:`duhamel.constants.STANDARD_GRAVITY`.
G = STANDARD_GRAVITY


def shear_building(
    n_storeys: int = 10,
    storey_mass: float = 2.0e5,
    period: float = 1.0,
    zeta: float = 0.05,
    taper: float = 0.5,
) -> duhamel.System:
    """A shear building with lumped storey masses and one horizontal dof per floor.

    Storey stiffnesses decrease linearly with height, from ``k`` at the ground storey to
    ``taper * k`` at the top one; ``k`` is chosen so the fundamental period is `period`.

    Parameters
    ----------
    n_storeys : int
        Number of storeys (= degrees of freedom, floor 1 first, roof last).
    storey_mass : float
        Mass of every floor (kg).
    period : float
        Fundamental natural period (s).
    zeta : float
        Modal damping ratio of every mode.
    taper : float
        Top-storey stiffness relative to the ground storey.

    Returns
    -------
    System

    Examples
    --------
    >>> from duhamel.demo import shear_building
    >>> import numpy as np
    >>> sys = shear_building()
    >>> round(float(2 * np.pi / sys.modal().omega[0]), 6)
    1.0
    """
    profile = np.linspace(1.0, taper, n_storeys)
    kk = np.diag(profile + np.append(profile[1:], 0.0))
    kk -= np.diag(profile[1:], 1) + np.diag(profile[1:], -1)
    lam1 = scipy.linalg.eigvalsh(kk, subset_by_index=[0, 0])[0]  # omega1^2 for k = m = 1
    k = storey_mass * (2.0 * np.pi / period) ** 2 / lam1
    return duhamel.System(storey_mass * np.eye(n_storeys), k * kk, zeta=zeta)


def synthetic_record(
    duration: float = 20.0,
    dt: float = 0.01,
    pga: float = 0.3 * G,
    seed: int = 1999,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A deterministic synthetic ground acceleration (Clough-Penzien filtered white noise).

    Gaussian white noise from ``numpy.random.default_rng(seed)`` is passed through a
    Kanai-Tajimi filter (firm soil, ``omega_g = 15 rad/s``, ``zeta_g = 0.6``) and a
    Clough-Penzien high-pass (``omega_f = 1.5 rad/s``, ``zeta_f = 0.6``), multiplied by a
    Jennings-type envelope (quadratic rise to ``0.1 duration``, strong phase to
    ``0.4 duration``, exponential decay shifted to reach zero at the end) and scaled to `pga`.

    Parameters
    ----------
    duration : float
        Record length (s).
    dt : float
        Sampling interval (s).
    pga : float
        Peak ground acceleration (m/s^2).
    seed : int
        Seed of the noise.

    Returns
    -------
    t, a : ndarray
        Sample times ``0, dt, ..., duration`` and accelerations (m/s^2); ``a`` is zero at
        both ends.

    Examples
    --------
    >>> from duhamel.demo import G, synthetic_record
    >>> t, a = synthetic_record()
    >>> t.size, round(float(abs(a).max() / G), 3), float(abs(a[0])), float(abs(a[-1]))
    (2001, 0.3, 0.0, 0.0)
    """
    n = round(duration / dt) + 1
    t = np.arange(n) * dt
    wg, zg, wf, zf = 15.0, 0.6, 1.5, 0.6
    num = np.polymul([2 * zg * wg, wg**2], [1.0, 0.0, 0.0])
    den = np.polymul([1.0, 2 * zg * wg, wg**2], [1.0, 2 * zf * wf, wf**2])
    b, a = scipy.signal.bilinear(num, den, fs=1.0 / dt)
    acc = scipy.signal.lfilter(b, a, np.random.default_rng(seed).standard_normal(n))
    t1, t2, c = 0.1 * duration, 0.4 * duration, 0.3
    tail = np.exp(-c * (duration - t2))
    env = np.where(
        t < t1,
        (t / t1) ** 2,
        np.where(t <= t2, 1.0, (np.exp(-c * (t - t2)) - tail) / (1.0 - tail)),
    )
    acc *= env
    acc[-1] = 0.0
    return t, acc * (pga / np.abs(acc).max())


@dataclass(frozen=True)
class DemoResult:
    """Everything the demo computed (SI units)."""

    system: duhamel.System
    t_g: NDArray[np.float64]
    a_g: NDArray[np.float64]
    solution: duhamel.Solution
    storey_height: float
    periods: NDArray[np.float64]
    roof_peak: float
    roof_peak_time: float
    drift_peak: float
    drift_storey: int
    base_shear: NDArray[np.float64]

    @property
    def base_shear_peak(self) -> float:
        """Largest ``|V_b|`` (N)."""
        return float(np.abs(self.base_shear).max())

    def summary(self) -> dict[str, Any]:
        """The headline numbers as a JSON-ready dict."""
        st = self.solution.stats
        weight = float(np.trace(np.asarray(self.system.M))) * G
        return {
            "version": duhamel.__version__,
            "periods_s": [float(p) for p in self.periods[:3]],
            "peak_roof_displacement_m": self.roof_peak,
            "peak_roof_displacement_time_s": self.roof_peak_time,
            "peak_drift_ratio": self.drift_peak,
            "peak_drift_storey": self.drift_storey,
            "storey_height_m": self.storey_height,
            "peak_base_shear_N": self.base_shear_peak,
            "peak_base_shear_over_weight": self.base_shear_peak / weight,
            "steps": st.steps,
            "modes": st.modes,
            "wall_time_s": st.wall_time,
            "mode_steps_per_second": st.mode_steps_per_second,
        }


def run_demo(
    t_end: float = 30.0, dt: float = 0.01, storey_height: float = 3.5, **building: float
) -> DemoResult:
    """Build the model, apply :func:`synthetic_record`, integrate, and post-process.

    Parameters
    ----------
    t_end : float
        End of the run (s); beyond the 20 s record the building vibrates freely.
    dt : float
        Time step (s), also the record's sampling interval.
    storey_height : float
        Storey height (m) for the drift ratios.
    **building
        Passed to :func:`shear_building`.

    Returns
    -------
    DemoResult

    Examples
    --------
    >>> from duhamel.demo import run_demo
    >>> res = run_demo(t_end=5.0)
    >>> res.solution.x.shape
    (501, 10)
    """
    system = shear_building(**building)
    t_g, a_g = synthetic_record(dt=dt)
    n = system.n_dof
    system.add_load(duhamel.loads.BaseAcceleration(np.ones(n), t=t_g, values=a_g))
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=t_end, dt=dt)
    roof = sol.x[:, -1]
    i_roof = int(np.argmax(np.abs(roof)))
    drift = np.abs(np.diff(sol.x, axis=1, prepend=0.0)).max(axis=0) / storey_height
    ag = np.interp(sol.t, t_g, a_g, right=0.0)
    masses = np.diag(np.asarray(system.M))
    base_shear = -(sol.a + ag[:, None]) @ masses  # sum of storey inertia forces
    return DemoResult(
        system=system,
        t_g=t_g,
        a_g=a_g,
        solution=sol,
        storey_height=storey_height,
        periods=2.0 * np.pi / system.modal().omega,
        roof_peak=float(roof[i_roof]),
        roof_peak_time=float(sol.t[i_roof]),
        drift_peak=float(drift.max()),
        drift_storey=int(np.argmax(drift)) + 1,
        base_shear=base_shear,
    )


def _figure_class() -> Any:
    """``matplotlib.figure.Figure`` (no pyplot, no global backend state), or an ImportError."""
    try:
        from matplotlib.figure import Figure
    except ImportError as exc:
        raise ImportError(
            "the demo plot needs matplotlib: pip install 'duhamel[plot]' (or use --no-plot)"
        ) from exc
    return Figure


def plot_demo(result: DemoResult, path: str | Path) -> Path:
    """Write the three-panel figure (ground motion, roof history, peak profile) to `path`.

    Raises
    ------
    ImportError
        matplotlib is not installed.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from duhamel.demo import plot_demo, run_demo
    >>> with tempfile.TemporaryDirectory() as d:
    ...     out = plot_demo(run_demo(t_end=2.0), pathlib.Path(d) / "demo.png")
    ...     out.stat().st_size > 0
    True
    """
    fig = _figure_class()(figsize=(8, 10), layout="constrained")
    ax1, ax2, ax3 = fig.subplots(3, 1)
    sol, h = result.solution, result.storey_height
    ax1.plot(result.t_g, result.a_g / G, lw=0.7)
    ax1.set(xlabel="t (s)", ylabel="a_g (g)", title="Synthetic ground acceleration")
    ax2.plot(sol.t, 100 * sol.x[:, -1], lw=0.9)
    ax2.plot(result.roof_peak_time, 100 * result.roof_peak, "o", color="C3")
    ax2.set(xlabel="t (s)", ylabel="x_roof (cm)", title="Roof displacement (relative)")
    for ax in (ax1, ax2):
        ax.set_xlim(0.0, sol.t[-1])
    peak = np.concatenate([[0.0], np.abs(sol.x).max(axis=0)])
    ax3.plot(100 * peak, h * np.arange(peak.size), "o-")
    ax3.set(xlabel="peak |x| (cm)", ylabel="height (m)", title="Peak displacement profile")
    for ax in (ax1, ax2, ax3):
        ax.grid(True, alpha=0.3)
    path = Path(path)
    fig.savefig(path, dpi=110)
    return path
