"""Labelled results (issue 14, part): Solution.to_xarray and to_dataframe, round trips
through netCDF (scipy engine) and zarr equal to the arrays of the run."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel

xr = pytest.importorskip("xarray")


def run(**kw) -> duhamel.Solution:
    s = duhamel.System(np.diag([1.0, 2.0, 1.5]), np.diag([4.0, 9.0, 1.0]), zeta=0.02)
    return duhamel.solve(s, duhamel.Semianalytic(), t_end=2.0, dt=0.05, x0=[1.0, 0.0, 0.5], **kw)


def test_dataset_holds_the_run() -> None:
    sol = run(dofs=[2, 0])
    ds = sol.to_xarray(labels=["x_0", "x_1", "x_2"])
    assert dict(ds.sizes) == {"time": 41, "dof": 2}
    np.testing.assert_array_equal(ds["x"].values, sol.x)
    np.testing.assert_array_equal(ds["v"].values, sol.v)
    np.testing.assert_array_equal(ds["a"].values, sol.a)
    np.testing.assert_array_equal(ds["time"].values, sol.t)
    assert list(ds["dof"].values) == [2, 0] and list(ds["label"].values) == ["x_2", "x_0"]
    assert ds.attrs["dt"] == 0.05 and ds.attrs["steps"] == 40
    assert "Semianalytic" in ds.attrs["integrator"]
    assert float(ds["x"].sel(dof=0, time=0.0)) == 1.0
    with pytest.raises(ValueError, match="`labels`"):
        sol.to_xarray(labels=["a", "b"])


def test_round_trips_netcdf_and_zarr(tmp_path) -> None:
    sol = run()
    ds = sol.to_xarray(labels=["a", "b", "c"])
    nc = tmp_path / "run.nc"
    ds.to_netcdf(nc, engine="scipy")
    with xr.open_dataset(nc, engine="scipy") as back:
        xr.testing.assert_identical(back.load(), ds)
    pytest.importorskip("zarr")
    store = tmp_path / "run.zarr"
    ds.to_zarr(store, consolidated=False)
    with xr.open_zarr(store, consolidated=False) as back:
        np.testing.assert_array_equal(back["x"].values, sol.x)
        assert list(back["label"].values) == ["a", "b", "c"]


def test_dataframe() -> None:
    pytest.importorskip("pandas")
    sol = run()
    df = sol.to_dataframe("v", labels=["a", "b", "c"])
    assert list(df.columns) == ["a", "b", "c"] and df.index.name == "time"
    np.testing.assert_array_equal(df.to_numpy(), sol.v)
    assert list(sol.to_dataframe().columns) == [0, 1, 2]
    with pytest.raises(ValueError, match="`quantity`"):
        sol.to_dataframe("q")


def test_models_carry_their_dof_labels(tmp_path) -> None:
    from duhamel.rotor import STEEL, Bearing, Rotor, Shaft

    rotor = Rotor(
        [Shaft(0.3, 0.05, material=STEEL)] * 2, [], [Bearing(0, 1e7, 1e7), Bearing(2, 1e7, 1e7)]
    )
    system = rotor.system(0.0)
    assert system.dof_labels == rotor.dof_labels and system.dof_labels[:5] == (
        "x_0", "y_0", "theta_x_0", "theta_y_0", "x_1",
    )  # fmt: skip
    kw = {"t_end": 1e-3, "dt": 1e-4, "x0": np.r_[1e-5, np.zeros(11)], "dofs": [7, 0]}
    for sol in (
        duhamel.solve(system, duhamel.Semianalytic(), **kw),
        duhamel.solve(system, duhamel.Newmark(), **kw),
        duhamel.solve(system, duhamel.Semianalytic(), store=tmp_path / "r.zarr", **kw),
    ):
        assert list(sol.to_xarray()["label"].values) == ["theta_y_1", "x_0"]
        assert list(sol.to_dataframe().columns) == ["theta_y_1", "x_0"]
    assert list(sol.to_xarray(labels=[f"d{i}" for i in range(12)])["label"].values) == [
        "d7", "d0",
    ]  # fmt: skip
    s = duhamel.System(np.eye(2), np.eye(2))
    with pytest.raises(ValueError, match="`labels` must name all 2"):
        s.label_dofs(["a"])
    with pytest.raises(ValueError, match="distinct"):
        s.label_dofs(["a", "a"])
