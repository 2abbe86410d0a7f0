"""The `Solution` of a streamed run, its arrays read from the store, and the failure of a
segment located on the whole run's grid."""

from __future__ import annotations

import time as _time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.background import LinearPart
from duhamel.loads import support_terms
from duhamel.results.solution import ModalHistory, Solution, SolveStats
from duhamel.results.structural import ElementHistory
from duhamel.store._array import StoredArray
from duhamel.store._energy import stored_model
from duhamel.store._ledger import Guard, Ledger
from duhamel.store._model import Model

__all__ = ["_shifted", "_solution"]


def _solution(
    group: Any,
    model: Model,
    grid: dict,
    rows: int,
    wall: float,
    counts: NDArray[np.int64],
    depth: int,
    started: float,
    *,
    elements: list[Any] | None = None,
    base: list[Any] | None = None,
    ledger: Ledger | None = None,
) -> Solution:
    """The Solution of the first `rows` stored rows, its arrays read from the store through
    a guard that checks each chunk read (against `ledger`, format 3; its CRC-32C alone for
    a legacy store, `ledger` None)."""
    data = group["data"]
    dofs = np.asarray(grid["dofs"], dtype=np.int64)
    path = str(getattr(group.store, "root", group.store))

    def read(name: str, columns: slice | None = None) -> Any:
        if name not in data:
            return None
        arr = data[name]
        guard = Guard(path, name, arr, grid["chunk_rows"], ledger)
        return StoredArray(arr, rows, columns, guard)

    t = read("t")
    basis = model.basis
    first_order = None
    coupling = None
    if "modal_eta" in data:
        assert model.modes is not None
        first_order = (read("modal_eta"), model.modes.back)
        coupling = (model.coupling_k, model.coupling_c)
    modal = (
        None
        if "load_values" not in data
        else ModalHistory(
            q=read("modal_q"),
            v=read("modal_v"),
            omega=basis.omega,
            c=basis.c,
            load_values=read("load_values"),
            patterns=model.patterns(),
            forcing=read("forcing"),
            pseudo=read("pseudo"),
            first_order=first_order,  # type: ignore[arg-type]
            coupling=coupling,
        )
    )
    histories: tuple[ElementHistory, ...] = ()
    if "element_force" in data and model.devices:
        objects = model.element_objects() if elements is None else elements
        widths = data["element_force"].attrs.get("widths")
        if isinstance(widths, list) and len(widths) == len(objects):
            out, at = [], 0
            for element, width in zip(objects, widths, strict=True):
                cut = slice(at, at + width)
                xs, vs, fs = (read(k, cut) for k in ("element_x", "element_v", "element_force"))
                part = model.linear[len(out)] if model.linear else None
                if part is not None:
                    fs = fs + LinearPart(tuple(part[0]), part[1], part[2]).force(xs, vs)
                out.append(ElementHistory(element, t, xs, vs, fs))
                at += width
            histories = tuple(out)
    if base is None:
        base = support_terms(model.base_loads(), dofs)
    sol = Solution(
        t=t,
        x=read("x"),
        v=read("v"),
        a=read("a"),
        dofs=dofs,
        modal=modal,
        stats=SolveStats(
            steps=min(grid["n_steps"], max(0, rows - 1) * grid["save_every"])
            if rows < grid["rows"]
            else grid["n_steps"],
            wall_time=wall,
            total_time=_time.perf_counter() - started,
            modes=basis.n_modes,
            newton_iterations=int(counts[0]),
            closed_form_steps=int(counts[1]),
            factorizations=int(counts[2]),
            subdivided_steps=int(counts[3]),
            subdivision_depth=int(depth),
            coupling=model.coupling,
            eigenvector_condition=None if model.modes is None else model.modes.condition,
        ),
        meta={
            "dt": grid["dt"],
            "t0": grid["t0"],
            "integrator": model.semianalytic(),
            "labels": model.labels,
            "store": path,
        },
        elements=histories,
        base=base,
    )
    if "energy" in data and "energy" in grid:
        objects = tuple(h.element for h in histories)
        sol._energy_run = (np.asarray(read("energy")), stored_model(grid["energy"], objects))
    return sol


@dataclass(frozen=True)
class ShiftedError:
    """A segment's run failure (the fields of a ``_core.RunError``) with its step counted
    from the start of the run."""

    kind: str
    message: str
    time: float
    step: int
    cause: Any


def _shifted(error: Any, step0: int) -> ShiftedError:
    """A segment's ``RunError`` with its step counted from the start of the run."""
    step = int(error.step) + step0
    message = str(error.message).replace(f"step {error.step}", f"step {step}")
    return ShiftedError(error.kind, message, error.time, step, error.cause)
