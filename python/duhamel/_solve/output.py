"""The one way from a modal run's history to the physical response, for every route.

Displacements and velocities of the output dofs come with the run (mapped by the engine
during a first-order run, one matrix product each otherwise); accelerations are computed on
first access from the modal equations, ``a = Phi_out (p + pseudo - D q' - S q)``.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from types import SimpleNamespace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._solve.plan import Plan
from duhamel.solution import ModalHistory

__all__ = ["check_memory", "output_maps", "physical"]


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


def output_maps(plan: Plan, phi_out: NDArray, n_loads: int) -> Any:
    """What the engine maps during a first-order run: ``[x | v]`` of the output dofs from
    ``[Re eta | Im eta]`` (the loads add nothing to them)."""
    modes = plan.modes
    assert modes is not None
    m = plan.basis.n_modes
    tq, tv = modes.back[:, :m], modes.back[:, m:]
    out_map = np.ascontiguousarray(np.concatenate([tq @ phi_out.T, tv @ phi_out.T], axis=1))
    return SimpleNamespace(
        map=out_map, loads=np.zeros((n_loads, out_map.shape[1])), n_cols=out_map.shape[1]
    )


def _finite_rows(x: NDArray, v: NDArray) -> int:
    """The number of leading rows whose displacements and velocities are finite."""
    finite = np.isfinite(x).all(axis=1) & np.isfinite(v).all(axis=1)
    return int(finite.size if finite.all() else np.argmin(finite))


def physical(
    result: Any, plan: Plan, phi_out: NDArray, patterns: NDArray
) -> tuple[int, NDArray, NDArray, Callable[[], NDArray], ModalHistory]:
    """The physical response of the output dofs from a modal run's `result`.

    Returns ``(kept, x, v, a, modal)``: `kept` rows (fewer than the run saved when a diverged
    run's outputs overflowed before its coordinates), ``x`` and ``v``, the accelerations as a
    function evaluated on first access, and the modal history.
    """
    basis = plan.basis
    n_out = phi_out.shape[0]
    failed = result.error is not None
    # A diverged run's last rows are near overflow: their products may overflow quietly.
    mode = "ignore" if failed else "warn"
    if result.eta is None:
        q, vel = result.q, result.v
        with np.errstate(over=mode, invalid=mode):
            x, v = q @ phi_out.T, vel @ phi_out.T
        coupling = None
        first_order = None
    else:
        out = result.outputs
        x, v = out[:, :n_out], out[:, n_out : 2 * n_out]
        coupling = (plan.couplings.k, plan.couplings.c)
        assert plan.modes is not None
        first_order = (result.eta, plan.modes.back)
    kept = _finite_rows(x, v) if failed else x.shape[0]
    cut = (lambda a: a) if kept == x.shape[0] else (lambda a: None if a is None else a[:kept])
    x, v = cut(x), cut(v)
    values, forcing, pseudo = cut(result.load_values), cut(result.forcing), cut(result.pseudo)
    if first_order is not None:
        first_order = (cut(first_order[0]), first_order[1])
        q = vel = None
    else:
        q, vel = cut(q), cut(vel)
    modal = ModalHistory(
        q=q,
        v=vel,
        omega=basis.omega,
        c=basis.c,
        load_values=values,
        patterns=patterns,
        forcing=forcing,
        pseudo=pseudo,
        first_order=first_order,
        coupling=coupling,
    )

    def acceleration() -> NDArray:
        with np.errstate(over=mode, invalid=mode):
            return state_part() + load_part()

    def state_part() -> NDArray:
        """``-(S q + D q')`` of the output dofs, couplings included, one pass over the history."""
        if first_order is None:
            a = modal.q @ (-phi_out * basis.omega2).T + modal.v @ (-phi_out * basis.c).T
        else:
            eta, back = first_order
            m = basis.n_modes
            s = np.diag(basis.omega2) + (0.0 if coupling[0] is None else coupling[0])
            d = np.diag(basis.c) + (0.0 if coupling[1] is None else coupling[1])
            a = eta @ (-(back[:, :m] @ s.T + back[:, m:] @ d.T) @ phi_out.T)
        return a

    def load_part() -> NDArray:
        """``p + pseudo`` of the output dofs."""
        a = values @ (phi_out @ patterns).T
        for extra in (forcing, pseudo):
            if extra is not None:
                a += extra @ phi_out.T
        return a

    return kept, x, v, acceleration, modal
