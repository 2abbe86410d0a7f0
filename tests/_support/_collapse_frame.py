"""The 3-storey hinged frame of examples/collapse_ida.py in duhamel and in OpenSees, with the
same damping, records, intensity grid and collapse criterion (issue 37's collapse and speed
acceptance; tests/ensemble/test_collapse_frame_opensees.py, benchmarks/ida_frame_opensees.py).

The model is the example's: one lateral dof per floor (4e5 kg), each storey an elastic part
(the columns, 10 % of the storey stiffness), the example's ``ModIMKPeakOriented`` storey hinge
(90 %, the parameters read off ``ex.hinge``) and the leaning column's geometric stiffness
``-P / h``. In OpenSees (``basic``, 1 dof per node) each storey is one ``zeroLength`` between
its floors with the materials ``Elastic(k_col - P/h)`` and the same ``ModIMKPeakOriented`` in
direction 1 (and a ``Viscous`` one with ``damping='storeys'``).

Damping (the example's ``zeta=0.03`` is modal on the columns' stiffness, which OpenSees has no
command for): Rayleigh 3 %, a constant matrix ``C = a0 M + a1 K_d`` in both programs, with
``a0, a1`` giving 3 % at the first and third periods of ``(M, K_d)``:

* ``damping='initial'`` (the default): ``K_d`` the initial stiffness (columns, hinges elastic
  and the geometric stiffness), OpenSees' ``rayleigh a0 0 a1 0`` (``betaKinit``: each
  element's initial tangent; the ``zeroLength`` elements with ``-doRayleigh 1``, without
  which they get no stiffness-proportional damping). Classical in duhamel's modes (those of
  ``K`` and the hinges' initial stiffness);
* ``damping='storeys'``: ``K_d`` the storeys' initial stiffness without the geometric
  stiffness, in OpenSees ``rayleigh a0 0 0 0`` and storey dashpots ``Viscous(a1 k, 1)`` (which
  assemble to ``a1 K_d`` exactly). Not classical in duhamel's modes: its first-order route.

Collapse: a storey drift ratio reaching 10 % (duhamel: the example's terminal event, located
inside the step; OpenSees: checked after every step), or no convergence (duhamel:
``SolverError`` with ``solver_error='collapse'``; OpenSees: ``analyze`` returning non-zero).
Records: the example's synthetic ones, each scaled by ``IM / Sa(T1, 5 %)`` of the unscaled
record (duhamel's response spectrum; the same scaled samples go to both programs).
OpenSees: Newmark average acceleration at the records' step, Newton, ``NormDispIncr`` 1e-8 m
(50 iterations), ``BandGeneral``.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

import duhamel
from duhamel.records import G, GroundMotion
from duhamel.spectra import response_spectrum

ROOT = Path(__file__).resolve().parents[2]
ZETA = 0.03
TOL, ITERATIONS = 1e-8, 50  # OpenSees: NormDispIncr (m), its iterations
#: the example's grid (0.25 g to 3 g, 12 intensities), m/s^2
GRID = G * np.linspace(0.25, 3.0, 12)

IMK_ORDER = [
    "K0", "as_plus", "as_neg", "My_plus", "My_neg", "lambda_s", "lambda_c", "lambda_a",
    "lambda_k", "c_s", "c_c", "c_a", "c_k", "theta_p_plus", "theta_p_neg", "theta_pc_plus",
    "theta_pc_neg", "res_plus", "res_neg", "theta_u_plus", "theta_u_neg", "D_plus", "D_neg",
]  # fmt: skip


def example() -> ModuleType:
    """examples/collapse_ida.py as a module."""
    spec = importlib.util.spec_from_file_location(
        "collapse_ex", ROOT / "examples" / "collapse_ida.py"
    )
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    return ex


ex = example()
M = ex.MASS * np.eye(3)
K_S = ex.storey_matrix(ex.K_STOREY)  # initial storey stiffness: columns + hinges
K_G = ex.storey_matrix(ex.leaning_load() / ex.H)  # the leaning column's geometric stiffness
DAMPED = {"initial": K_S - K_G, "storeys": K_S}


def rayleigh(damping: str = "initial") -> tuple[float, float]:
    """``a0, a1``: ZETA at the first and third periods of ``(M, K_d)``."""
    w = np.sqrt(np.linalg.eigvalsh(np.linalg.solve(M, DAMPED[damping])))
    w1, w3 = w[0], w[-1]
    return 2 * ZETA * w1 * w3 / (w1 + w3), 2 * ZETA / (w1 + w3)


T1 = ex.first_period()


def frame(motion: GroundMotion | None = None, damping: str = "initial") -> duhamel.System:
    """The example's frame with the Rayleigh damping matrix of `damping` (loaded by
    `motion`)."""
    a0, a1 = rayleigh(damping)
    C = a0 * M + a1 * DAMPED[damping]
    s = duhamel.System(M, ex.storey_matrix(ex.LINEAR * ex.K_STOREY), C=C)
    for storey, (k, p) in enumerate(zip(ex.K_STOREY, ex.leaning_load(), strict=True)):
        j = None if storey == 0 else storey - 1
        s.add(duhamel.elements.PDelta(storey, j, P=p, height=ex.H))
        s.add(ex.hinge(storey, j, k))
    if motion is not None:
        s.add_load(motion.as_load(np.ones(3)))
    return s


def records(n: int) -> list[GroundMotion]:
    """The example's first `n` synthetic records."""
    return ex.records(n)


def sa1(motion: GroundMotion) -> float:
    """Sa(T1, 5 %) of `motion` at scale 1 (m/s^2), as ``ida`` scales it."""
    return float(response_spectrum(motion, [T1], 0.05, threads=1).psa[0, 0, 0])


def opensees_model(ops: Any, accel: np.ndarray, dt: float, damping: str = "initial") -> None:
    """The frame in OpenSees, loaded by the base acceleration `accel` (m/s^2, sampled at
    `dt`), its transient analysis defined."""
    a0, a1 = rayleigh(damping)
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(0, 0.0)
    ops.fix(0, 1)
    for n in (1, 2, 3):
        ops.node(n, 0.0, "-mass", ex.MASS)
    for storey, (k, p) in enumerate(zip(ex.K_STOREY, ex.leaning_load(), strict=True)):
        params = ex.hinge(0, None, k).parameters
        base = 10 * storey
        ops.uniaxialMaterial("Elastic", base + 1, ex.LINEAR * k - p / ex.H)
        ops.uniaxialMaterial("ModIMKPeakOriented", base + 2, *(params[n] for n in IMK_ORDER))
        mats = [base + 1, base + 2]
        if damping == "storeys":
            ops.uniaxialMaterial("Viscous", base + 3, a1 * k, 1.0)
            mats.append(base + 3)
        dirs = [1] * len(mats)
        flag = ["-doRayleigh", 1] if damping == "initial" else []  # zeroLength: off by default
        ops.element("zeroLength", storey + 1, storey, storey + 1, "-mat", *mats, "-dir", *dirs,
                    *flag)  # fmt: skip
    if damping == "storeys":
        ops.rayleigh(a0, 0.0, 0.0, 0.0)
    else:
        ops.rayleigh(a0, 0.0, a1, 0.0)
    ops.timeSeries("Path", 1, "-dt", dt, "-values", *accel.tolist())
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", TOL, ITERATIONS)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")


def opensees_run(
    ops: Any, accel: np.ndarray, dt: float, damping: str = "initial"
) -> tuple[str, float]:
    """One OpenSees transient of the frame under the base acceleration `accel` (m/s^2):
    ``('drift', t)`` when a storey drift ratio reached the collapse limit at time t,
    ``('nonconvergence', t)`` when a step found no equilibrium, else ``('none', peak
    storey drift ratio)``."""
    opensees_model(ops, accel, dt, damping)
    peak = 0.0
    for step in range(1, accel.size):
        if ops.analyze(1, dt) != 0:
            return "nonconvergence", step * dt
        x = np.array([ops.nodeDisp(n, 1) for n in (1, 2, 3)])
        drift = float(ex.storey_drifts(x).max())
        if drift >= ex.COLLAPSE_DRIFT:
            return "drift", step * dt
        peak = max(peak, drift)
    return "none", peak


def opensees_history(
    ops: Any, accel: np.ndarray, dt: float, damping: str = "initial"
) -> np.ndarray:
    """The floors' displacements (m) of one OpenSees transient at every step, from rest
    (``(accel.size, 3)``); RuntimeError if a step finds no equilibrium."""
    opensees_model(ops, accel, dt, damping)
    x = np.zeros((accel.size, 3))
    for step in range(1, accel.size):
        if ops.analyze(1, dt) != 0:
            raise RuntimeError(f"OpenSees found no equilibrium at t = {step * dt:g} s")
        x[step] = [ops.nodeDisp(n, 1) for n in (1, 2, 3)]
    return x


def opensees_first_collapse(
    ops: Any, motion: GroundMotion, grid: np.ndarray, damping: str = "initial"
) -> tuple[float, list[tuple[float, str, float]]]:
    """A hunt up `grid` (Sa(T1), m/s^2) with `motion`: the first intensity that collapses
    (``inf`` when none) and every run's ``(intensity, outcome, time or peak drift)``."""
    unit = sa1(motion)
    runs = []
    for im in grid:
        kind, value = opensees_run(ops, motion.scaled(im / unit).a, motion.dt, damping)
        runs.append((float(im), kind, value))
        if kind != "none":
            return float(im), runs
    return np.inf, runs
