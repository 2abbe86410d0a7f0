"""What a run that accumulates its energy (``solve(..., energy=True)``) gives the core, and
what its :class:`duhamel.Solution` keeps to finish the balance: the modal damping matrix,
the base excitations (which core load is which ground acceleration, ``Phi^T M r``,
``r^T M r'``), and the modal mass and stiffness of the state functions.

The work integrals are accumulated in the core every step
(``crates/duhamel-core/src/energy.rs``); :func:`duhamel.results.energy.energy_from_run`
adds the state functions at the saved instants.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel import _core
from duhamel._engine import dispatch
from duhamel.loads import BaseAcceleration, Callable
from duhamel.results.forces import StructureModel

__all__ = [
    "EnergyModel",
    "direct_energy_model",
    "energy_model",
    "energy_spec",
    "stepwise",
]


@dataclass(frozen=True, eq=False)
class EnergyModel:
    """The modal model of a run's energy balance.

    Attributes
    ----------
    mm, km : ndarray, shape (n_modes, n_modes)
        ``Phi^T M Phi`` and ``Phi^T K Phi`` (``K`` the linear stiffness, constant couplings
        included; the elements' linear parts are theirs).
    cm : ndarray, shape (n_modes, n_modes)
        ``Phi^T C Phi``.
    base_loads : ndarray of int
        The index among the run's core loads of each base excitation's ground acceleration.
    base_w : ndarray, shape (n_bases, n_modes)
        ``Phi^T M r`` of each base excitation.
    base_rr : ndarray, shape (n_bases, n_bases)
        ``r^T M r'``.
    structure : StructureModel
        The physical model (the elements, for their stored energy).
    linear : ndarray
        The linear parts the background took over from the elements (``k0`` then ``c0``
        per element, flattened; empty: none), added back to their recorded forces.
    """

    mm: NDArray[np.float64]
    km: NDArray[np.float64]
    cm: NDArray[np.float64]
    base_loads: NDArray[np.int64]
    base_w: NDArray[np.float64]
    base_rr: NDArray[np.float64]
    structure: StructureModel
    linear: NDArray[np.float64]


def _modal(matrix: Any, phi: NDArray[np.float64], n: int) -> NDArray[np.float64]:
    if matrix is None:
        return np.zeros((n, n))
    return np.ascontiguousarray(phi.T @ np.asarray(matrix @ phi), dtype=np.float64)


def energy_model(
    system: Any, phi: NDArray[np.float64], patterns: NDArray[np.float64], loads: Any,
    structure: StructureModel, linear: Any = (),
) -> EnergyModel:  # fmt: skip
    """The :class:`EnergyModel` of a run of `system` on the modes `phi` with `loads` (the
    run's load objects, projected in order into the core loads of modal `patterns`);
    `linear`: per force element, the ``LinearPart`` the background took over, or None."""
    n = phi.shape[1]
    base_loads, _, base_rr = _bases(system, loads)
    m = system.M
    base_w = np.array([-patterns[:, i] for i in base_loads]).reshape(len(base_loads), n)
    return EnergyModel(
        mm=_modal(m, phi, n),
        km=_modal(structure.k, phi, n),
        cm=_modal(structure.c, phi, n),
        base_loads=np.asarray(base_loads, dtype=np.int64),
        base_w=np.ascontiguousarray(base_w),
        base_rr=np.ascontiguousarray(base_rr),
        structure=structure,
        linear=_linear(structure, linear),
    )


def _bases(
    system: Any, loads: Any
) -> tuple[list[int], list[NDArray[np.float64]], NDArray[np.float64]]:
    """The index among the core loads of each base excitation, its influence vector, and
    ``r^T M r'``."""
    index, base_loads, directions = 0, [], []
    for item in loads:
        if isinstance(item, Callable):
            continue
        count = len(item._terms(system))
        if isinstance(item, BaseAcceleration) and count == 1:
            base_loads.append(index)
            directions.append(np.asarray(item.direction_vector, dtype=np.float64))
        index += count
    mr = [np.asarray(system.M @ r, dtype=np.float64).ravel() for r in directions]
    rr = np.array([[float(r @ w) for w in mr] for r in directions])
    return base_loads, directions, rr.reshape(len(directions), len(directions))


def direct_energy_model(system: Any, loads: Any, structure: StructureModel) -> EnergyModel:
    """The :class:`EnergyModel` of a direct integrator's run (physical coordinates: no
    modal matrices, the damping power from the run's own ``C``)."""
    base_loads, directions, base_rr = _bases(system, loads)
    n = system.n_dof
    mr = [np.asarray(system.M @ r, dtype=np.float64).ravel() for r in directions]
    none = np.zeros((0, 0))
    return EnergyModel(
        mm=none,
        km=none,
        cm=none,
        base_loads=np.asarray(base_loads, dtype=np.int64),
        base_w=np.ascontiguousarray(np.array(mr).reshape(len(mr), n)),
        base_rr=np.ascontiguousarray(base_rr),
        structure=structure,
        linear=np.zeros(0),
    )


def _linear(structure: StructureModel, linear: Any) -> NDArray[np.float64]:
    parts = list(linear)
    if not any(p is not None for p in parts):
        return np.zeros(0)
    out = []
    for k, (_, dofs) in enumerate(structure.elements):
        w = len(dofs)
        part = parts[k] if k < len(parts) else None
        if part is None:
            out.append(np.zeros(2 * w * w))
        else:
            out += [np.asarray(part.k0, float).ravel(), np.asarray(part.c0, float).ravel()]
    return np.concatenate(out)


def energy_spec(
    model: EnergyModel, vg0: NDArray[np.float64] | None = None, back: Any = None
) -> Any:
    """The core's ``EnergySpec`` of `model`, the ground velocities starting at `vg0`
    (zeros: a run from rest of the ground); `back` the first-order route's
    back-transformation to the real modal state."""
    nb = model.base_loads.size
    vg = np.zeros(nb) if vg0 is None else np.asarray(vg0, dtype=np.float64)
    flat = None if back is None else np.ascontiguousarray(back, dtype=np.float64).ravel()
    base = (model.base_loads, model.base_w.ravel(), model.base_rr.ravel())
    return _core.EnergySpec(model.cm.ravel(), base, vg, model.linear, flat)


def stepwise(route: Any, loads: list[Any], integrator: Any) -> Any:
    """The core's model of an uncoupled route stepped one step at a time, as the pseudo-force
    route steps it with nothing to correct (the same exact modal step, to round-off), so
    that the energy integrals see every step."""
    plan = dataclasses.replace(route, route="pseudo-force", elements=[])
    return dispatch.modal_model(plan, loads, integrator, None)
