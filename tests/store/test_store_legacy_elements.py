"""Stores written by the previous release hold their elements as ``_spec`` tuples and
``{"class", "fields"}`` records (the dataclass fields, old parameter names); this release
writes each element's definition as data. A stored run of the previous release must still
rebuild the very elements its run evaluated: the same definitions, and for an element whose
linear part went into the background the same remainder (its ``k0`` and the damping ``c0``
taken out with it), bit for bit. (A real store of the previous release was resumed bit for
bit by hand when this changed; this test pins the reading of its records.)"""

from __future__ import annotations

import pickle
import warnings

import numpy as np

import duhamel
from duhamel.store._model import capture, run_elements

E = duhamel.elements


def _frame() -> duhamel.System:
    m = np.diag([1e5, 1e5, 8e4, 6e4])
    k = 2e7 * np.array(
        [[2.0, -1.0, 0.0, 0.0], [-1.0, 2.0, -1.0, 0.0], [0.0, -1.0, 2.0, -1.0], [0, 0, -1, 1]]
    )
    s = duhamel.System(m, k, rayleigh=(0.1, 0.002))  # beta != 0: the remainders carry c0
    s.add(E.Bilinear(0, None, k=3e6, fy=4e4, alpha=0.05))
    s.add(E.Spring(1, 0, k=1e6, k3=1e9))
    s.add(E.ViscousDamper(2, 1, c=1e5, exponent=0.5))
    s.add(E.FrictionPendulum((3,), radius=2.0, mu=0.05, weight=6e4 * 9.81))
    return s


#: The records the previous release wrote for the elements of `_frame` (its dataclasses'
#: fields, by their old names), and its ``_spec`` tuples (read only as "not data").
LEGACY_DEVICES = [
    {"class": "Bilinear", "fields": {"i": 0, "j": None, "k": 3e6, "fy": 4e4, "alpha": 0.05}},
    {"class": "Spring", "fields": {"i": 1, "j": 0, "k": 1e6, "k3": 1e9}},
    {
        "class": "ViscousDamper",
        "fields": {"i": 2, "j": 1, "c": 1e5, "exponent": 0.5, "v0": 1e-4, "brace_stiffness": None},
    },
    {
        "class": "FrictionPendulum",
        "fields": {
            "dof_x": 3,
            "dof_y": None,
            "radius": 2.0,
            "mu": 0.05,
            "weight": 6e4 * 9.81,
            "yield_displacement": 2.5e-4,
            "mu_slow": None,
            "rate": 0.0,
            "dof_z": None,
            "vertical_stiffness": None,
            "contact_area": None,
            "delta_mu": 0.0,
            "pressure_alpha": 0.0,
        },
    },
]
LEGACY_SPECS = [("shifted",), ("spring",), ("viscous_damper",), ("shifted",)]


def test_a_previous_release_store_rebuilds_the_same_run_elements() -> None:
    system = _frame()
    model = capture(system, duhamel.Semianalytic(linear_parts="background"), None, None)
    assert all(isinstance(item, dict) for item in model.elements)  # this release's data
    new = run_elements(model)
    model.devices = [dict(d) for d in LEGACY_DEVICES]
    model.elements = list(LEGACY_SPECS)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the legacy reading warns of nothing
        old = run_elements(model)
    assert len(old) == len(new) == 4
    for a, b in zip(old, new, strict=True):
        # the same definition and remainder (k0, c0), down to the bits of the parameters
        assert pickle.dumps(a) == pickle.dumps(b)
    # the Spring's remainder is its closed form (k = 0) less c0, the others less k0 and c0
    spring = old[1].__reduce__()[1]
    assert spring[0].k == 0.0 and spring[0].k3 == 1e9 and not np.any(spring[1])
    shifted = old[0].__reduce__()[1]
    assert shifted[0] == system.elements[0]
    np.testing.assert_array_equal(shifted[2], 0.002 * np.asarray(shifted[1]))


def test_a_record_of_an_unknown_class_cannot_be_continued() -> None:
    model = capture(_frame(), duhamel.Semianalytic(linear_parts="background"), None, None)
    model.devices = [{"class": "NoSuchElement", "fields": {}}, *LEGACY_DEVICES[1:]]
    model.elements = list(LEGACY_SPECS)
    from duhamel.store._codec import StoreError

    try:
        run_elements(model)
    except StoreError as exc:
        assert "NoSuchElement" in str(exc)
    else:  # pragma: no cover - the assertion's message
        raise AssertionError("an unknown element record was rebuilt")
