"""Links and what OpenSees refuses (issue 36): ``twoNodeLink`` with a uniaxial material per
direction imported as the ``zeroLength`` it is between coincident nodes (a ``Steel01`` as
:class:`duhamel.elements.Bilinear`, a ``ViscousDamper`` as the damper) and against
OpenSees' run; a link whose shear couples its nodes' rotations (length and shear distance)
refused; ``nonlinear="linearize"`` never drops a damper (it refuses); a 2-D
``TripleFrictionPendulum`` (OpenSees: "6 dof required") refused, also under ``linearize``.
The refusals run in a subprocess that must end with a ``ValueError``, not a dead
interpreter."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import numpy as np
import pytest

import duhamel
import duhamel.opensees

try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
    import openseespy.opensees as ops
except Exception as exc:  # pragma: no cover - depends on the machine
    pytest.skip(reason=f"openseespy cannot be loaded: {exc}", allow_module_level=True)

import _hinged as hf

M = 1e3


def _mass_on(element: list, mats: list[list]) -> None:
    """A 2-D mass (ux, uy) on one element from the fixed node 1 to node 2 (coincident)."""
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)
    ops.node(2, 0.0, 0.0)
    ops.fix(1, 1, 1, 1)
    ops.fix(2, 0, 0, 1)
    ops.mass(2, M, M, 0.0)
    for mat in mats:
        ops.uniaxialMaterial(*mat)
    ops.element(*element)


def _run(t: np.ndarray, a: np.ndarray, substeps: int) -> np.ndarray:
    dt = float(t[1] - t[0])
    ops.timeSeries("Path", 2, "-dt", dt, "-values", *a.tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    for name, *args in (("constraints", "Plain"), ("numberer", "Plain"),
                        ("system", "BandGeneral"), ("test", "NormDispIncr", 1e-12, 50),
                        ("algorithm", "Newton"), ("integrator", "Newmark", 0.5, 0.25),
                        ("analysis", "Transient")):  # fmt: skip
        getattr(ops, name)(*args)
    x = np.zeros(t.size - 1)
    for k in range(1, t.size - 1):
        assert ops.analyze(substeps, dt / substeps) == 0
        x[k] = ops.nodeDisp(2, 1)
    return x


@pytest.mark.parametrize(
    ("mat", "kind"),
    [
        (["Steel01", 1, 1e4, 1e6, 0.05], "Bilinear"),
        (["ViscousDamper", 1, 1e6, 2e4, 0.6], "ViscousDamper"),
    ],
)
def test_two_node_link_against_opensees(mat: list, kind: str) -> None:
    t, a = hf.record(duration=3.0, pga=3.0)
    link = ["twoNodeLink", 1, 1, 2, "-mat", 1, 2, "-dir", 1, 2, "-orient", 1, 0, 0, 0, 1, 0]
    mats = [mat, ["Elastic", 2, 1e8]]
    _mass_on(link, mats)
    s = duhamel.opensees.from_opensees()
    (element,) = s.opensees.elements[1]
    assert type(element).__name__ == kind
    assert s.K[s.dof(2, "uy"), s.dof(2, "uy")] == 1e8  # the linear direction stays in K
    assert s.K[s.dof(2, "ux"), s.dof(2, "ux")] == 0.0  # the translated one is taken out
    s.add_load(duhamel.loads.BaseAcceleration("ux", t, a))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=float(t[-2]), dt=0.01 / 16, save_every=16)
    ours = sol.x[:, s.dof(2, "ux")]
    _mass_on(link, mats)
    ref = _run(t, a, 32)
    if kind == "ViscousDamper":
        assert np.abs(sol.v[:, s.dof(2, "ux")]).max() > 0.05  # the damper works
    assert np.abs(ours - ref).max() <= 5e-3 * np.abs(ref).max()


def test_elastomeric_plasticity_is_its_bilinear() -> None:
    """2-D ``elastomericBearingPlasticity`` (kInit, qd, alpha1): a Bilinear of
    ``k = kInit``, ``fy = qd / (1 - alpha1)``, ``alpha = alpha1`` on its shear dof."""
    _mass_on(
        ["elastomericBearingPlasticity", 1, 1, 2, 1e6, 9e3, 0.1, 0.0, 1.0, "-P", 3, "-Mz", 4,
         "-orient", 0, 1, 0, -1, 0, 0],
        [["Elastic", 3, 1e9], ["Elastic", 4, 1e3]],
    )  # fmt: skip
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, -1e4, 0.0)
    for name, *args in (("constraints", "Plain"), ("numberer", "Plain"), ("system", "FullGeneral"),
                        ("test", "NormDispIncr", 1e-12, 20), ("algorithm", "Newton"),
                        ("integrator", "LoadControl", 1.0), ("analysis", "Static")):  # fmt: skip
        getattr(ops, name)(*args)
    assert ops.analyze(1) == 0
    ops.loadConst("-time", 0.0)
    s = duhamel.opensees.from_opensees()
    (b,) = s.opensees.elements[1]
    assert (b.k, b.alpha) == (pytest.approx(1e6, rel=1e-12), pytest.approx(0.1, rel=1e-12))
    assert b.fy == pytest.approx(9e3 / 0.9, rel=1e-12)


REFUSED = {
    # a damper in a link's shear over its length: not translatable, and linearize would
    # keep its stiffness only (a dropped damper is a silent wrong answer)
    "damper in shear over a length": """
        ops.model("basic", "-ndm", 2, "-ndf", 3)
        ops.node(1, 0.0, 0.0); ops.node(2, 0.0, 1.0)
        ops.fix(1, 1, 1, 1); ops.mass(2, 1e3, 1e3, 1.0)
        ops.uniaxialMaterial("ViscousDamper", 1, 1e6, 1e5, 0.5)
        ops.uniaxialMaterial("Elastic", 2, 1e7)
        ops.element("twoNodeLink", 1, 1, 2, "-mat", 1, 2, 2, "-dir", 2, 1, 3)
    """,
    # OpenSees: "TripleFrictionPendulum::setDomain(): 6 dof required at nodes"
    "2-D triple pendulum": """
        ops.model("basic", "-ndm", 2, "-ndf", 3)
        ops.node(1, 0.0, 0.0); ops.node(2, 0.0, 0.0)
        ops.fix(1, 1, 1, 1); ops.fix(2, 0, 0, 1); ops.mass(2, 1e3, 1e3, 0.0)
        for k in (1, 2, 3):
            ops.frictionModel("Coulomb", k, 0.05)
        ops.uniaxialMaterial("Elastic", 1, 1e12); ops.uniaxialMaterial("Elastic", 2, 1e10)
        ops.element("TripleFrictionPendulum", 1, 1, 2, 1, 2, 3, 1, 2, 2, 2, 0.5, 2.0, 0.5,
                    0.05, 0.2, 0.05, 1e4, 5e-4, 1.0, 0.1, 1e-10)
    """,
}


@pytest.mark.parametrize("case", list(REFUSED))
@pytest.mark.parametrize("nonlinear", ["translate", "linearize"])
def test_refused_in_a_subprocess_with_a_value_error(case: str, nonlinear: str) -> None:
    code = "import openseespy.opensees as ops, duhamel.opensees\nops.wipe()\n" + textwrap.dedent(
        REFUSED[case]
    ) + textwrap.dedent(f"""
        try:
            duhamel.opensees.from_opensees(nonlinear={nonlinear!r})
        except ValueError as exc:
            print("REFUSED:", exc)
    """)  # fmt: skip
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert "REFUSED: " in done.stdout, done.stdout[-2000:]
    if case.startswith("damper"):
        words = "drop the damping" if nonlinear == "linearize" else "shear distance"
    else:
        words = "6 dofs at its nodes"
    assert words in done.stdout
    assert "element 1" in done.stdout
