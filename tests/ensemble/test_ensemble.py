"""Ensembles (issue 14, part): solve_many in-process threads and on a Dask LocalCluster give
the runs of one-at-a-time solve bit for bit, in the order of the parameters; reductions,
labelled stacking, failures named by case."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel.ensemble import solve_many
from duhamel.records import GroundMotion

N = 10
T = 0.01 * np.arange(801)
RECORDS = [
    GroundMotion(np.sin((3 + k) * T) * np.exp(-0.3 * T) * (1 + 0.1 * k), 0.01, units="g")
    for k in range(4)
]


def building(p: dict) -> duhamel.System:
    """A 10-storey shear building with a yielding first storey under a scaled record."""
    k = 2e7 * np.ones(N)
    K = np.diag(k + np.r_[k[1:], 0.0]) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
    s = duhamel.System(1e5 * np.eye(N), K, zeta=0.05)
    s.add(duhamel.elements.Bilinear(0, k=1e7, fy=2e5, alpha=0.05))
    return s.add_load(RECORDS[p["record"]].scaled(p["scale"]).as_load(np.ones(N)))


#: The same building, made once: a study of it varies only the record (`study`).
MODEL = building({"record": 0, "scale": 0.0})
MODEL.loads.clear()


def study(p: dict) -> tuple[duhamel.System, dict]:
    """The case `p` as one model under that case's record: solve_many prepares it once."""
    return MODEL, {"loads": [RECORDS[p["record"]].scaled(p["scale"]).as_load(np.ones(N))]}


PARAMS = [{"record": r, "scale": s} for r in range(4) for s in (0.5, 1.0, 1.5)]
KW = {"t_end": 8.0, "dt": 0.01}


def peak_drift(sol: duhamel.Solution) -> dict:
    return {"roof": float(np.abs(sol.x[:, -1]).max()), "drift": float(np.abs(sol.x[:, 0]).max())}


def test_threads_equal_one_at_a_time() -> None:
    ens = solve_many(building, PARAMS, duhamel.Semianalytic(), workers=2, **KW)
    assert len(ens) == len(PARAMS) and ens.stats.where == "threads"
    for p, sol in zip(PARAMS, ens.results, strict=True):
        one = duhamel.solve(building(p), duhamel.Semianalytic(), threads=1, **KW)
        np.testing.assert_array_equal(sol.x, one.x)
    ds = ens.to_xarray()
    assert dict(ds.sizes) == {"case": 12, "time": 801, "dof": N}
    np.testing.assert_array_equal(ds["scale"].values, [p["scale"] for p in PARAMS])


def test_stats_are_typed_and_solve_many_is_top_level() -> None:
    """Issue 35: `Ensemble.stats` is a dataclass (the previous release's dict access still
    works, with a DeprecationWarning naming the attribute); `duhamel.solve_many` is
    `duhamel.ensemble.solve_many`."""
    import dataclasses

    assert duhamel.solve_many is solve_many and "solve_many" in duhamel.__all__
    ens = duhamel.solve_many(building, PARAMS[:2], duhamel.Semianalytic(), workers=2, **KW)
    stats = ens.stats
    assert isinstance(stats, duhamel.ensemble.EnsembleStats)
    assert (stats.runs, stats.where, stats.workers, stats.basis) == (2, "threads", 2, "per run")
    assert stats.chunk_size == 1 and stats.wall_time > 0.0
    with pytest.warns(DeprecationWarning, match=r"use `Ensemble.stats.runs`"):
        assert stats["runs"] == 2
    with pytest.warns(DeprecationWarning, match=r"use `Ensemble.stats.where`"):
        assert stats.get("where") == "threads"
    with pytest.warns(DeprecationWarning, match="dataclasses.asdict"):
        assert dict(stats.items()) == dataclasses.asdict(stats)
    assert "basis" in stats and stats.get("nothing", 3) == 3
    with pytest.raises(KeyError):
        stats["nothing"]


def test_one_prepared_model_under_every_record_equals_a_model_per_run() -> None:
    from duhamel.ensemble import batches as ensemble_run

    fresh = solve_many(building, PARAMS, duhamel.Semianalytic(), workers=2, **KW)
    ensemble_run._PREPARED.clear()
    shared = solve_many(study, PARAMS, duhamel.Semianalytic(), workers=2, **KW)
    for a, b in zip(fresh.results, shared.results, strict=True):
        np.testing.assert_array_equal(a.x, b.x)
        np.testing.assert_array_equal(a.elements[0].force, b.elements[0].force)
    # with a shared basis too (made from the first case's model)
    based = solve_many(study, PARAMS[:2], duhamel.Semianalytic(), basis="first", **KW)
    assert based.stats.basis == "shared" and based.results[0].x.shape == shared.results[0].x.shape
    # one preparation served every run of the shared model (the cache holds it once)
    prepared = [
        p for p in ensemble_run._PREPARED.values() if p.matches(MODEL, duhamel.Semianalytic(), 0.01)
    ]
    assert len(prepared) == 1
    # a model changed between runs is prepared again, not run as it was
    MODEL.add(duhamel.elements.Spring(N - 1, None, k=1e6))
    try:
        changed = solve_many(study, PARAMS[:1], duhamel.Semianalytic(), workers=1, **KW)
        assert not np.array_equal(changed.results[0].x, shared.results[0].x)
    finally:
        MODEL.elements.pop()


def test_reduce_and_dask_cluster_bit_for_bit() -> None:
    distributed = pytest.importorskip("distributed")
    local = solve_many(building, PARAMS, duhamel.Semianalytic(), reduce=peak_drift, **KW)
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        remote = solve_many(
            building, PARAMS, duhamel.Semianalytic(), reduce=peak_drift, client=client, **KW
        )
    assert remote.stats.where == "dask" and 1 <= remote.stats.chunk_size <= len(PARAMS)
    assert remote.results == local.results  # bit for bit, in order
    ds = local.to_xarray()
    np.testing.assert_array_equal(ds["roof"].values, [r["roof"] for r in local.results])
    # the peaks grow with the scale of each record
    roof = ds["roof"].values.reshape(4, 3)
    assert np.all(np.diff(roof, axis=1) > 0)


def test_failures_name_the_case() -> None:
    def bad(p):
        if p == 2:
            raise ValueError("`k` is broken")
        return duhamel.System(np.eye(1), np.eye(1))

    with pytest.raises(ValueError, match="`k` is broken") as err:
        solve_many(bad, range(4), duhamel.Semianalytic(), t_end=0.1, dt=0.01, workers=2)
    assert any("case 2: params = 2" in n for n in err.value.__notes__)
    with pytest.raises(TypeError, match="`make_system`"):
        solve_many(3, [1], duhamel.Semianalytic(), t_end=0.1, dt=0.01)
    with pytest.raises(ValueError, match="`threads`"):
        solve_many(bad, [1], duhamel.Semianalytic(), t_end=0.1, dt=0.01, threads=2)


def test_on_error_keep_and_ida_scaling() -> None:
    """A diverging run is kept as its SolverError with on_error='keep'; IDA scales every
    motion to the target Sa(T) exactly, and a linear structure's measure is proportional to
    the intensity (measure / intensity constant per motion to round-off)."""

    def unstable(c):
        return duhamel.System(np.eye(1), np.eye(1), C=c * np.eye(1))

    ens = solve_many(
        unstable, [0.1, -300.0], duhamel.Semianalytic(), t_end=10.0, dt=0.01, x0=[1.0],
        on_error="keep", workers=2,
    )  # fmt: skip
    assert isinstance(ens.results[0], duhamel.Solution)
    assert isinstance(ens.results[1], duhamel.SolverError)
    with pytest.raises(duhamel.SolverError) as err:
        solve_many(unstable, [-300.0], duhamel.Semianalytic(), t_end=10.0, dt=0.01, x0=[1.0])
    assert any("case 0" in n for n in err.value.__notes__)

    from duhamel.ensemble import ida
    from duhamel.spectra import response_spectrum

    def linear(motion):
        s = duhamel.System(1e5 * np.eye(2), 4e7 * np.array([[2.0, -1.0], [-1.0, 1.0]]), zeta=0.05)
        return s.add_load(motion.as_load(np.ones(2)))

    roof = lambda sol: float(np.abs(sol.x[:, 1]).max())  # noqa: E731
    res = ida(linear, RECORDS[:3], [1.0, 2.0, 4.0], roof, period=0.5)
    ratio = res.measures / res.intensities
    np.testing.assert_allclose(ratio, ratio[:, :1] * np.ones(3), rtol=1e-10)
    scaled = RECORDS[1].scaled(res.factors[1, 2])
    psa = response_spectrum(scaled, [0.5], 0.05).psa[0, 0, 0]
    assert psa == pytest.approx(4.0, rel=1e-12)
    assert res.fractiles().shape == (3, 3)
    with pytest.raises(ValueError, match="`period`"):
        ida(linear, RECORDS[:1], [1.0], roof)


def test_to_xarray_refuses_failed_cases() -> None:
    def unstable(c):
        return duhamel.System(np.eye(1), np.eye(1), C=c * np.eye(1))

    ens = solve_many(
        unstable, [0.1, -300.0], duhamel.Semianalytic(), t_end=10.0, dt=0.01, x0=[1.0],
        on_error="keep", reduce=lambda sol: float(np.abs(sol.x).max()),
    )  # fmt: skip
    with pytest.raises(ValueError, match=r"cases \[1\] failed"):
        ens.to_xarray()


def test_shared_basis_and_zarr_store(tmp_path) -> None:
    """One basis for all runs gives the per-run results bit for bit (threads and a cluster
    that receives it scattered once); results appended to zarr equal the in-memory dataset;
    a basis that does not fit a case's model is refused naming the case."""
    distributed = pytest.importorskip("distributed")
    integ = duhamel.Semianalytic()
    own = solve_many(building, PARAMS, integ, reduce=peak_drift, **KW)
    shared = solve_many(building, PARAMS, integ, reduce=peak_drift, basis="first", **KW)
    assert shared.results == own.results and shared.stats.basis == "shared"
    store = solve_many(
        building, PARAMS, integ, basis=building(PARAMS[0]).modal(), to_zarr=tmp_path / "a.zarr",
        chunk_size=5, dofs=[0, 9], **KW,
    )  # fmt: skip
    assert store.results == [] and len(store) == 12
    full = solve_many(building, PARAMS, integ, dofs=[0, 9], **KW).to_xarray()
    back = store.to_xarray()
    np.testing.assert_array_equal(back["x"].values, full["x"].values)
    np.testing.assert_array_equal(back["scale"].values, full["scale"].values)
    assert back["x"].encoding["chunks"][0] == 5
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        remote = solve_many(
            building, PARAMS, integ, reduce=peak_drift, client=client, basis="first",
            to_zarr=tmp_path / "b.zarr", **KW,
        )  # fmt: skip
    ds = remote.to_xarray()
    assert ds["roof"].values.tolist() == [r["roof"] for r in own.results]

    def stiffer(k):
        return duhamel.System(np.eye(2), k * np.array([[2.0, -1.0], [-1.0, 1.0]]))

    with pytest.raises(ValueError) as err:
        solve_many(stiffer, [1.0, 2.0], integ, t_end=0.1, dt=0.01, basis="first", workers=1)
    assert any("case 1" in n for n in err.value.__notes__)
    with pytest.raises(ValueError, match="`basis`"):
        solve_many(stiffer, [1.0], integ, t_end=0.1, dt=0.01, basis="all")
    with pytest.raises(ValueError, match="`to_zarr`"):
        solve_many(stiffer, [1.0], integ, t_end=0.1, dt=0.01, to_zarr="x", on_error="keep")


def test_per_run_initial_states() -> None:
    """make_system may return (system, options): a Monte Carlo over initial states."""

    def free(x0):
        return duhamel.System(np.eye(1), 4.0 * np.eye(1)), {"x0": [x0]}

    ens = solve_many(free, [0.5, 1.0, 2.0], duhamel.Semianalytic(), t_end=1.0, dt=0.01,
                     reduce=lambda sol: float(sol.x[-1, 0]))  # fmt: skip
    np.testing.assert_allclose(ens.results, np.array([0.5, 1.0, 2.0]) * np.cos(2.0), rtol=1e-12)

    def bad(p):
        return duhamel.System(np.eye(1), np.eye(1)), {"dt": 0.1}

    with pytest.raises(ValueError, match="`dt`"):
        solve_many(bad, [1], duhamel.Semianalytic(), t_end=0.1, dt=0.01)


def test_ida_collapse_event_against_a_brute_force_scan() -> None:
    """IDA with a terminal drift event as collapse criterion: the runs that collapse, and
    when, agree with a scan of the full histories at a 10 times smaller step."""
    from duhamel import events
    from duhamel.ensemble import ida

    t = np.arange(0, 6.0, 0.01)
    motions = [
        GroundMotion(np.sin((3 + k) * t) * np.exp(-0.4 * t) * (1 + 0.2 * k), 0.01, units="g")
        for k in range(2)
    ]
    height, limit = 3.0, 0.02

    def model(motion):
        s = duhamel.System(1e5 * np.eye(2), 4e7 * np.array([[1.0, -1.0], [-1.0, 1.0]]),
                           zeta=0.05)  # fmt: skip
        s.add(duhamel.elements.Bilinear(0, None, k=4e7, fy=1.2e6, alpha=0.05))
        return s.add_load(motion.as_load(np.ones(2)))

    drift = lambda sol: float(np.abs(sol.x[:, 0]).max() / height)  # noqa: E731
    stop = events.drift(0, None, limit, height, terminal=True)
    res = ida(model, motions, [2.0, 5.0, 7.0, 8.0, 11.0], drift, period=0.5, collapse=stop)
    for i, m in enumerate(motions):
        for j, f in enumerate(res.factors[i]):
            sol = duhamel.solve(model(m.scaled(f)), duhamel.Semianalytic(), t_end=m.duration,
                                dt=0.001)  # fmt: skip
            d = np.abs(sol.x[:, 0]) / height
            assert abs(d.max() / limit - 1.0) > 0.05  # no case on the edge
            if d.max() < limit:
                assert np.isnan(res.collapse_times[i, j])
                assert res.measures[i, j] == pytest.approx(d.max(), rel=1e-2)
            else:
                assert res.measures[i, j] == np.inf
                first = sol.t[np.argmax(d >= limit)]
                assert first - 0.001 - 1e-3 <= res.collapse_times[i, j] <= first + 1e-3
    assert np.isinf(res.measures).sum() == 4  # both motions collapse at 8 and 11
    with pytest.raises(ValueError, match="collapse"):
        ida(model, motions[:1], [1.0], drift, period=0.5, collapse=events.drift(0, None, 0.1))


def test_progress_reports_every_run_and_changes_nothing(capsys) -> None:
    """``progress`` (issue 39): a function hears ``(done, n_runs)`` once per run in case order;
    ``progress=True`` (a tqdm bar over the runs) gives the same results; a bad value is
    refused naming the parameter."""
    calls: list[tuple[int, int]] = []
    quiet = solve_many(study, PARAMS, duhamel.Semianalytic(), workers=2, reduce=peak_drift, **KW)
    heard = solve_many(
        study,
        PARAMS,
        duhamel.Semianalytic(),
        workers=2,
        reduce=peak_drift,
        progress=lambda done, n: calls.append((done, n)),
        **KW,
    )
    assert calls == [(k, len(PARAMS)) for k in range(1, len(PARAMS) + 1)]
    bar = solve_many(
        study, PARAMS, duhamel.Semianalytic(), workers=2, reduce=peak_drift, progress=True, **KW
    )
    assert heard.results == quiet.results == bar.results
    with pytest.raises(TypeError, match="`progress`"):
        solve_many(study, PARAMS, duhamel.Semianalytic(), progress="yes", **KW)


def test_progress_bar_shows_on_a_long_study(monkeypatch) -> None:
    """The bar is tqdm's over the runs (``unit="run"``), shown after a second like solve's."""
    import tqdm.auto

    made: list[dict] = []
    real = tqdm.auto.tqdm

    def spy(*args, **kwargs):
        made.append(kwargs)
        return real(*args, **kwargs)

    monkeypatch.setattr(tqdm.auto, "tqdm", spy)
    solve_many(study, PARAMS[:3], duhamel.Semianalytic(), workers=1, progress=True, **KW)
    assert made == [{"total": 3, "unit": "run", "delay": 1.0, "leave": False, "desc": "solve_many"}]
