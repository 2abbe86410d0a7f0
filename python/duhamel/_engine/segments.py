"""A modal run in segments: the one loop of a run taken in parts.

Each segment continues the one before exactly: from the last saved state, with the elements'
committed variables and the growth guard's bounds carried (:class:`Carry`) and the grid
counted from the run's start, so the joined history equals a whole run's, bit for bit. Two
sinks take a run this way: a run in memory that stops after the part where a terminal event
crosses (:func:`chunked`: the work after the event is not done), and a streamed run written
segment by segment into its store, with checkpoints (``duhamel.store``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine import dispatch
from duhamel._engine.plan import Plan

__all__ = ["CHUNKS", "SMALLEST", "Carry", "Grid", "Joined", "Part", "chunked", "segments"]

#: Chunks of a run stopped by a terminal event: the check's cost is linear in the rows, so a
#: run is checked this many times at most (and the work after the stop is at most this
#: fraction of the run).
CHUNKS = 32
#: Fewest steps of a chunk (a core run's set-up is amortised over them).
SMALLEST = 256

_ARRAYS = ("t", "q", "v", "eta", "outputs", "load_values", "forcing", "pseudo",
           "element_x", "element_v", "element_force")  # fmt: skip


@dataclass(frozen=True, eq=False)
class Carry:
    """What a segment starts from: the state (``q | v``, or ``Re eta | Im eta`` on the
    first-order route), the elements' committed variables and the growth guard's bounds
    (None: from their initial values; the guard counted from this segment's start)."""

    state: NDArray[np.float64]
    element_state: NDArray[np.float64] | None = None
    guard_state: NDArray[np.float64] | None = None

    @staticmethod
    def after(result: Any) -> Carry:
        """The carry at the end of a core run's `result` (its last saved row)."""
        if result.eta is not None:
            state = np.array(result.eta[-1], dtype=np.float64)
        else:
            state = np.concatenate([result.q[-1], result.v[-1]])
        elements = None if result.element_state is None else np.asarray(result.element_state)
        guard = None if result.guard_state is None else np.asarray(result.guard_state)
        return Carry(state, elements, guard)


@dataclass(frozen=True, eq=False)
class Grid:
    """A modal run's grid of (internal) steps, ``t0 + n dt``, and its route: what every
    segment's ``_core.RunSpec`` is made of. `q0`, `v0`: the run's initial modal state (what
    the first-order route's spec carries besides its coordinates)."""

    route: Plan
    t0: float
    dt: float
    n_steps: int
    save_every: int
    threads: int | None
    q0: NDArray[np.float64]
    v0: NDArray[np.float64]

    def start(self) -> Carry:
        """The carry of the run's start."""
        if self.route.route == "first-order":
            return Carry(dispatch.eta0(self.route, self.q0, self.v0))
        return Carry(np.concatenate([self.q0, self.v0]))

    def whole(self, energy: Any = None) -> Any:
        """The ``_core.RunSpec`` of the whole grid from the run's start (:meth:`spec` from
        :meth:`start`, without taking the state apart)."""
        grid = dispatch.grid(self.t0, self.dt, self.n_steps, self.save_every, 0, self.threads)
        return dispatch.run_spec(self.route, grid, (self.q0, self.v0), energy=energy)

    def spec(self, step0: int, n: int, carry: Carry, energy: Any = None) -> Any:
        """The ``_core.RunSpec`` of `n` steps from grid point `step0`, from `carry`; `energy`
        the integrals to accumulate (a ``_core.EnergySpec``) or None."""
        grid = dispatch.grid(self.t0, self.dt, n, self.save_every, step0, self.threads)
        if self.route.route == "first-order":
            return dispatch.run_spec(
                self.route, grid, (self.q0, self.v0), carry.element_state, eta=carry.state,
                guard_state=carry.guard_state, energy=energy,
            )  # fmt: skip
        m = self.q0.size
        halves = (np.ascontiguousarray(carry.state[:m]), np.ascontiguousarray(carry.state[m:]))
        return dispatch.run_spec(
            self.route, grid, halves, carry.element_state, guard_state=carry.guard_state,
            energy=energy,
        )  # fmt: skip


class Part:
    """A segment run: steps ``step0 .. step0 + n`` and the core's `result`."""

    def __init__(self, step0: int, n: int, result: Any) -> None:
        self.step0, self.n, self.result = step0, n, result
        self._carry: Carry | None = None

    def carry(self) -> Carry:
        """The carry at its end (made once)."""
        if self._carry is None:
            self._carry = Carry.after(self.result)
        return self._carry


def segments(
    total: int,
    size: int,
    first: Carry,
    advance: Callable[[int, int, Carry], Any],
    step: int = 0,
) -> Iterator[Part]:
    """The segments of grid points ``step .. total``, at most `size` steps each, from
    `first`: ``advance(step0, n, carry)`` runs one in the core. The consumer stops the run
    by leaving the loop (a failed segment, a terminal event)."""
    carry = first
    while step < total:
        n = min(size, total - step)
        part = Part(step, n, advance(step, n, carry))
        yield part
        carry = part.carry()
        step += n


class Joined:
    """The ``RunResult`` of consecutive segments: their histories end to end (each one's
    first row, its start, is the row the one before ended with, and is left out), their
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
    grid: Grid,
    sub: int,
    run: Callable[[Any], Any],
    seen: Callable[[Any, int], bool],
) -> tuple[Joined, int] | None:
    """Runs `grid` (`sub` internal steps per step) in chunks; `run(spec)` runs one chunk in
    the core, ``seen(result, steps)`` says whether a chunk's result (``steps`` user steps)
    holds a terminal crossing. Returns the joined result and the user steps taken, or None
    when a chunk failed (the caller runs the whole grid again, so a failure is raised as a
    whole run raises it)."""
    total = grid.n_steps
    size = max(SMALLEST * sub, -(-total // CHUNKS))
    size = -(-size // sub) * sub  # whole user steps
    parts: list[Any] = []
    step = 0
    for part in segments(total, size, grid.start(), lambda s, n, c: run(grid.spec(s, n, c))):
        if part.result.error is not None:
            return None
        parts.append(part.result)
        step = part.step0 + part.n
        if step < total and seen(part.result, part.n // sub):
            break
    return Joined(parts), step // sub
