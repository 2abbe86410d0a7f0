"""Collapse intensities of a softening SDOF against OpenSees (issue 37's acceptance: same
model, same collapse criterion, same intensity steps; within one intensity step).

The model: an elastic column and a leaning column (a spring of stiffness ``KE - P/h``), a
kinematic bilinear hinge with a negative post-yield stiffness (duhamel's ``Bilinear``,
OpenSees' ``Steel01`` with ``b < 0``) and a linear dashpot; collapse when ``|u|`` reaches
20 yield displacements. Five records, a PGA grid of 12 intensities. OpenSees: Newmark
(average acceleration), Newton to a displacement increment of 1e-12, the criterion checked
at every step; duhamel: ``ida`` with the drift event (located inside its step), with
``Newmark()`` and with ``Semianalytic()``.
"""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel.ensemble import ida
from duhamel.records import GroundMotion

try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
    import openseespy.opensees as ops
except Exception as exc:  # pragma: no cover - depends on the machine
    pytest.skip(reason=f"openseespy cannot be loaded: {exc}", allow_module_level=True)

KE, TH, KB, FY, ALPHA = 10.0, 8.0, 30.0, 0.3, -0.1  # as tests/ensemble/test_collapse_ida.py
C = 2 * 0.03 * np.sqrt(KE - TH + KB)  # 3 % of critical at the initial stiffness
UY = FY / KB
LIMIT = 20 * UY
DT = 0.01
GRID = np.linspace(0.1, 1.2, 12)


def records() -> list[GroundMotion]:
    rng = np.random.default_rng(11)
    t = np.arange(0.0, 12.0, DT)
    out = []
    for i in range(5):
        w = rng.uniform(3.0, 8.0)
        a = np.sin(w * t + rng.uniform(0, np.pi)) * np.exp(-0.25 * t) * np.minimum(t, 1.0)
        a += 0.3 * np.sin(2.3 * w * t) * np.exp(-0.4 * t)
        out.append(GroundMotion(a / np.abs(a).max(), DT, units="m/s^2", name=f"r{i}"))
    return out


def sdof(motion: GroundMotion) -> duhamel.System:
    s = duhamel.System(np.eye(1), [[KE]], C=[[C]])
    s.add(duhamel.elements.PDelta(0, None, P=TH, height=1.0))
    s.add(duhamel.elements.Bilinear(0, k=KB, fy=FY, alpha=ALPHA))
    return s.add_load(motion.as_load([1.0]))


def opensees_collapses(accel: np.ndarray) -> bool:
    """One OpenSees run of the SDOF under the base acceleration `accel`: whether |u|
    reaches the limit at a step."""
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0, "-mass", 1.0)
    ops.fix(1, 1)
    ops.uniaxialMaterial("Elastic", 1, KE - TH)
    ops.uniaxialMaterial("Steel01", 2, FY, KB, ALPHA)
    ops.uniaxialMaterial("Viscous", 3, C, 1.0)
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, 2, 3, "-dir", 1, 1, 1)
    ops.timeSeries("Path", 1, "-dt", DT, "-values", *accel.tolist())
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    for _ in range(accel.size - 1):
        if ops.analyze(1, DT) != 0:
            raise RuntimeError("OpenSees did not converge")
        if abs(ops.nodeDisp(2, 1)) >= LIMIT:
            return True
    return False


@pytest.mark.parametrize("integrator", [duhamel.Newmark(), duhamel.Semianalytic()], ids=str)
def test_collapse_intensities_equal_opensees(integrator: object) -> None:
    """On the grid: the same first collapse per record as OpenSees hunting up the same
    grid. Bisected to 1e-3: OpenSees bisected the same way from its own grid bracket lands
    within the tolerance."""
    motions = records()
    stop = duhamel.events.drift(0, None, LIMIT, height=1.0, terminal=True)
    peak = lambda sol: float(np.abs(sol.x).max())  # noqa: E731
    grid = ida(sdof, motions, GRID, peak, integrator, intensity="pga", collapse=stop,
               solver_error="raise", workers=2)  # fmt: skip
    fine = ida(sdof, motions, GRID, peak, integrator, intensity="pga", collapse=stop,
               solver_error="raise", workers=2, tolerance=1e-3)  # fmt: skip
    theirs = np.full(len(motions), np.inf)
    bisected = np.full(len(motions), np.inf)
    for i, m in enumerate(motions):
        collapses = lambda im, a=m.a / m.pga: opensees_collapses(a * im)  # noqa: E731
        lo = 0.0
        for im in GRID:  # a hunt up the same grid: the first collapse
            if collapses(im):
                theirs[i] = im
                break
            lo = im
        hi = theirs[i]
        while np.isfinite(hi) and hi - lo > 1e-3 * hi:
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if collapses(mid) else (mid, hi)
        bisected[i] = hi
    ops.wipe()
    print(type(integrator).__name__, "duhamel", grid.collapse_intensities, "OpenSees", theirs)
    print("bisected: duhamel", fine.collapse_intensities, "OpenSees", bisected)
    assert np.isfinite(theirs).sum() >= 4, theirs  # the grid spans the collapses
    ours = grid.collapse_intensities
    assert np.array_equal(np.isinf(ours), np.isinf(theirs))
    done = np.isfinite(theirs)
    assert np.all(np.abs(ours[done] - theirs[done]) <= GRID[1] - GRID[0] + 1e-12)
    np.testing.assert_allclose(fine.collapse_intensities[done], bisected[done], rtol=1e-3)
