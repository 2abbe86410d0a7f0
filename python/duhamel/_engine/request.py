"""A run's description checked against its prepared model: the :class:`Request` every engine
and sink of the pipeline reads (``duhamel.RunSpec`` made concrete: the grid's step count,
the output dofs as indices, the run's loads checked, the instants within the run).

Every input check of a run is here, once, with messages naming the keyword of
:func:`duhamel.solve`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.labels import resolve_fields, resolve_list
from duhamel._engine.validate import MAX_COUNT, dof_list
from duhamel.events import Event
from duhamel.loads import Load
from duhamel.system import System

__all__ = ["ACCUMULATED", "Request", "checked_loads", "request", "steps"]

#: The routes whose runs accumulate the energy in the core: the pseudo-force route, the
#: uncoupled route stepped one step at a time, the first-order route and the direct
#: integrators.
ACCUMULATED = ("pseudo-force", "uncoupled", "direct", "first-order")


@dataclass(slots=True)
class Request:
    """One run, checked (see the module docstring); a value the pipeline reads and never
    changes (``dataclasses.replace`` makes another).

    `interpolant` and `stop` are set by the pipeline for the run inside a run that locates
    events or evaluates the response inside its steps: keep what the exact interpolant of a
    linear route needs, and ``stop(solution)``, whether a part of the run holds a terminal
    event's crossing (the run then stops after it)."""

    t0: float
    dt: float
    n_steps: int
    save_every: int
    dofs: NDArray[np.intp] | None
    x0: Any
    v0: Any
    loads: list[Load] | None
    progress: Any
    started: float
    events: tuple[Event, ...] = ()
    times: NDArray[np.float64] | None = None
    dense: bool = False
    energy: bool = False
    elements: bool = True
    interpolant: bool = False
    stop: Any = None

    @property
    def located(self) -> bool:
        """Whether events are located or the response is evaluated inside the steps."""
        return bool(self.events) or self.times is not None or self.dense


def steps(t_end: float, dt: float, t0: float) -> int:
    """The steps of a run from `t0` to `t_end` (refused: fewer than one, more than a run can
    take, or steps the times cannot tell apart)."""
    span = t_end - t0
    if not span >= dt * (1.0 - 1e-9):
        raise ValueError(
            f"`t_end` ({t_end:g}) must be at least one step `dt` ({dt:g}) after `t0` ({t0:g})"
        )
    count = span / dt * (1.0 + 1e-12) + 1e-9
    if not count <= MAX_COUNT:
        raise ValueError(
            f"`dt` = {dt:g} is too small for `t_end` - `t0` = {span:g}: that is {count:.3g} "
            f"steps, more than the {MAX_COUNT:.3g} a run can take; use a larger `dt` or a "
            "shorter run"
        )
    # The step times t0 + n dt must be told apart: the grid's largest time resolves dt.
    largest = max(abs(t0), abs(t_end))
    if math.ulp(largest) > 1e-3 * dt:
        raise ValueError(
            f"`dt` = {dt:g} is below the resolution of the times around `t0` = {t0:g} "
            f"(`t_end` = {t_end:g}): doubles there are {math.ulp(largest):.3g} apart, "
            "so the step times would not be distinct; measure time from a nearer origin "
            "(a smaller `t0`) or use a larger `dt`"
        )
    return max(1, math.floor(count))


def checked_loads(loads: Any, system: System) -> list[Load]:
    """A run's `loads`, each checked against `system`."""
    if isinstance(loads, Load) or not isinstance(loads, list | tuple):
        raise TypeError(
            f"`loads` must be a list of duhamel.loads loads (or None for the system's own), "
            f"got {type(loads).__name__}"
        )
    loads = [resolve_fields(system, load) for load in loads]
    for i, load in enumerate(loads):
        if not isinstance(load, Load):
            raise TypeError(
                f"`loads[{i}]` must be a duhamel.loads load (Step, Harmonic, Tabulated, "
                f"BaseAcceleration, Unbalance, Callable), got {type(load).__name__}"
            )
        try:
            load._validate(system)
        except (TypeError, ValueError) as exc:
            exc.add_note(f"in `loads[{i}]` ({type(load).__name__}) of Prepared.run")
            raise
    return list(loads)


def request(
    system: System,
    dt: float,
    route: str,
    spec: Any,
    started: float,
) -> Request:
    """The :class:`Request` of `spec` (a ``duhamel.RunSpec``) on a model prepared with step
    `dt` on `route`."""
    t0 = spec.t0
    n_steps = steps(spec.t_end, dt, t0)
    save = spec.saveat
    # A stride beyond the run keeps its first and last instants, as the run's length does.
    save_every = min(save.every, n_steps)
    dofs = save.dofs
    out_dofs = None
    if dofs is not None:
        out_dofs = dof_list(resolve_list(system, dofs, "dofs"), "dofs", system.n_dof)
    loads = spec.loads
    if loads is not None:
        loads = checked_loads(loads, system)
    store = spec.store
    if save.energy and route not in ACCUMULATED and (save_every != 1 or out_dofs is not None
                                                     or store is not None):  # fmt: skip
        raise ValueError(
            "`energy`: the work integrals are accumulated during the run on the pseudo-force "
            f"and uncoupled routes only; this run's route is {route!r}, whose energy balance "
            "is computed after the run from every step and dof: solve with `save_every=1`, "
            "`dofs=None` and no `store`"
        )
    times = None
    if save.located:
        if save.t_eval is not None:
            times = save.t_eval
            t_end = t0 + n_steps * dt
            if times.size and (times[0] < t0 or times[-1] > t_end):
                raise ValueError(
                    f"`t_eval` must lie within the run, [{t0:g}, {t_end:g}]; got "
                    f"[{times[0]:g}, {times[-1]:g}]"
                )
        if store is not None or save_every != 1:
            raise ValueError(
                "`events`, `t_eval` and `dense` need every step kept in memory: "
                "`save_every` must be 1 and `store` None"
            )
    return Request(
        t0, dt, n_steps, save_every, out_dofs, spec.x0, spec.v0, loads, spec.progress, started,
        tuple(save.events), times, save.dense, save.energy, save.elements,
    )  # fmt: skip
