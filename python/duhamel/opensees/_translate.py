"""OpenSees elements as duhamel elements: the linear ones stay in the stiffness matrix, the
nonlinear ones that have a duhamel counterpart become that element (with their stiffness
taken out of the matrix, so it is not counted twice), the others are refused (or kept at
their stiffness at import under ``nonlinear="linearize"``)."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.elements import (
    Bilinear,
    BoucWen,
    Element,
    FrictionPendulum,
    Gap,
    TripleFrictionPendulum,
    ViscousDamper,
)
from duhamel.opensees._read import DofMap, Printout, components

__all__ = ["Damped", "Translation", "translate"]

#: Element classes that are linear at fixed geometry (their tangent at import is exact).
LINEAR = {
    "ElasticBeam2d",
    "ElasticBeam3d",
    "ElasticTimoshenkoBeam2d",
    "ElasticTimoshenkoBeam3d",
    "ModElasticBeam2d",
    "ElasticBeamWarping3d",
}
#: Coordinate transformations that make a linear element nonlinear (large displacements).
NONLINEAR_GEOMETRY = ("Corot",)
#: The flat and single friction pendulum bearings.
SLIDERS = {"FlatSliderSimple2d", "FlatSliderSimple3d", "SingleFPSimple2d", "SingleFPSimple3d"}
#: A friction pendulum of this radius is flat (its gravity stiffness W/R vanishes).
FLAT_RADIUS = 1e30
#: ElasticPPGap with a yield force at least this many times E |gap| never yields.
NO_YIELD = 1e12

_ZL_DIRS = {
    1: {"P": (0, False)},
    2: {"P": (0, False), "Vy": (1, False), "Mz": (2, True)},
    3: {
        "P": (0, False),
        "Vy": (1, False),
        "Vz": (2, False),
        "T": (0, True),
        "My": (1, True),
        "Mz": (2, True),
    },
}


class Untranslatable(Exception):
    """An element (or one of its materials) without a duhamel counterpart."""


@dataclass
class Damped:
    """A translated element that OpenSees damps with its Rayleigh factors (``zeroLength``
    ``-doRayleigh 1``, a bearing's ``-doRayleigh``): its type, its materials (or `None` for a
    bearing) and, per translated direction, its tangent at import and the damping OpenSees
    gives it there (``nan`` where it cannot be read)."""

    kind: str
    what: str
    directions: list[tuple[float, float]]


@dataclass
class Translation:
    """The translated elements, by OpenSees tag; the stiffness to take out of K (each
    ``(dofs, k)``); the elements kept linear; notes for the user; the translated elements
    OpenSees damps with its Rayleigh factors, by tag."""

    elements: dict[int, list[Element]] = field(default_factory=dict)
    removed: list[tuple[tuple[int, ...], NDArray[np.float64]]] = field(default_factory=list)
    linearized: dict[int, str] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    damped: dict[int, Damped] = field(default_factory=dict)


def _eq(dmap: DofMap, node: int, comp: str, index: dict) -> int | None:
    """The equation of a node dof, None when it is fixed; Untranslatable when it is tied to
    others by a constraint that is not one to one."""
    key = (node, comp)
    if key in index:
        return index[key]
    why = dmap.absent.get(key, f"node {node} has no dof {comp}")
    if "fixed" in why:
        return None
    raise Untranslatable(why)


def _pair(i: int | None, j: int | None, k: float) -> tuple[tuple[int, ...], NDArray]:
    dofs = tuple(d for d in (i, j) if d is not None)
    if len(dofs) == 1:
        return dofs, np.array([[k]])
    return dofs, np.array([[k, -k], [-k, k]])


def _resp(ops: Any, tag: int, *args: str) -> list[float]:
    return [float(v) for v in np.atleast_1d(ops.eleResponse(tag, *args))]


def _material(mat: dict[str, Any], i: int | None, j: int | None, sign: float) -> Element | None:
    """The duhamel element of a zeroLength material between the dofs `i`, `j` (deformation
    ``sign (x_j - x_i)`` in OpenSees), or None when the material is linear (it stays in K)."""
    kind = str(mat.get("type"))
    # duhamel's deformation is x_a - x_b: OpenSees' strain when (a, b) = (j, i) for sign +1
    a, b = (j, i) if sign > 0 else (i, j)
    sym = (a, b) if a is not None else (b, a)  # a symmetric law may change the sign
    if kind == "ElasticMaterial":
        if float(mat["Epos"]) != float(mat["Eneg"]):
            raise Untranslatable(f"Elastic material {mat['name']} with Epos != Eneg")
        return None
    if kind == "Steel01":
        if float(mat.get("a1", 0.0)) != 0.0 or float(mat.get("a3", 0.0)) != 0.0:
            raise Untranslatable(f"Steel01 material {mat['name']} with isotropic hardening")
        return Bilinear(
            sym[0], sym[1], k=float(mat["E"]), fy=float(mat["fy"]), alpha=float(mat["b"])
        )
    if kind == "BoucWenMaterial":
        for key in ("deltaA", "deltaNu", "deltaEta"):
            if float(mat.get(key, 0.0)) != 0.0:
                raise Untranslatable(f"BoucWen material {mat['name']} with degradation ({key})")
        if float(mat.get("Ao", 1.0)) != 1.0:
            raise Untranslatable(f"BoucWen material {mat['name']} with A0 != 1")
        n, beta, gamma = float(mat["n"]), float(mat["beta"]), float(mat["gamma"])
        ko, alpha = float(mat["ko"]), float(mat["alpha"])
        if beta + gamma <= 0:
            raise Untranslatable(f"BoucWen material {mat['name']}: beta + gamma <= 0 (unbounded)")
        z_max = (1.0 / (beta + gamma)) ** (1.0 / n)  # OpenSees' z is a displacement
        return BoucWen(
            sym[0],
            sym[1],
            k=ko,
            fy=ko * z_max,
            alpha=alpha,
            n=n,
            beta=beta / (beta + gamma),
            gamma=gamma / (beta + gamma),
        )
    if kind == "EPPGap":
        e, fy, gap = float(mat["E"]), float(mat["fy"]), float(mat["gap"])
        if float(mat.get("eta", 0.0)) != 0.0 or abs(fy) < NO_YIELD * e * max(abs(gap), 1e-300):
            raise Untranslatable(f"ElasticPPGap material {mat['name']} that yields (fy = {fy})")
        # gap < 0: contact in compression, strain < gap; gap > 0: in tension, strain > gap
        pos, neg = (a, b) if gap <= 0 else (b, a)
        if pos is None:
            raise Untranslatable("a gap whose moving side is the fixed node")
        return Gap(pos, neg, gap=abs(gap), k=e)
    if kind == "ENTMaterial":
        if float(mat.get("a", 0.0)) != 0.0:
            raise Untranslatable(f"ENT material {mat['name']} with tension stiffness (a != 0)")
        if a is None:
            raise Untranslatable("a gap whose moving side is the fixed node")
        return Gap(a, b, gap=0.0, k=float(mat["E"]))
    if kind == "ViscousDamper":
        # the damper in series with its brace K (the Maxwell model); the pin's gap is not
        if float(mat.get("LGap", 0.0)) != 0.0:
            raise Untranslatable(f"ViscousDamper material {mat['name']} with a gap (LGap)")
        return ViscousDamper(
            sym[0],
            sym[1],
            c=float(mat["C"]),
            exponent=float(mat["Alpha"]),
            brace_stiffness=float(mat["K"]),
        )
    raise Untranslatable(f"material {mat.get('name')} of type {kind}")


#: What translating one element gives: its duhamel elements, the stiffness to take out of K,
#: notes, and its Rayleigh damping when OpenSees gives it one (None: none).
Made = tuple[
    list[Element], list[tuple[tuple[int, ...], NDArray[np.float64]]], list[str], Damped | None
]


def _rayleigh_forces(ops: Any, tag: int, node: int, response: str) -> NDArray[np.float64]:
    """The element's Rayleigh damping force (`response`: its name) under a unit trial
    velocity of every dof of its node `node` (the other node at rest): the damping OpenSees
    gives it, read without changing the model (the trial velocities are set back)."""
    nodes = [int(v) for v in ops.eleNodes(tag)]
    saved = {n: [float(v) for v in ops.nodeVel(n)] for n in nodes}
    try:
        for n in nodes:
            for d, _ in enumerate(saved[n]):
                ops.setNodeVel(n, d + 1, 1.0 if n == node else 0.0)
        return np.array(_resp(ops, tag, response), dtype=np.float64)
    finally:
        for n in nodes:
            for d, v in enumerate(saved[n]):
                ops.setNodeVel(n, d + 1, v)


def _zero_length(ops: Any, tag: int, ele: dict, pr: Printout, dmap: DofMap, idx: dict) -> Made:
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    ni, nj = (int(v) for v in ele["nodes"])
    trans = np.array(ele["transMatrix"], dtype=np.float64)
    comps = components(ndm, len(ops.nodeDisp(nj)))
    made: list[Element] = []
    removed = []
    damping: list[tuple[float, float]] = []
    rayleigh: NDArray[np.float64] | None = None
    for k, (mtag, dname) in enumerate(zip(ele["materials"], ele["dof"], strict=True)):
        mat = pr.materials.get(int(mtag))
        if mat is None:
            raise Untranslatable(f"material {mtag} (not printed by OpenSees)")
        axis, rot = _ZL_DIRS[ndm][dname] if dname in _ZL_DIRS.get(ndm, {}) else (None, False)
        if axis is None:
            raise Untranslatable(f"direction {dname}")
        row = trans[axis]
        a = int(np.argmax(np.abs(row)))
        if abs(abs(row[a]) - 1.0) > 1e-12 or np.sum(np.abs(row)) - abs(row[a]) > 1e-12:
            raise Untranslatable(f"direction {dname} not along a global axis")
        comp = ("rx", "ry", "rz")[a] if rot else ("ux", "uy", "uz")[a]
        if comp not in comps:
            raise Untranslatable(f"direction {dname} ({comp}) absent from the nodes")
        i, j = _eq(dmap, ni, comp, idx), _eq(dmap, nj, comp, idx)
        if i is None and j is None:
            continue
        element = _material(mat, i, j, float(np.sign(row[a])))
        if element is None:
            continue
        stress = _resp(ops, tag, "material", str(k + 1), "stress")[0]
        strain = _resp(ops, tag, "material", str(k + 1), "strain")[0]
        if stress != 0.0 or (strain != 0.0 and not isinstance(element, Gap)):
            raise Untranslatable(
                f"material {mtag} is loaded at import (strain {strain:.3g}, stress "
                f"{stress:.3g}); translated elements start undeformed"
            )
        tangent = _resp(ops, tag, "material", str(k + 1), "tangent")[0]
        if tangent != 0.0:
            removed.append(_pair(i, j, tangent))
        made.append(element)
        if rayleigh is None:  # zero unless the element was defined with -doRayleigh 1
            rayleigh = _rayleigh_forces(ops, tag, nj, "rayleighForces")
        half = rayleigh.size // 2
        damping.append((tangent, abs(float(rayleigh[half + comps.index(comp)]))))
    damped = None
    if made and any(c != 0.0 for _, c in damping):
        what = ", ".join(
            f"{pr.materials[int(m)].get('type')} material {m}" for m in ele["materials"]
        )
        damped = Damped("ZeroLength", what, damping)
    return made, removed, [], damped


def _slider(ops: Any, tag: int, ele: dict, dmap: DofMap, idx: dict) -> Made:
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
    force = np.array(_resp(ops, tag, "globalForce")[:ndm])  # the axial force at node i
    axis = int(np.argmax(np.abs(force)))
    if np.sum(np.abs(force)) - abs(force[axis]) > 1e-6 * abs(force[axis]):
        raise Untranslatable("bearing whose axis is not a global axis, or sheared at import")
    shear = [c for c in ("ux", "uy", "uz")[:ndm] if c != ("ux", "uy", "uz")[axis]]
    pairs = [(_eq(dmap, ni, c, idx), _eq(dmap, nj, c, idx)) for c in shear]
    # a single friction pendulum: the elastic part N / R in kInit (OpenSees' k2 and k0)
    radius = float(ele.get("Reff", math.inf))
    k2 = weight / radius
    if not k2 < k0:
        raise Untranslatable(f"pendulum whose gravity stiffness N / R = {k2:g} >= kInit")
    made: list[Element]
    if len(shear) == 1:
        i, j = pairs[0]
        if i is None and j is None:
            return [], [], [], None
        a, b = (j, i) if j is not None else (i, j)
        alpha = k2 / k0  # post-sliding over initial stiffness: (1 - alpha) fy = mu N
        made = [Bilinear(a, b, k=k0, fy=mu * weight / (1.0 - alpha), alpha=alpha)]
    else:
        if any(i is not None for i, _ in pairs) and any(j is not None for _, j in pairs):
            raise Untranslatable("3-D bearing between two free nodes (duhamel's is to ground)")
        dofs = [j if i is None else i for i, j in pairs]
        if any(d is None for d in dofs):
            return [], [], [], None
        made = [
            FrictionPendulum(
                (dofs[0], dofs[1]),
                radius=min(radius, FLAT_RADIUS),
                mu=mu,
                weight=weight,
                yield_displacement=mu * weight / (k0 - k2),
            )
        ]
    removed = [_pair(i, j, k0) for i, j in pairs if (i, j) != (None, None)]
    note = (
        f"element {tag}: friction taken as Coulomb with mu = {mu:g} (its value at import) "
        f"under the axial load at import {weight:g}"
    )
    damped = None
    if int(float(ele.get("addRayleigh", 0))) == 1:  # -doRayleigh: its damping not read
        damped = Damped("bearing", "its kInit", [(k0, math.nan)] * len(removed))
    return made, removed, [note], damped


def _triple(ops: Any, tag: int, ele: dict, dmap: DofMap, idx: dict) -> Made:
    """OpenSees' ``TripleFrictionPendulum`` (vertical, 3-D) as duhamel's, to the ground,
    under its axial load at import and the friction coefficients at import (Coulomb)."""
    ni, nj = (int(v) for v in ops.eleNodes(tag))
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


def translate(ops: Any, pr: Printout, dmap: DofMap, nonlinear: str) -> Translation:
    """Every element of the session: kept (linear), translated, or refused by tag and type
    (kept at its stiffness at import, with a warning, under ``nonlinear="linearize"``)."""
    out = Translation()
    idx: dict = {lab: e for e, lab in enumerate(dmap.labels)}
    idx.update(dmap.aliases)
    for tag in (int(v) for v in ops.getEleTags()):
        kind = str(ops.eleType(tag))
        ele = pr.elements.get(tag, {})
        try:
            if kind in LINEAR:
                name = pr.transforms.get(str(ele.get("crdTransformation", "")), "")
                if any(word in name for word in NONLINEAR_GEOMETRY):
                    raise Untranslatable(f"geometric transformation {name} (large displacements)")
            elif kind == "ZeroLength":
                made, removed, notes, damped = _zero_length(ops, tag, ele, pr, dmap, idx)
            elif kind in SLIDERS:
                made, removed, notes, damped = _slider(ops, tag, ele, dmap, idx)
            elif kind == "TripleFrictionPendulum":
                made, removed, notes, damped = _triple(ops, tag, ele, dmap, idx)
            else:
                raise Untranslatable("no duhamel counterpart")
            if kind not in LINEAR and made:
                out.elements[tag] = made
                out.removed.extend(removed)
                out.notes.extend(notes)
                if damped is not None:
                    out.damped[tag] = damped
        except (Untranslatable, KeyError, ValueError) as exc:
            what = f"element {tag} ({kind}): {exc}"
            if nonlinear != "linearize":
                raise ValueError(
                    f"cannot translate OpenSees {what}; pass nonlinear='linearize' to keep it "
                    "at its stiffness at import"
                ) from None
            out.linearized[tag] = kind
            warnings.warn(
                f"OpenSees {what}: kept linear at its tangent stiffness at import",
                UserWarning,
                stacklevel=3,
            )
    return out
