"""A run described by values (issue 35, item 2): ``duhamel.SaveAt`` and ``duhamel.RunSpec``,
run by ``Prepared.execute``, give what the keywords of ``solve`` and ``Prepared.run`` give, bit
for bit, on every route and sink; their checks name the parameter."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L
from duhamel.store import Store


def frame(element: bool = True) -> duhamel.System:
    k = 4e4 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    s = duhamel.System(np.diag([2.0, 2.0, 1.5]), k, zeta=0.05)
    t = np.linspace(0.0, 2.0, 201)
    s.add_load(L.BaseAcceleration(np.ones(3), t, 3.0 * np.sin(9.0 * t)))
    if element:
        s.add(E.Bilinear(0, k=2e4, fy=40.0, alpha=0.05))
    return s


def same(a: duhamel.Solution, b: duhamel.Solution) -> None:
    for name in ("t", "x", "v", "a", "dofs"):
        assert np.array_equal(np.asarray(getattr(a, name)), np.asarray(getattr(b, name))), name
    assert len(a.elements) == len(b.elements)
    for ea, eb in zip(a.elements, b.elements, strict=True):
        assert np.array_equal(np.asarray(ea.force), np.asarray(eb.force))


@pytest.mark.parametrize(
    "integrator",
    [duhamel.Semianalytic(), duhamel.Newmark(), duhamel.Semianalytic(coupling="pseudo-force")],
    ids=["semianalytic", "newmark", "pseudo-force"],
)
@pytest.mark.parametrize("element", [False, True], ids=["linear", "bilinear"])
def test_execute_equals_the_keywords(integrator, element):
    s = frame(element)
    p = duhamel.prepare(s, integrator, dt=0.005)
    keep = duhamel.SaveAt(every=3, dofs=[2, 0], energy=True)
    spec = duhamel.RunSpec(t_end=1.5, t0=0.1, x0=[0.0, 1e-3, 0.0], saveat=keep)
    a = p.execute(spec)
    b = p.run(t_end=1.5, t0=0.1, x0=[0.0, 1e-3, 0.0], save_every=3, dofs=[2, 0], energy=True)
    c = duhamel.solve(s, integrator, dt=0.005, t_end=1.5, t0=0.1, x0=[0.0, 1e-3, 0.0],
                      save_every=3, dofs=[2, 0], energy=True)  # fmt: skip
    same(a, b)
    same(a, c)
    assert a.t[0] == 0.1 and a.dofs.tolist() == [2, 0]
    assert np.array_equal(a.energy.input, b.energy.input)
    assert np.array_equal(a.energy.damping, c.energy.damping)


def test_events_dense_and_instants_as_values():
    s = frame()
    p = duhamel.prepare(s, duhamel.Semianalytic(), dt=0.01)
    up = duhamel.Event(lambda t, x, v: x[2] - 2e-4, direction=1, name="up")
    times = np.linspace(0.2, 1.4, 7)
    keep = duhamel.SaveAt(events=[up], t_eval=times, dense=True)
    a = p.execute(duhamel.RunSpec(t_end=1.5, saveat=keep))
    b = p.run(t_end=1.5, events=[up], t_eval=times, dense=True)
    same(a, b)
    assert [o.time for o in a.events] == [o.time for o in b.events] and a.events
    assert np.array_equal(a.at(0.73)[0], b.at(0.73)[0])


def test_a_store_as_a_value(tmp_path):
    pytest.importorskip("zarr")
    s = frame()
    p = duhamel.prepare(s, duhamel.Semianalytic(), dt=0.005)
    where = Store(tmp_path / "a.zarr", modal=False, segment_bytes=2**16, checkpoint_every=2)
    a = p.execute(duhamel.RunSpec(t_end=1.5, saveat=duhamel.SaveAt(every=2), store=where))
    b = p.run(t_end=1.5, save_every=2, store=tmp_path / "b.zarr", checkpoint_every=2)
    memory = p.run(t_end=1.5, save_every=2)
    same(a, b)
    same(a, memory)
    again = duhamel.resume(tmp_path / "a.zarr")
    same(again, memory)


def test_without_element_histories(tmp_path):
    pytest.importorskip("zarr")
    s = frame()
    p = duhamel.prepare(s, duhamel.Semianalytic(), dt=0.005)
    full = p.run(t_end=1.0)
    bare = p.execute(duhamel.RunSpec(t_end=1.0, saveat=duhamel.SaveAt(elements=False)))
    assert bare.elements == () and len(full.elements) == 1
    assert np.array_equal(bare.x, full.x)
    # the balance after the run needs the elements' work: refused, not silently without it
    with pytest.raises(ValueError, match="element histories"):
        _ = bare.energy
    with pytest.raises(ValueError, match="`elements`: the energy balance reads"):
        duhamel.SaveAt(elements=False, energy=True)
    stored = p.execute(duhamel.RunSpec(t_end=1.0, saveat=duhamel.SaveAt(elements=False),
                                       store=tmp_path / "bare.zarr"))  # fmt: skip
    assert stored.elements == ()
    assert np.array_equal(np.asarray(stored.x), full.x)
    assert duhamel.resume(tmp_path / "bare.zarr").elements == ()


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"every": 0}, ValueError, "`every` must be a positive integer"),
        ({"every": 1.5}, TypeError, "`every` must be an integer"),
        ({"dense": "yes"}, TypeError, "`dense` must be True or False"),
        ({"energy": 1}, TypeError, "`energy` must be True or False"),
        ({"elements": None}, TypeError, "`elements` must be True or False"),
        ({"events": 3}, TypeError, "`events` must be a list of duhamel.Event"),
        ({"events": [3]}, TypeError, r"`events\[0\]` must be a duhamel.Event"),
        ({"t_eval": [[0.0]]}, ValueError, "`t_eval` must be a 1-D array"),
        ({"t_eval": [1.0, 0.5]}, ValueError, "`t_eval` must be increasing"),
    ],
)
def test_saveat_checks_name_the_field(kwargs, error, match):
    with pytest.raises(error, match=match):
        duhamel.SaveAt(**kwargs)


def test_keywords_keep_their_names_in_the_messages():
    s = frame(False)
    with pytest.raises(ValueError, match="`save_every` must be a positive integer"):
        duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.01, save_every=0)
    with pytest.raises(ValueError, match="`checkpoint_every` = 2 needs `store`"):
        duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.01, checkpoint_every=2)


def test_runspec_checks():
    with pytest.raises(TypeError, match="`t_end` must be a real number"):
        duhamel.RunSpec(t_end="1")
    with pytest.raises(ValueError, match="`t0` must be finite"):
        duhamel.RunSpec(t_end=1.0, t0=np.inf)
    with pytest.raises(TypeError, match=r"`saveat` must be a duhamel\.SaveAt"):
        duhamel.RunSpec(t_end=1.0, saveat={"every": 2})
    with pytest.raises(TypeError, match="`store` must be a path"):
        duhamel.RunSpec(t_end=1.0, store=3)
    with pytest.raises(ValueError, match="`checkpoint_every` must be a positive integer"):
        Store("x.zarr", checkpoint_every=0)
    assert duhamel.RunSpec(t_end=1.0, store="x.zarr").store == Store("x.zarr")
    p = duhamel.prepare(frame(False), duhamel.Semianalytic(), dt=0.01)
    with pytest.raises(TypeError, match=r"`spec` must be a duhamel\.RunSpec"):
        p.execute({"t_end": 1.0})
    located = duhamel.RunSpec(t_end=1.0, saveat=duhamel.SaveAt(every=2, dense=True))
    with pytest.raises(ValueError, match="`save_every` must be 1 and `store` None"):
        p.execute(located)
    outside = duhamel.RunSpec(t_end=1.0, saveat=duhamel.SaveAt(t_eval=[0.5, 2.0]))
    with pytest.raises(ValueError, match=r"`t_eval` must lie within the run, \[0, 1\]"):
        p.execute(outside)
