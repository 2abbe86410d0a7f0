"""Studies in batches (issue 42, "Studies that scale"): solve_many's Dask tasks carry many
runs each, sized from the measured time of the first runs; the results are those of the
unbatched study bit for bit and in case order, a failing run is named by its own case index,
and ida's single study over every motion equals one study per motion."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import duhamel
from duhamel.ensemble import ida, solve_many
from duhamel.ensemble.batches import TAIL_SECONDS, TASK_SECONDS, batch_sizes
from duhamel.records import GroundMotion

distributed = pytest.importorskip("distributed")

T = 0.01 * np.arange(301)


def sdof(p: float) -> duhamel.System:
    """A yielding oscillator under a pulse scaled by `p` (about 1 ms a run)."""
    s = duhamel.System(np.eye(1), [[40.0]], zeta=0.05)
    s.add(duhamel.elements.Bilinear(0, k=40.0, fy=0.5, alpha=0.1))
    load = GroundMotion(np.sin(6.0 * T) * np.exp(-0.5 * T), 0.01).scaled(p)
    return s.add_load(load.as_load([1.0]))


def peak(sol: duhamel.Solution) -> float:
    return float(np.abs(sol.x).max())


PS = [0.2 + 0.05 * k for k in range(40)]
KW = {"t_end": 3.0, "dt": 0.01, "reduce": peak}


@pytest.fixture(scope="module")
def client():
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        yield client


@pytest.mark.parametrize("n", [1, 7, 40, 1000])
@pytest.mark.parametrize("seconds", [1e-5, 0.004, 0.05, 1.0])
@pytest.mark.parametrize("workers", [1, 2, 8])
def test_batch_sizes_cover_the_runs_and_shrink_toward_the_end(n, seconds, workers) -> None:
    sizes = batch_sizes(n, seconds, workers)
    assert sum(sizes) == n and min(sizes) >= 1
    # no task beyond TASK_SECONDS (but one run), none before the tail below TAIL_SECONDS
    assert max(sizes) == 1 or max(sizes) * seconds <= TASK_SECONDS
    least = min(max(1, int(TASK_SECONDS / seconds)), int(np.ceil(TAIL_SECONDS / seconds)))
    assert all(s >= least for s in sizes[:-1])
    assert all(b <= a for a, b in itertools.pairwise(sizes))  # non-increasing
    # the last tasks are short: the workers finish within about a tail task of each other
    assert sizes[-1] * seconds <= max(TAIL_SECONDS, seconds) or len(sizes) == 1


def test_batched_tasks_equal_unbatched_runs_in_order(client) -> None:
    threads = solve_many(sdof, PS, duhamel.Semianalytic(), workers=1, **KW)
    batched = solve_many(sdof, PS, duhamel.Semianalytic(), client=client, **KW)
    single = solve_many(sdof, PS, duhamel.Semianalytic(), client=client, chunk_size=1, **KW)
    assert single.stats.chunk_size == 1
    # short runs: the measured first runs put several in a task
    assert 1 < batched.stats.chunk_size <= len(PS)
    assert batched.results == threads.results == single.results  # bit for bit, in order
    assert len(set(threads.results)) == len(PS)  # every case its own answer (order checked)
    fixed = solve_many(sdof, PS, duhamel.Semianalytic(), client=client, chunk_size=7, **KW)
    assert fixed.stats.chunk_size == 7 and fixed.results == threads.results
    # Solutions in batches too, as from threads
    sols = solve_many(sdof, PS[:5], duhamel.Semianalytic(), client=client, t_end=3.0, dt=0.01)
    for sol, p in zip(sols.results, PS[:5], strict=True):
        one = duhamel.solve(sdof(p), duhamel.Semianalytic(), t_end=3.0, dt=0.01, threads=1)
        np.testing.assert_array_equal(sol.x, one.x)


def bad_at_23(p: float) -> duhamel.System:
    if p == PS[23]:
        raise ValueError("`fy` is broken")
    return sdof(p)


def unstable_at_5_and_30(p: float) -> duhamel.System:
    if p in (PS[5], PS[30]):
        return duhamel.System(np.eye(1), np.eye(1), C=-300.0 * np.eye(1))
    return sdof(p)


@pytest.mark.parametrize("where", ["threads", "dask"])
def test_a_failing_run_is_named_by_its_case_index(client, where) -> None:
    on = {"client": client} if where == "dask" else {"workers": 2}
    with pytest.raises(ValueError, match="`fy` is broken") as err:
        solve_many(bad_at_23, PS, duhamel.Semianalytic(), **on, **KW)
    assert any(f"case 23: params = {PS[23]!r}" in n for n in err.value.__notes__)
    kept = solve_many(unstable_at_5_and_30, PS, duhamel.Semianalytic(), on_error="keep",
                      x0=[0.1], **on, **KW)  # fmt: skip
    wrong = [i for i, r in enumerate(kept.results) if isinstance(r, duhamel.SolverError)]
    assert wrong == [5, 30]
    ok = solve_many(sdof, PS, duhamel.Semianalytic(), workers=1, x0=[0.1], **KW).results
    assert [r for i, r in enumerate(kept.results) if i not in (5, 30)] == [
        r for i, r in enumerate(ok) if i not in (5, 30)
    ]


MOTIONS = [
    GroundMotion(np.sin((4 + k) * t) * np.exp(-0.4 * t), 0.01, name=f"m{k}")
    for k, t in enumerate([0.01 * np.arange(n) for n in (301, 251, 401)])
]


def frame(motion: GroundMotion) -> duhamel.System:
    s = duhamel.System(np.eye(2), [[80.0, -40.0], [-40.0, 40.0]], zeta=0.05)
    s.add(duhamel.elements.Bilinear(0, k=40.0, fy=0.8, alpha=0.05))
    return s.add_load(motion.as_load(np.ones(2)))


def roof(sol: duhamel.Solution) -> float:
    return float(np.abs(sol.x[:, 1]).max())


@pytest.mark.parametrize("where", ["threads", "dask"])
def test_ida_as_one_study_equals_a_study_per_motion(client, where) -> None:
    """Records of different lengths in one study: each run on its own record's grid, as
    when each motion was its own solve_many."""
    from duhamel.ensemble.ida import _ida_case

    ims = [0.5, 1.0, 2.0, 4.0, 8.0]
    on = {"client": client} if where == "dask" else {"workers": 2}
    res = ida(frame, MOTIONS, ims, roof, intensity="pga", **on)
    for i, m in enumerate(MOTIONS):
        one = solve_many(_ida_case, [(frame, m, float(f)) for f in res.factors[i]],
                         duhamel.Semianalytic(), t_end=m.duration, dt=m.dt, reduce=roof,
                         workers=1)  # fmt: skip
        assert res.measures[i].tolist() == one.results
    assert np.all(np.diff(res.measures, axis=1) > 0)  # larger records, larger peaks
