"""The arguments of openseespy's model commands, recorded while the model is built
(:func:`recording`), for the materials OpenSees prints without their parameters: the
``Pinching4`` law (printed with its state only) and the ``MultiLinear`` one (whose copy in an
element or a wrapper prints its tag as 0). :func:`apply` checks a recording against the
model OpenSees prints and hands :func:`~duhamel.opensees._materials.material_element` the
duhamel element of each such material; everything else is read from the printout."""

from __future__ import annotations

import contextlib
import math
import numbers
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from duhamel.elements import MultiLinear, Pinching4
from duhamel.opensees._read import Printout

__all__ = ["Recording", "apply", "recording"]

#: The printed type of each material command the import knows (to check a recording).
PRINTED = {
    "Elastic": "ElasticMaterial", "Steel01": "Steel01", "Steel02": "Steel02",
    "BoucWen": "BoucWenMaterial", "ElasticPPGap": "EPPGap", "ENT": "ENTMaterial",
    "ViscousDamper": "ViscousDamper", "ModIMKPeakOriented": "ModIMKPeakOriented",
    "IMKBilin": "IMKPeakOriented", "IMKPeakOriented": "IMKPeakOriented",
    "Hysteretic": "HystereticMaterial", "ElasticMultiLinear": "ElasticMultiLinear",
    "MinMax": "MinMaxMaterial", "Parallel": "ParallelMaterial", "Series": "SeriesMaterial",
    "Pinching4": "Pinching4Material", "MultiLinear": "MultiLinear",
}  # fmt: skip
#: Pinching4's numbers in OpenSees' order (``OPS_Pinching4Material``): the full form (38)
#: and the short one (27: the positive side, mirrored by OpenSees as by duhamel)
_P4_ENVELOPE = [f"e{s}{x}{k}" for s in "PN" for k in range(1, 5) for x in "fd"]
_P4_DAMAGE = [f"g{g}{k}" for g in "KDF" for k in ("1", "2", "3", "4", "Lim")] + ["gE"]
P4_FULL = [*_P4_ENVELOPE, "rDispP", "rForceP", "uForceP", "rDispN", "rForceN", "uForceN"]
P4_FULL += _P4_DAMAGE
P4_SHORT = [*_P4_ENVELOPE[:8], "rDispP", "rForceP", "uForceP", *_P4_DAMAGE]
#: The damage types OpenSees' parser accepts
_DAMAGE = {
    **dict.fromkeys(("cycle", "Cycle", "DamageCycle", "damageCycle"), "cycle"),
    **dict.fromkeys(("energy", "Energy", "DamageEnergy", "damageEnergy"), "energy"),
}
#: Relative agreement of a recorded number with OpenSees' printed one (6 significant digits)
PRINTED_DIGITS = 1e-5


@dataclass
class Recording:
    """The arguments of openseespy's ``uniaxialMaterial`` and ``element`` commands, by tag:
    ``materials[tag] = (type, *arguments after the tag)`` and ``elements[tag] = (type,
    *arguments after the tag)``, as :func:`recording` keeps them or as written by hand
    (``Recording(materials={1: ("Pinching4", 0.8, 0.02, ...)})``)."""

    materials: dict[int, tuple[Any, ...]] = field(default_factory=dict)
    elements: dict[int, tuple[Any, ...]] = field(default_factory=dict)


@contextlib.contextmanager
def recording() -> Iterator[Recording]:
    """Records the arguments of openseespy's ``uniaxialMaterial`` and ``element`` commands
    while the model is built in the block, for :func:`from_opensees` (``recorded=``), which
    reads ``Pinching4`` and ``MultiLinear`` materials from them (OpenSees prints neither's
    parameters) and checks them against the printed model.

    The commands are recorded when called through the module (``ops.uniaxialMaterial``
    after ``import openseespy.opensees as ops``, or names imported from it inside the
    block); a command OpenSees rejects is not recorded; ``ops.wipe()`` in the block starts
    the recording afresh (the model it described is gone).

    Yields
    ------
    Recording
        Filled as the block runs; keep it for :func:`from_opensees` after the block (e.g.
        after the gravity analysis).

    Examples
    --------
    A mass on a ``MultiLinear`` spring (OpenSees' ``zeroLength`` prints its material's tag
    as 0: the recording gives it):

    >>> import openseespy.opensees as ops
    >>> import duhamel.opensees
    >>> ops.wipe(); ops.model("basic", "-ndm", 1, "-ndf", 1)
    >>> with duhamel.opensees.recording() as rec:
    ...     ops.node(1, 0.0); ops.node(2, 0.0); ops.fix(1, 1); ops.mass(2, 1.0)
    ...     ops.uniaxialMaterial("MultiLinear", 1, 0.02, 0.8, 0.06, 1.0)
    ...     ops.element("zeroLength", 1, 1, 2, "-mat", 1, "-dir", 1)
    >>> rec.materials
    {1: ('MultiLinear', 0.02, 0.8, 0.06, 1.0)}
    >>> system = duhamel.opensees.from_opensees(recorded=rec)
    >>> system.opensees.elements[1]
    [MultiLinear(0, None, strain=(0.02, 0.06), stress=(0.8, 1.0), initial_deformation=0.0)]
    """
    from duhamel.opensees import _openseespy

    ops = _openseespy()
    rec = Recording()
    originals = {name: getattr(ops, name) for name in ("uniaxialMaterial", "element", "wipe")}

    def command(name: str, kept: dict[int, tuple[Any, ...]]) -> Any:
        def wrapped(*args: Any) -> Any:
            out = originals[name](*args)
            if len(args) >= 2:
                with contextlib.suppress(TypeError, ValueError):
                    kept[int(args[1])] = (args[0], *args[2:])
            return out

        wrapped.__doc__ = getattr(originals[name], "__doc__", None)
        return wrapped

    def wipe(*args: Any) -> Any:
        rec.materials.clear()
        rec.elements.clear()
        return originals["wipe"](*args)

    ops.uniaxialMaterial = command("uniaxialMaterial", rec.materials)
    ops.element = command("element", rec.elements)
    ops.wipe = wipe
    try:
        yield rec
    finally:
        for name, f in originals.items():
            setattr(ops, name, f)


def _numbers(values: tuple[Any, ...], what: str, names: list[str]) -> list[float]:
    """`values` as floats; an error names the argument (counted from the tag, 1) and its
    parameter (`names`)."""
    out = []
    for k, (v, name) in enumerate(zip(values, names, strict=True)):
        try:
            x = float(v)
        except (TypeError, ValueError):
            x = math.nan
        if not math.isfinite(x):
            raise ValueError(
                f"`recorded`: {what}: argument {k + 2} ({name} = {v!r}) is not a finite number"
            )
        out.append(x)
    return out


def _pinching4(args: tuple[Any, ...], what: str) -> tuple[type, dict[str, Any]]:
    """duhamel's Pinching4 parameters of OpenSees' arguments after the tag."""
    if len(args) not in (len(P4_FULL) + 1, len(P4_SHORT) + 1):
        raise ValueError(
            f"`recorded`: {what} has {len(args)} arguments after its tag; OpenSees' Pinching4 "
            f"takes {len(P4_FULL) + 1} ({len(P4_FULL)} numbers and the damage type) or "
            f"{len(P4_SHORT) + 1} (the positive side only: {len(P4_SHORT)} and the type)"
        )
    names = P4_FULL if len(args) == len(P4_FULL) + 1 else P4_SHORT
    damage = _DAMAGE.get(args[-1]) if isinstance(args[-1], str) else None
    if damage is None:
        raise ValueError(
            f"`recorded`: {what}: its damage type (the last argument) must be 'energy' or "
            f"'cycle' (or OpenSees' other spellings of these), got {args[-1]!r}"
        )
    params: dict[str, Any] = dict(zip(names, _numbers(args[:-1], what, names), strict=True))
    return Pinching4, params | {"dmgType": damage}


def _multilinear(
    args: tuple[Any, ...], what: str, printed: dict[str, Any]
) -> tuple[type, dict[str, Any]]:
    """duhamel's MultiLinear parameters of OpenSees' ``e1 s1 e2 s2 ...``, checked against
    the points OpenSees printed (its segment table, whose rows hold ``-e, e, -s, s``)."""
    if len(args) < 4 or len(args) % 2:
        raise ValueError(
            f"`recorded`: {what} has {len(args)} numbers after its tag; OpenSees' MultiLinear "
            "takes pairs of strain and stress, at least two (an odd count: OpenSees drops the "
            "last number)"
        )
    values = _numbers(
        args, what, [f"{x}{k // 2 + 1}" for k, x in enumerate("es" * (len(args) // 2))]
    )
    strain, stress = values[0::2], values[1::2]
    rows = []
    for line in printed.get("_lines", []):
        with contextlib.suppress(ValueError):
            row = [float(v) for v in line.split()]
            if len(row) == 6:
                rows.append((row[1], row[3]))
    if rows:
        if len(rows) != len(strain):
            raise ValueError(
                f"`recorded`: {what} has {len(strain)} points, OpenSees printed {len(rows)}: "
                "the recording is not of this model"
            )
        for k, (mine, theirs) in enumerate(
            zip(zip(strain, stress, strict=True), rows, strict=True)
        ):
            if any(abs(a - b) > PRINTED_DIGITS * abs(b) for a, b in zip(mine, theirs, strict=True)):
                raise ValueError(
                    f"`recorded`: {what}: point {k + 1} is {mine} recorded, {theirs} as "
                    "OpenSees prints it: the recording is not of this model"
                )
    return MultiLinear, {"strain": strain, "stress": stress}


def _tags(values: tuple[Any, ...], what: str) -> list[int]:
    """The leading tags of an argument list (up to its first option, e.g. ``-factors``)."""
    out = []
    for v in values:
        if isinstance(v, str) and v.startswith("-"):
            break
        try:
            out.append(int(v))
        except (TypeError, ValueError):
            raise ValueError(f"`recorded`: {what}: {v!r} is not a material tag") from None
    return out


def _element_materials(args: tuple[Any, ...], what: str) -> list[int] | None:
    """The material tags after ``-mat`` of a recorded ``zeroLength``/``twoNodeLink``."""
    if str(args[0]).lower() not in ("zerolength", "twonodelink") or "-mat" not in args:
        return None
    return _tags(args[args.index("-mat") + 1 :], what)


def _fill(tags: list[Any], recorded: list[int], what: str) -> list[Any]:
    """The printed material `tags` with those printed as 0 taken from `recorded`; the
    others must agree."""
    if len(recorded) != len(tags):
        raise ValueError(
            f"`recorded`: {what} has {len(recorded)} materials recorded, {len(tags)} in the "
            "model: the recording is not of this model"
        )
    out = []
    for printed, mine in zip(tags, recorded, strict=True):
        if int(float(printed)) not in (0, mine):
            raise ValueError(
                f"`recorded`: {what} has material {mine} recorded, {printed} in the "
                "model: the recording is not of this model"
            )
        out.append(str(mine) if int(float(printed)) == 0 else printed)
    return out


def apply(recorded: Recording, pr: Printout, element_tags: list[int]) -> None:
    """Checks `recorded` against the printout `pr` (materials and elements of the model,
    `element_tags`) and completes it: each recorded Pinching4 and MultiLinear material gets
    its duhamel element (``_recorded``: the class and its parameters), each material tag
    printed as 0 (a MultiLinear copied into an element or a wrapper) the recorded one."""
    if not isinstance(recorded, Recording):
        raise TypeError(
            "`recorded` must be a duhamel.opensees.Recording (from `with "
            f"duhamel.opensees.recording() as rec:`), got {type(recorded).__name__}"
        )
    for kept, name in ((recorded.materials, "material"), (recorded.elements, "element")):
        for tag, command in kept.items():
            if not isinstance(tag, numbers.Integral) or not (
                isinstance(command, tuple | list) and command and isinstance(command[0], str)
            ):
                raise ValueError(
                    f"`recorded`: {name} {tag!r}: want an integer tag and a tuple (type, "
                    f"*arguments after the tag), got {command!r}"
                )
    for tag, (kind, *args) in recorded.materials.items():
        what = f"{kind} material {tag}"
        mat = pr.materials.get(int(tag))
        if mat is None:
            raise ValueError(
                f"`recorded`: {what} is not in the model (the model was built again after "
                "the recording?)"
            )
        want = PRINTED.get(str(kind))
        if want is not None and str(mat.get("type")) != want:
            raise ValueError(
                f"`recorded`: material {tag} is a {kind} in the recording, a {mat.get('type')} "
                "in the model: the recording is not of this model"
            )
        if kind == "Pinching4":
            made = _pinching4(tuple(args), what)
        elif kind == "MultiLinear":
            made = _multilinear(tuple(args), what, mat)
        else:
            if kind in ("MinMax", "Parallel", "Series"):
                key = "material" if kind == "MinMax" else "materials"
                printed = mat.get(key)
                if printed is not None:
                    parts = list(printed) if isinstance(printed, list) else [printed]
                    filled = _fill(parts, _tags(tuple(args), what)[: len(parts)], what)
                    mat[key] = filled if isinstance(printed, list) else filled[0]
            continue
        try:  # the parameters checked as duhamel's element checks them
            made[0](0, **made[1])
        except ValueError as exc:
            raise ValueError(f"`recorded`: {what}: {exc}") from None
        mat["_recorded"] = made
    for tag, command in recorded.elements.items():
        if int(tag) not in element_tags:
            raise ValueError(
                f"`recorded`: element {tag} ({command[0]}) is not in the model (the model was "
                "built again after the recording?)"
            )
        mine = _element_materials(tuple(command), f"element {tag}")
        ele = pr.elements.get(int(tag))
        if mine is not None and ele is not None and "materials" in ele:
            ele["materials"] = _fill(list(ele["materials"]), mine, f"element {tag}")
    for entry in (*pr.materials.values(), *pr.elements.values()):
        entry["_unseen"] = UNSEEN  # what is still unreadable was not recorded


#: Why a material or element is missing from a recording (the refusal says it).
UNSEEN = (
    "`recorded` does not hold its command: call it inside the `recording()` block through "
    "the module (`ops.uniaxialMaterial`, `ops.element`; names imported from "
    "openseespy.opensees before the block are not recorded)"
)
