"""The inputs of a prepared run (:mod:`duhamel.prepared`), checked: the model and the
integrator, a run's own loads, what a streamed run supports."""

from __future__ import annotations

from typing import Any

import numpy as np

from duhamel._engine.labels import resolve_fields
from duhamel._engine.validate import positive_int
from duhamel.integrators import DirectIntegrator, Semianalytic
from duhamel.loads import Load
from duhamel.system import System

__all__ = ["checked_checkpoint_every", "checked_loads", "checked_models", "massless_store_check"]


def massless_store_check(system: System) -> None:
    """Refuses a streamed run of a model whose massless dofs carry loads or elements, or
    that a damping matrix reaches: the store does not yet add their static part or give
    their coordinates an initial state (in-memory runs do)."""
    c = system._condensation
    if c is None:
        return
    from duhamel.loads import Callable

    touched = bool(system.elements) or any(
        isinstance(load, Callable) or any(np.any(term.pattern[c.s]) for term in load._terms(system))
        for load in system.loads
    )
    if touched:
        raise ValueError(
            "`store`: a streamed run does not yet support loads or elements at massless dofs "
            f"(dofs {c.s.tolist()[:8]}...); run without `store`"
        )
    from duhamel._engine.massless import massless_damping

    how = massless_damping(system)
    if how is not None and how.kind == "matrix":
        raise ValueError(
            "`store`: a streamed run does not yet support a damping matrix `C` that reaches "
            f"massless dofs (dofs {c.s.tolist()[:8]}...: their first-order coordinates); run "
            "without `store`"
        )


def checked_checkpoint_every(value: Any, store: Any) -> int | None:
    """`checkpoint_every` as a positive int (None: the default), refused without `store`
    (there is nothing to checkpoint into: the value would be ignored)."""
    if value is None:
        return None
    out = positive_int(value, "checkpoint_every")
    if store is None:
        raise ValueError(
            f"`checkpoint_every` = {out} needs `store` (checkpoints are written into a "
            "streamed run's store); pass `store=` or leave `checkpoint_every` out"
        )
    return out


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


def checked_models(system: Any, integrator: Any) -> None:
    """Refuses a `system` that is not a System and an `integrator` that is not one of duhamel's."""
    if not isinstance(system, System):
        raise TypeError(f"`system` must be a duhamel.System, got {type(system).__name__}")
    if not isinstance(integrator, Semianalytic | DirectIntegrator):
        raise TypeError(
            f"`integrator` must be a duhamel integrator such as duhamel.Semianalytic() or "
            f"duhamel.Newmark(), got {type(integrator).__name__}"
        )
