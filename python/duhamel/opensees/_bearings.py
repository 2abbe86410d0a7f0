"""OpenSees' bearings as duhamel's: ``flatSliderBearing`` and ``singleFPBearing`` (2-D and
3-D) as :class:`~duhamel.elements.FrictionPendulum` with its vertical dof and the axial force
at import, ``TripleFrictionPendulum`` (3-D, with its vertical dof when free),
``elastomericBearingPlasticity`` (2-D) as the bilinear it is."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.elements import (
    Bilinear,
    Element,
    FrictionPendulum,
    LeadRubberBearing,
    TripleFrictionPendulum,
)
from duhamel.opensees._parts import Damped, Made, Refused, Untranslatable, _eq, _pair, _resp
from duhamel.opensees._read import DofMap, Printout

__all__ = ["BEARINGS", "FLAT_RADIUS", "PDelta", "bearing", "pdelta_elements", "pdelta_info"]

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
    """OpenSees' ``TripleFrictionPendulum`` (vertical, 3-D) as duhamel's, to the ground, with
    the friction coefficients at import (Coulomb): with its vertical dof when that is free
    (the axial force from the vertical material, its state at import the initial axial
    force), else under the axial load at import."""
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
    if any(abs(v) > 1e-9 * float(ele["uy"]) for v in sheared):  # beyond round-off
        raise Untranslatable(f"bearing sheared at import ({sheared}); it starts undeformed")
    pairs = [(_eq(dmap, ni, c, idx), _eq(dmap, nj, c, idx)) for c in ("ux", "uy")]
    if any(i is not None for i, _ in pairs) and any(j is not None for _, j in pairs):
        raise Untranslatable("bearing between two free nodes (duhamel's is to the ground)")
    dofs = [j if i is None else i for i, j in pairs]  # the force is odd in the deformation
    free = [d for d in dofs if d is not None]
    if not free:
        return [], [], [], None
    uy = float(ele["uy"])
    # OpenSees' P-Delta moments (N u / 2, and the torsion of the shear) on its nodes'
    # rotations: duhamel's element carries them on the top node j's
    rotations = [_eq(dmap, nj, c, idx) for c in ("rx", "ry", "rz")]
    if pairs[0][0] is not None or pairs[1][0] is not None:
        if any(_eq(dmap, ni, c, idx) is not None for c in ("rx", "ry", "rz")):
            raise Untranslatable("bearing sliding at node i with its rotations free there")
        rotations = [None, None, None]
    rotated = tuple(rotations) if any(r is not None for r in rotations) else ()
    radius = (float(ele["L1"]), float(ele["L2"]), float(ele["L3"]))
    capacity = (float(ele["d1"]), float(ele["d2"]), float(ele["d3"]))
    k0 = mu[0] * weight / uy  # its initial stiffness in the matrix, in each direction
    removed = [_pair(i, j, k0) for i, j in pairs if (i, j) != (None, None)]
    vertical = (_eq(dmap, ni, "uz", idx), _eq(dmap, nj, "uz", idx))
    moving = [n for n in (ni, nj) if _eq(dmap, n, "uz", idx) is not None]
    massless = all(ops.nodeMass(n, 3) == 0.0 for n in moving)
    if vertical != (None, None) and massless:
        # a massless vertical dof whose stiffness is all in the bearing: a mechanism of K
        # for the static condensation of the massless dofs; the axial load is held
        warnings.warn(
            f"OpenSees element {tag} (TripleFrictionPendulum): its axial force is held at the "
            f"value at import ({weight:g}) in duhamel, while in OpenSees it follows the "
            f"vertical motion of node {moving[0]} (its uz is free but without mass: give it "
            "a mass for the bearing to be imported with its vertical dof, or fix it)",
            UserWarning,
            stacklevel=5,
        )
        vertical = (None, None)
    if vertical == (None, None):
        made: list[Element] = [
            TripleFrictionPendulum(
                (*free, *([None] * (3 - len(free))), *rotated) if rotated else tuple(free),
                mu=mu,  # type: ignore[arg-type]
                radius=radius,
                displacement_capacity=capacity,
                weight=weight,
                yield_displacement=uy,
            )
        ]
        note = (
            f"element {tag}: friction taken as Coulomb with mu = {mu} (the values at import) "
            f"under the axial load at import {weight:g}"
        )
        return made, removed, [note], None
    # its vertical dof free: the axial force N = -kv Dz (Dz = uz_j - uz_i) of its vertical
    # material, OpenSees' MinFv in tension; duhamel's vertical dof is the free node's uplift
    if vertical[0] is not None:
        raise Untranslatable(
            "bearing whose bottom node (node i) moves vertically: duhamel's vertical dof is "
            "the uplift of its top node j over the ground"
        )
    if pairs[0][0] is not None or pairs[1][0] is not None:
        raise Untranslatable("bearing sliding at node i but lifting at node j")
    kv = _axial_stiffness(pr, ele)
    axial = -_resp(ops, tag, "basicForce")[0]  # compression positive
    dz = _resp(ops, tag, "basicDeformation")[0]
    if not (axial > 0 and abs(axial - kv * -dz) <= 1e-8 * axial):
        raise Untranslatable(
            f"axial force {axial:g} at import that is not the compression kv * {-dz:g} of its "
            "vertical material (uplift, or no gravity analysis before the import)"
        )
    made = [
        TripleFrictionPendulum(
            (free[0], free[1] if len(free) == 2 else None, vertical[1], *rotated),
            mu=mu,  # type: ignore[arg-type]
            radius=radius,
            displacement_capacity=capacity,
            weight=weight,
            yield_displacement=uy,
            vertical_stiffness=kv,
            min_axial_force=float(ele.get("minFv", 0.0)),
            initial_axial_force=axial,
        )
    ]
    removed.append(_pair(*vertical, kv))
    note = (
        f"element {tag}: friction taken as Coulomb with mu = {mu} (the values at import), "
        f"the axial force from the vertical dof (at import {axial:g})"
    )
    return made, removed, [note], None


def _elastomeric(ops: Any, tag: int, ele: dict, pr: Printout, dmap: DofMap, idx: dict) -> Made:
    """OpenSees' ``elastomericBearingPlasticity`` and ``elastomericBearingBoucWen`` (2-D and
    3-D, OpenSees prints ``k0 = (1 - alpha1) kInit``, ``k2 = alpha1 kInit``, ``qYield``): a
    hysteretic part ``(k0, qYield)`` in parallel with the linear ``k2`` on the shear dofs.
    The plasticity model is duhamel's :class:`~duhamel.elements.Bilinear` (``k = k0 + k2``,
    ``fy = qYield k / k0``, ``alpha = k2 / k``) on a line; in 3-D its circular yield surface
    with the isotropic ``k2`` is a flat-or-dished :class:`~duhamel.elements.FrictionPendulum`
    (``mu = 1``, ``weight = qYield``, ``radius = qYield / k2``, ``yield_displacement =
    qYield / k0``). The Bouc-Wen model is :class:`~duhamel.elements.LeadRubberBearing`
    (``eta``, ``beta``, ``gamma`` as OpenSees'). Their shear does not depend on the axial
    force (OpenSees' models): the axial and moment materials stay in K, linear."""
    k0, k2, qy = (float(ele[key]) for key in ("k0", "k2", "qYield"))
    if float(ele.get("k3", 0.0)) != 0.0:
        raise Untranslatable(f"nonlinear hardening alpha2 (k3 = {ele['k3']}) != 0")
    if not (k0 > 0 and qy > 0 and k2 >= 0):
        raise Untranslatable(f"k0 = {k0}, qYield = {qy}, k2 = {k2}")
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    force = np.array(_resp(ops, tag, "globalForce")[:ndm])  # the axial force at node i
    axis = int(np.argmax(np.abs(force)))
    if not abs(force[axis]) > 0 or np.sum(np.abs(force)) - abs(force[axis]) > 1e-9 * abs(
        force[axis]
    ):
        raise Untranslatable(
            "bearing without axial load at import, or sheared (its axis is read from the "
            "gravity load's axial force: run the gravity analysis before importing)"
        )
    _axial_stiffness(pr, ele)  # its axial and moment materials stay in K: linear
    ni, nj = (int(v) for v in ops.eleNodes(tag))
    names = ("ux", "uy", "uz")[:ndm]
    pairs = [(_eq(dmap, ni, c, idx), _eq(dmap, nj, c, idx)) for c in names if c != names[axis]]
    pairs = [p for p in pairs if p != (None, None)]
    if not pairs:
        return [], [], [], None
    if len(pairs) == 2 and (any(i is not None for i, _ in pairs) and any(j for _, j in pairs)):
        raise Untranslatable("3-D bearing between two free nodes (duhamel's is to the ground)")
    k = k0 + k2
    kind = str(ops.eleType(tag))
    made: list[Element]
    if len(pairs) == 1:  # a symmetric law on a line: the free dof first
        a, b = (pairs[0][1], pairs[0][0]) if pairs[0][1] is not None else pairs[0]
        if "BoucWen" in kind:
            if b is not None:
                raise Untranslatable("bearing between two free nodes (duhamel's is to the ground)")
            made = [_rubber(ele, (a,), k, qy * k / k0, k2 / k)]
        else:
            made = [Bilinear(a, b, k=k, fy=qy * k / k0, alpha=k2 / k)]  # type: ignore[arg-type]
    else:
        dofs = tuple(j if i is None else i for i, j in pairs)
        if "BoucWen" in kind:
            made = [_rubber(ele, dofs, k, qy * k / k0, k2 / k)]
        else:
            made = [
                FrictionPendulum(
                    dofs,
                    radius=min(qy / k2, FLAT_RADIUS) if k2 > 0 else FLAT_RADIUS,
                    mu=1.0,
                    weight=qy,
                    yield_displacement=qy / k0,
                )
            ]
    damped = None
    if int(float(ele.get("addRayleigh", 0))) == 1:
        damped = Damped("bearing", "its initial stiffness", [(k, math.nan)] * len(pairs))
    return made, [_pair(i, j, k) for i, j in pairs], [], damped


def _rubber(ele: dict, dofs: tuple, k: float, fy: float, alpha: float) -> Element:
    """OpenSees' Bouc-Wen bearing's shear as :class:`~duhamel.elements.LeadRubberBearing`."""
    eta, beta, gamma = (float(ele[key]) for key in ("eta", "beta", "gamma"))
    return LeadRubberBearing(
        dofs if len(dofs) > 1 else dofs[0],
        k=k, fy=fy, alpha=alpha, eta=eta, beta=beta, gamma=gamma,
    )  # fmt: skip


#: The bearings translated here, by OpenSees class.
BEARINGS = {
    **dict.fromkeys(SLIDERS, _slider),
    "TripleFrictionPendulum": _triple,
    **dict.fromkeys(
        [f"ElastomericBearing{m}{d}d" for m in ("Plasticity", "BoucWen") for d in (2, 3)],
        _elastomeric,
    ),
}


def bearing(
    ops: Any, kind: str, tag: int, ele: dict, pr: Printout, dmap: DofMap, idx: dict
) -> Made:
    """The translation of the bearing `tag` of OpenSees class `kind` (in :data:`BEARINGS`)."""
    return BEARINGS[kind](ops, tag, ele, pr, dmap, idx)  # type: ignore[operator, no-any-return]


@dataclass
class PDelta:
    """An elastomeric bearing's P-Delta moments on its free node: its shear dofs, vertical
    dof (None: fixed), rotations, its axial force at import and axial stiffness."""

    tag: int
    shear: list[int]
    z: int | None
    rotations: list[int]
    n0: float
    kv: float


def pdelta_info(ops: Any, tag: int, pr: Printout, dmap: DofMap, idx: dict) -> PDelta | None:
    """Where OpenSees' elastomeric bearing `tag` puts its P-Delta moments ``0.5 N`` times
    its shear displacement (on its free node's rotations), or None (nothing free there)."""
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    force = np.array(_resp(ops, tag, "globalForce")[:ndm])
    axis = int(np.argmax(np.abs(force)))
    ni, nj = (int(v) for v in ops.eleNodes(tag))
    names = ("ux", "uy", "uz")[:ndm]
    rot = ("rz",) if ndm == 2 else ("rx", "ry", "rz")
    free = nj if any(_eq(dmap, nj, c, idx) is not None for c in names) else ni
    shear = [_eq(dmap, free, c, idx) for c in names if c != names[axis]]
    rotations = [_eq(dmap, free, c, idx) for c in rot]
    ele = pr.elements.get(tag, {})
    return PDelta(
        tag,
        [d for d in shear if d is not None],
        _eq(dmap, free, names[axis], idx),
        [d for d in rotations if d is not None],
        -_resp(ops, tag, "basicForce")[0],
        _axial_stiffness(pr, ele),
    )


def pdelta_elements(K: NDArray[np.float64], infos: list[PDelta], notes: list[str]) -> list:
    """The bearings' P-Delta moments as one element that follows their axial forces:
    OpenSees adds ``0.5 N`` times the shear displacement to the moments of an elastomeric
    bearing's nodes with the current axial force ``N`` (a tangent that is not symmetric).
    Their coefficients at import (the skew entries of `K` between the free node's rotations
    and shear dofs) are taken out of `K` (in place) into an element whose force on each
    bearing's rotations is ``C u (N0 - kv w) / N0`` (one Python element for all: one call
    per evaluation)."""
    from duhamel.elements import Callable

    blocks = []
    for p in infos:
        if not p.shear or not p.rotations or not p.n0 > 0:
            continue
        r, u = np.ix_(p.rotations, p.shear)
        c = K[r, u] - K[u.T, r.T].T
        if not np.any(c):
            continue
        K[r, u] -= c
        blocks.append((p, c))
        notes.append(
            f"element {p.tag}: OpenSees' P-Delta moments (0.5 N times the shear displacement, "
            "with the current axial force N) kept as a Callable element"
        )
    if not blocks:
        return []
    dofs = sorted({d for p, _ in blocks for d in (*p.shear, *p.rotations, p.z) if d is not None})
    at = {d: k for k, d in enumerate(dofs)}
    parts = [
        (
            np.array([at[d] for d in p.shear]),
            np.array([at[d] for d in p.rotations]),
            at[p.z] if p.z is not None else None,
            c,
            p.kv / p.n0,
        )
        for p, c in blocks
    ]

    def force(x: NDArray, v: NDArray, t: float) -> NDArray:
        f = np.zeros(len(dofs))
        for s, r, z, c, scale in parts:
            f[r] += (c @ x[s]) * (1.0 - (scale * x[z] if z is not None else 0.0))
        return f

    def jacobian(x: NDArray, v: NDArray, t: float) -> tuple[NDArray, NDArray]:
        k = np.zeros((len(dofs), len(dofs)))
        for s, r, z, c, scale in parts:
            ratio = 1.0 - (scale * x[z] if z is not None else 0.0)
            k[np.ix_(r, s)] += c * ratio
            if z is not None:
                k[r, z] -= (c @ x[s]) * scale
        return k, np.zeros_like(k)

    return [Callable(dofs, force, jacobian)]
