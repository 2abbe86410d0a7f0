"""Events located inside the steps of a run, a run ended by a terminal event, and the
response at requested instants (``t_eval``): what ``Prepared.run`` does after the core's
run when given ``events``, ``t_eval`` or ``dense`` (docs/events.md)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.dense import Dense, hermite
from duhamel.events import Event, Occurrence
from duhamel.results.solution import ModalHistory, Solution
from duhamel.results.structural import ElementHistory

__all__ = ["dense_run", "finish", "locate", "terminal_check"]

#: Root-finding tolerance, as a fraction of the step.
XTOL = 1e-12


def _crossings(g: NDArray[np.float64], direction: int) -> NDArray[np.int64]:
    s0, s1 = g[:-1], g[1:]
    up = (s0 < 0) & (s1 >= 0)
    down = (s0 > 0) & (s1 <= 0)
    mask = up if direction > 0 else down if direction < 0 else up | down
    return np.flatnonzero(mask)


def terminal_check(events: Sequence[Event]) -> Any:
    """``check(solution)``: whether a terminal one of `events` crosses (or is not finite)
    along `solution`'s saved rows, as :func:`locate` finds its crossings; None without a
    terminal event. A run in chunks stops after the first chunk where it is true."""
    terminal = [ev for ev in events if ev.terminal]
    if not terminal:
        return None

    def check(sol: Solution) -> bool:
        for ev in terminal:
            ev._bind(sol)
            g = ev._values(sol.t, sol.x, sol.v, sol)
            if not np.all(np.isfinite(g)) or _crossings(g, ev.direction).size:
                return True
        return False

    return check


def locate(events: Sequence[Event], sol: Solution, dense: Dense) -> list[Occurrence]:
    """Every crossing of `events` along `sol`, in time order, each located inside its step
    by root finding (Brent) on `dense`'s interpolant to ``XTOL`` of the step; a crossing
    that happens and undoes itself inside one step is not seen."""
    from scipy.optimize import brentq

    t = dense.t
    found: list[tuple[float, int, Occurrence]] = []
    for k, ev in enumerate(events):
        ev._bind(sol)
        g = ev._values(t, dense.x, dense.v, sol)
        if not np.all(np.isfinite(g)):
            row = int(np.argmin(np.isfinite(g)))
            raise ValueError(
                f"event {ev.name or k!r}: its function (`fn`, or a built-in's quantity) is "
                f"not finite at t = {t[row]:g} (value {g[row]})"
            )
        name = ev.name if ev.name is not None else f"event{k}"
        for n in _crossings(g, ev.direction):
            n = int(n)
            h = float(t[n + 1] - t[n])
            if g[n + 1] == 0.0:
                tau = h
            else:

                def f(tau: float, n: int = n, h: float = h, ev: Event = ev) -> float:
                    (x, v, _), _ = dense.in_step(n, tau)
                    return ev._value(float(t[n]) + tau, x, v, sol, n, tau / h)

                tau = brentq(f, 0.0, h, xtol=XTOL * h, rtol=1e-15, maxiter=200)
            (x, v, _), _ = dense.in_step(n, tau)
            when = float(t[n]) + tau
            occ = Occurrence(name, k, when, np.array(x), np.array(v), ev.terminal, (n, tau))
            found.append((when, k, occ))
    found.sort(key=lambda item: (item[0], item[1]))
    return [occ for _, _, occ in found]


def _cut_modal(modal: ModalHistory | None, rows: int, row: dict[str, NDArray[np.float64]] | None,
               s: float, h: float) -> ModalHistory | None:  # fmt: skip
    """The first `rows` rows of `modal` and a last one: `row` (exact) or interpolated in
    step ``rows - 1`` at the fraction `s` (``q`` by Hermite, the rest linearly)."""
    if modal is None:
        return None
    n = rows - 1

    def take(name: str, a: NDArray[np.float64] | None) -> NDArray[np.float64] | None:
        if a is None:
            return None
        if row is not None and name in row:
            extra = row[name]
        else:
            extra = (1.0 - s) * a[n] + s * a[n + 1] if n + 1 < a.shape[0] else a[n]
        return np.vstack([a[:rows], extra[None, :]])

    first = modal._first_order
    if first is None:
        if row is not None:
            q, v = row["q"], row["v"]
        else:
            q, v, _ = hermite(modal.q, modal.v, _accelerations(modal, n, h), n, s, h)
        q = np.vstack([modal.q[:rows], q[None, :]])
        v = np.vstack([modal.v[:rows], v[None, :]])
        first_new = None
    else:
        q = v = None  # type: ignore[assignment]
        first_new = (take("eta", first[0]), first[1])
    return ModalHistory(
        q, v, modal.omega, modal.c, take("load_values", modal.load_values), modal.patterns,  # type: ignore[arg-type]
        take("forcing", modal.forcing), take("pseudo", modal.pseudo),
        first_order=first_new, coupling=modal._coupling,  # type: ignore[arg-type]
    )  # fmt: skip


def _accelerations(modal: ModalHistory, n: int, h: float) -> NDArray[np.float64]:
    """The modal accelerations of rows `n`, `n + 1` for the Hermite interpolation; those of
    the massless dofs' coordinates (``omega = inf``, no inertia) are not formed: their
    velocity's secant over the step (``v`` linear there)."""
    massless = np.isinf(modal.omega)
    if not np.any(massless):
        return modal.a
    with np.errstate(invalid="ignore", over="ignore"):
        acc = modal.a[: n + 2].copy()
    acc[n : n + 2, massless] = ((modal.v[n + 1] - modal.v[n]) / h)[massless]
    return acc


def _slice_modal(modal: ModalHistory | None, rows: int) -> ModalHistory | None:
    """The first `rows` rows of `modal`."""
    if modal is None:
        return None

    def cut(a: NDArray[np.float64] | None) -> NDArray[np.float64] | None:
        return None if a is None else a[:rows]

    first = modal._first_order
    return ModalHistory(
        None if first else modal.q[:rows], None if first else modal.v[:rows], modal.omega,
        modal.c, modal.load_values[:rows], modal.patterns, cut(modal.forcing),
        cut(modal.pseudo), first_order=None if first is None else (first[0][:rows], first[1]),
        coupling=modal._coupling,
    )  # fmt: skip


def _cut_elements(
    elements: tuple[ElementHistory, ...], t: NDArray[np.float64], rows: int, s: float
) -> tuple[ElementHistory, ...]:
    n = rows - 1

    def take(a: NDArray[np.float64]) -> NDArray[np.float64]:
        extra = (1.0 - s) * a[n] + s * a[n + 1] if n + 1 < a.shape[0] else a[n]
        return np.vstack([a[:rows], extra[None, :]])

    return tuple(
        ElementHistory(e.element, t, take(e.x), take(e.v), take(e.force)) for e in elements
    )


def _with_rows(sol: Solution, t: NDArray[np.float64], x: NDArray[np.float64],
               v: NDArray[np.float64], a: NDArray[np.float64], modal: ModalHistory | None,
               elements: Any) -> Solution:  # fmt: skip
    out = Solution(t, x, v, a, sol.dofs, modal, sol.stats, sol.meta, elements=elements,
                   base=sol._base)  # fmt: skip
    out.events = sol.events
    out._dense = sol._dense
    return out


def _stop(sol: Solution, dense: Dense, when: float, n: int, tau: float) -> Solution:
    """`sol` ended at `when` (`tau` into step `n`): its rows before it and the state there
    as the last row."""
    h = float(dense.t[n + 1] - dense.t[n])
    if tau >= h:  # on a grid point
        n, tau = n + 1, 0.0
    if tau <= 0.0:
        rows = n + 1
        t = sol.t[:rows]
        elements = sol._elements_source or sol.__dict__.get("elements", ())
        elements = elements() if callable(elements) else elements
        cut = tuple(ElementHistory(e.element, t, e.x[:rows], e.v[:rows], e.force[:rows])
                    for e in elements)  # fmt: skip
        modal = _slice_modal(sol.modal, rows)
        return _with_rows(sol, t, sol.x[:rows], sol.v[:rows], sol.a[:rows], modal, cut)
    (x, v, a), row = dense.in_step(n, tau)
    rows = n + 1
    t = np.append(sol.t[:rows], when)
    s = tau / h
    modal = _cut_modal(sol.modal, rows, row, s, h)
    cut = _cut_elements(sol.elements, t, rows, s) if sol.elements else ()
    return _with_rows(
        sol, t, np.vstack([sol.x[:rows], x]), np.vstack([sol.v[:rows], v]),
        np.vstack([sol.a[:rows], a]), modal, cut,
    )  # fmt: skip


def finish(
    sol: Solution,
    dense: Dense,
    events: Sequence[Event],
    t_eval: NDArray[np.float64] | None,
    keep: bool,
) -> Solution:
    """`sol` with its events located (ended at the first terminal one), at the instants
    `t_eval` if given, and with ``at`` available if `keep`."""
    sol._dense = dense if keep else None
    end = None
    if events:
        found = locate(events, sol, dense)
        stops = [o for o in found if o.terminal]
        if stops:
            end = stops[0].time
            found = [o for o in found if o.time <= end]
            sol = _stop(sol, dense, end, *stops[0]._step)
            dense.end = end
        sol.events = found
    if t_eval is not None:
        times = t_eval if end is None else t_eval[t_eval <= end]
        x, v, a = dense.at(times)
        out = Solution(times, x, v, a, sol.dofs, None, sol.stats, sol.meta, base=sol._base)
        out.events = sol.events
        out._dense = sol._dense
        sol = out
    return sol


def dense_run(
    run: Any,
    events: Sequence[Event],
    t_eval: NDArray[np.float64] | None,
    keep: bool,
) -> Solution:
    """``run()`` (a run saving every step) finished by :func:`finish`. A run that fails
    (``SolverError``) after a terminal event returns the solution ended at that event;
    otherwise the failure is raised as it was."""
    from duhamel.errors import SolverError

    try:
        sol = run()
    except SolverError as exc:
        partial = exc.partial
        if not any(ev.terminal for ev in events) or partial is None or partial.t.size < 2:
            raise
        dense = _dense_of(partial)
        ended = finish(partial, dense, events, None, keep=False)
        if not (ended.events and ended.events[-1].terminal):
            raise
        return finish(partial, dense, events, t_eval, keep)
    return finish(sol, _dense_of(sol), events, t_eval, keep)


def _dense_of(sol: Solution) -> Dense:
    if sol.t.size < 2:
        raise ValueError("`events`, `t_eval` and `dense` need a run of at least one step")
    return Dense(sol.t, sol.x, sol.v, lambda: sol.a, sol._exact)
