"""A modal run in chunks that stops after the first chunk in which a check (a terminal
event's crossing, docs/events.md) fires: the work after a terminal event is not done.

Each chunk continues the one before exactly, as the store's segments do
(``duhamel.store._run``): from the last saved state, with the elements' variables and the
growth guard's bounds carried and the grid counted from the run's start, so the joined
history equals a whole run's, bit for bit, up to the chunk where it stops.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from duhamel._engine import dispatch

__all__ = ["Joined", "chunked"]

#: Chunks of a run: the check's cost is linear in the rows, so a run is checked this many
#: times at most (and the work after the stop is at most this fraction of the run).
CHUNKS = 32
#: Fewest steps of a chunk (a core run's set-up is amortised over them).
SMALLEST = 256

_ARRAYS = ("t", "q", "v", "eta", "outputs", "load_values", "forcing", "pseudo",
           "element_x", "element_v", "element_force")  # fmt: skip


class Joined:
    """The ``RunResult`` of consecutive chunks: their histories end to end (each chunk's
    first row, its start, is the row the chunk before ended with, and is left out), their
    counts summed, the last one's end variables."""

    def __init__(self, parts: list[Any]) -> None:
        for name in _ARRAYS:
            rows = [getattr(p, name) for p in parts]
            if rows[0] is None:
                setattr(self, name, None)
            else:
                tail = [np.asarray(r)[1:] for r in rows[1:]]
                setattr(self, name, np.concatenate([np.asarray(rows[0]), *tail]))
        last = parts[-1]
        self.element_widths = parts[0].element_widths
        self.element_state = last.element_state
        self.guard_state = last.guard_state
        self.error = None
        for name in ("newton_iterations", "closed_form_steps", "factorizations",
                     "subdivided_steps"):  # fmt: skip
            setattr(self, name, sum(int(getattr(p, name)) for p in parts))
        self.subdivision_depth = max(int(p.subdivision_depth) for p in parts)
        self.loop_time = sum(float(p.loop_time) for p in parts)


def chunked(
    prep: Any,
    opts: Any,
    state: tuple[Any, Any],
    sub: int,
    run: Callable[[Any], Any],
    seen: Callable[[Any, Any], bool],
) -> tuple[Joined, int] | None:
    """Runs `opts`'s grid (`sub` internal steps per step) in chunks from `state`; `run(spec)`
    runs one chunk in the core, ``seen(result, steps)`` says whether a chunk's result
    (``steps`` user steps) holds a terminal crossing. Returns the joined result and the
    user steps taken, or None when a chunk failed (the caller runs the whole grid again, so
    a failure is raised as a whole run raises it)."""
    route = prep.route
    total = opts.n_steps * sub
    size = max(SMALLEST * sub, -(-total // CHUNKS))
    size = -(-size // sub) * sub  # whole user steps
    parts: list[Any] = []
    step, q_v, eta, elements, guard = 0, state, None, None, None
    while step < total:
        n = min(size, total - step)
        grid = dispatch.grid(opts.t0, opts.dt / sub, n, opts.save_every * sub, step, prep.threads)
        spec = dispatch.run_spec(route, grid, q_v, elements, eta=eta, guard_state=guard)
        result = run(spec)
        if result.error is not None:
            return None
        parts.append(result)
        step += n
        if step < total and seen(result, n // sub):
            break
        if result.eta is not None:
            eta = np.array(result.eta[-1], dtype=np.float64)
        else:
            q_v = (np.array(result.q[-1], dtype=np.float64),
                   np.array(result.v[-1], dtype=np.float64))  # fmt: skip
        elements = None if result.element_state is None else np.asarray(result.element_state)
        guard = None if result.guard_state is None else np.asarray(result.guard_state)
    return Joined(parts), step // sub
