"""The one run pipeline: a run described by values (``duhamel.RunSpec``), checked into a
:class:`~duhamel._engine.request.Request`, run by the prepared model's engine (the modal
routes or a direct integrator, each a core model run by the core's one driver) into its
sink (memory, or a store the caller gives), and finished by the outputs that read the
whole history: events located inside their steps, the response at ``t_eval``, the dense
interpolant (docs/architecture.md, "One run pipeline").

The energy integrals, the element histories and the modal history are outputs of the
core's loop, kept with the history by the engine; the store is a sink that takes the run in
segments (``duhamel.store``); events, ``t_eval`` and ``dense`` read the history kept in
memory.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any, Protocol

from duhamel._engine.locate import dense_run, terminal_check
from duhamel._engine.request import Request
from duhamel.results.solution import Solution

__all__ = ["Engine", "execute"]


class Engine(Protocol):
    """A prepared model's runs (``_engine.modal.ModalSetup``, ``_engine.direct_run.
    DirectSetup``): one run of a checked request, kept in memory."""

    def run(self, req: Request) -> Solution: ...


def execute(
    engine: Engine, req: Request, sink: Callable[[Request], Solution] | None = None
) -> Solution:
    """Runs `req` on `engine` in memory, or into `sink` (a store's), and finishes it with
    the outputs that read its whole history."""
    if req.located:
        # Every step kept in memory, what the exact interpolant of a linear route needs,
        # and the run stopped after the part that holds a terminal event's crossing.
        inner = replace(req, save_every=1, interpolant=True, stop=terminal_check(req.events))
        return dense_run(lambda: _run(engine, inner, None), req.events, req.times, req.dense)
    return _run(engine, req, sink)


def _run(engine: Engine, req: Request, sink: Any) -> Solution:
    return engine.run(req) if sink is None else sink(req)
