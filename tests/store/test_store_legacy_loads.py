"""Stores written by the previous release hold their loads, speed laws and mass law as
``(kind, params)`` tuples (the ``_spec`` protocol); this release writes each of them as the
core value's data (``_core.TimeFunction``, ``_core.SpeedLaw``, ``_core.MassLaw``
``_to_value``). A stored run of the previous release must still rebuild the very loads and
laws its run stepped, bit for bit. (A real store of the previous release, with every kind of
load, a run-up coupling and each mass law, was resumed bit for bit by hand when this
changed; this test pins the reading of its records.)"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import duhamel
from duhamel import _core
from duhamel._engine.plan import mass as run_mass
from duhamel.rotor.misalignment import _CouplingForce
from duhamel.store._model import capture, load_terms

E, L = duhamel.elements, duhamel.loads
LAW = duhamel.speed.LinearRunUp(omega0=10.0, omega1=200.0, t1=0.7)
RUNUP = ("runup", (10.0, 200.0, 0.7))
T_TABLE, V_TABLE = np.array([0.0, 0.1, 0.35]), np.array([0.0, 1.0 / 3.0, -0.25])
T_GROUND = np.linspace(0.0, 1.0, 11)
A_GROUND = np.sin(7.0 * T_GROUND) * 0.1
PARALLEL, ANGULAR = (2e-4, 1e-4, 4e4), (0.01, 100.0)


def _rotor(law: duhamel.mass.MassLaw) -> duhamel.System:
    m = np.diag([2.0, 2.0, 1.0, 1.0])
    k = 1e4 * np.array([[2, 0, -1, 0], [0, 2, 0, -1], [-1, 0, 1, 0], [0, -1, 0, 1.0]])
    g = 0.3 * np.array([[0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1], [0, 0, -1, 0.0]])
    s = duhamel.System(m, k, zeta=0.02)
    s.add(E.LinearCoupling(C=g, scale=LAW))
    s.add_load(L.Step(0, amplitude=2.0, t0=0.13))
    s.add_load(L.Harmonic(1, amplitude=0.5, omega=7.0, phase=0.3))
    s.add_load(L.Tabulated(2, t=T_TABLE, values=V_TABLE, hold=True))
    s.add_load(L.BaseAcceleration(np.ones(4), t=T_GROUND, values=A_GROUND))
    s.add_load(L.Unbalance((0, 1), m_e=1e-3, speed=LAW, phase=0.2))
    for axis in "xy":
        s.add_load(_CouplingForce(2, 3, LAW, 0.0095, PARALLEL, ANGULAR, axis))
    return s.set_mass_law(law)


#: The previous release's records of `_rotor`'s loads, one per core term, in order.
LEGACY_LOADS = [
    ("step", (0.13,)),
    ("harmonic", (7.0, 0.3)),
    ("table", (T_TABLE, V_TABLE, True)),
    ("table", (T_GROUND, A_GROUND, False)),
    ("unbalance", (RUNUP, 0.2, "x")),
    ("unbalance", (RUNUP, 0.2, "y")),
    ("misalignment", (RUNUP, 0.0095, PARALLEL, ANGULAR, "x")),
    ("misalignment", (RUNUP, 0.0095, PARALLEL, ANGULAR, "y")),
]

#: Each mass law and the previous release's record of it.
MASS_LAWS = [
    (duhamel.mass.Exponential(rate=-0.1, scale=1.5), ("exponential", (-0.1, 1.5))),
    (duhamel.mass.Harmonic(amplitude=0.1, frequency=3.0), ("harmonic", (0.1, 3.0))),
    (
        duhamel.mass.Tabulated(t=[0.0, 0.5, 2.0], mu=[1.0, 0.8, 0.9]),
        ("table", (np.array([0.0, 0.5, 2.0]), np.array([1.0, 0.8, 0.9]))),
    ),
]


@pytest.mark.parametrize(("law", "legacy_law"), MASS_LAWS, ids=["exp", "harmonic", "table"])
def test_a_previous_release_store_rebuilds_the_same_loads_and_laws(law, legacy_law) -> None:
    system = _rotor(law)
    integrator = duhamel.Semianalytic()
    model = capture(system, integrator, None, None)
    # this release's data: the core values' JSON text
    assert all(isinstance(item, dict) and isinstance(item["time"], str) for item in model.loads)
    assert isinstance(model.mass["law"], str) and isinstance(model.scaled[0][2], str)
    new_loads, new_scaled = load_terms(model), model.plan().couplings.scaled
    new_mass = model.core_mass()
    # what a run of the system itself builds, bit for bit
    assert repr(new_mass) == repr(run_mass(system, integrator))
    assert len(new_loads) == len(LEGACY_LOADS)

    model.loads = [
        (item["pattern"], kind, params)
        for item, (kind, params) in zip(model.loads, LEGACY_LOADS, strict=True)
    ]
    model.scaled = [(k, c, RUNUP) for k, c, _ in model.scaled]
    model.mass = {**model.mass, "law": legacy_law}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the legacy reading warns of nothing
        old_loads, old_scaled = load_terms(model), model.plan().couplings.scaled
        old_mass = model.core_mass()
    for a, b in zip(old_loads, new_loads, strict=True):
        assert a.time._to_value() == b.time._to_value()
        assert a.pattern.tobytes() == b.pattern.tobytes()
    assert [s.law._to_value() for s in old_scaled] == [s.law._to_value() for s in new_scaled]
    assert repr(old_mass) == repr(new_mass)
    # the stored patterns are the ones the in-memory run projects
    phi = np.ascontiguousarray(model.basis.phi)
    direct = [phi.T @ term.pattern for load in system.loads for term in load._terms(system)]
    for a, b in zip(new_loads, direct, strict=True):
        np.testing.assert_array_equal(a.pattern, b)


def test_an_unknown_legacy_kind_is_refused_by_name() -> None:
    from duhamel.store._codec import StoreError

    model = capture(_rotor(MASS_LAWS[0][0]), duhamel.Semianalytic(), None, None)
    model.loads = [(model.loads[0]["pattern"], "ramp", (0.0,))]
    with pytest.raises(StoreError, match="'ramp'"):
        load_terms(model)
    model.mass = {**model.mass, "law": ("linear", (1.0,))}
    with pytest.raises(StoreError, match="'linear'"):
        model.core_mass()


def test_the_data_form_round_trips_through_the_store_codec() -> None:
    """This release's records through the store's JSON and arrays: the same core values."""
    zarr = pytest.importorskip("zarr")
    import json

    from duhamel.store._codec import decode, dumps, encode
    from duhamel.store._model import Model

    model = capture(_rotor(MASS_LAWS[2][0]), duhamel.Semianalytic(), None, None)
    group = zarr.open_group(store=zarr.storage.MemoryStore(), mode="w")
    back = Model.from_tree(decode(json.loads(dumps(encode(model.to_tree(), group))), group))
    for a, b in zip(load_terms(back), load_terms(model), strict=True):
        assert a.time._to_value() == b.time._to_value()
        assert a.pattern.tobytes() == b.pattern.tobytes()
    assert repr(back.core_mass()) == repr(model.core_mass())
    laws = [s.law._to_value() for s in back.plan().couplings.scaled]
    assert laws == [_core.SpeedLaw.run_up(10.0, 200.0, 0.7)._to_value()]
