"""The inputs of a prepared run (:mod:`duhamel.prepared`), checked: the model and the
integrator, a run's own loads, what a streamed run supports."""

from __future__ import annotations

from typing import Any

import numpy as np

from duhamel.integrators import DirectIntegrator, Semianalytic
from duhamel.system import System

__all__ = ["checked_models", "massless_store_check"]


def massless_store_check(system: System) -> None:
    """Refuses a streamed run of a model whose massless dofs carry loads or elements, or
    that a damping matrix reaches: the store does not yet add their static part or give
    their coordinates an initial state (in-memory runs do)."""
    c = system._condensation
    if c is None:
        return
    from duhamel.loads import Callable

    touched = bool(system.elements or system.couplings) or any(
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


def checked_models(system: Any, integrator: Any) -> None:
    """Refuses a `system` that is not a System and an `integrator` that is not one of duhamel's."""
    if not isinstance(system, System):
        raise TypeError(f"`system` must be a duhamel.System, got {type(system).__name__}")
    if not isinstance(integrator, Semianalytic | DirectIntegrator):
        raise TypeError(
            f"`integrator` must be a duhamel integrator such as duhamel.Semianalytic() or "
            f"duhamel.Newmark(), got {type(integrator).__name__}"
        )
