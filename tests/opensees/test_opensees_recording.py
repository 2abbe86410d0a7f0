"""``from_opensees(recorded=...)``: the ``Pinching4`` and ``MultiLinear`` materials, whose
parameters OpenSees does not print (a ``zeroLength`` prints a MultiLinear's tag as 0), read
from the arguments :func:`duhamel.opensees.recording` kept while the model was built
(python/duhamel/opensees/_recording.py).

Each in a ``zeroLength`` between a mass and the ground (tests/_support/_materials_system.py:
mass 1, period 1 s, yield at 0.02, Rayleigh damping with ``-doRayleigh 1``), imported and run
under the band-limited record by ``Semianalytic`` and ``Newmark()``: displacement and spring
force equal OpenSees' own transient of the same model (Newmark, Newton to 1e-12, the same
step ``DT / 16``) within 1e-4 of their peaks at every step (the acceptance asks 0.5 %).
Without the recording both are refused, naming the API; a recording that disagrees with the
model, or holds arguments OpenSees' parser would not take, is refused naming what. The
hinged frame with both materials imported this way: tests/opensees/test_frame_materials.py."""

from __future__ import annotations

import os
import tempfile
from typing import Any

import numpy as np
import pytest
from _materials_system import A0, A1, DT, MATERIALS, SECONDS, UY, newmark_transient, record

import duhamel
import duhamel.opensees
from duhamel import elements as E
from duhamel.opensees import Recording

try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
    import openseespy.opensees as ops
except Exception as exc:  # pragma: no cover - depends on the machine
    pytest.skip(reason=f"openseespy cannot be loaded: {exc}", allow_module_level=True)

K = 16  # steps per record interval
KINDS = {"Pinching4": E.Pinching4, "MultiLinear": E.MultiLinear}


def build(args: tuple[Any, ...], rec: bool = True) -> Recording | None:
    """The SDOF with the material `args` (OpenSees' type and arguments) in a zeroLength,
    built inside a recording (returned) or without one."""
    ops.wipe()
    with duhamel.opensees.recording() as kept:
        ops.model("basic", "-ndm", 1, "-ndf", 1)
        ops.node(1, 0.0)
        ops.node(2, 0.0)
        ops.fix(1, 1)
        ops.mass(2, 1.0)
        if not rec:
            kept = None
        ops.uniaxialMaterial(args[0], 1, *args[1:])
        ops.element("zeroLength", 1, 1, 2, "-mat", 1, "-dir", 1, "-doRayleigh", 1)
        ops.rayleigh(A0, 0.0, A1, 0.0)
    return kept


def opensees_run(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """OpenSees' transient of the session's SDOF: displacement and spring force after every
    step (from rest: 0 first)."""
    tmp = tempfile.mkdtemp()
    disp, force = os.path.join(tmp, "disp.out"), os.path.join(tmp, "force.out")
    recorders = [
        ("Node", "-file", disp, "-node", 2, "-dof", 1, "disp"),
        ("Element", "-file", force, "-ele", 1, "material", "1", "stress"),
    ]
    assert newmark_transient(ops, a, DT, K, recorders), "OpenSees' transient did not converge"
    x, f = (np.concatenate([[0.0], np.loadtxt(p).reshape(-1)]) for p in (disp, force))
    return x, f


def _imported(kind: str) -> duhamel.System:
    rec = build(MATERIALS[kind][1])
    return duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0), recorded=rec)


@pytest.mark.parametrize("kind", list(KINDS))
def test_recorded_material_runs_as_opensees(kind: str) -> None:
    t, a = record()
    s = _imported(kind)
    (element,) = s.opensees.elements[1]
    assert type(element) is KINDS[kind]
    assert s.K[0, 0] == 0.0  # its stiffness is the element's, not the matrix's
    s.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=a))
    build(MATERIALS[kind][1])
    x_os, f_os = opensees_run(a)
    assert np.abs(x_os).max() > 2.5 * UY, "the record should take it well past yield"
    for integrator in (duhamel.Semianalytic(), duhamel.Newmark()):
        x = duhamel.solve(s, integrator, t_end=SECONDS, dt=DT / K).x[:, 0]
        f = E.drive(element, x).force
        n = min(x.size, x_os.size)
        ex = np.abs(x[:n] - x_os[:n]).max() / np.abs(x_os).max()
        ef = np.abs(f[:n] - f_os[:n]).max() / np.abs(f_os).max()
        name = type(integrator).__name__
        # found (load 3.4): 5e-7 (MultiLinear, Newmark) to 1.3e-5 (Pinching4, Semianalytic)
        assert ex <= 1e-4, f"{kind}, {name}: displacement {ex:.2e} of the peak from OpenSees"
        assert ef <= 1e-4, f"{kind}, {name}: force {ef:.2e} of the peak from OpenSees"


def test_recorded_parameters_are_opensees_arguments() -> None:
    """OpenSees' short Pinching4 (the positive side, mirrored) is duhamel's short form; its
    damage type spelled as OpenSees also takes it."""
    args = MATERIALS["Pinching4"][1]
    short = (*args[1:9], *args[17:20], *args[23:-1], "DamageCycle")
    rec = build(("Pinching4", *short))
    imported = duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0), recorded=rec)
    (element,) = imported.opensees.elements[1]
    p = element.parameters  # type: ignore[attr-defined]
    assert p["eNf1"] is None and p["dmgType"] == "cycle" and p["ePd4"] == args[8]
    assert p["gE"] == args[-2]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (MATERIALS["Pinching4"][1], r"Pinching4Material material 1: OpenSees prints none.*"),
        (MATERIALS["MultiLinear"][1], r"its material is printed with tag 0.*"),
    ],
    ids=["Pinching4", "MultiLinear"],
)
def test_without_the_recording_the_material_is_refused_naming_the_api(
    args: tuple[Any, ...], message: str
) -> None:
    build(args, rec=False)
    with pytest.raises(ValueError, match=message + r"duhamel\.opensees\.recording\(\)"):
        duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0))


P4 = MATERIALS["Pinching4"][1]
MULTI = MATERIALS["MultiLinear"][1]


@pytest.mark.parametrize(
    ("built", "recorded", "message"),
    [
        (MULTI, {1: ("Pinching4", *P4[1:])}, r"material 1 is a Pinching4 in the recording, a "),
        (MULTI, {2: MULTI}, r"MultiLinear material 2 is not in the model"),
        (
            MULTI,
            {1: ("MultiLinear", *MULTI[1:3], 0.07, *MULTI[4:])},
            r"MultiLinear material 1: point 2 is \(0.07, .*OpenSees prints it",
        ),
        (MULTI, {1: MULTI[:-2]}, r"MultiLinear material 1 has 2 points, OpenSees printed 3"),
        (MULTI, {1: MULTI[:-1]}, r"MultiLinear material 1 has 5 numbers after its tag"),
        (P4, {1: P4[:-2]}, r"Pinching4 material 1 has 37 arguments after its tag"),
        (P4, {1: (*P4[:-1], "area")}, r"its damage type .* got 'area'"),
        (P4, {1: (*P4[:3], "x", *P4[4:])}, r"argument 4 \(ePf2 = 'x'\) is not a finite number"),
    ],
    ids=["type", "tag", "point", "points", "odd", "count", "damage", "number"],
)
def test_a_recording_that_disagrees_is_refused_naming_it(
    built: tuple[Any, ...], recorded: dict[int, tuple[Any, ...]], message: str
) -> None:
    build(built)
    with pytest.raises(ValueError, match=r"`recorded`: .*" + message):
        duhamel.opensees.from_opensees(
            rayleigh=(A0, 0.0, A1, 0.0), recorded=Recording(materials=recorded)
        )


def test_a_recorded_element_with_other_materials_is_refused_naming_it() -> None:
    build(("Steel02", 0.8, 40.0, 0.02))
    for elements, message in (
        ({1: ("zeroLength", 1, 2, "-mat", 3, "-dir", 1)}, "has material 3 recorded, 1 in"),
        ({1: ("zeroLength", 1, 2, "-mat", 1, 1, "-dir", 1, 1)}, "has 2 materials recorded, 1"),
        ({7: ("zeroLength", 1, 2, "-mat", 1, "-dir", 1)}, "\\(zeroLength\\) is not in"),
    ):
        rec = Recording(elements=elements)
        with pytest.raises(ValueError, match=r"`recorded`: element \d+ " + message):
            duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0), recorded=rec)
    for rec, message in (
        (Recording(materials={1: ()}), r"material 1: want an integer tag and a tuple"),
        (Recording(elements={"1": ("zeroLength",)}), r"element '1': want an integer tag"),
        (
            Recording(elements={1: ("zeroLength", 1, 2, "-mat", "x")}),
            r"element 1: 'x' is not a material",
        ),
    ):
        with pytest.raises(ValueError, match=r"`recorded`: " + message):
            duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0), recorded=rec)
    with pytest.raises(TypeError, match=r"`recorded` must be a duhamel.opensees.Recording"):
        duhamel.opensees.from_opensees(recorded={1: MULTI})  # type: ignore[arg-type]


def test_an_odd_multilinear_recorded_as_opensees_took_it_is_refused() -> None:
    """OpenSees drops the last of an odd count of MultiLinear numbers without a word: the
    recording keeps what was given, the import refuses it."""
    rec = build((*MULTI, 0.3))
    with pytest.raises(ValueError, match=r"an odd count: OpenSees drops the last number"):
        duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0), recorded=rec)


def test_wipe_in_the_block_starts_the_recording_afresh() -> None:
    with duhamel.opensees.recording() as rec:
        ops.wipe()
        ops.model("basic", "-ndm", 1, "-ndf", 1)
        ops.uniaxialMaterial(*MULTI[:1], 5, *MULTI[1:])
        assert rec.materials == {5: MULTI}
        ops.wipe()
    assert rec.materials == {}
    assert ops.uniaxialMaterial.__name__ == "uniaxialMaterial"  # restored


def test_wrappers_of_recorded_materials_are_imported() -> None:
    """A MinMax and a Parallel whose parts are a MultiLinear (printed with tag 0 inside
    them) and a Pinching4: their parts from the recording; refused without it."""
    for rec in (True, False):
        ops.wipe()
        with duhamel.opensees.recording() as kept:
            ops.model("basic", "-ndm", 1, "-ndf", 1)
            ops.node(1, 0.0)
            ops.node(2, 0.0)
            ops.fix(1, 1)
            ops.mass(2, 1.0)
            ops.uniaxialMaterial(MULTI[0], 1, *MULTI[1:])
            ops.uniaxialMaterial(P4[0], 2, *P4[1:])
            ops.uniaxialMaterial("MinMax", 3, 1, "-min", -0.1, "-max", 0.1)
            ops.uniaxialMaterial("Parallel", 4, 1, 2, "-factors", 0.5, 0.5)
            ops.element("zeroLength", 1, 1, 2, "-mat", 3, 4, "-dir", 1, 1)
        if not rec:
            with pytest.raises(ValueError, match=r"MinMaxMaterial material 3: a part is printed "):
                duhamel.opensees.from_opensees(recorded=None)
            continue
        minmax, parallel = duhamel.opensees.from_opensees(recorded=kept).opensees.elements[1]
        inner = minmax.parameters["material"]  # type: ignore[attr-defined]
        parts = parallel.parameters["materials"]  # type: ignore[attr-defined]
        assert type(inner) is E.MultiLinear
        assert [type(p) for p in parts] == [E.MultiLinear, E.Pinching4]
        assert inner.parameters["strain"] == tuple(MULTI[1::2])  # type: ignore[attr-defined]


def test_a_two_node_link_takes_its_multilinear_from_the_recording() -> None:
    """A twoNodeLink also prints a MultiLinear's tag as 0: the recorded ``-mat`` gives it."""
    ops.wipe()
    with duhamel.opensees.recording() as rec:
        ops.model("basic", "-ndm", 2, "-ndf", 3)
        ops.node(1, 0.0, 0.0)
        ops.node(2, 0.0, 0.0)
        ops.fix(1, 1, 1, 1)
        ops.fix(2, 0, 1, 1)
        ops.mass(2, 1.0, 1.0, 0.0)
        ops.uniaxialMaterial(MULTI[0], 1, *MULTI[1:])
        ops.element("twoNodeLink", 1, 1, 2, "-mat", 1, "-dir", 1, "-orient", 1, 0, 0, 0, 1, 0)
    (element,) = duhamel.opensees.from_opensees(recorded=rec).opensees.elements[1]
    assert type(element) is E.MultiLinear
    assert element.parameters["stress"] == tuple(MULTI[2::2])  # type: ignore[attr-defined]


def test_commands_the_recording_did_not_see_are_named() -> None:
    """A recording that does not hold the material's (or element's) command: the refusal
    says how the commands are recorded."""
    for args, what in ((P4, "Pinching4Material material 1"), (MULTI, "element 1")):
        build(args, rec=False)
        with pytest.raises(ValueError, match=what + r".*`recorded` does not hold its command"):
            duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0), recorded=Recording())
