"""The physical model of a run for its structural outputs (base shear, energy): the matrices,
the elements' global dofs and the support loads, as a
:class:`duhamel.results.forces.StructureModel`, made on first use."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.direct import damping_matrix, physical_matrices
from duhamel.feedback import Feedback
from duhamel.loads import BaseAcceleration
from duhamel.results.forces import StructureModel

__all__ = ["structure_model"]


def structure_model(
    system: Any, basis: Any = None, elements: Any = None, loads: Any = None
) -> StructureModel:
    """The :class:`StructureModel` of `system`; `basis` (the run's modes) gives the damping
    of modal damping ratios when the system's own full basis is not what the run used;
    `elements` and `loads`: the system's as they were at the run (default: as they are)."""
    elements = tuple(system.elements) if elements is None else tuple(elements)
    loads = tuple(system.loads) if loads is None else tuple(loads)
    if system.mass_law is not None:
        raise ValueError(
            "structural outputs (base shear, energy) need a constant mass matrix; this system "
            "has a time-varying mass law"
        )
    mats = physical_matrices(system) if system.damping != "zeta" else None
    # (physical_matrices reads the system's current couplings; they are checked below)
    if mats is not None:
        if mats["scaled"]:
            raise ValueError(
                "structural outputs (base shear, energy) need constant matrices; this system "
                "has couplings scaled by a speed law"
            )
        k, c = mats["k"], mats["c"]
        if mats["k_fixed"] is not None:
            k = k + mats["k_fixed"]
    else:
        k = system.K
        try:
            c = damping_matrix(system)
        except ValueError:
            if basis is None:
                raise
            mphi = np.asarray(system.M @ basis.phi)
            c = (mphi * basis.c) @ mphi.T
        for coupling in system.couplings:
            if isinstance(coupling, Feedback):
                raise ValueError(
                    "structural outputs (base shear, energy) need the forces of the model's "
                    "matrices; this system has feedback states (controllers) that push too"
                )
            factor = coupling.constant_factor()
            if factor is None:
                raise ValueError(
                    "structural outputs (base shear, energy) need constant matrices; this "
                    "system has couplings scaled by a speed law"
                )
            if coupling.K is not None:
                k = k + factor * coupling.K
            if coupling.C is not None:
                c = factor * coupling.C if c is None else c + factor * coupling.C
    alpha = float(system.rayleigh[0]) if system.damping == "rayleigh" else 0.0
    forces = tuple((e, np.asarray(e._dofs, dtype=np.int64)) for e in elements)
    base: list[tuple[NDArray[np.float64], Callable[[Any], Any]]] = [
        (np.asarray(load.direction_vector, dtype=np.float64), load._scalar)
        for load in loads
        if isinstance(load, BaseAcceleration)
    ]
    others = sum(1 for load in loads if not isinstance(load, BaseAcceleration))
    return StructureModel(system.M, k, c, alpha, forces, base, others)
