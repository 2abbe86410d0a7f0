"""duhamel.design.Study (issue 39) on a small isolated building: the runs are solve's, the
statistics equal a hand computation over solve_many's results (1e-12), the dataset holds
every run's peaks, the checks take the design values of the governing model, and the report
(HTML and Markdown) prints the study's numbers and holds every table and figure."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _design_study import (
    QUANTITIES,
    check_report,
    hand_statistics,
    pairs,
    small_building,
    small_study,
)

import duhamel
from duhamel.design import Study, asce7
from duhamel.records import Suite


@pytest.fixture(scope="module")
def study() -> Study:
    return small_study().run()


def test_statistics_equal_a_hand_computation(study: Study) -> None:
    hand = hand_statistics(study)
    stats = study.statistics
    assert list(stats) == ["lower", "nominal", "upper"]
    for model in stats:
        for key in QUANTITIES:
            for kind in ("design", "mean", "mean_plus_sigma", "max"):
                np.testing.assert_allclose(
                    stats[model][key][kind], hand[model][key][kind], rtol=1e-12, atol=0
                )
    # the checks use them: the isolator displacement of the governing model
    values = study.design_values()
    value, model = values["isolator_displacement"]
    assert value == max(float(stats[m]["isolator_displacement_max"]["design"]) for m in stats)
    assert float(stats[model]["isolator_displacement_max"]["design"]) == value


def test_each_run_is_solve_and_its_peaks_are_the_solution_s(study: Study) -> None:
    """One case run on its own with duhamel.solve: the study's peaks are the solution's
    (isolators, drifts, shears above and below, floor accelerations) to round-off."""
    ds = study.dataset
    case = study.cases[len(study.suite) * 2 + 3]  # the nominal model, record 1, 90 degrees
    assert case["model"] == "nominal" and case["orientation"] == 90.0
    system = study.models["nominal"]
    first, _ = study.suite.motions(case)
    loads_system = duhamel.System(system.M, system.K, zeta=0.03)
    for e in system.elements:
        loads_system.add(e)
    loads_system.add_load(first.as_load(study.building.x))
    sol = duhamel.solve(loads_system, duhamel.Semianalytic(), t_end=study.t_end, dt=0.01)
    at = {"model": 1, "record": case["index"], "orientation": 1}
    iso = [np.abs(sol.elements[i].x[:, 0]).max() for i in study.building.isolators]
    np.testing.assert_allclose(ds["isolator_displacement"][at].values, iso, rtol=1e-12)
    x = sol.x[:, :4]
    drift = np.abs(np.diff(x, axis=1)).max(axis=0) / 3.2
    np.testing.assert_allclose(ds["storey_drift_ratio"][at].values, drift, rtol=1e-12)
    below = np.abs(sum(sol.elements[i].force[:, 0] for i in study.building.isolators)).max()
    assert float(ds["base_shear_below"][at]) == pytest.approx(below, rel=1e-9)
    # above the base level: the force across the first storey, r^T (K x + C v) with r the
    # floors above and C = M Phi diag(2 zeta omega) Phi^T M of the modes of K (zeta 3 %)
    import scipy.linalg

    m = np.asarray(loads_system.M)
    k = np.asarray(loads_system.K)
    w2, phi = scipy.linalg.eigh(k, m)
    omega = np.sqrt(np.clip(w2, 0.0, None))
    c = m @ phi @ np.diag(2 * 0.03 * omega) @ phi.T @ m
    r = np.array([0.0, 1.0, 1.0, 1.0])
    above = np.abs(r @ (k @ sol.x.T + c @ sol.v.T)).max()
    assert float(ds["base_shear_above"][at]) == pytest.approx(above, rel=1e-9)
    np.testing.assert_allclose(
        ds["floor_acceleration"][at].values, np.abs(sol.a_absolute).max(axis=0), rtol=1e-12
    )


def test_dataset_holds_every_run(study: Study) -> None:
    ds = study.dataset
    n_rec = len(study.suite)
    assert dict(ds.sizes) | {"time": 0} == {
        "model": 3,
        "record": n_rec,
        "orientation": 2,
        "isolator": 2,
        "storey": 3,
        "level": 4,
        "period": 40,
        "time": 0,
        "axis": 1,
        "term": 4,
    }
    runs = zip(study.ensemble.params, study.ensemble.results, strict=True)
    for k, (case, result) in enumerate(runs):
        m, rest = divmod(k, n_rec * 2)
        r, o = divmod(rest, 2)
        assert (ds["model"].values[m], ds["record"].values[r]) == (case["model"], case["record"])
        assert float(ds["base_shear_below"].values[m, r, o]) == result["base_shear_below"]
    np.testing.assert_array_equal(ds["factor"].values, study.suite.factors)
    assert ds["storey_drift_ratio"].attrs["units"] == "" and ds["energy"].attrs["units"] == "J"
    # the energy balance of each run closes (second order in dt: a few 1e-3 at 0.01 s)
    assert float(ds["energy_error"].max()) < 2e-2


def test_checks(study: Study) -> None:
    checks = study.checks
    clauses = [c.clause for c in checks]
    assert clauses == [
        "ASCE 7-22 17.3.3",
        "ASCE 7-22 16.2.3.2 (17.3.3)",
        "ASCE 7-22 17.6.4.1",
        "ASCE 7-22 17.6.4.1",
        "ASCE 7-22 17.6.4.2",
        "ASCE 7-22 17.6.4.4",
        "ASCE 7-22 16.4.1.2",
    ]
    count, scaling, disp, below, above, drift, accept = checks
    assert count.value == 7 and count.passes
    assert scaling.value == pytest.approx(0.9, rel=1e-9) and scaling.passes
    values = study.design_values()
    elf = study.elf
    assert disp.value == values["isolator_displacement"][0]
    assert disp.limit == pytest.approx(0.8 * elf.d_tm, rel=1e-15)
    assert below.limit == pytest.approx(0.9 * elf.v_b, rel=1e-15)
    assert above.value == pytest.approx(values["base_shear_above"][0] / 2.0, rel=1e-15)
    assert above.limit == pytest.approx(0.6 * elf.v_s, rel=1e-15)
    stats = study.statistics
    worst = max(float(stats[m]["storey_drift_ratio"]["design"].max()) for m in stats)
    assert drift.value == worst and accept.value == worst
    assert drift.limit == 0.020 and accept.limit == 0.040
    # each design check names the model (property set) it comes from
    assert all(c.quantity.endswith(" properties]") for c in checks[2:])


def test_report(study: Study, tmp_path: Path) -> None:
    html, md = study.report(tmp_path / "study.html", command="pytest")
    assert html == tmp_path / "study.html" and md == tmp_path / "study.md"
    page = check_report(study, html, md)
    reproduce = dict(page.tables["table-reproduce"])
    assert reproduce["command"] == "pytest"
    assert reproduce["duhamel"] == duhamel.__version__
    assert len(reproduce["model digest (sha256)"]) == 16
    with pytest.raises(ValueError, match="`path`"):
        study.report(tmp_path / "study.txt")


def test_three_dimensional_building() -> None:
    """x and y: the pair's components along both axes at once; the bearings' displacement is
    the vector's length; each direction's drifts and shears, the larger kept."""
    study = Study(
        small_building(three_d=True),
        Suite(pairs(2, duration=5.0)),
        duhamel.Semianalytic(),
        dt=0.01,
        sm1=0.9,
        workers=1,
        progress=False,
    ).run()
    ds = study.dataset
    assert ds.sizes["axis"] == 2 and list(ds["model"].values) == ["nominal"]
    u = ds["isolator_deformation"].values  # (model, record, orientation, time, isolator, axis)
    radial = np.sqrt((u**2).sum(axis=-1)).max(axis=3)
    np.testing.assert_allclose(ds["isolator_displacement"].values, radial, rtol=1e-12)
    assert np.all(np.abs(u[..., 1]).max(axis=3) > 0)  # y moves
    # fewer than seven records: the design value is the largest (17.6.3.4)
    s = study.statistics["nominal"]["base_shear_below"]
    assert float(s["design"]) == float(s["max"])
    assert not study.checks[0].passes


def test_a_study_s_runs_travel_to_a_cluster(study: Study) -> None:
    """What solve_many sends to Dask workers (the case maker and the per-run reduction)
    pickles, and the copies give the same peaks."""
    import pickle

    from duhamel.design.quantities import Cases, RunPeaks

    make = Cases(study.models, study.suite, study.building.x)
    reduce = RunPeaks(study.building, study.periods)
    make2, reduce2 = pickle.loads(pickle.dumps((make, reduce)))
    case = study.cases[0]
    system, options = make2(case)
    prepared = duhamel.prepare(system, study.integrator, dt=0.01, threads=1)
    sol = prepared.run(t_end=study.t_end, energy=True, **options)
    peaks = reduce2(sol)
    np.testing.assert_array_equal(
        peaks["isolator_displacement"], study.ensemble.results[0]["isolator_displacement"]
    )


def test_bad_input() -> None:
    b = small_building()
    suite = Suite(pairs(1, duration=2.0))
    with pytest.raises(TypeError, match="`model`"):
        Study(b.system, suite, duhamel.Semianalytic(), dt=0.01, sm1=0.9)
    with pytest.raises(TypeError, match="`suite`"):
        Study(b, pairs(1), duhamel.Semianalytic(), dt=0.01, sm1=0.9)
    with pytest.raises(ValueError, match="`sm1`"):
        Study(b, suite, duhamel.Semianalytic(), dt=0.01)
    with pytest.raises(ValueError, match="`risk_category`"):
        Study(b, suite, duhamel.Semianalytic(), dt=0.01, sm1=0.9, risk_category="V")
    with pytest.raises(ValueError, match="`heights`"):
        duhamel.design.Building(b.system, [0, 1, 2, 3], [3.0, 3.0])
    with pytest.raises(ValueError, match="`isolators`"):
        duhamel.design.Building(b.system, [0, 1, 2, 3], [3.0] * 3, isolators=[5])
    assert asce7.MIN_RECORDS == 7
