"""Streamed runs: a modal run in segments, each appended to a zarr store, with checkpoints
to resume from (docs/store.md)."""

from __future__ import annotations

import dataclasses
import os
import time as _time
from dataclasses import dataclass
from typing import Any

import numpy as np

from duhamel._core import __version__
from duhamel._engine import dispatch
from duhamel._engine.correction import substeps
from duhamel._engine.output import ROW_BLOCK, physical
from duhamel._engine.plan import plan
from duhamel._engine.request import Request
from duhamel._engine.run import Progress, failure_note, overflow_error, raise_failure, watch
from duhamel._engine.segments import Carry, Grid, segments
from duhamel._engine.validate import positive_int
from duhamel.integrators import DirectIntegrator, Semianalytic
from duhamel.loads import support_terms
from duhamel.results.solution import Solution
from duhamel.store._arrays import _columns, _write
from duhamel.store._codec import Checkpoint, dumps, encode
from duhamel.store._energy import Carry as Totals
from duhamel.store._energy import (
    energy_record,
    load_carry,
    save_carry,
    segment_energy,
    spec_of,
    stored_model,
)
from duhamel.store._integrity import damaged, digest
from duhamel.store._ledger import Ledger, new_identity
from duhamel.store._model import Model, capture
from duhamel.store._open import FORMAT, KEY, checkpoint, latest, open_store, start, zarr
from duhamel.store._solution import _shifted, _solution
from duhamel.system import System

__all__ = ["FORMAT", "SEGMENT_BYTES", "Store", "resume", "run_stored"]

#: Memory budget of one segment's saved rows (engine history and physical outputs), bytes.
#: A segment holds a multiple of 1024 saved rows (at least 1024, whatever the budget).
SEGMENT_BYTES = 32 * 2**20


@dataclass(frozen=True)
class Store:
    """Where and how :func:`duhamel.solve` streams a run (``store=Store(...)``; a plain path
    means ``Store(path)``).

    Parameters
    ----------
    path : str or os.PathLike
        The new store (a directory; refused if it exists).
    modal : bool
        Keep the modal history (``Solution.modal``: modal coordinates, load values,
        pseudo-forces), as an in-memory run does. False keeps only the times, ``x``, ``v``,
        ``a`` of the output dofs and the element histories: far less disk for long runs of
        models with many modes (``Solution.modal`` is then None).
    segment_bytes : int
        Memory budget of one segment's saved rows (engine history and physical outputs).
        A segment holds a multiple of 1024 saved rows, at least 1024.
    checkpoint_every : int
        A checkpoint every this many segments (``checkpoint_every`` of :func:`duhamel.solve`
        sets it).

    Examples
    --------
    >>> import tempfile, numpy as np, duhamel
    >>> from duhamel.store import Store
    >>> sys = duhamel.System(np.eye(2), np.diag([1.0, 4.0]), zeta=0.02)
    >>> where = Store(tempfile.mkdtemp() + "/run.zarr", modal=False, segment_bytes=2**20)
    >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=100.0, dt=0.01, dofs=[1],
    ...                     x0=[0.0, 1.0], store=where)
    >>> sol.modal is None, sol.x.shape
    (True, (10001, 1))
    """

    path: str | os.PathLike[str]
    modal: bool = True
    segment_bytes: int = SEGMENT_BYTES
    checkpoint_every: int = 1

    def __post_init__(self) -> None:
        _path(self.path)
        if not isinstance(self.modal, bool):
            raise TypeError(f"`modal` must be True or False, got {self.modal!r}")
        object.__setattr__(self, "segment_bytes", positive_int(self.segment_bytes, "segment_bytes"))
        every = positive_int(self.checkpoint_every, "checkpoint_every")
        object.__setattr__(self, "checkpoint_every", every)


def _path(store: Any, name: str = "store") -> str:
    if not isinstance(store, str | os.PathLike):
        raise TypeError(f"`{name}` must be a path (str or os.PathLike), got {type(store).__name__}")
    return os.fspath(store)


def _grid(
    model: Model, n_out: int, t0: float, dt: float, n_steps: int, s: int, budget: int
) -> dict:
    """The time grid and the segmentation: rows per segment (and chunk) from the budget."""
    m, n_loads = model.basis.n_modes, len(model.loads)
    width = 2 + 5 * n_out + 6 * m + n_loads + 6 * len(model.elements)
    rows = max(1, budget // (8 * width)) // ROW_BLOCK * ROW_BLOCK
    rows = max(ROW_BLOCK, rows)
    total = n_steps // s + 1 + (1 if n_steps % s else 0)
    return {
        "t0": t0,
        "dt": dt,
        "n_steps": n_steps,
        "save_every": s,
        "rows": total,
        "segment_rows": rows,
        "chunk_rows": min(rows, total),
    }


def run_stored(
    system: System,
    integrator: Semianalytic | DirectIntegrator,
    options: Store,
    req: Request,
    threads: int | None,
) -> Solution:
    """``duhamel.solve(..., store=...)``: creates the store `options` describes and runs
    `req` into it (the run's loads are `system`'s)."""
    path = os.fspath(options.path)
    if isinstance(integrator, DirectIntegrator):
        raise ValueError(
            f"`store`: streaming to a store is available for duhamel.Semianalytic() only, "
            f"not for {type(integrator).__name__} (direct integrators keep their state "
            "outside the engine's checkpoints); solve without `store`"
        )
    every = options.checkpoint_every
    t0, dt, n_steps, save_every = req.t0, req.dt, req.n_steps, req.save_every
    out_dofs = np.arange(system.n_dof) if req.dofs is None else req.dofs
    z = zarr()
    model = capture(system, integrator, req.x0, req.v0)
    # As duhamel.solve: static-correction coordinates under nonlinear elements resolved in
    # time (the store holds the internal grid, its saved instants unchanged).
    route = plan(system, integrator)
    correction = route.correction
    sub = substeps(route.resolve, dt)
    n_steps, save_every = n_steps * sub, save_every * sub
    grid = _grid(model, len(out_dofs), t0, dt / sub, n_steps, save_every, options.segment_bytes)
    grid["dofs"] = [int(d) for d in out_dofs]
    grid["substeps"] = sub
    grid["correction"] = [float(w) for w in correction]
    grid["checkpoint_every"] = every
    grid["modal"] = options.modal
    if not req.elements:
        grid["elements"] = False
    if req.energy:
        if model.route == "uncoupled":  # stepped one step at a time (energy_run.stepwise)
            model.route = "pseudo-force"
        grid["energy"] = energy_record(system, model)
    try:
        group = z.open_group(path, mode="w-")
    except (FileExistsError, z.errors.ContainsGroupError, z.errors.ContainsArrayError):
        raise FileExistsError(
            f"`store`: {path!r} already exists; continue it with duhamel.resume({path!r}) or "
            "delete it first"
        ) from None
    model_group = group.create_group("model")
    text = dumps(encode(model.to_tree(), model_group))
    identity = new_identity()
    # The record that makes the store a store: written last, after the model it refers to.
    group.attrs[KEY] = {
        "format": FORMAT,
        "version": __version__,
        "store": identity,
        "grid": grid,
        "model": text,
        "checksum": digest(grid, text, model_group, identity),
    }
    forces = list(system.elements)
    return _proceed(
        group,
        model,
        grid,
        start(model),
        Ledger(path, group, grid, identity),
        threads,
        req.progress,
        req.started,
        elements=forces,
        base=support_terms(system.loads, np.asarray(out_dofs, dtype=np.int64)),
    )


def resume(path: str | os.PathLike[str], progress: bool | Progress | None = None) -> Solution:
    """Continue a stored run (``duhamel.solve(..., store=path)``) from its last checkpoint.

    The run continues on its own time grid from the state, element variables and saved
    rows of the checkpoint (rows written after it are written again), and needs nothing but
    the store: the model, integrator and grid are kept in it as data. The completed result
    equals that of the uninterrupted run bit for bit. A completed store is returned as is.

    Parameters
    ----------
    path : str or os.PathLike
        The store (a directory) ``solve`` wrote.
    progress : bool or callable, optional
        As for :func:`duhamel.solve` (steps counted over the whole run).

    Returns
    -------
    Solution
        The whole run, its arrays read from the store on access
        (:class:`duhamel.store.StoredArray`).

    Raises
    ------
    FileNotFoundError
        No store at `path`.
    duhamel.store.StoreError
        Not a duhamel store, an unknown format version (format 1 stores of duhamel before
        the data checksums included), or a damaged store: a root record (grid, model)
        whose checksum does not match or whose grid no run can have, a committed data
        chunk missing, cut short, with a changed byte, or not the chunk this store wrote at
        its place (a chunk of another store, of another array or of another place in this
        one; a ``data`` folder or manifest of another store), a checkpoint of another store
        or rewritten (off the grid, or not matching the rows written before it). The
        message names the store and the chunk or checkpoint slot. A torn checkpoint slot
        (its CRC broken, as a kill during its write leaves it) is not an error: the other
        slot is used, or the run starts again when neither is intact (docs/store.md,
        "Damage"). The returned Solution's arrays check every chunk they read the same way.
        Format-2 stores are resumed (and continued) as a legacy format, with the checks it
        allows.

    Examples
    --------
    >>> import tempfile, numpy as np, duhamel
    >>> sys = duhamel.System(np.eye(1), np.eye(1), zeta=0.05)
    >>> path = tempfile.mkdtemp() + "/run.zarr"
    >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=5.0, dt=0.1, x0=[1.0],
    ...                     store=path)
    >>> again = duhamel.resume(path)           # complete: read back
    >>> bool(np.array_equal(again.x, sol.x)), again.t.shape
    (True, (51,))
    """
    started = _time.perf_counter()
    where = _path(path, "path")
    group, model, grid, ledger = open_store(where)
    at = latest(group, model, grid, where, ledger)
    return _proceed(group, model, grid, at, ledger, None, progress, started)


def _proceed(
    group: Any,
    model: Model,
    grid: dict,
    at: Checkpoint,
    ledger: Ledger | None,
    threads: int | None,
    progress: bool | Progress | None,
    started: float,
    *,
    elements: list[Any] | None = None,
    base: list[Any] | None = None,
) -> Solution:
    """Runs the segments from checkpoint `at` to the end; returns the Solution. `ledger`
    records each chunk's digest (format 3; None: a legacy format-2 store, continued as
    one)."""
    n_steps, s = grid["n_steps"], grid["save_every"]
    seg_steps = grid["segment_rows"] * s
    every = grid["checkpoint_every"]
    dofs = np.asarray(grid["dofs"], dtype=np.int64)
    phi_out = np.ascontiguousarray(model.basis.phi[dofs, :])
    route, patterns = model.plan(), model.patterns()
    core = model.core(route)
    maps = dispatch.outputs(route, phi_out, patterns.shape[1])
    data = group.require_group("data")
    em, totals = None, None
    if "energy" in grid:
        em = stored_model(grid["energy"])
        nb, n_cols = em.base_loads.size, 3 + em.base_loads.size + grid["energy"]["n_elements"]
        if at.step == 0:
            totals = Totals(n_cols, nb)
        elif ledger is None:  # format 2: the totals beside the checkpoint
            totals = load_carry(group, at.seq, n_cols, nb)
        elif at.carry is not None and at.carry.size == n_cols:
            totals = Totals(n_cols, nb, at.carry)
        else:
            raise damaged(str(ledger.path), "its checkpoint's energy totals do not fit its grid")
        if totals is None:  # the checkpoint's energy is lost: the run starts again
            at, totals = start(model), Totals(n_cols, nb)
    rows = at.rows
    # The growth guard's bounds are carried from segment to segment in memory (a resumed run
    # counts them from the checkpoint it resumes at).
    first = Carry(at.state, at.element_state)
    steps = Grid(route, grid["t0"], grid["dt"], n_steps, s, threads, model.q0, model.v0)
    counts = np.array(
        [at.newton_iterations, at.closed_form_steps, at.factorizations, at.subdivided_steps],
        dtype=np.int64,
    )
    depth, wall, seq, pending = at.subdivision_depth, at.wall_time, at.seq + 1, 0
    with watch(progress, n_steps) as report:

        def advance(step: int, n: int, carry: Carry) -> Any:
            nonlocal wall

            def seg_report(k: int, _total: int, t: float) -> Any:
                assert report is not None
                return report(step + k, n_steps, t)

            loop_start = _time.perf_counter()
            energy = None if em is None or totals is None else spec_of(em, totals)
            spec = steps.spec(step, n, carry, energy)
            result = core.run(spec, None, maps, None, None if report is None else seg_report)
            wall += _time.perf_counter() - loop_start
            return result

        for part in segments(n_steps, seg_steps, first, advance, at.step):
            result, step, n = part.result, part.step0, part.n
            final = step + n == n_steps
            kept, x, v, a, _ = physical(result, route, phi_out, patterns)
            size = result.t.size
            failed = result.error is not None or kept < size
            keep = kept if failed else (size if final else size - 1)
            if not failed:
                a = a()  # type: ignore[operator]
            arrays = _columns(result, x, v, a, grid["modal"], grid.get("elements", True))
            ended = totals
            if em is not None and totals is not None and result.energy is not None:
                arrays["energy"], ended = segment_energy(result, em, totals)
            written = _write(data, grid, arrays, rows, keep, result.element_widths)
            if ledger is not None and keep:
                ledger.record(written, rows // grid["chunk_rows"])
            if failed:
                partial = _solution(
                    group, model, grid, rows + keep, wall, counts, depth, started, ledger=ledger
                )
                if result.error is None:
                    raise overflow_error(result.t, kept, grid["dt"], grid["t0"], partial)
                _fail(result.error, step, partial, model, grid)
            rows += keep
            if em is not None:
                totals = ended
            counts += [
                result.newton_iterations,
                result.closed_form_steps,
                result.factorizations,
                result.subdivided_steps,
            ]
            depth = max(depth, int(result.subdivision_depth))
            pending += 1
            if final or pending >= every:
                end = part.carry()
                c = Checkpoint(
                    seq, step + n, rows, end.state, end.element_state,
                    *(int(k) for k in counts), depth, wall,
                )  # fmt: skip
                if ledger is not None:  # format 3: bound to the store and the rows written
                    values = None if totals is None else totals.values()
                    chain = ledger.chain(rows)
                    c = dataclasses.replace(c, store=ledger.key, chain=chain, carry=values)
                elif totals is not None:
                    save_carry(group, seq, totals)
                checkpoint(group, c)
                seq, pending = seq + 1, 0
    return _solution(
        group, model, grid, rows, wall, counts, depth, started, elements=elements, base=base,
        ledger=ledger,
    )  # fmt: skip


def _fail(error: Any, step0: int, partial: Solution, model: Model, grid: dict) -> None:
    """Raises the failure of the segment from grid point `step0` (its step counted from the
    run's start, the user's step when the run took internal steps)."""
    error = _shifted(error, step0)
    sub = int(grid.get("substeps", 1))
    note = failure_note(
        error,
        partial.modal,
        forces=bool(model.devices),
        route=model.route,
        omega=model.basis.omega,
        correction=np.asarray(grid.get("correction", []), dtype=np.float64),
        subdivisions=model.semianalytic().subdivisions,
        dt=grid["dt"],
        sub=sub,
    )
    raise_failure(error, partial, note, None if sub == 1 else -(-error.step // sub))
