"""The base-isolated building example (examples/isolated_building.py) runs, and its
isolated response obeys global equilibrium: the storeys' inertia forces are carried by the
isolator alone, bounded by its friction and pendulum forces."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np


def test_isolated_building_example() -> None:
    path = Path(__file__).resolve().parents[1] / "examples" / "isolated_building.py"
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
