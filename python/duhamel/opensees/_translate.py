"""OpenSees elements as duhamel elements: the linear ones stay in the stiffness matrix, the
nonlinear ones that have a duhamel counterpart become that element (with their stiffness
taken out of the matrix, so it is not counted twice), the others are refused (or kept at
their stiffness at import under ``nonlinear="linearize"``)."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.elements import (
    Bilinear,
    BoucWen,
    Element,
    Gap,
    ViscousDamper,
    drive,
)
from duhamel.opensees._bearings import BEARINGS, bearing, pdelta_info
from duhamel.opensees._materials import KINDS, material_element
from duhamel.opensees._parts import (
    Damped,
    Made,
    Refused,
    Translation,
    Untranslatable,
    _eq,
    _pair,
    _resp,
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


def _material(
    mat: dict[str, Any], i: int | None, j: int | None, sign: float,
    materials: dict[int, dict[str, Any]],
) -> Element | None:  # fmt: skip
    """The duhamel element of a zeroLength material between the dofs `i`, `j` (deformation
    ``sign (x_j - x_i)`` in OpenSees), or None when the material is linear (it stays in K);
    `materials`: the printed materials by tag (the parts of a wrapper)."""
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
    if kind in KINDS:
        return material_element(mat, materials, a, b)
    raise Untranslatable(f"material {mat.get('name')} of type {kind}")


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


#: Translated elements that take a loaded state at import: ``Bilinear`` (a ``Steel01``) with
#: the material's strain and stress as its initial deformation and force (any state in its
#: band); the uniaxial materials of :data:`KINDS` with the strain as their
#: ``initial_deformation`` (reached from rest monotonically: checked against the stress).
CARRIED = {"Bilinear"}
#: The state reached by driving duhamel's material equals OpenSees' within this fraction
#: of the force (and of the tangent's scale): OpenSees prints the parameters to six
#: significant digits, a different path (a hinge unloaded during gravity) or law is off by
#: far more.
STATE_TOL = 1e-6
#: The increments duhamel's uniaxial materials reach their ``initial_deformation`` in
#: (crates/duhamel-core/src/elements/materials/uniaxial.rs, ``INITIAL_STEPS``).
INITIAL_STEPS = 100


def _driven(
    element: Element, name: str, strain: float, stress: float, tangent: float | None
) -> Element:
    """The material element `element` (virgin, duhamel's deformation along OpenSees'
    strain) loaded to `strain`, checked: the force (and `tangent`, when given) duhamel's law
    reaches from rest must be OpenSees' `stress` at import, else the state is refused."""
    path = np.linspace(0.0, strain, INITIAL_STEPS + 1)
    try:
        reached = drive(element, path)
    except (ValueError, RuntimeError) as exc:
        raise Untranslatable(f"{name}: its strain at import {strain:.6g} {exc}") from None
    force, kt = float(reached.force[-1]), float(reached.tangent[-1])
    scale = max(abs(stress), abs(force))
    off = abs(force - stress) > STATE_TOL * scale
    if not off and tangent is not None:
        k_scale = max(abs(tangent), abs(kt), abs(stress / strain) if strain else 0.0)
        off = abs(kt - tangent) > STATE_TOL * k_scale
    if off:
        tangents = "" if tangent is None else f", tangent {tangent:.9g} vs duhamel's {kt:.9g}"
        raise Untranslatable(
            f"{name} is loaded at import (strain {strain:.9g}, stress {stress:.9g}"
            f"{tangents}) in a state duhamel's {type(element).__name__} does not reach "
            f"from rest monotonically (its force there {force:.9g}): the gravity path "
            "unloaded it, or the law differs; its state cannot be carried over"
        )
    return element.replace(initial_deformation=strain)  # type: ignore[attr-defined, no-any-return]


def _loaded(
    element: Element, mat: dict[str, Any], where: tuple[int | None, int | None, float],
    state: tuple[float, float, float | None],
) -> Element:  # fmt: skip
    """`element` (the translation of `mat` between the dofs ``where = (i, j, sign)``) in the
    material's state at import, ``state = (strain, stress, tangent)`` (e.g. after a gravity
    analysis): a ``Bilinear``'s initial deformation and force, a uniaxial material's
    initial deformation (checked: :func:`_driven`). A state that cannot be carried over is
    refused naming the material."""
    strain, stress, tangent = state
    if stress == 0.0 and strain == 0.0:
        return element  # undeformed
    name = f"{mat.get('type')} material {mat.get('name')}"
    if isinstance(element, Gap) and stress == 0.0:
        # open at import: the distance left to contact (a compression gap closes as the
        # strain falls to -|gap|, a tension gap as it rises to gap)
        gap = float(mat.get("gap", 0.0))
        closes_down = mat.get("type") == "ENTMaterial" or gap <= 0.0
        left = abs(gap) + (strain if closes_down else -strain)
        if not left >= 0.0:
            raise Untranslatable(f"{name} is in contact at import without force")
        return element.replace(gap=left)  # type: ignore[attr-defined, no-any-return]
    i, j, sign = where
    # duhamel's deformation x_e.i - x_e.j is OpenSees' strain, or its opposite where the
    # moving node is the element's i (see _material)
    a = j if sign > 0 else i
    flip = 1.0 if a is not None else -1.0
    if str(mat.get("type")) in KINDS:
        return _driven(element, name, flip * strain, flip * stress, tangent)
    if type(element).__name__ not in CARRIED:
        raise Untranslatable(
            f"{name} is loaded at import (strain {strain:.3g}, stress {stress:.3g}): its "
            f"state cannot be carried over to duhamel's {type(element).__name__}, which "
            "starts undeformed"
        )
    try:
        return element.replace(  # type: ignore[attr-defined, no-any-return]
            initial_deformation=flip * strain, initial_force=flip * stress
        )
    except ValueError as exc:  # a state the duhamel element cannot reach
        raise Untranslatable(f"{name}: its state at import {exc}") from None


def _length(ops: Any, ni: int, nj: int) -> float:
    """The distance between the nodes `ni` and `nj`."""
    return float(np.linalg.norm(np.subtract(ops.nodeCoord(nj), ops.nodeCoord(ni))))


def _zero_length(ops: Any, tag: int, ele: dict, pr: Printout, dmap: DofMap, idx: dict) -> Made:
    """A ``zeroLength`` or ``twoNodeLink`` element: a duhamel element per nonlinear material
    along its direction (a global axis), the linear ones left in K. A ``twoNodeLink`` of
    length ``L > 0`` deforms in shear with its nodes' rotations (its shear distance): its
    shear directions are translated only between coincident nodes."""
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    ni, nj = (int(v) for v in ele["nodes"])
    trans = np.array(ele["transMatrix"], dtype=np.float64)
    if not np.all(np.isfinite(trans)):
        raise Untranslatable(
            "local axes undefined (NaN in OpenSees' transformation: a link between coincident "
            "nodes needs '-orient')"
        )
    comps = components(ndm, len(ops.nodeDisp(nj)))
    made: list[Element] = []
    removed = []
    damping: list[tuple[float, float]] = []
    rayleigh: NDArray[np.float64] | None = None
    for k, (mtag, dname) in enumerate(zip(ele["materials"], ele["dof"], strict=True)):
        mat = pr.materials.get(int(mtag))
        if mat is None and int(mtag) == 0:
            raise Untranslatable(
                "its material is printed with tag 0 (OpenSees' copy lost its tag, as a "
                "MultiLinear's does), so it cannot be read back; "
                + ele.get(
                    "_unseen",
                    "build the model inside `with duhamel.opensees.recording() as rec:` and "
                    "import it with `from_opensees(recorded=rec)`",
                )
            )
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
        element = _material(mat, i, j, float(np.sign(row[a])), pr.materials)
        if element is None:
            continue
        if dname in ("Vy", "Vz") and (length := _length(ops, ni, nj)) > 0.0:
            raise Untranslatable(
                f"{mat.get('type')} material {mtag} in shear ({dname}) over the length "
                f"{length:g}: its deformation involves the nodes' rotations (shear distance)"
            )
        stress = _resp(ops, tag, "material", str(k + 1), "stress")[0]
        strain = _resp(ops, tag, "material", str(k + 1), "strain")[0]
        tangent = _resp(ops, tag, "material", str(k + 1), "tangent")[0]
        element = _loaded(element, mat, (i, j, float(np.sign(row[a]))), (strain, stress, tangent))
        if tangent != 0.0:
            removed.append(_pair(i, j, tangent))
        made.append(element)
        if rayleigh is None:  # zero unless the element was defined with -doRayleigh 1
            rayleigh = _rayleigh_forces(ops, tag, nj, "rayleighForces")
        half = rayleigh.size // 2
        # OpenSees' betaK0 damps the initial stiffness (the tangent at import differs from
        # it where gravity loaded the material)
        linear = element._linear()  # type: ignore[attr-defined]
        k0 = tangent if linear is None else float(np.asarray(linear[1]).flat[0])
        if rayleigh.size:
            damping.append((k0, abs(float(rayleigh[half + comps.index(comp)]))))
        else:  # a twoNodeLink returns no Rayleigh forces: only whether it has any
            damping.append((k0, math.nan if int(float(ele["addRayleigh"])) else 0.0))
    damped = None
    if made and any(c != 0.0 for _, c in damping):
        what = ", ".join(
            f"{pr.materials[int(m)].get('type')} material {m}" for m in ele["materials"]
        )
        damped = Damped(str(ops.eleType(tag)), what, damping)
    return made, removed, [], damped


#: Words of the uniaxial materials whose force depends on the deformation rate (a damper):
#: their tangent stiffness at import holds none of their damping.
RATE_DEPENDENT = ("Viscous", "Damper", "Maxwell", "Oil")


def _keeps_damping(tag: int, kind: str, ele: dict, pr: Printout, what: str) -> None:
    """Refuses to linearise an element with a damper among its materials: its tangent at
    import keeps the stiffness but drops the damping, a silent wrong answer."""
    for m in ele.get("materials", []):
        mat = pr.materials.get(int(m), {})
        name = str(mat.get("type", ""))
        if any(word in name for word in RATE_DEPENDENT):
            raise ValueError(
                f"cannot translate OpenSees {what}; nonlinear='linearize' would keep only its "
                f"stiffness at import and drop the damping of its {name} material {m}: "
                "model the damper as an element duhamel translates (a zeroLength, or a "
                "twoNodeLink between coincident nodes or along its axis)"
            )


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
            elif kind in ("ZeroLength", "TwoNodeLink"):
                made, removed, notes, damped = _zero_length(ops, tag, ele, pr, dmap, idx)
            elif kind in BEARINGS:
                made, removed, notes, damped = bearing(ops, kind, tag, ele, pr, dmap, idx)
                if kind.startswith("ElastomericBearing") and made:
                    out.pdelta.append(pdelta_info(ops, tag, pr, dmap, idx))
            else:
                raise Untranslatable("no duhamel counterpart")
            if kind not in LINEAR and made:
                out.elements[tag] = made
                out.removed.extend(removed)
                out.notes.extend(notes)
                if damped is not None:
                    out.damped[tag] = damped
        except Refused as exc:
            raise ValueError(f"OpenSees element {tag} ({kind}): {exc}") from None
        except (Untranslatable, KeyError, ValueError) as exc:
            what = f"element {tag} ({kind}): {exc}"
            if nonlinear != "linearize":
                raise ValueError(
                    f"cannot translate OpenSees {what}; pass nonlinear='linearize' to keep it "
                    "at its stiffness at import"
                ) from None
            _keeps_damping(tag, kind, ele, pr, what)
            out.linearized[tag] = kind
            warnings.warn(
                f"OpenSees {what}: kept linear at its tangent stiffness at import",
                UserWarning,
                stacklevel=3,
            )
    return out
