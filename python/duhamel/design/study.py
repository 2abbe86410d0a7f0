"""A design study of an isolated building (:class:`Study`): a scaled suite of records run
on the nominal, lower- and upper-bound models through :func:`duhamel.ensemble.solve_many`,
the peaks a design needs as a labelled xarray dataset, the suite statistics and the code
checks of ASCE 7-22 chapters 16 and 17, and the report (:meth:`Study.report`)."""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, positive_float
from duhamel.design.asce7 import history
from duhamel.design.asce7.elf import IsolatedELF, isolated_elf
from duhamel.design.building import Building
from duhamel.design.checks import Check
from duhamel.design.quantities import PEAKS, Cases, RunPeaks

__all__ = ["STATISTICS", "Study"]

#: The peak quantities the study gives statistics of, per model.
STATISTICS = (
    "isolator_displacement",
    "isolator_displacement_max",
    "base_shear_below",
    "base_shear_above",
    "storey_drift_ratio",
    "floor_acceleration",
)


def _suite(suite: Any) -> tuple[Any, Any]:
    """(the Suite, the ScaledSuite or None)."""
    from duhamel.records.scaling import ScaledSuite
    from duhamel.records.suite import Suite

    if isinstance(suite, ScaledSuite):
        return suite.suite, suite
    if isinstance(suite, Suite):
        return suite, None
    raise TypeError(
        "`suite` must be a duhamel.records.ScaledSuite (scale_suite's result) or Suite, got "
        f"{type(suite).__name__}"
    )


class Study:
    """A response-history design study of an isolated building (ASCE 7-22 chapters 16, 17).

    Parameters
    ----------
    model : Building
        The building (:class:`~duhamel.design.Building`).
    suite : ScaledSuite or Suite
        The records, scaled (:func:`duhamel.records.scale_suite`); a ScaledSuite also gives
        the report its target spectrum and scaling check.
    integrator : Semianalytic or DirectIntegrator
        For every run.
    dt : float
        The step (s).
    bounds : mapping, optional
        Property modification factors of the isolators (:func:`duhamel.ensemble.
        property_bounds`: ``{"mu": (0.85, 1.3)}``): the lower- and upper-bound models run
        beside the nominal one (section 17.2.8.4).
    t_end : float, optional
        Default: the longest record.
    sm1 : float, optional
        ``S_M1`` (g) of the equivalent lateral force procedure; default 1.5 ``S_D1`` of the
        suite's ASCE 7 target.
    r_i : float, optional
        ``R_I`` (2.0).
    regular : bool, optional
        Whether the structure above the isolation system is regular (section 17.6.4.2).
    risk_category, structure : str, optional
        Table 12.12-1's row and column for chapter 16's drift acceptance.
    orientations : sequence of float, optional
        The angles (degrees) each pair is applied at (default 0 and 90: each component along
        x in turn; in 3-D the pair turned by 90 degrees); per record the larger response.
    periods : array_like, optional
        Of the floor spectra (s; default 40 from 0.05 to 5 s).
    workers, client : optional
        As :func:`~duhamel.ensemble.solve_many` (threads, or a Dask client).
    progress : bool, optional
        A progress bar over the runs (default True).
    elf : IsolatedELF, optional
        Computed from the building when not given.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.design import Building, Study
    >>> from duhamel.records import GroundMotion, GroundMotionPair, Suite
    >>> m, k = np.diag([2e5, 1e5]), 2e8 * np.array([[1.0, -1.0], [-1.0, 1.0]])
    >>> s = duhamel.System(m, k, zeta=0.03)
    >>> s = s.add(duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.05, weight=3e5 * 9.80665))
    >>> t = np.arange(0.0, 6.0, 0.01)
    >>> pairs = [GroundMotionPair(GroundMotion(np.sin(2 * t + j) * np.exp(-0.3 * t), 0.01, "g"),
    ...                           GroundMotion(np.cos(3 * t + j) * np.exp(-0.3 * t), 0.01, "g"),
    ...                           name=f"R{j}") for j in range(2)]
    >>> study = Study(Building(s, [0, 1], [3.0]), Suite(pairs), duhamel.Semianalytic(),
    ...               dt=0.01, sm1=0.6, progress=False).run()
    >>> study.dataset["isolator_displacement"].dims
    ('model', 'record', 'orientation', 'isolator')
    >>> [c.verdict for c in study.checks][:1]
    ['fail']
    """

    def __init__(
        self,
        model: Building,
        suite: Any,
        integrator: Any,
        *,
        dt: float,
        bounds: Mapping[str, Any] | None = None,
        t_end: float | None = None,
        sm1: float | None = None,
        r_i: float = 2.0,
        regular: bool = True,
        risk_category: str = "II",
        structure: str = "other",
        orientations: Sequence[float] = (0.0, 90.0),
        periods: ArrayLike | None = None,
        workers: int | None = None,
        client: Any = None,
        progress: bool = True,
        elf: IsolatedELF | None = None,
    ) -> None:
        if not isinstance(model, Building):
            raise TypeError(f"`model` must be a duhamel.design.Building, got {type(model)}")
        self.building = model
        self.suite, self.scaled = _suite(suite)
        self.integrator = integrator
        self.dt = positive_float(dt, "dt")
        self.bounds = None if bounds is None else dict(bounds)
        records = self.suite.scaled()
        longest = max(r.t[-1] for r in records)
        self.t_end = float(longest) if t_end is None else positive_float(t_end, "t_end")
        meta = getattr(getattr(self.scaled, "target", None), "metadata", {}) or {}
        if sm1 is None and "sd1" not in meta:
            raise ValueError("`sm1` is needed: the suite has no ASCE 7 target to take it from")
        self.sm1 = 1.5 * float(meta["sd1"]) if sm1 is None else positive_float(sm1, "sm1")
        self.r_i = positive_float(r_i, "r_i")
        self.regular = bool(regular)
        history.allowable_drift(risk_category, structure)  # checks both names
        self.risk_category, self.structure = risk_category, structure
        pairs = {type(r).__name__ for r in self.suite.records}
        if len(pairs) != 1:
            raise ValueError("`suite` must hold only pairs or only single records")
        self.orientations = [float(a) for a in as_float_array(orientations, "orientations", 1)]
        if not pairs == {"GroundMotionPair"}:
            self.orientations = self.orientations[:1]
        p = np.geomspace(0.05, 5.0, 40) if periods is None else periods
        self.periods = as_float_array(p, "periods", ndim=1)
        self.workers, self.client, self.progress = workers, client, bool(progress)
        self._elf = elf
        self._dataset: Any = None
        self.ensemble: Any = None
        self.wall_time: dict[str, float] = {}

    # ------------------------------------------------------------------ running
    @property
    def models(self) -> dict[str, Any]:
        """The systems run: ``"nominal"`` and, with `bounds`, ``"lower"`` and ``"upper"``
        (:func:`duhamel.ensemble.property_bounds`), made once."""
        if getattr(self, "_models", None) is None:
            out = {"nominal": self.building.system}
            if self.bounds is not None:
                from duhamel.ensemble.bounds import property_bounds

                out = {**property_bounds(self.building.system, self.bounds), **out}
            self._models = {k: out[k] for k in ("lower", "nominal", "upper") if k in out}
        return self._models

    @property
    def cases(self) -> list[dict[str, Any]]:
        """The runs' parameters, model by model: ``model``, ``index``, ``record``,
        ``factor``, ``orientation``."""
        return [
            {"model": name, **case}
            for name in self.models
            for case in self.suite.cases(orientations=self.orientations)
        ]

    @property
    def elf(self) -> IsolatedELF:
        """The equivalent lateral force values the lower limits refer to."""
        if self._elf is None:
            started = time.perf_counter()
            self._elf = isolated_elf(self.building, sm1=self.sm1, lambdas=self.bounds, r_i=self.r_i)
            self.wall_time["elf"] = time.perf_counter() - started
        return self._elf

    def run(self) -> Study:
        """Runs every case (once; again after :meth:`clear`) and returns the study."""
        if self.ensemble is not None:
            return self
        from duhamel.ensemble.run import solve_many

        started = time.perf_counter()
        models = self.models
        self._cases = self.cases
        make = Cases(models, self.suite, self.building.x, self.building.y)
        self.ensemble = solve_many(
            make,
            self._cases,
            self.integrator,
            t_end=self.t_end,
            dt=self.dt,
            reduce=RunPeaks(self.building, self.periods),
            workers=self.workers,
            client=self.client,
            progress=self.progress,
            energy=True,
        )
        self.wall_time["runs"] = time.perf_counter() - started
        self._dataset = None
        return self

    def clear(self) -> None:
        """Forgets the runs (the next access runs them again)."""
        self.ensemble = None
        self._dataset = None

    # ------------------------------------------------------------------ results
    def _results(self) -> Any:
        return self.run().ensemble.results

    def _shape(self) -> tuple[int, int, int]:
        return len(self.models), len(self.suite), len(self.orientations)

    def _stacked(self, key: str) -> NDArray[np.float64]:
        """``key`` of every run, shape (model, record, orientation, ...)."""
        values = np.asarray([np.asarray(r[key], dtype=np.float64) for r in self._results()])
        return values.reshape(self._shape() + values.shape[1:])

    @property
    def dataset(self) -> Any:
        """The peaks of every run as an xarray Dataset over ``model``, ``record``,
        ``orientation`` (and ``isolator``, ``storey``, ``level``, ``period``), the isolator
        and energy histories over ``time``, with units in the variables' attributes."""
        if self._dataset is None:
            import xarray as xr

            results = self._results()
            n_iso = len(self.building.isolators)
            n_levels = len(self.building.levels)
            dims = ("model", "record", "orientation")
            extra = {
                "isolator_displacement": ("isolator",),
                "storey_drift_ratio": ("storey",),
                "floor_acceleration": ("level",),
                "floor_spectrum": ("level", "period"),
            }
            data = {
                k: (dims + extra.get(k, ()), self._stacked(k), {"units": u})
                for k, u in PEAKS.items()
            }
            width = results[0]["isolator_deformation"].shape[2]
            hist = (*dims, "time", "isolator", "axis")
            data["isolator_deformation"] = (
                hist,
                self._stacked("isolator_deformation"),
                {"units": "m"},
            )
            data["isolator_force"] = (hist, self._stacked("isolator_force"), {"units": "N"})
            data["energy"] = ((*dims, "time", "term"), self._stacked("energy"), {"units": "J"})
            coords = {
                "model": list(self.models),
                "record": list(self.suite.names),
                "orientation": self.orientations,
                "isolator": list(self.building.isolators)[:n_iso],
                "storey": np.arange(1, n_levels),
                "level": np.arange(n_levels),
                "period": self.periods,
                "time": results[0]["t"],
                "axis": ["x", "y"][:width],
                "term": ["input", "kinetic + strain", "damping", "hysteretic"],
                "factor": ("record", np.asarray(self.suite.factors, dtype=np.float64)),
            }
            self._dataset = xr.Dataset(data, coords=coords)
        return self._dataset

    @property
    def statistics(self) -> dict[str, dict[str, dict[str, NDArray[np.float64]]]]:
        """Per model and quantity (:data:`STATISTICS`): ``per_record`` (each record's peak,
        the larger over the orientations), ``design`` (section 17.6.3.4: their mean for seven
        or more records, else the largest), ``mean``, ``mean_plus_sigma`` (sample standard
        deviation) and ``max`` over the records."""
        out: dict[str, dict[str, dict[str, NDArray[np.float64]]]] = {}
        for m, model in enumerate(self.models):
            out[model] = {}
            for key in STATISTICS:
                per_record = self._stacked(key)[m].max(axis=1)
                n = per_record.shape[0]
                sigma = per_record.std(axis=0, ddof=1) if n > 1 else np.zeros(per_record.shape[1:])
                out[model][key] = {
                    "per_record": per_record,
                    "design": history.suite_value(per_record),
                    "mean": per_record.mean(axis=0),
                    "mean_plus_sigma": per_record.mean(axis=0) + sigma,
                    "max": per_record.max(axis=0),
                }
        return out

    def design_values(self) -> dict[str, tuple[float, str]]:
        """The scalar design values the checks use, each the largest over the models, with
        the model it comes from: isolator displacement (largest isolator), shears below
        and above the isolation interface."""
        stats = self.statistics
        out = {}
        for key, name in (
            ("isolator_displacement_max", "isolator_displacement"),
            ("base_shear_below", "base_shear_below"),
            ("base_shear_above", "base_shear_above"),
        ):
            model = max(stats, key=lambda m: float(stats[m][key]["design"]))
            out[name] = (float(stats[model][key]["design"]), model)
        return out

    @property
    def checks(self) -> list[Check]:
        """The code checks: the suite's size and scaling, the lower limits of section 17.6.4
        against the ELF values, the drift limit of section 17.6.4.4 and chapter 16's drift
        acceptance (section 16.4.1.2), each on the governing model."""
        out = [
            Check(
                "ASCE 7-22 17.3.3",
                "record pairs in the suite",
                float(len(self.suite)),
                float(history.MIN_RECORDS),
                "minimum",
                "",
                "seven or more: the suite's mean is the design value (17.6.3.4), else the largest",
            )
        ]
        if self.scaled is not None:
            table = self.scaled.table
            out.append(
                Check(
                    "ASCE 7-22 16.2.3.2 (17.3.3)",
                    "suite mean spectrum over the target, lowest over the period range",
                    float(np.min(table.mean / table.target)),
                    float(table.fraction),
                    "minimum",
                    "",
                    f"{self.scaled.method} scaling over {table.period[0]:.3g}-"
                    f"{table.period[-1]:.3g} s",
                )
            )
        values = self.design_values()
        limits = history.lower_limit_checks(
            {k: v for k, (v, _) in values.items()}, self.elf, regular=self.regular
        )
        for check, (_, model) in zip(limits, values.values(), strict=True):
            out.append(_with_model(check, model))
        stats = self.statistics
        drifts = {m: stats[m]["storey_drift_ratio"]["per_record"] for m in stats}
        iso = {m: history.isolated_drift_check(d) for m, d in drifts.items()}
        worst = max(iso, key=lambda m: iso[m].value)
        out.append(_with_model(iso[worst], worst))
        accept = {
            m: history.drift_acceptance(
                d, risk_category=self.risk_category, structure=self.structure
            )
            for m, d in drifts.items()
        }
        worst = max(accept, key=lambda m: accept[m].value)
        out.append(_with_model(accept[worst], worst))
        return out

    def report(self, path: str | Path, *, command: str | None = None) -> tuple[Path, Path]:
        """Writes the report: a self-contained HTML file at `path` (figures embedded) and its
        Markdown twin beside it (same name, ``.md``, figures in ``<name>_files/``).
        `command` is recorded as the one that made it (default: this process's command
        line). Returns both paths."""
        from duhamel.design.report import write_report

        return write_report(self, Path(path), command=command)


def _with_model(check: Check, model: str) -> Check:
    from dataclasses import replace

    return replace(check, quantity=f"{check.quantity} [{model} properties]")
