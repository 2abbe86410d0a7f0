"""The one way from a modal run's history to the physical response, for every route.

Displacements and velocities of the output dofs come with the run (mapped by the engine
during a first-order run, one matrix product each otherwise); accelerations are computed on
first access from the modal equations, ``a = Phi_out (p + pseudo - D q' - S q)`` (the
coordinates of massless dofs, without inertia, contribute none: docs/basis.md).
"""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.plan import Plan
from duhamel.results.solution import ModalHistory

__all__ = ["ROW_BLOCK", "check_memory", "physical", "rows_product"]

#: Rows per matrix product of :func:`rows_product`.
ROW_BLOCK = 1024


def rows_product(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """``a @ b`` computed in blocks of :data:`ROW_BLOCK` rows of `a` from its first row.

    BLAS rounds a row of a product differently depending on where it falls in the blocking
    of the rows (and a single row takes another kernel), so ``(a @ b)[i]`` is not always
    ``a[i:j] @ b``'s first row. Computed block by block, the rows of a history split at
    multiples of :data:`ROW_BLOCK` (a streamed run, ``duhamel.store``) come out bit for bit
    as those of the whole history.
    """
    n = a.shape[0]
    if n == 0:  # no row kept (a run failing on its initial state): whatever `a`'s width
        return np.empty((0, b.shape[1]), dtype=np.result_type(a, b))
    if n <= ROW_BLOCK:
        return a @ b
    out = np.empty((n, b.shape[1]), dtype=np.result_type(a, b))
    for start in range(0, n, ROW_BLOCK):
        out[start : start + ROW_BLOCK] = a[start : start + ROW_BLOCK] @ b
    return out


@functools.cache
def _physical_memory() -> float:
    """The machine's physical memory in bytes (unbounded where it cannot be read)."""
    try:
        return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, OSError, ValueError):  # pragma: no cover - not POSIX
        return math.inf


def check_memory(n_steps: int, save_every: int, n_out: int, history_width: int) -> None:
    """Refuses a run whose saved history (`history_width` numbers per saved instant, kept by
    the engine) and physical response (``x``, ``v``, ``a`` of `n_out` dofs) cannot fit in
    the machine's memory, before anything is computed; the message says what it needs and
    what to change."""
    n_saved = n_steps // save_every + 1 + (1 if n_steps % save_every else 0)
    need = 8.0 * n_saved * (history_width + 3 * n_out)
    have = _physical_memory()
    if need > have:
        gib = 1024.0**3
        raise ValueError(
            f"`save_every` is too small for this run: keeping {n_saved:,} instants of "
            f"{n_out} dofs (x, v, a) and the modal history needs {need / gib:.3g} GiB, more "
            f"than the machine's {have / gib:.1f} GiB of memory; save fewer steps (a larger "
            "`save_every` or a shorter `t_end`), fewer `dofs` or fewer modes"
        )


#: ``ndarray.sum`` of every entry, without its Python-level wrapper (a run's finiteness test).
_SUM = np.add.reduce


def _finite_rows(*arrays: NDArray[np.float64]) -> int:
    """The number of leading rows finite in every one of `arrays`."""
    finite = np.logical_and.reduce([np.isfinite(a).all(axis=1) for a in arrays])
    return int(finite.size if finite.all() else np.argmin(finite))


def physical(
    result: Any, plan: Plan, phi_out: NDArray[np.float64], patterns: NDArray[np.float64]
) -> tuple[
    int,
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.float64] | Callable[[], NDArray[np.float64]],
    ModalHistory,
]:
    """The physical response of the output dofs from a modal run's `result`.

    Returns ``(kept, x, v, a, modal)``: ``x`` and ``v`` of the output dofs, the accelerations
    (a function evaluated on first access) and the modal history. A run that stopped early,
    or whose physical outputs overflowed although its coordinates did not (`kept` < the rows
    saved: the caller raises), keeps only its leading rows whose ``x``, ``v`` and ``a`` are
    all finite, and its accelerations are computed at once to find them.
    """
    n = result.t.size
    error = result.error
    with np.errstate(over="ignore", invalid="ignore"):
        x, v, acceleration, modal = _assemble(result, plan, phi_out, patterns, n)
        # Sums are finite when every entry is (a finite sum that overflows only sends the
        # check to the exact one, row by row).
        overflowed = error is None and not (
            math.isfinite(_SUM(x, None) + _SUM(v, None)) or _finite_rows(x, v) == n
        )
    if error is None and not overflowed:

        def checked() -> NDArray[np.float64]:
            with np.errstate(over="ignore", invalid="ignore"):
                a = acceleration()
            row = _finite_rows(a)
            if row < n:
                when = float(result.t[row])
                raise FloatingPointError(
                    f"the accelerations of the output dofs overflow at t = {when!r} "
                    "(omega^2 x beyond the double range) while the displacements stay finite; "
                    "rescale the model's units (mass, stiffness, time)"
                )
            return a

        return n, x, v, checked, modal
    # A failed run, or one whose physical outputs overflowed (the caller raises then).
    with np.errstate(over="ignore", invalid="ignore"):
        kept = _finite_rows(x, v)
        x, v, acceleration, modal = _assemble(result, plan, phi_out, patterns, kept)
        a = acceleration()
        finite = _finite_rows(a)
        if finite < kept:
            kept = finite
            x, v, _, modal = _assemble(result, plan, phi_out, patterns, kept)
            a = a[:kept]
    return kept, x, v, a, modal


def _assemble(
    result: Any, plan: Plan, phi_out: NDArray[np.float64], patterns: NDArray[np.float64], rows: int
) -> tuple[
    NDArray[np.float64], NDArray[np.float64], Callable[[], NDArray[np.float64]], ModalHistory
]:
    """``x``, ``v``, the accelerations (as a function) and the modal history of the first
    `rows` saved instants."""
    basis = plan.basis
    n_out = phi_out.shape[0]

    whole = rows == result.t.size

    m = basis.n_modes

    def cut(a: NDArray[np.float64] | None, width: int = m) -> NDArray[np.float64] | None:
        if a is not None and rows == 0:  # nothing kept: no row, the right columns
            return np.empty((0, a.shape[1] if a.ndim == 2 and a.shape[1] else width))
        return a if a is None or whole else a[:rows]

    values = cut(result.load_values, patterns.shape[1])
    forcing, pseudo = cut(result.forcing), cut(result.pseudo)
    if result.eta is None:
        q, vel = cut(result.q), cut(result.v)
        x, v = rows_product(q, phi_out.T), rows_product(vel, phi_out.T)  # type: ignore[arg-type]
        coupling = None
        first_order = None
    else:
        out = cut(result.outputs, 3 * n_out)
        x, v = out[:, :n_out], out[:, n_out : 2 * n_out]  # type: ignore[index]
        coupling = (plan.couplings.k, plan.couplings.c)
        assert plan.modes is not None
        first_order = (cut(result.eta, plan.modes.back.shape[0]), plan.modes.back)
        q = vel = None
    modal = ModalHistory(
        q=q,
        v=vel,
        omega=basis.omega,
        c=basis.c,
        load_values=values,  # type: ignore[arg-type]
        patterns=patterns,
        forcing=forcing,
        pseudo=pseudo,
        first_order=first_order,  # type: ignore[arg-type]
        coupling=coupling,
    )

    def acceleration() -> NDArray[np.float64]:
        """``Phi_out (p + pseudo - S q - D q')``: the modal accelerations first, then one
        product with the mode shapes (whose scale may be far from that of ``S``)."""
        massless = np.isinf(basis.omega2)  # coordinates of massless dofs: no inertia
        if first_order is None:
            if np.any(massless):  # their modal acceleration is not formed: 0
                k, c = np.where(massless, 0.0, basis.omega2), np.where(massless, 0.0, basis.c)
                a = -(modal.q * k) - modal.v * c
            else:
                a = -(modal.q * basis.omega2) - modal.v * basis.c
        else:
            eta, back = first_order
            m = basis.n_modes
            q, vel = rows_product(eta, back[:, :m]), rows_product(eta, back[:, m:])  # type: ignore[arg-type]
            a = -(q * basis.omega2) - vel * basis.c
            for part, matrix in ((q, coupling[0]), (vel, coupling[1])):  # type: ignore[index]
                if matrix is not None:
                    a -= rows_product(part, np.asarray(matrix).T)
        a += rows_product(values, patterns.T)  # type: ignore[arg-type]
        for extra in (forcing, pseudo):
            if extra is not None:
                a += extra
        if np.any(massless):
            a[:, massless] = 0.0
        return rows_product(a, phi_out.T)

    return x, v, acceleration, modal
