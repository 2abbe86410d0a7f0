"""The pinching materials (issue 37) against OpenSees' materials of the same name,
``Hysteretic`` (trilinear and bilinear envelopes) and ``Pinching4`` (energy and cycle damage,
full and symmetric forms), driven point by point as OpenSees' ``testUniaxialMaterial`` /
``setStrain`` drives them (a commit after each point).

Three deformation histories each — cycles of growing amplitude past the last envelope point,
a random walk, small cycles after a large excursion — and forces equal to 1e-8 of the largest
force, tangents to 1e-8 of the largest tangent.
"""

from __future__ import annotations

from types import ModuleType

import numpy as np
import pytest
from _materials import drive
from _materials_deteriorating import histories, load_opensees, opensees

HYST = {
    "s1p": 100.0, "e1p": 0.01, "s2p": 130.0, "e2p": 0.04, "s3p": 60.0, "e3p": 0.1,
    "s1n": -90.0, "e1n": -0.01, "s2n": -120.0, "e2n": -0.05, "s3n": -50.0, "e3n": -0.12,
    "pinch_x": 0.6, "pinch_y": 0.3, "damage1": 0.01, "damage2": 0.05, "beta": 0.3,
}  # fmt: skip
#: the bilinear form (OpenSees' 13/14-argument command)
HYST_TWO = {k: v for k, v in HYST.items() if k[:2] not in ("s3", "e3")}
#: hardening to the last point and beyond, no damage, no unloading degradation
HYST_HARD = HYST | {"s3p": 150.0, "s3n": -140.0, "damage1": 0.0, "damage2": 0.0, "beta": 0.0}
#: full pinching
HYST_PINCH = HYST | {"pinch_x": 1.0, "pinch_y": 0.0, "beta": 0.0}

P4 = {
    "ePf1": 100.0, "ePd1": 0.005, "ePf2": 150.0, "ePd2": 0.015,
    "ePf3": 170.0, "ePd3": 0.03, "ePf4": 40.0, "ePd4": 0.06,
    "eNf1": -90.0, "eNd1": -0.005, "eNf2": -140.0, "eNd2": -0.015,
    "eNf3": -160.0, "eNd3": -0.03, "eNf4": -35.0, "eNd4": -0.06,
    "rDispP": 0.5, "rForceP": 0.25, "uForceP": 0.05,
    "rDispN": 0.5, "rForceN": 0.25, "uForceN": 0.05,
    "gK1": 1.0, "gK2": 0.2, "gK3": 0.3, "gK4": 0.2, "gKLim": 0.9,
    "gD1": 0.5, "gD2": 0.5, "gD3": 2.0, "gD4": 2.0, "gDLim": 0.5,
    "gF1": 1.0, "gF2": 0.0, "gF3": 1.0, "gF4": 1.0, "gFLim": 0.9,
    "gE": 10.0, "dmgType": "energy",
}  # fmt: skip
NEGATIVE = [f"eN{x}{i}" for i in range(1, 5) for x in "fd"] + ["rDispN", "rForceN", "uForceN"]


@pytest.fixture(scope="module")
def ops() -> ModuleType:
    return load_opensees()


def hysteretic_args(p: dict) -> list[float]:
    points = [1, 2, 3] if "s3p" in p else [1, 2]
    pos = [p[f"{x}{i}p"] for i in points for x in "se"]
    neg = [p[f"{x}{i}n"] for i in points for x in "se"]
    return [*pos, *neg, p["pinch_x"], p["pinch_y"], p["damage1"], p["damage2"], p["beta"]]


def pinching4_args(p: dict) -> list:
    pos = [p[f"eP{x}{i}"] for i in range(1, 5) for x in "fd"]
    neg = [p[f"eN{x}{i}"] for i in range(1, 5) for x in "fd"] if "eNf1" in p else []
    pinch = ["rDispP", "rForceP", "uForceP"] + (["rDispN", "rForceN", "uForceN"] if neg else [])
    gammas = [f"g{g}{i}" for g in "KDF" for i in ("1", "2", "3", "4", "Lim")] + ["gE"]
    return [*pos, *neg, *(p[k] for k in pinch), *(p[k] for k in gammas), p["dmgType"]]


def check(ops: ModuleType, kind: str, params: dict, args: list, u: np.ndarray) -> np.ndarray:
    f, k = drive(kind, params, u)
    fo, ko = opensees(ops, kind, args, u)
    np.testing.assert_allclose(f, fo, rtol=0, atol=1e-8 * np.abs(fo).max())
    np.testing.assert_allclose(k, ko, rtol=0, atol=1e-8 * np.abs(ko).max())
    return f


@pytest.mark.parametrize(
    "params",
    [HYST, HYST_TWO, HYST_HARD, HYST_PINCH],
    ids=["trilinear", "bilinear", "hardening", "pinched"],
)
@pytest.mark.parametrize("history", ["cyclic", "random", "small"])
def test_hysteretic_equals_opensees(ops: ModuleType, params: dict, history: str) -> None:
    ultimate = params.get("e3p", params["e2p"])
    u = histories(0.01, ultimate)[history]
    f = check(ops, "Hysteretic", params, hysteretic_args(params), u)
    if history == "cyclic":
        assert u.max() > ultimate and np.abs(f).max() > 0.9 * params["s2p"]


@pytest.mark.parametrize(
    "params",
    [
        P4,
        P4 | {"dmgType": "cycle"},
        {k: v for k, v in P4.items() if k not in NEGATIVE},
        {k: v for k, v in P4.items() if k not in NEGATIVE} | {"dmgType": "cycle"},
        P4 | {"uForceP": 0.0, "uForceN": -0.1, "rForceN": -0.05},
    ],
    ids=["energy", "cycle", "symmetric_energy", "symmetric_cycle", "unloading_forces"],
)
@pytest.mark.parametrize("history", ["cyclic", "random", "small"])
def test_pinching4_equals_opensees(ops: ModuleType, params: dict, history: str) -> None:
    u = histories(0.004, params["ePd4"])[history]
    f = check(ops, "Pinching4", params, pinching4_args(params), u)
    if history == "cyclic":
        assert u.max() > params["ePd4"] and np.abs(f).max() > 100.0


@pytest.mark.parametrize(
    ("kind", "params", "message"),
    [
        ("Hysteretic", HYST | {"e2p": 0.005}, "`e2p`"),
        ("Hysteretic", HYST | {"s1n": 90.0}, "`s1n`"),
        ("Hysteretic", {k: v for k, v in HYST.items() if k != "s3n"}, "`s3n` and `e3n`"),
        ("Hysteretic", HYST | {"pinch_x": -0.1}, "`pinch_x`"),
        ("Pinching4", P4 | {"ePd3": 0.01}, "`ePd3`"),
        ("Pinching4", P4 | {"gFLim": -1.0}, "`gFLim`"),
        ("Pinching4", P4 | {"dmgType": "damage"}, "`dmgType`"),
        ("Pinching4", {k: v for k, v in P4.items() if k != "uForceN"}, "all eleven values or none"),
    ],
)
def test_bad_parameters_are_named(kind: str, params: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        drive(kind, params, np.zeros(3))
