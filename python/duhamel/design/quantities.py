"""What a design study keeps of each run (:class:`RunPeaks`, the ``reduce`` of
:func:`duhamel.ensemble.solve_many`) and how a case becomes a model under its record
(:class:`Cases`, its ``make_system``): both picklable, for a Dask cluster."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["ENERGY_TERMS", "PEAKS", "Cases", "RunPeaks"]

#: The peak quantities of one run, with their units (SI).
PEAKS = {
    "isolator_displacement": "m",
    "isolator_displacement_max": "m",
    "base_shear_below": "N",
    "base_shear_above": "N",
    "storey_drift_ratio": "",
    "floor_acceleration": "m/s^2",
    "floor_spectrum": "m/s^2",
    "energy_input": "J",
    "energy_damping": "J",
    "energy_hysteretic": "J",
    "energy_error": "",
    "error_estimate": "",
    "error_bound": "",
}
#: The energy histories kept per run, in this order.
ENERGY_TERMS = ("input", "kinetic + strain", "damping", "hysteretic")


class Cases:
    """``case -> (model, {"loads": [...]})``: the case's property set (``case["model"]``)
    under its record, scaled and turned (``Suite.motions``), the first component along x and
    the second along y (a 2-D building takes the first only)."""

    def __init__(self, models: dict[str, Any], suite: Any, x: Any, y: Any = None) -> None:
        self.models, self.suite, self.x, self.y = models, suite, x, y

    def __call__(self, case: dict[str, Any]) -> tuple[Any, dict[str, Any]]:
        first, second = self.suite.motions(case)
        loads = [first.as_load(self.x)]
        if self.y is not None and second is not None:
            loads.append(second.as_load(self.y))
        return self.models[case["model"]], {"loads": loads}


def _peak(a: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.abs(a).max(axis=0)


class RunPeaks:
    """Per run (a :class:`duhamel.Solution` solved with ``energy=True``): the peaks a
    report needs and a few histories, thinned to at most `keep` instants.

    Each direction of the building contributes its own peaks; the larger over the
    directions is kept (storey drifts, floor accelerations and spectra per level, shears).
    """

    def __init__(self, building: Any, periods: NDArray[np.float64], keep: int = 1500) -> None:
        self.directions = [
            (r, [list(level) for level in levels]) for _, r, levels in building.directions()
        ]
        self.heights = np.asarray(building.heights, dtype=np.float64)
        self.isolators = list(building.isolators)
        self.periods = np.asarray(periods, dtype=np.float64)
        self.keep = int(keep)

    def __call__(self, sol: Any) -> dict[str, Any]:
        out: dict[str, Any] = {}
        histories = [sol.elements[i] for i in self.isolators]
        width = max(h.x.shape[1] for h in histories)
        n = sol.t.size
        u = np.zeros((n, len(histories), width))
        f = np.zeros_like(u)
        for k, h in enumerate(histories):
            u[:, k, : h.x.shape[1]] = h.x
            f[:, k, : h.x.shape[1]] = h.force
        radial = np.sqrt((u**2).sum(axis=2))  # the vector's length of a bidirectional one
        out["isolator_displacement"] = radial.max(axis=0)
        out["isolator_displacement_max"] = float(radial.max())
        below, above, drift, acc, spectra = [], [], [], [], []
        for r, levels in self.directions:
            below.append(float(_peak(sol.base_shear(r))))
            above.append(float(_peak(sol.base_shear(r, storeys=levels[1:])[:, 0])))
            d = sol.drifts(levels)[:, 1:] / self.heights  # the base level's is the isolators'
            drift.append(_peak(d))
            cols = [lv[0] for lv in levels]
            acc.append(_peak(sol.a_absolute[:, cols]))
            spectra.append(sol.floor_spectra(cols, self.periods, 0.05).sa[:, 0, :])
        out["base_shear_below"] = max(below)
        out["base_shear_above"] = max(above)
        out["storey_drift_ratio"] = np.max(drift, axis=0)
        out["floor_acceleration"] = np.max(acc, axis=0)
        out["floor_spectrum"] = np.max(spectra, axis=0)
        e = sol.energy
        out["energy_input"] = float(e.input[-1])
        out["energy_damping"] = float(e.damping[-1])
        out["energy_hysteretic"] = float(e.hysteretic[-1])
        out["energy_error"] = float(e.relative_error)
        # the time step's estimated error and its bound, the worst of the saved dofs and the
        # elements (relative to their peaks; NaN where the integrator does not estimate it)
        st = sol.stats
        for key, dofs, elements in (
            ("error_estimate", st.error_estimate, st.element_error_estimate),
            ("error_bound", st.error_bound, st.element_error_bound),
        ):
            values = [v for v in (dofs, *elements) if v is not None]
            out[key] = float(max(values)) if values else float("nan")
        step = max(1, -(-n // self.keep))
        out["t"] = sol.t[::step].copy()
        out["isolator_deformation"] = u[::step].copy()
        out["isolator_force"] = f[::step].copy()
        terms = [e.input, e.kinetic + e.strain, e.damping, e.hysteretic]
        out["energy"] = np.column_stack(terms)[::step].copy()
        return out
