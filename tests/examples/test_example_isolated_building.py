"""The base-isolated building example (examples/isolated_building.py) runs, and its
isolated response obeys global equilibrium: the storeys' inertia forces are carried by the
isolator alone, bounded by its friction and pendulum forces."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np


def test_isolated_building_example() -> None:
    path = Path(__file__).resolve().parents[2] / "examples" / "isolated_building.py"
    spec = importlib.util.spec_from_file_location("isolated_building", path)
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    out = ex.main(["--no-plot"])
    sol = out["isolated"]["solution"]
    n = ex.FLOORS + 1
    masses = np.array([ex.M_MAT] + [ex.M_FLOOR] * ex.FLOORS)
    weight = masses.sum() * ex.G
    inertia = sol.a_absolute[:, :n] @ masses
    isolator = sol.elements[0]
    # equilibrium of the whole building along x, to round-off
    assert np.abs(inertia + isolator.force[:, 0]).max() <= 1e-9 * weight
    # the isolator bounds the base shear: friction plus the pendulum's restoring force
    bound = ex.MU * weight + weight / ex.RADIUS * np.abs(isolator.x[:, 0]).max()
    assert np.abs(isolator.force[:, 0]).max() <= bound * (1 + 1e-9)
    assert out["isolated"]["base_shear"] < 0.5 * out["fixed"]["base_shear"]
    assert out["isolated"]["drift"] < out["fixed"]["drift"]


def test_isolated_building_plane_variant() -> None:
    path = Path(__file__).resolve().parents[2] / "examples" / "isolated_building.py"
    spec = importlib.util.spec_from_file_location("isolated_building_plane", path)
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    out = ex.main(["--plane", "--no-plot"])
    masses = np.array([ex.M_MAT] + [ex.M_FLOOR] * ex.FLOORS)
    weight = masses.sum() * ex.G
    for name in ("lower", "nominal", "upper"):
        sol = out[name]["solution"]
        # the base shear is the isolator's force: the frame above the mat has no ground
        # spring (K r = 0) and its modal damping none along the rigid-body mode (C r = 0)
        np.testing.assert_allclose(
            sol.base_shear(), sol.elements[0].force[:, 0], rtol=0, atol=1e-8 * weight
        )
        assert out[name]["balance"] < 1e-3
        assert out[name]["dissipated"] > 0.5
    # more friction: a stronger isolator (its force bounded by mu W + W/R |u|)
    assert out["upper"]["base_shear"] > out["nominal"]["base_shear"] > out["lower"]["base_shear"]
