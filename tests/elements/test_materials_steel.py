"""Steel02 (issue 37) against OpenSees' ``Steel02`` driven by ``setStrain``: each variant
(OpenSees' 3-, 6-, 10- and 11-argument forms: default curvature, own curvature, isotropic
hardening, initial stress) through the three histories, forces and tangents equal to 1e-8 of
the largest. The closed-form and finite-difference properties are the Rust unit tests
(``elements/materials/steel02_tests.rs``).
"""

from __future__ import annotations

import numpy as np
import pytest
from _materials import assert_matches, drive, histories, opensees, opensees_drive

FY, E = 355.0, 2.0e5  # MPa: a steel with yield strain 1.775e-3
UY = FY / E

#: (OpenSees' arguments after the tag, duhamel's parameters)
VARIANTS = {
    "fy E b": ((FY, E, 0.01), {"fy": FY, "E": E, "b": 0.01}),
    "curvature": (
        (FY, E, 0.02, 18.0, 0.925, 0.15),
        {"fy": FY, "E": E, "b": 0.02, "R0": 18.0, "cR1": 0.925, "cR2": 0.15},
    ),
    "isotropic hardening": (
        (FY, E, 0.01, 20.0, 0.925, 0.15, 0.04, 1.0, 0.06, 1.5),
        {
            "fy": FY,
            "E": E,
            "b": 0.01,
            "R0": 20.0,
            "cR1": 0.925,
            "cR2": 0.15,
            "a1": 0.04,
            "a2": 1.0,
            "a3": 0.06,
            "a4": 1.5,
        },
    ),
    "initial stress": (
        (FY, E, 0.01, 20.0, 0.925, 0.15, 0.0, 1.0, 0.0, 1.0, 0.25 * FY),
        {"fy": FY, "E": E, "b": 0.01, "R0": 20.0, "cR1": 0.925, "cR2": 0.15, "sig_init": 0.25 * FY},
    ),
    "hardening and initial stress": (
        (FY, E, 0.005, 15.0, 0.9, 0.1, 0.02, 2.0, 0.03, 2.0, -0.4 * FY),
        {
            "fy": FY,
            "E": E,
            "b": 0.005,
            "R0": 15.0,
            "cR1": 0.9,
            "cR2": 0.1,
            "a1": 0.02,
            "a2": 2.0,
            "a3": 0.03,
            "a4": 2.0,
            "sig_init": -0.4 * FY,
        },
    ),
}


@pytest.mark.parametrize("variant", list(VARIANTS))
@pytest.mark.parametrize("history", ["cyclic", "random", "small after large"])
def test_steel02_equals_opensees(variant: str, history: str) -> None:
    ops = opensees()
    args, params = VARIANTS[variant]
    u = histories(UY)[history]

    def define(ops):
        ops.uniaxialMaterial("Steel02", 1, *args)
        return 1

    assert_matches(drive("Steel02", params, u), opensees_drive(ops, define, u), variant)


def test_steel02_defaults_are_opensees_three_argument_form() -> None:
    u = histories(UY)["cyclic"]
    default = drive("Steel02", {"fy": FY, "E": E, "b": 0.01}, u)
    explicit = drive(
        "Steel02",
        {
            "fy": FY,
            "E": E,
            "b": 0.01,
            "R0": 15.0,
            "cR1": 0.925,
            "cR2": 0.15,
            "a1": 0.0,
            "a2": 1.0,
            "a3": 0.0,
            "a4": 1.0,
            "sig_init": 0.0,
        },
        u,
    )
    np.testing.assert_array_equal(default[0], explicit[0])


def test_bad_parameters_name_themselves() -> None:
    u = np.array([0.001])
    with pytest.raises(ValueError, match="`b`"):
        drive("Steel02", {"fy": FY, "E": E, "b": 1.5}, u)
    with pytest.raises(ValueError, match="`a2`"):
        drive("Steel02", {"fy": FY, "E": E, "b": 0.01, "a2": 0.0}, u)
    with pytest.raises(TypeError, match="missing required keyword argument `fy`"):
        drive("Steel02", {"E": E, "b": 0.01}, u)
    with pytest.raises(TypeError, match="unexpected keyword argument `Fy`"):
        drive("Steel02", {"Fy": FY, "fy": FY, "E": E, "b": 0.01}, u)
    with pytest.raises(ValueError, match="`deformation` contains NaN"):
        drive("Steel02", {"fy": FY, "E": E, "b": 0.01}, np.array([0.0, np.nan]))
