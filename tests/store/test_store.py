"""Streamed runs (``solve(..., store=)``) and ``duhamel.resume``: bit for bit against the
in-memory run, killed runs resumed, damaged stores, refused models, bounded memory."""

from __future__ import annotations

import itertools
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

zarr = pytest.importorskip("zarr")

import duhamel  # noqa: E402
from duhamel import elements as el  # noqa: E402
from duhamel.store import Store, StoreError, resume  # noqa: E402
from duhamel.store._codec import unpack  # noqa: E402

#: One block of 1024 rows per segment: several segments in short runs.
SMALL = 1


def chain(n: int = 4, *, zeta: float = 0.03, C: np.ndarray | None = None) -> duhamel.System:
    K = 100.0 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    K[-1, -1] = 100.0
    return (
        duhamel.System(np.eye(n), K, zeta=zeta) if C is None else duhamel.System(np.eye(n), K, C=C)
    )


def record(n: int = 4, amplitude: float = 3.0) -> duhamel.loads.BaseAcceleration:
    t = np.linspace(0.0, 20.0, 2001)
    return duhamel.loads.BaseAcceleration(np.ones(n), t=t, values=amplitude * np.sin(7 * t))


def linear() -> duhamel.System:
    s = chain()
    s.add_load(duhamel.loads.Harmonic(dof=3, amplitude=5.0, omega=3.0))
    s.add_load(record())
    return s


def hysteretic() -> duhamel.System:
    s = chain()
    s.add_load(record())
    s.add(el.Bilinear(0, None, k=50.0, fy=0.5, alpha=0.1))
    s.add(el.BoucWen(1, 2, k=40.0, fy=0.3, alpha=0.05))
    s.add(el.Cubic(3, k3=30.0))
    return s


def coupled(elements: bool = False) -> duhamel.System:
    C = np.diag([0.1] * 4)
    C[0, 1] = C[1, 0] = 0.3
    s = chain(C=C)
    s.add_load(duhamel.loads.Harmonic(dof=1, amplitude=5.0, omega=3.0))
    if elements:
        s.add(el.BoucWen(1, 2, k=40.0, fy=0.3, alpha=0.05))
    return s


def same(a: object, b: object) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and np.array_equal(a, b)


def assert_same(st: duhamel.Solution, ref: duhamel.Solution, *, modal: bool = True) -> None:
    for name in ("t", "x", "v", "a", "a_absolute"):
        assert same(getattr(st, name), getattr(ref, name)), name
    assert same(st.dofs, ref.dofs)
    if modal:
        for name in ("q", "v", "a", "p", "pseudo_force"):
            assert same(getattr(st.modal, name), getattr(ref.modal, name)), f"modal.{name}"
    assert len(st.elements) == len(ref.elements)
    for e, f in zip(st.elements, ref.elements, strict=True):
        assert type(e.element) is type(f.element)
        for name in ("x", "v", "force"):
            assert same(getattr(e, name), getattr(f, name)), f"element {name}"
    assert st.stats.steps == ref.stats.steps


CASES = {
    "uncoupled": (linear, {"save_every": 1}),
    "hysteretic": (hysteretic, {"save_every": 3, "dofs": [0, 3]}),
    "first-order": (coupled, {"save_every": 2}),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_store_run_is_the_in_memory_run_bit_for_bit(tmp_path, case):
    make, options = CASES[case]
    kw = {"t_end": 80.0, "dt": 0.01, "x0": [0.01, 0.0, -0.01, 0.02], **options}
    ref = duhamel.solve(make(), duhamel.Semianalytic(), **kw)
    st = duhamel.solve(
        make(), duhamel.Semianalytic(), store=Store(tmp_path / "r.zarr", segment_bytes=SMALL), **kw
    )
    assert ref.t.size > 2 * 1024  # three segments or more
    assert isinstance(st.x, duhamel.store.StoredArray)
    assert_same(st, ref)
    assert st.stats.newton_iterations == ref.stats.newton_iterations
    assert st.stats.coupling == ref.stats.coupling
    # read back without the system
    again = resume(tmp_path / "r.zarr")
    assert_same(again, ref)
    assert [type(e.element) for e in again.elements] == [type(e.element) for e in ref.elements]
    assert again.meta["integrator"] == duhamel.Semianalytic()


def test_first_order_elements_restart_their_newton_matrix(tmp_path):
    # The exact coupled route with elements keeps its Newton iteration matrix across steps;
    # a segment starts a new one: the store run agrees to the Newton tolerance (not bit for
    # bit) with the in-memory run, and a resumed store run is the uninterrupted one exactly.
    kw = {"t_end": 30.0, "dt": 0.01}
    ref = duhamel.solve(coupled(True), duhamel.Semianalytic(), **kw)
    where = Store(tmp_path / "r.zarr", segment_bytes=SMALL)
    st = duhamel.solve(coupled(True), duhamel.Semianalytic(), store=where, **kw)
    assert np.allclose(st.x, ref.x, rtol=0, atol=1e-9 * np.abs(ref.x).max())
    slots = zarr.open_group(tmp_path / "r.zarr")["checkpoints"]
    # back to the checkpoint before the last: the final segment is recomputed
    newest = max(("0", "1"), key=lambda k: unpack(slots[k][...]).seq)
    slots[newest][...] = np.zeros(slots[newest].shape, dtype=np.uint8)
    assert_same(resume(tmp_path / "r.zarr"), st)


def test_modal_false_keeps_the_physical_response(tmp_path):
    kw = {"t_end": 20.0, "dt": 0.01, "dofs": [2]}
    ref = duhamel.solve(hysteretic(), duhamel.Semianalytic(), **kw)
    where = Store(tmp_path / "r.zarr", modal=False, segment_bytes=SMALL)
    st = duhamel.solve(hysteretic(), duhamel.Semianalytic(), store=where, **kw)
    assert st.modal is None
    assert_same(st, ref, modal=False)
    assert "modal_q" not in zarr.open_group(tmp_path / "r.zarr")["data"]


def test_checkpoint_every_and_interrupted_resume(tmp_path):
    """A run stopped by its progress function keeps its checkpoints; resume finishes it."""
    kw = {"t_end": 60.0, "dt": 0.01, "save_every": 1}
    ref = duhamel.solve(hysteretic(), duhamel.Semianalytic(), **kw)
    path = tmp_path / "r.zarr"
    seen = []

    def stop(step: int, total: int, t: float) -> None:
        seen.append(step)
        if step > 4000:
            raise RuntimeError("stop here")

    where = Store(path, segment_bytes=SMALL)
    with pytest.raises(RuntimeError, match="stop here") as info:
        duhamel.solve(
            hysteretic(), duhamel.Semianalytic(), store=where, checkpoint_every=2,
            progress=stop, **kw,
        )  # fmt: skip
    assert info.value.partial.t.size > 2048
    assert all(b >= a for a, b in itertools.pairwise(seen))
    done = [unpack(zarr.open_group(path)["checkpoints"][k][...]) for k in ("0", "1")]
    assert max(c.step for c in done) % 2048 == 0  # every second segment
    assert_same(resume(path), ref)


@pytest.mark.parametrize("every", [1, 3, -5, 0])
@pytest.mark.parametrize("integrator", [duhamel.Semianalytic(), duhamel.Newmark()])
def test_checkpoint_every_without_store_is_refused(every, integrator):
    """Issue 38: `checkpoint_every` without `store` was accepted and ignored."""
    s = linear()
    prepared = duhamel.prepare(s, integrator, dt=0.01)
    for run in (
        lambda: duhamel.solve(s, integrator, t_end=1.0, dt=0.01, checkpoint_every=every),
        lambda: prepared.run(t_end=1.0, checkpoint_every=every),
        lambda: prepared.run(t_end=1.0, checkpoint_every=every, t_eval=[0.5]),
    ):
        with pytest.raises(ValueError, match="`checkpoint_every`"):
            run()


@pytest.mark.parametrize("every", [-5, 0, 2**70])
def test_checkpoint_every_with_store_must_be_a_positive_integer(tmp_path, every):
    p = duhamel.prepare(linear(), duhamel.Semianalytic(), dt=0.01)
    for run in (
        lambda: p.run(t_end=1.0, store=tmp_path / "a.zarr", checkpoint_every=every),
        lambda: duhamel.solve(linear(), duhamel.Semianalytic(), t_end=1.0, dt=0.01,
                              store=tmp_path / "b.zarr", checkpoint_every=every),
    ):  # fmt: skip
        with pytest.raises(ValueError, match="`checkpoint_every`"):
            run()
    for bad in (1.5, "2", True):
        with pytest.raises(TypeError, match="`checkpoint_every`"):
            p.run(t_end=1.0, store=tmp_path / "c.zarr", checkpoint_every=bad)
    assert not any(tmp_path.iterdir())  # refused before any store is created


KILLED = """
import sys, duhamel
sys.path.insert(0, {tests!r})
from test_store import hysteretic
from duhamel.store import Store
path = sys.argv[1]
if sys.argv[2] == "start":
    duhamel.solve(hysteretic(), duhamel.Semianalytic(), t_end={t_end}, dt=0.01, dofs=[0, 2],
                  store=Store(path, segment_bytes=1))
else:
    duhamel.resume(path)
"""


def committed(path: Path) -> int:
    """The step of the newest intact checkpoint (0 before the first)."""
    try:
        slots = zarr.open_group(path, mode="r")["checkpoints"]
    except Exception:
        return 0
    found = [unpack(slots[k][...]) for k in ("0", "1") if k in slots]
    return max((c.step for c in found if c is not None), default=0)


def test_sigkill_at_random_points_then_resume_is_bit_for_bit(tmp_path):
    t_end = 400.0
    script = tmp_path / "killed.py"
    script.write_text(
        KILLED.format(tests=str(Path(__file__).parent), t_end=t_end), encoding="utf-8"
    )
    path = tmp_path / "killed.zarr"
    rng = np.random.default_rng(14)
    progress = []
    for attempt in range(3):
        mode = "start" if attempt == 0 else "resume"
        before = committed(path)
        child = subprocess.Popen([sys.executable, str(script), str(path), mode])
        deadline = time.monotonic() + 60.0
        while committed(path) <= before and child.poll() is None:
            assert time.monotonic() < deadline, "no checkpoint within 60 s"
            time.sleep(0.01)
        time.sleep(rng.uniform(0.0, 0.3))  # somewhere inside a later segment
        child.send_signal(signal.SIGKILL)
        child.wait()
        progress.append(committed(path))
    assert progress[0] > 0 and progress == sorted(progress)
    resumed = resume(path)
    kw = {"t_end": t_end, "dt": 0.01, "dofs": [0, 2]}
    whole = duhamel.solve(
        hysteretic(), duhamel.Semianalytic(), store=Store(tmp_path / "w.zarr", segment_bytes=1),
        **kw,
    )  # fmt: skip
    assert_same(resumed, whole)
    assert_same(resumed, duhamel.solve(hysteretic(), duhamel.Semianalytic(), **kw))


def test_damaged_missing_and_foreign_stores(tmp_path):
    with pytest.raises(FileNotFoundError, match="`path`"):
        resume(tmp_path / "nothing.zarr")
    zarr.open_group(tmp_path / "other.zarr", mode="w").attrs["x"] = 1
    with pytest.raises(StoreError, match="not a duhamel store"):
        resume(tmp_path / "other.zarr")
    (tmp_path / "junk").mkdir()
    (tmp_path / "junk" / "zarr.json").write_text("{not json", encoding="utf-8")
    with pytest.raises(StoreError, match="not a readable zarr store"):
        resume(tmp_path / "junk")
    path = tmp_path / "r.zarr"
    kw = {"t_end": 30.0, "dt": 0.01}
    st = duhamel.solve(linear(), duhamel.Semianalytic(), store=Store(path, segment_bytes=1), **kw)
    with pytest.raises(FileExistsError, match=r"`store`.*already exists"):
        duhamel.solve(linear(), duhamel.Semianalytic(), store=path, **kw)
    # torn checkpoints: both slots damaged -> the run starts again, same result
    slots = zarr.open_group(path)["checkpoints"]
    for k in ("0", "1"):
        raw = slots[k][...]
        raw[len(raw) // 2] ^= 0xFF
        slots[k][...] = raw
    assert_same(resume(path), st)
    group = zarr.open_group(path)
    record = dict(group.attrs["duhamel"])
    group.attrs["duhamel"] = {**record, "format": 99}
    with pytest.raises(StoreError, match="format 99"):
        resume(path)
    group.attrs["duhamel"] = {**record, "model": json.dumps({"route": 1})}
    with pytest.raises(StoreError, match="damaged"):
        resume(path)


def test_python_functions_and_direct_integrators_are_refused(tmp_path):
    s = chain()
    s.add_load(duhamel.loads.Callable(lambda t: np.zeros(4)))
    with pytest.raises(ValueError, match=r"`store`.*Callable.*Python code"):
        duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.1, store=tmp_path / "a")
    s = chain()
    s.add(el.Callable([0], lambda x, v, t: x**3))
    with pytest.raises(ValueError, match=r"`store`.*Callable"):
        duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.1, store=tmp_path / "b")
    with pytest.raises(ValueError, match=r"`store`.*Semianalytic"):
        duhamel.solve(chain(), duhamel.Newmark(), t_end=1.0, dt=0.1, store=tmp_path / "c")
    with pytest.raises(TypeError, match="`store`"):
        duhamel.solve(chain(), duhamel.Semianalytic(), t_end=1.0, dt=0.1, store=3)
    with pytest.raises(ValueError, match="`checkpoint_every`"):
        duhamel.solve(
            chain(), duhamel.Semianalytic(), t_end=1.0, dt=0.1, store=tmp_path / "d",
            checkpoint_every=0,
        )  # fmt: skip
    assert not any((tmp_path / n).exists() for n in "abc")


PEAK = """
import sys, numpy as np, duhamel
from duhamel.store import Store

def hwm():  # peak resident memory of this process image in KiB (ru_maxrss survives exec)
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmHWM:"))

n = 10
K = 100.0 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
s = duhamel.System(np.eye(n), K, zeta=0.02)
s.add_load(duhamel.loads.Harmonic(dof=n - 1, amplitude=1.0, omega=3.0))
base = hwm()
kw = dict(t_end=1.5e6 * 1e-3, dt=1e-3, dofs=[n - 1])
if sys.argv[1] == "store":
    where = Store(sys.argv[2], segment_bytes=2**22)
    sol = duhamel.solve(s, duhamel.Semianalytic(), store=where, **kw)
    ok = sol.t.shape[0] == 1_500_001 and float(sol.t[-1]) == 1500.0
else:
    sol = duhamel.solve(s, duhamel.Semianalytic(), **kw)
    ok = True
print(base, hwm(), ok)
"""


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads /proc (Linux)")
def test_memory_stays_bounded(tmp_path):
    """1.5e6 steps: the in-memory run holds a history of about 300 MB (modal q, v, loads and
    x, v, a of one dof); the streamed run's peak grows by a few segments of 4 MB."""
    peaks = {}
    for mode in ("store", "memory"):
        done = subprocess.run(
            [sys.executable, "-c", PEAK, mode, str(tmp_path / "m.zarr")],
            capture_output=True, text=True, timeout=120,
            env={**os.environ, "OPENBLAS_NUM_THREADS": "1"},
        )  # fmt: skip
        assert done.returncode == 0, done.stderr
        base, peak, ok = done.stdout.split()
        assert ok == "True"
        peaks[mode] = (int(peak) - int(base)) / 1024  # MiB
    assert peaks["memory"] > 150
    assert peaks["store"] < 60, peaks


def test_a_failing_run_fails_as_in_memory(tmp_path):
    s = duhamel.System(np.eye(1), np.eye(1))
    s.add(el.Cubic(0, k3=-1.0))  # unstable beyond x = 1: diverges in the second segment
    kw = {"t_end": 50.0, "dt": 0.01, "x0": [1.0 + 1e-9]}
    caught = []
    for store in (None, Store(tmp_path / "r.zarr", segment_bytes=SMALL)):
        with pytest.raises(duhamel.SolverError) as info:
            duhamel.solve(s, duhamel.Semianalytic(subdivisions=0), store=store, **kw)
        caught.append(info.value)
    ref, st = caught
    assert ref.step > 1024
    assert (st.reason, st.step, st.time, str(st)) == (ref.reason, ref.step, ref.time, str(ref))
    assert same(st.partial.t, ref.partial.t) and same(st.partial.x, ref.partial.x)
