"""The energy balance of a streamed run (``solve(..., store=..., energy=True)``): the core's
work integrals of each segment continued from the segment before (their totals and the
ground velocities carried, in memory and with each checkpoint), written with the state
functions of the saved instants as the store's ``energy`` array.

The stored columns are the core's (``[damping, input, absolute - relative input, v_g per
base, work per element]``, counted from the run's start) followed by the kinetic energy,
the linear strain energy and ``w_b . v`` per base at the saved instants, so the balance is
read back without the modal history (``Store(modal=False)`` too).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.energy_run import EnergyModel, energy_model, energy_spec
from duhamel._engine.structure import structure_model
from duhamel.results.forces import StructureModel

__all__ = ["Carry", "energy_record", "load_carry", "save_carry", "segment_energy", "stored_model"]

_MATRICES = ("mm", "km", "cm", "base_w", "base_rr", "linear")


def energy_record(system: Any, model: Any) -> dict[str, Any]:
    """The energy model of a stored run as plain data for its grid record (`model` the
    captured :class:`duhamel.store._model.Model`)."""
    route = model.plan()
    structure = structure_model(system, model.basis, tuple(system.elements), tuple(system.loads))
    em = energy_model(
        system, model.basis.phi, model.patterns(), system.loads, structure, route.linear
    )
    record: dict[str, Any] = {name: np.asarray(getattr(em, name)).tolist() for name in _MATRICES}
    record["base_loads"] = [int(i) for i in em.base_loads]
    record["n_elements"] = len(structure.elements)
    return record


def stored_model(record: dict[str, Any], elements: Any = ()) -> EnergyModel:
    """The :class:`EnergyModel` of a grid record; `elements` the force elements (for their
    stored energy)."""
    arrays = {name: np.asarray(record[name], dtype=np.float64) for name in _MATRICES}
    n = arrays["mm"].shape[0]
    nb = len(record["base_loads"])
    pairs = tuple((e, np.zeros(0, dtype=np.int64)) for e in elements)
    return EnergyModel(
        mm=arrays["mm"].reshape(n, n),
        km=arrays["km"].reshape(n, n),
        cm=arrays["cm"].reshape(n, n),
        base_loads=np.asarray(record["base_loads"], dtype=np.int64),
        base_w=arrays["base_w"].reshape(nb, n),
        base_rr=arrays["base_rr"].reshape(nb, nb),
        structure=StructureModel(None, None, None, 0.0, pairs, []),
        linear=arrays["linear"],
    )


class Carry:
    """The integrals' totals at the end of the segments run so far (`totals`, one per core
    column, the ground velocities' columns 0) and the ground velocities `vg`."""

    def __init__(self, n_cols: int, nb: int, values: NDArray[np.float64] | None = None) -> None:
        self.nb = nb
        self.totals = np.zeros(n_cols) if values is None else np.array(values[:n_cols])
        self.vg = np.zeros(nb) if values is None else np.array(values[3 : 3 + nb])
        self.totals[3 : 3 + nb] = 0.0

    def values(self) -> NDArray[np.float64]:
        out = self.totals.copy()
        out[3 : 3 + self.nb] = self.vg
        return out


def segment_energy(result: Any, em: EnergyModel, carry: Carry) -> tuple[NDArray[np.float64], Carry]:
    """A segment's stored energy rows (the core's integrals continued from `carry`, then the
    state functions) and the carry at its last row."""
    rows = np.asarray(result.energy) + carry.totals
    q, v = np.asarray(result.q), np.asarray(result.v)
    kinetic = 0.5 * np.einsum("ij,ij->i", v, v @ em.mm.T)
    strain = 0.5 * np.einsum("ij,ij->i", q, q @ em.km.T)
    states = np.column_stack([kinetic, strain, v @ em.base_w.T])
    last = Carry(rows.shape[1], carry.nb, rows[-1]) if rows.shape[0] else carry
    return np.hstack([rows, states]), last


def spec_of(em: EnergyModel, carry: Carry) -> Any:
    """The core's spec of a segment starting from `carry`."""
    return energy_spec(em, carry.vg)


def save_carry(group: Any, seq: int, carry: Carry) -> None:
    """Writes the carry of checkpoint `seq` beside it (slot ``seq % 2``), before it."""
    slots = group.require_group("energy_carry")
    blob = np.concatenate([[float(seq)], carry.values()])
    slots.create_array(str(seq % 2), shape=blob.shape, dtype="f8", overwrite=True)
    slots[str(seq % 2)][...] = blob


def load_carry(group: Any, seq: int, n_cols: int, nb: int) -> Carry | None:
    """The carry written with checkpoint `seq` (None: missing or not that checkpoint's)."""
    try:
        blob = np.asarray(group["energy_carry"][str(seq % 2)][...])
    except Exception:  # a missing or damaged slot: the caller starts again
        return None
    if blob.shape != (n_cols + 1,) or blob[0] != seq or not np.all(np.isfinite(blob)):
        return None
    return Carry(n_cols, nb, blob[1:])
