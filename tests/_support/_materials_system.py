"""What the tests of the uniaxial materials in a System share (issue 37): one element of each
material scaled to the same SDOF (mass 1, initial period 1 s, yield deformation ``UY``), the
OpenSees arguments of the same material, a band-limited record, and the runs.

Every material is given with its initial stiffness ``K0`` and yield force ``FY`` so that one
record of ``0.4 g`` takes each several yield deformations (the hinges past capping).
"""

from __future__ import annotations

import os
import tempfile
from types import ModuleType
from typing import Any

import numpy as np

import duhamel
from duhamel import elements as E
from duhamel import loads as L

DT = 0.01
SECONDS = 12.0
W = 2.0 * np.pi  # 1 Hz
K0 = W**2  # mass 1
UY = 0.02
FY = K0 * UY
#: Rayleigh damping, 5 % at 1 Hz, on the mass and the initial stiffness
A0, A1 = 0.05 * W, 0.05 / W

IMK_ORDER = [
    "K0", "as_plus", "as_neg", "My_plus", "My_neg", "lambda_s", "lambda_c", "lambda_a",
    "lambda_k", "c_s", "c_c", "c_a", "c_k", "theta_p_plus", "theta_p_neg", "theta_pc_plus",
    "theta_pc_neg", "res_plus", "res_neg", "theta_u_plus", "theta_u_neg", "D_plus", "D_neg",
]  # fmt: skip
IMK = {
    "K0": K0, "as_plus": 0.03, "as_neg": 0.03, "My_plus": FY, "My_neg": -FY,
    "lambda_s": 2.0, "lambda_c": 2.0, "lambda_a": 2.0, "lambda_k": 2.0,
    "c_s": 1.0, "c_c": 1.0, "c_a": 1.0, "c_k": 1.0,
    "theta_p_plus": 0.03, "theta_p_neg": 0.03, "theta_pc_plus": 0.1, "theta_pc_neg": 0.1,
    "res_plus": 0.4, "res_neg": 0.4, "theta_u_plus": 0.3, "theta_u_neg": 0.3,
    "D_plus": 1.0, "D_neg": 1.0,
}  # fmt: skip
BILIN_ORDER = [
    "Ke", "theta_p_plus", "theta_pc_plus", "theta_u_plus", "My_plus", "Mmax_My_plus",
    "res_plus", "theta_p_neg", "theta_pc_neg", "theta_u_neg", "My_neg", "Mmax_My_neg",
    "res_neg", "lambda_s", "lambda_c", "lambda_k", "c_s", "c_c", "c_k", "D_plus", "D_neg",
]  # fmt: skip
BILIN = {
    "Ke": K0, "theta_p_plus": 0.03, "theta_pc_plus": 0.1, "theta_u_plus": 0.3,
    "My_plus": FY, "Mmax_My_plus": 1.1, "res_plus": 0.4,
    "theta_p_neg": 0.03, "theta_pc_neg": 0.1, "theta_u_neg": 0.3,
    "My_neg": FY, "Mmax_My_neg": 1.1, "res_neg": 0.4,
    "lambda_s": 2.0, "lambda_c": 2.0, "lambda_k": 2.0, "c_s": 1.0, "c_c": 1.0, "c_k": 1.0,
    "D_plus": 1.0, "D_neg": 1.0,
}  # fmt: skip
_SF, _SD = FY / 100.0, UY / 0.01  # tests/elements/test_materials_pinching.py's laws, scaled
HYST = {
    "s1p": 100.0 * _SF, "e1p": 0.01 * _SD, "s2p": 130.0 * _SF, "e2p": 0.04 * _SD,
    "s3p": 60.0 * _SF, "e3p": 0.1 * _SD, "s1n": -90.0 * _SF, "e1n": -0.01 * _SD,
    "s2n": -120.0 * _SF, "e2n": -0.05 * _SD, "s3n": -50.0 * _SF, "e3n": -0.12 * _SD,
    "pinch_x": 0.6, "pinch_y": 0.3, "damage1": 0.01, "damage2": 0.05, "beta": 0.3,
}  # fmt: skip
_SD4 = UY / 0.005
P4 = {
    "ePf1": 100.0 * _SF, "ePd1": 0.005 * _SD4, "ePf2": 150.0 * _SF, "ePd2": 0.015 * _SD4,
    "ePf3": 170.0 * _SF, "ePd3": 0.03 * _SD4, "ePf4": 40.0 * _SF, "ePd4": 0.06 * _SD4,
    "eNf1": -90.0 * _SF, "eNd1": -0.005 * _SD4, "eNf2": -140.0 * _SF, "eNd2": -0.015 * _SD4,
    "eNf3": -160.0 * _SF, "eNd3": -0.03 * _SD4, "eNf4": -35.0 * _SF, "eNd4": -0.06 * _SD4,
    "rDispP": 0.5, "rForceP": 0.25, "uForceP": 0.05,
    "rDispN": 0.5, "rForceN": 0.25, "uForceN": 0.05,
    "gK1": 1.0, "gK2": 0.2, "gK3": 0.3, "gK4": 0.2, "gKLim": 0.9,
    "gD1": 0.5, "gD2": 0.5, "gD3": 2.0, "gD4": 2.0, "gDLim": 0.5,
    "gF1": 1.0, "gF2": 0.0, "gF3": 1.0, "gF4": 1.0, "gFLim": 0.9,
    "gE": 10.0, "dmgType": "energy",
}  # fmt: skip
MULTI = {"strain": [UY, 3 * UY, 8 * UY], "stress": [FY, 1.2 * FY, 1.3 * FY]}
SPRING = {
    "strain": [-10 * UY, -UY, 0.0, UY, 10 * UY],
    "stress": [-1.5 * FY, -FY, 0.0, FY, 1.5 * FY],
}
STEEL = {"fy": FY, "E": K0, "b": 0.02}


def steel_in_series() -> dict[str, Any]:
    """A Steel02 five times as stiff as the SDOF's in series with a stiff elastic spring:
    together about ``K0``."""
    stiff = {"strain": [-1.0, 0.0, 1.0], "stress": [-5 * K0 / 4, 0.0, 5 * K0 / 4]}
    return {"materials": [("ElasticMultiLinear", stiff), ("Steel02", STEEL | {"E": 5 * K0})]}


HYST_ORDER = [
    "s1p", "e1p", "s2p", "e2p", "s3p", "e3p", "s1n", "e1n", "s2n", "e2n", "s3n", "e3n",
    "pinch_x", "pinch_y", "damage1", "damage2", "beta",
]  # fmt: skip
P4_ORDER = [
    *(f"eP{x}{i}" for i in range(1, 5) for x in "fd"),
    *(f"eN{x}{i}" for i in range(1, 5) for x in "fd"),
    "rDispP", "rForceP", "uForceP", "rDispN", "rForceN", "uForceN",
    *(f"g{g}{i}" for g in "KDF" for i in ("1", "2", "3", "4", "Lim")), "gE", "dmgType",
]  # fmt: skip

#: kind -> (duhamel's parameters with parts as (kind, parameters), OpenSees' arguments or None)
MATERIALS: dict[str, tuple[dict[str, Any], tuple[Any, ...] | None]] = {
    "Steel02": (STEEL, ("Steel02", FY, K0, 0.02)),
    "MultiLinear": (MULTI, ("MultiLinear", UY, FY, 3 * UY, 1.2 * FY, 8 * UY, 1.3 * FY)),
    "ElasticMultiLinear": (SPRING, None),
    "Takeda": ({"strain": [0.4 * UY, UY, 6 * UY], "stress": [0.5 * FY, FY, 1.15 * FY]}, None),
    "MinMax": ({"material": ("Steel02", STEEL), "min": -3.0 * UY, "max": 3.0 * UY}, None),
    "Parallel": ({"materials": [("Steel02", STEEL), ("ElasticMultiLinear", SPRING)]}, None),
    "Series": (steel_in_series(), None),
    "ModIMKPeakOriented": (IMK, ("ModIMKPeakOriented", *(IMK[k] for k in IMK_ORDER))),
    "IMKBilin": (BILIN, ("IMKBilin", *(BILIN[k] for k in BILIN_ORDER))),
    "Hysteretic": (HYST, ("Hysteretic", *(HYST[k] for k in HYST_ORDER))),
    "Pinching4": (P4, ("Pinching4", *(P4[k] for k in P4_ORDER))),
}


def keywords(params: dict[str, Any], i: Any = 0, j: Any = None) -> dict[str, Any]:
    """`params` with the parts given as ``(kind, parameters)`` made elements on ``i, j``."""

    def value(v: Any) -> Any:
        if isinstance(v, tuple) and len(v) == 2 and isinstance(v[1], dict):
            return element(v[0], v[1], i, j)
        if isinstance(v, list) and v and all(isinstance(x, tuple) for x in v):
            return [value(x) for x in v]
        return v

    return {k: value(v) for k, v in params.items()}


def element(kind: str, params: dict[str, Any], i: Any = 0, j: Any = None) -> E.Element:
    """The element ``kind`` on ``x_i - x_j``; parts given as ``(kind, parameters)``."""
    return getattr(E, kind)(i, j, **keywords(params, i, j))


def record(amplitude: float = 0.4 * 9.81) -> tuple[np.ndarray, np.ndarray]:
    """A band-limited (0.3-8 Hz) random ground acceleration with a build-up and a decay."""
    import scipy.signal

    n = round(SECONDS / DT) + 1
    rng = np.random.default_rng(37)
    t = DT * np.arange(n)
    b, a = scipy.signal.butter(4, [0.3, 8.0], btype="band", fs=1 / DT)
    env = np.minimum(t / 2.0, 1.0) * np.exp(-np.maximum(t - 8.0, 0.0) / 4.0)
    x = env * scipy.signal.lfilter(b, a, rng.normal(size=n))
    return t, amplitude * x / np.abs(x).max()


def sdof(kind: str) -> duhamel.System:
    """The SDOF (mass 1) with the material ``kind`` to the ground, Rayleigh damping on the
    mass and the initial stiffness ``K0``, under :func:`record`."""
    t, a = record()
    s = duhamel.System(np.eye(1), np.zeros((1, 1)), (A0 + A1 * K0) * np.eye(1))
    s.add(element(kind, MATERIALS[kind][0]))
    s.add_load(L.BaseAcceleration(np.ones(1), t, a))
    return s


def run(system: duhamel.System, integrator: Any, k: int) -> np.ndarray:
    """The displacements at the record's instants with the step ``DT / k``."""
    return duhamel.solve(system, integrator, t_end=SECONDS, dt=DT / k, save_every=k).x


def opensees_sdof(ops: ModuleType, args: tuple[Any, ...], k: int) -> np.ndarray:
    """OpenSees' SDOF: the material in a ``zeroLength`` with Rayleigh damping
    (``-doRayleigh 1``; initial stiffness), Newmark's average acceleration with the step
    ``DT / k``, Newton to a displacement increment of 1e-12; the displacement at the record's
    instants."""
    t, a = record()
    path = os.path.join(tempfile.mkdtemp(), "disp.out")
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.fix(1, 1)
    ops.mass(2, 1.0)
    ops.uniaxialMaterial(args[0], 1, *args[1:])
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, "-dir", 1, "-doRayleigh", 1)
    ops.rayleigh(A0, 0.0, A1, 0.0)
    recorders = [("Node", "-file", path, "-node", 2, "-dof", 1, "disp")]
    assert newmark_transient(ops, a, DT, k, recorders), "OpenSees' transient did not converge"
    x = np.loadtxt(path).reshape(-1)
    return np.concatenate([[0.0], x[k - 1 :: k]])[: t.size]


def newmark_transient(
    ops: ModuleType, a: np.ndarray, dt: float, k: int, recorders: list[tuple[Any, ...]]
) -> bool:
    """OpenSees' transient of the built model under the ground acceleration `a` (sampled at
    `dt`, ``UniformExcitation`` of a ``Path`` series along dof 1): Newmark's average
    acceleration with the step ``dt / k``, Newton to a displacement increment of 1e-12, the
    `recorders` (``ops.recorder`` arguments); whether it ran to the end. Wipes the model
    (closing the recorders)."""
    ops.timeSeries("Path", 2, "-dt", dt, "-values", *a.tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 100)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    for args in recorders:
        ops.recorder(*args)
    ran = ops.analyze((a.size - 1) * k, dt / k) == 0
    ops.wipe()
    return ran
