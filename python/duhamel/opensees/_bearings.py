"""OpenSees' bearings as duhamel's: ``flatSliderBearing`` and ``singleFPBearing`` (2-D and
3-D) as :class:`~duhamel.elements.FrictionPendulum` with its vertical dof and the axial force
at import, ``TripleFrictionPendulum`` (3-D), ``elastomericBearingPlasticity`` (2-D) as the
bilinear it is."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from duhamel.elements import Bilinear, Element, FrictionPendulum, TripleFrictionPendulum
from duhamel.opensees._parts import Damped, Made, Refused, Untranslatable, _eq, _pair, _resp
from duhamel.opensees._read import DofMap, Printout

__all__ = ["BEARINGS", "FLAT_RADIUS", "bearing"]

#: The flat and single friction pendulum bearings.
SLIDERS = {"FlatSliderSimple2d", "FlatSliderSimple3d", "SingleFPSimple2d", "SingleFPSimple3d"}
#: A friction pendulum of this radius is flat (its gravity stiffness W/R vanishes).
FLAT_RADIUS = 1e30


def _axial_stiffness(pr: Printout, ele: dict) -> float:
    """A bearing's axial stiffness: its first material (``-P``), linear elastic."""
    mats = [str(m) for m in ele.get("materials", [])]
    mat = pr.materials.get(int(mats[0])) if mats else None
    if mat is None or mat.get("type") != "ElasticMaterial":
        kind = None if mat is None else mat.get("type")
        raise Untranslatable(f"axial material ({kind}) that is not Elastic")
    if float(mat["Epos"]) != float(mat["Eneg"]) or not float(mat["Epos"]) > 0:
        raise Untranslatable(f"axial Elastic material {mat['name']} with Epos != Eneg or <= 0")
    for m in mats[1:]:  # the moment materials stay in K: they must be linear
        other = pr.materials.get(int(m))
        if other is None or other.get("type") != "ElasticMaterial":
            raise Untranslatable(f"moment material {m} that is not Elastic")
    return float(mat["Epos"])


def _slider(ops: Any, tag: int, ele: dict, pr: Printout, dmap: DofMap, idx: dict) -> Made:
    """OpenSees' ``flatSliderBearing`` and ``singleFPBearing`` (2-D and 3-D) as duhamel's
    :class:`~duhamel.elements.FrictionPendulum` with its vertical dof: the axial force
    varies with the vertical displacement (the axial material's stiffness) and the state at
    import (the gravity load's axial force) is its initial axial force."""
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    ni, nj = (int(v) for v in ops.eleNodes(tag))
    k0 = float(ele.get("kInit", math.nan))
    if not k0 > 0:
        raise Untranslatable("bearing without a printed kInit")
    mu = _resp(ops, tag, "frictionModel", "frictionCoeff")[0]
    weight = _resp(ops, tag, "frictionModel", "normalForce")[0]
    if not weight > 0:
        raise Untranslatable(
            "bearing without axial load at import (run the gravity analysis before importing)"
        )
    if not mu > 0:
        raise Untranslatable(f"friction coefficient {mu:g} at import (duhamel's needs > 0)")
    force = np.array(_resp(ops, tag, "globalForce")[:ndm])  # the axial force at node i
    axis = int(np.argmax(np.abs(force)))
    if np.sum(np.abs(force)) - abs(force[axis]) > 1e-6 * abs(force[axis]):
        raise Untranslatable("bearing whose axis is not a global axis, or sheared at import")
    names = ("ux", "uy", "uz")[:ndm]
    shear = [c for c in names if c != names[axis]]
    pairs = [(_eq(dmap, ni, c, idx), _eq(dmap, nj, c, idx)) for c in shear]
    vertical = (_eq(dmap, ni, names[axis], idx), _eq(dmap, nj, names[axis], idx))
    basic = _resp(ops, tag, "basicDeformation")
    axial = -_resp(ops, tag, "basicForce")[0]  # compression positive
    moved = ops.nodeDisp(nj, axis + 1) - ops.nodeDisp(ni, axis + 1)
    if moved == 0.0 or basic[0] == 0.0:
        raise Untranslatable("bearing without axial deformation at import")
    along = math.copysign(1.0, basic[0] / moved)  # +1: its axis points from node i to j
    ends = [p for p in (*pairs, vertical) if p != (None, None)]
    if any(i is not None for i, _ in ends) and any(j is not None for _, j in ends):
        raise Untranslatable("bearing between two free nodes (duhamel's is to the ground)")
    free_j = any(j is not None for _, j in ends)
    if not ends:
        return [], [], [], None
    # duhamel's vertical displacement is up (uplift) on the free node: the bearing's axis
    # must point from the fixed node to the free one
    if (along > 0) != free_j or vertical == (None, None):
        raise Untranslatable(
            "bearing whose axis points from its free node to its fixed one (or whose axial "
            "dof is fixed): duhamel's vertical dof is the free node's uplift"
        )
    kv = _axial_stiffness(pr, ele)
    if abs(axial - kv * -basic[0]) > 1e-8 * abs(axial):
        raise Untranslatable(f"axial force {axial:g} != kv times the shortening (uplift?)")
    dofs = [j if i is None else i for i, j in pairs]
    z = vertical[1] if free_j else vertical[0]
    radius = min(float(ele.get("Reff", math.inf)), FLAT_RADIUS)
    if weight / radius >= k0:
        raise Untranslatable(
            f"pendulum whose gravity stiffness N / R = {weight / radius:g} >= kInit"
        )
    made = [
        FrictionPendulum(
            (dofs[0], dofs[1] if len(dofs) == 2 else None, z),
            radius=radius,
            mu=mu,
            weight=weight,
            yield_displacement=mu * weight / k0,  # OpenSees' kInit: mu W / Y
            vertical_stiffness=kv,
            initial_axial_force=axial,
        )
    ]
    removed = [_pair(i, j, k0) for i, j in pairs if (i, j) != (None, None)]
    removed.append(_pair(*vertical, kv))
    note = (
        f"element {tag}: friction taken as Coulomb with mu = {mu:g} (its value at import), "
        f"the axial force from the vertical dof (at import {axial:g})"
    )
    damped = None
    if int(float(ele.get("addRayleigh", 0))) == 1:  # -doRayleigh: its damping not read
        damped = Damped("bearing", "its kInit", [(k0, math.nan)] * len(removed))
    return made, removed, [note], damped


def _triple(ops: Any, tag: int, ele: dict, pr: Printout, dmap: DofMap, idx: dict) -> Made:
    """OpenSees' ``TripleFrictionPendulum`` (vertical, 3-D) as duhamel's, to the ground,
    under its axial load at import and the friction coefficients at import (Coulomb)."""
    ni, nj = (int(v) for v in ops.eleNodes(tag))
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    ndf = {len(ops.nodeDisp(n)) for n in (ni, nj)}
    if ndm != 3 or ndf != {6}:
        # OpenSees itself cannot analyse it ("6 dof required"): its state is no state
        raise Refused(
            f"OpenSees' TripleFrictionPendulum needs a 3-D model with 6 dofs at its nodes "
            f"('6 dof required'), here ndm = {ndm}, ndf = {sorted(ndf)}"
        )
    mu = tuple(_resp(ops, tag, "frictionModel", str(k), "frictionCoeff")[0] for k in (1, 2, 3))
    weight = _resp(ops, tag, "frictionModel", "1", "normalForce")[0]
    if not weight > 0:
        raise Untranslatable(
            "bearing without axial load at import (run the gravity analysis before importing)"
        )
    sheared = [ops.nodeDisp(nj, d) - ops.nodeDisp(ni, d) for d in (1, 2)]
    if any(abs(v) > 0.0 for v in sheared):
        raise Untranslatable(f"bearing sheared at import ({sheared}); it starts undeformed")
    pairs = [(_eq(dmap, ni, c, idx), _eq(dmap, nj, c, idx)) for c in ("ux", "uy")]
    if any(i is not None for i, _ in pairs) and any(j is not None for _, j in pairs):
        raise Untranslatable("bearing between two free nodes (duhamel's is to the ground)")
    dofs = [j if i is None else i for i, j in pairs]  # the force is odd in the deformation
    free = [d for d in dofs if d is not None]
    if not free:
        return [], [], [], None
    uy = float(ele["uy"])
    made: list[Element] = [
        TripleFrictionPendulum(
            tuple(free),
            mu=mu,  # type: ignore[arg-type]
            radius=(float(ele["L1"]), float(ele["L2"]), float(ele["L3"])),
            displacement_capacity=(float(ele["d1"]), float(ele["d2"]), float(ele["d3"])),
            weight=weight,
            yield_displacement=uy,
        )
    ]
    k0 = mu[0] * weight / uy  # its initial stiffness in the matrix, in each direction
    removed = [_pair(i, j, k0) for i, j in pairs if (i, j) != (None, None)]
    note = (
        f"element {tag}: friction taken as Coulomb with mu = {mu} (the values at import) "
        f"under the axial load at import {weight:g}"
    )
    return made, removed, [note], None


def _plasticity(ops: Any, tag: int, ele: dict, pr: Printout, dmap: DofMap, idx: dict) -> Made:
    """OpenSees' ``elastomericBearingPlasticity`` in 2-D: an elastic-perfectly plastic
    spring ``(k0, qYield)`` in parallel with the linear ``k2`` on its shear dof (OpenSees
    prints ``k0 = (1 - alpha1) kInit``, ``k2 = alpha1 kInit``), which is duhamel's
    :class:`~duhamel.elements.Bilinear` with ``k = k0 + k2``, ``fy = qYield k / k0``,
    ``alpha = k2 / k``; its nonlinear hardening (``alpha2``, printed ``k3``) is not."""
    k0, k2, qy = (float(ele[key]) for key in ("k0", "k2", "qYield"))
    if float(ele.get("k3", 0.0)) != 0.0:
        raise Untranslatable(f"nonlinear hardening alpha2 (k3 = {ele['k3']}) != 0")
    if not (k0 > 0 and qy > 0 and k2 >= 0):
        raise Untranslatable(f"k0 = {k0}, qYield = {qy}, k2 = {k2}")
    force = np.array(_resp(ops, tag, "globalForce")[:2])  # the axial force at node i
    axis = int(np.argmax(np.abs(force)))
    if not abs(force[axis]) > 0 or abs(force[1 - axis]) > 1e-9 * abs(force[axis]):
        raise Untranslatable(
            "bearing without axial load at import, or sheared (its axis is read from the "
            "gravity load's axial force: run the gravity analysis before importing)"
        )
    _axial_stiffness(pr, ele)  # its axial and moment materials stay in K: linear
    ni, nj = (int(v) for v in ops.eleNodes(tag))
    comp = ("uy", "ux")[axis]  # the shear dof
    i, j = _eq(dmap, ni, comp, idx), _eq(dmap, nj, comp, idx)
    if (i, j) == (None, None):
        return [], [], [], None
    k = k0 + k2
    a, b = (j, i) if j is not None else (i, j)  # a symmetric law: the free dof first
    made: list[Element] = [Bilinear(a, b, k=k, fy=qy * k / k0, alpha=k2 / k)]  # type: ignore[arg-type]
    damped = None
    if int(float(ele.get("addRayleigh", 0))) == 1:
        damped = Damped("bearing", "its initial stiffness", [(k, math.nan)])
    return made, [_pair(i, j, k)], [], damped


#: The bearings translated here, by OpenSees class.
BEARINGS = {
    **dict.fromkeys(SLIDERS, _slider),
    "TripleFrictionPendulum": _triple,
    "ElastomericBearingPlasticity2d": _plasticity,
}


def bearing(
    ops: Any, kind: str, tag: int, ele: dict, pr: Printout, dmap: DofMap, idx: dict
) -> Made:
    """The translation of the bearing `tag` of OpenSees class `kind` (in :data:`BEARINGS`)."""
    return BEARINGS[kind](ops, tag, ele, pr, dmap, idx)  # type: ignore[operator, no-any-return]
