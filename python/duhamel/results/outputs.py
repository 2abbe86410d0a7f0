"""The design outputs of a :class:`~duhamel.Solution` (a mixin it inherits): base and storey
shears, floor response spectra, peak tables, the energy balance. The computations live in
:mod:`.forces`, :mod:`.energy` and :mod:`.peaks`."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel.results.energy import Energy, energy_balance, energy_from_run
from duhamel.results.forces import (
    StructureModel,
    base_shear,
    columns,
    dof_sequence,
    real_array,
)
from duhamel.results.peaks import Peaks, peak_table

__all__ = ["StructuralOutputs"]


class StructuralOutputs:
    """Base shear, floor spectra, peaks and energy of a run (mixed into ``Solution``)."""

    t: NDArray[np.float64]
    x: NDArray[np.float64]
    v: NDArray[np.float64]
    a: NDArray[np.float64]
    dofs: NDArray[np.int64]
    meta: dict[str, Any]
    elements: tuple[Any, ...]
    a_absolute: NDArray[np.float64]
    _structure_source: Callable[[], StructureModel] | StructureModel | None

    def _structure(self) -> StructureModel:
        """The run's physical model (kept by the run)."""
        source = self._structure_source
        if source is None:
            raise ValueError(
                "this Solution does not hold its model (read from a store, or of a model with "
                "a time-varying mass): base shear and energy are not available"
            )
        if callable(source):
            source = source()
            self._structure_source = source
        return source

    def base_shear(
        self,
        direction: ArrayLike | None = None,
        *,
        storeys: Sequence[Any] | None = None,
    ) -> NDArray[np.float64]:
        """The force the structure sends to its supports along `direction`:
        ``r^T (K x + C_s x' + r_el(x, x'))`` — the linear ground stiffness and damping and
        the ground-connected elements (internal springs, dashpots and elements cancel along
        a rigid-body direction). ``C_s`` is the damping matrix without the mass-proportional
        part ``alpha M`` of Rayleigh damping (dashpots from every mass to the ground, which
        do not act through the supports; modal damping ratios and a given ``C`` count whole).
        With no other load, ``base_shear = -sum(M a_abs) - alpha sum(M v)`` along `r`.

        Parameters
        ----------
        direction : array_like, shape (n_dof,), optional
            The influence vector over the model's dofs (ones on the dofs along x, ...);
            default: the base excitation's (the ``BaseAcceleration`` loads' direction).
        storeys : sequence, optional
            Floors bottom to top (each a dof or a sequence of dofs): the storey shears, the
            force across the cut below each floor (`direction` restricted to that floor and
            those above), instead of the base shear.

        Returns
        -------
        ndarray, shape (n_saved,) or (n_saved, len(storeys))

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> t = np.linspace(0.0, 2.0, 201)
        >>> s = duhamel.System(np.eye(1), 100.0 * np.eye(1))
        >>> s = s.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=np.sin(5 * t)))
        >>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.01)
        >>> bool(np.allclose(sol.base_shear(), -sol.a_absolute[:, 0]))
        True
        """
        return base_shear(self, self._structure(), direction, storeys)

    def floor_spectra(
        self, dofs: Sequence[int], periods: ArrayLike, damping: float | ArrayLike = 0.05
    ) -> Any:
        """Floor response spectra: :func:`duhamel.spectra.response_spectrum` of the absolute
        accelerations (:attr:`a_absolute`) at `dofs`, one "motion" per dof (named
        ``"dof k"``), linear between the saved instants (which must be equally spaced).

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> t = np.linspace(0.0, 2.0, 201)
        >>> s = duhamel.System(np.eye(1), 100.0 * np.eye(1), zeta=0.05)
        >>> s = s.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=np.sin(5 * t)))
        >>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.01)
        >>> sol.floor_spectra([0], periods=[0.1, 0.5]).sa.shape
        (1, 1, 2)
        """
        from duhamel import _core
        from duhamel.spectra.elastic import ResponseSpectrum

        dofs = dof_sequence(dofs, "dofs")
        cols = columns(self.dofs, dofs, "dofs")
        if not cols:
            raise ValueError("`dofs` must list at least one dof")
        steps = np.diff(self.t)
        if steps.size == 0 or np.any(np.abs(steps - steps.mean()) > 1e-9 * steps.mean()):
            raise ValueError("floor spectra need at least two equally spaced saved instants")
        dt = float((self.t[-1] - self.t[0]) / (self.t.size - 1))
        p = np.atleast_1d(real_array(periods, "periods"))
        z = np.atleast_1d(real_array(damping, "damping"))
        if p.ndim != 1 or p.size == 0 or not np.all(np.isfinite(p)) or np.any(p < 0):
            raise ValueError(f"`periods` must be finite periods >= 0, got {periods!r}")
        if z.ndim != 1 or z.size == 0 or not np.all(np.isfinite(z)) or np.any(z < 0):
            raise ValueError(f"`damping` must be finite damping ratios >= 0, got {damping!r}")
        acc = self.a_absolute
        records = [np.ascontiguousarray(acc[:, c]) for c in cols]
        sd, sv, sa = _core.elastic_spectra(records, [dt] * len(cols), p, z, None)
        shape = (len(cols), z.size, p.size)
        names = [f"dof {d}" for d in dofs]
        return ResponseSpectrum(
            p, z, sd.reshape(shape), sv.reshape(shape), sa.reshape(shape), names
        )

    def peaks(self, *quantities: str, dofs: Sequence[int] | None = None, **extra: Any) -> Peaks:
        """A table of peaks: for each requested quantity and column, the value of largest
        magnitude (signed) and its time.

        Parameters
        ----------
        *quantities : str
            Any of ``"x"``, ``"v"``, ``"a"``, ``"a_absolute"``, ``"base_shear"``; default
            ``"x"``, ``"a_absolute"``.
        dofs : sequence of int, optional
            Which saved dofs (default all) for the per-dof quantities.
        **extra : array_like
            More histories by name, shape (n_saved,) or (n_saved, k) (drifts, storey shears).

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> sol = duhamel.solve(duhamel.System(np.eye(1), np.eye(1)), duhamel.Semianalytic(),
        ...                     t_end=4.0, dt=0.01, x0=[1.0])
        >>> table = sol.peaks("x")
        >>> float(table.peak[0]), float(table.time[0])
        (1.0, 0.0)
        """
        wanted = quantities or ("x", "a_absolute")
        cols = None if dofs is None else columns(self.dofs, dof_sequence(dofs, "dofs"), "dofs")
        chosen = self.dofs if cols is None else self.dofs[cols]
        series: dict[str, tuple[NDArray[np.float64], list[str]]] = {}
        for q in wanted:
            if not isinstance(q, str):
                raise TypeError(f"`quantities` must be names (strings), got {q!r}")
            if q == "base_shear":
                series[q] = (self.base_shear()[:, None], [""])
            elif q in ("x", "v", "a", "a_absolute"):
                data = np.asarray(getattr(self, q))
                series[q] = (data if cols is None else data[:, cols], [f"dof {d}" for d in chosen])
            else:
                raise ValueError(
                    "`quantities` must be among 'x', 'v', 'a', 'a_absolute', 'base_shear', "
                    f"got {q!r}"
                )
        for name, values in extra.items():
            arr = real_array(values, name)
            arr = arr[:, None] if arr.ndim == 1 else arr
            if arr.ndim != 2 or arr.shape[0] != self.t.size:
                raise ValueError(
                    f"`{name}` must have {self.t.size} rows (one per saved instant), got shape "
                    f"{np.shape(values)}"
                )
            series[name] = (arr, [str(k) for k in range(arr.shape[1])])
        return peak_table(self.t, series)

    @property
    def energy(self) -> Energy:
        """The energy balance of the run (:class:`duhamel.results.energy.Energy`): kinetic,
        strain, damping, element work, input (relative and absolute) and the balance
        error, over the saved instants.

        A run solved with ``energy=True`` on the pseudo-force route (elements) accumulated
        the work integrals in the core every step: any `save_every`, `dofs` or streamed
        store. Otherwise the balance is computed after the run from the saved histories,
        which then need every step (``save_every=1``) and every dof (``dofs=None``).

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> s = duhamel.System(np.eye(1), np.eye(1), zeta=0.05)
        >>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=10.0, dt=0.01, x0=[1.0])
        >>> e = sol.energy
        >>> bool(abs(e.kinetic[-1] + e.strain[-1] + e.damping[-1] - 0.5) < 1e-4)
        True
        """
        cached = self.__dict__.get("_energy")
        if cached is None:
            run = getattr(self, "_energy_run", None)
            if run is not None:
                cached = energy_from_run(self, *run)
            else:
                cached = energy_balance(self, self._structure())
            self.__dict__["_energy"] = cached
        return cached

    def plot_energy(self, ax: Any = None) -> Any:
        """The energy balance against time (stacked: kinetic, strain, damping, elements; the
        input on top). Returns the matplotlib Axes.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> s = duhamel.System(np.eye(1), np.eye(1), zeta=0.05)
        >>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=10.0, dt=0.01, x0=[1.0])
        >>> ax = sol.plot_energy()
        """
        return self.energy.plot(ax)
