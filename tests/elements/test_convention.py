"""One convention for where things act (docs/models.md, "Where things act"; issue 35), checked
on every public element class (the ``Element`` subclasses of ``duhamel.elements.__all__``)
and every load constructor of ``duhamel.loads``:

* the dofs come first and positionally, named as the page names them: ``i, j=None`` for a
  deformation ``x_i - x_j``, ``i`` for one dof, ``dofs`` for a device on several (and for a
  load on two), ``dof`` for a load at one; a Python element takes ``dofs`` then ``fn``; a
  support acceleration its ``direction_vector``;
* every other parameter is keyword-only; the physical ones without a standard value have no
  default, and the defaults there are are absent effects (None, 0, False), options, or the
  standard values the page names;
* the signature's defaults are what an object made with only the required parameters holds;
* dof labels are taken wherever an index is (resolved when added to a system);
* the previous release's spellings still work, warn (``DeprecationWarning`` naming the new
  signature) and give an equal object.

A new element or load fails here until its row says how it follows the convention.
"""

from __future__ import annotations

import dataclasses
import inspect
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pytest
from _materials_system import MATERIALS, keywords

import duhamel
from duhamel import elements as E
from duhamel import loads as L

#: The forms of "where" the page documents, by what acts.
WHERE_FORMS = {
    "deformation": ("i", "j"),
    "one dof": ("i",),
    "device": ("dofs",),
    "load at one dof": ("dof",),
    "load on two dofs": ("dofs",),
    "support": ("direction_vector",),
    "everywhere": (),
}

#: Defaults that are a standard value of the model (docs/models.md: they keep it).
STANDARD_VALUES = {
    ("BoucWen", "n"): 1.0,
    ("BoucWen", "beta"): 0.5,
    ("BoucWen", "gamma"): 0.5,
    ("LeadRubberBearing", "eta"): 1.0,
    ("LeadRubberBearing", "beta"): 0.5,
    ("LeadRubberBearing", "gamma"): 0.5,
    ("FrictionPendulum", "yield_displacement"): 2.5e-4,  # OpenSees'
    ("TripleFrictionPendulum", "yield_displacement"): 2.5e-4,
    ("ViscousDamper", "exponent"): 1.0,  # a linear damper
    ("ViscousDamper", "v0"): 1e-4,  # the regularisation velocity of a fractional exponent
    # OpenSees' defaults (docs/materials.md)
    ("Steel02", "R0"): 15.0,
    ("Steel02", "cR1"): 0.925,
    ("Steel02", "cR2"): 0.15,
    ("Steel02", "a2"): 1.0,
    ("Steel02", "a4"): 1.0,
    ("MinMax", "min"): -1e16,
    ("MinMax", "max"): 1e16,
    ("Series", "max_iter"): 100,
    ("Series", "tol"): 1e-10,
    ("Takeda", "alpha"): 0.4,  # Takeda, Sozen & Nielsen's unloading exponent
}

T = np.array([0.0, 0.5, 1.0, 3.0])
V = np.array([0.0, 30.0, -10.0, 0.0])


def _restoring(x: Any, v: Any, t: float) -> Any:
    return -np.asarray(x)


@dataclass
class Case:
    """A class and how it follows the convention: its `form` of where (a key of
    WHERE_FORMS), the `minimal` call (the dofs, then every required parameter), positional
    parameters after the dofs that are not physical (`extra`), and its `old` spellings:
    ``(args, kwargs, new_kwargs)``, the previous release's call and the new spelling of the
    same object (the dofs of `minimal` with `new_kwargs` over its other parameters)."""

    cls: type
    form: str
    minimal: dict[str, Any]
    extra: tuple[str, ...] = ()
    old: list[tuple[tuple, dict, dict]] = field(default_factory=list)
    #: a wrapper's parts made on its dofs ``(i, j)`` (they act where it acts)
    parts: Callable[[Any, Any], dict[str, Any]] | None = None

    @property
    def where(self) -> tuple[str, ...]:
        return WHERE_FORMS[self.form]

    def make(self, **changes: Any) -> Any:
        given = {**self.minimal, **changes}
        if self.parts is not None:
            given |= self.parts(given.get("i"), given.get("j"))
        names = (*self.where, *self.extra)
        args = [given.pop(n) for n in names if n in given]
        return self.cls(*args, **given)


SPEEDS = np.array([0.0, 100.0])
TABLES = np.array(
    [[1e7, 1.1e7], [0, 0], [0, 0], [1e7, 1.2e7], [1e3, 1e3], [0, 0], [0, 0], [1e3, 1e3]]
)

CASES = [
    Case(
        E.Bilinear,
        "deformation",
        {"i": 0, "k": 3e6, "fy": 4e4, "alpha": 0.05},
        old=[
            ((0, None, 3e6, 4e4, 0.05), {}, {}),
            ((0,), {"k": 3e6, "fy": 4e4}, {"alpha": 0.0}),  # alpha left to its old default
            ((0,), {}, {"k": 1.0, "fy": 1.0, "alpha": 0.0}),
        ],
    ),
    Case(
        E.BoucWen,
        "deformation",
        {"i": 0, "k": 3e6, "fy": 4e4, "alpha": 0.05},
        old=[
            (
                (0, 1, 3e6, 4e4, 0.05, 2.0, 0.4, 0.6),
                {},
                {"j": 1, "n": 2.0, "beta": 0.4, "gamma": 0.6},
            ),
        ],
    ),
    Case(
        E.BreathingCrack,
        "device",
        {"dofs": (0, 1), "dk_xi": 1e5},
        old=[
            ((0, 1, 1e5, 2e4), {}, {"dk_eta": 2e4}),
            ((), {"dof_x": 0, "dof_y": 1, "dk_xi": 1e5, "speed": 30.0}, {"speed": 30.0}),
        ],
    ),
    Case(
        E.Callable,
        "device",
        {"dofs": (0,), "fn": _restoring},
        extra=("fn", "jacobian", "state"),
        old=[((_restoring, (0,)), {}, {})],
    ),
    Case(
        E.Contact,
        "device",
        {"dofs": (0, 1), "clearance": 1e-3, "stiffness": 1e7},
        old=[
            ((0, 1, 1e-3, 1e7, 0.1), {}, {"friction": 0.1}),
            ((), {"dof_x": 0, "dof_y": 1, "clearance": 1e-3, "stiffness": 1e7}, {}),
        ],
    ),
    Case(
        E.Cubic,
        "one dof",
        {"i": 0, "k3": 4.0},
        old=[
            ((0, 4.0), {}, {}),
            ((), {"dof": 0, "k3": 4.0}, {}),
        ],
    ),
    Case(
        E.Damper,
        "deformation",
        {"i": 0, "c": 5.0},
        old=[
            ((0, None, 5.0), {}, {}),
            ((0, 1), {}, {"j": 1, "c": 0.0}),
        ],
    ),
    Case(
        E.FrictionPendulum,
        "device",
        {"dofs": (0, 1), "radius": 2.0, "mu": 0.05, "weight": 1e4},
        old=[
            ((0, 1, 2.0, 0.05, 1e4), {}, {}),
            ((), {"dof_x": 0, "dof_y": 1, "radius": 2.0, "mu": 0.05, "weight": 1e4}, {}),
            ((0, 1), {}, {"radius": 1.0, "mu": 0.05, "weight": 1.0}),
        ],
    ),
    Case(
        E.Gap,
        "deformation",
        {"i": 0, "gap": 0.01, "k": 1e5},
        old=[
            ((0, None, 0.01, 1e5), {}, {}),
            ((0,), {"k": 1e5}, {"gap": 0.0}),
        ],
    ),
    Case(
        E.JournalElement,
        "device",
        {"dofs": (0, 1), "radius": 0.05, "length": 0.04, "clearance": 1e-4, "viscosity": 0.02},
        old=[((0, 1, 0.05, 0.04, 1e-4, 0.02, 300.0), {}, {"speed": 300.0})],
    ),
    Case(
        E.LeadRubberBearing,
        "device",
        {"dofs": (0, 1), "k": 1e6, "fy": 1e4, "alpha": 0.1},
        old=[
            ((0, 1, 1e6, 1e4, 0.1), {}, {}),
            ((), {"dof_x": 0, "dof_y": 1, "k": 1e6, "fy": 1e4, "alpha": 0.1}, {}),
        ],
    ),
    Case(
        E.Polynomial,
        "one dof",
        {"i": 0, "coefficients": (1.0, 0.0, 2.0)},
        old=[
            ((0, (1.0, 0.0, 2.0)), {}, {}),
            ((), {"dof": 0, "coefficients": (1.0, 0.0, 2.0)}, {}),
        ],
    ),
    Case(
        E.SpeedTableBearing,
        "device",
        {
            "dofs": (0, 1),
            "speeds": SPEEDS,
            "values": TABLES,
            "speed": 50.0,
            "k0": np.diag([1e7, 1e7]),
            "c0": np.diag([1e3, 1e3]),
        },
    ),
    Case(
        E.Spring,
        "deformation",
        {"i": 0, "k": 5.0},
        old=[
            ((0, None, 5.0, 2.0), {}, {"k3": 2.0}),
            ((0,), {"k3": 2.0}, {"k": 0.0, "k3": 2.0}),
        ],
    ),
    Case(
        E.TripleFrictionPendulum,
        "device",
        {
            "dofs": (0, 1),
            "mu": (0.02, 0.06, 0.1),
            "radius": (0.3, 2.0, 2.0),
            "displacement_capacity": (0.05, 0.3, 0.3),
            "weight": 1e4,
        },
        old=[
            (
                (0, 1),
                {
                    "mu": (0.02, 0.06, 0.1),
                    "radius": (0.3, 2.0, 2.0),
                    "displacement_capacity": (0.05, 0.3, 0.3),
                    "weight": 1e4,
                },
                {},
            ),
            ((0,), {}, {"dofs": (0,), "weight": 1.0}),
        ],
    ),
    Case(
        E.ViscousDamper,
        "deformation",
        {"i": 0, "c": 5.0},
        old=[
            ((0, None, 5.0, 0.5), {}, {"exponent": 0.5}),
        ],
    ),
    Case(
        E.PDelta,
        "deformation",
        {"i": 0, "P": 300.0, "height": 10.0},
        old=[
            ((0, None, 300.0, 10.0), {}, {}),
            ((0,), {"P": 300.0}, {"height": 1.0}),  # the previous release's default height
            ((0,), {}, {"P": 0.0, "height": 1.0}),
        ],
    ),
    Case(
        L.Step,
        "load at one dof",
        {"dof": 0, "amplitude": 5.0},
        old=[
            ((0, 5.0), {}, {}),
            ((0, 5.0, 0.5), {}, {"t0": 0.5}),
            ((), {"dof": 0, "amplitude": 5.0}, {}),  # the keywords were and stay the spelling
        ],
    ),
    Case(
        L.Harmonic,
        "load at one dof",
        {"dof": 0, "amplitude": 5.0, "omega": 3.0},
        old=[
            ((0, 5.0, 3.0), {}, {}),
            ((0, 5.0, 3.0, 0.2), {}, {"phase": 0.2}),
        ],
    ),
    Case(
        L.Tabulated,
        "load at one dof",
        {"dof": 0, "t": T, "values": V},
        old=[
            ((0, T, V), {}, {}),
            ((0, T, V, True), {}, {"hold": True}),
        ],
    ),
    Case(
        L.BaseAcceleration,
        "support",
        {"direction_vector": np.ones(4), "t": T, "values": V},
        old=[((np.ones(4), T, V), {}, {})],
    ),
    Case(
        L.Unbalance,
        "load on two dofs",
        {"dofs": (0, 1), "m_e": 1e-3, "speed": 300.0},
        old=[
            ((0, 1, 1e-3, 300.0), {}, {}),
            ((0, 1), {"m_e": 1e-3, "speed": 300.0, "phase": 0.2}, {"phase": 0.2}),
            ((), {"dof_x": 0, "dof_y": 1, "m_e": 1e-3, "speed": 300.0}, {}),
        ],
    ),
    Case(L.Callable, "everywhere", {"fn": np.zeros}, extra=("fn",)),
]


# the uniaxial materials (issue 37): new, no old spellings
def _required(kind: str, params: dict[str, Any]) -> dict[str, Any]:
    signature = inspect.signature(getattr(E, kind)).parameters
    given = keywords(params)
    return {"i": 0} | {k: v for k, v in given.items() if signature[k].default is inspect._empty}


def _parts(params: dict[str, Any]) -> Callable[[Any, Any], dict[str, Any]] | None:
    wrapped = {"material", "materials"} & set(params)
    if not wrapped:
        return None
    return lambda i, j: {k: v for k, v in keywords(params, i, j).items() if k in wrapped}


CASES += [
    Case(getattr(E, kind), "deformation", _required(kind, params), parts=_parts(params))
    for kind, (params, _) in MATERIALS.items()
]
BY_CLASS = {case.cls: case for case in CASES}


#: Names of duhamel.elements.__all__ that are not constructors of something placed on dofs:
#: the base class, a result, and the coupling of the background (placed by its matrices).
NOT_PLACED = {"Element", "Hysteresis", "LinearCoupling", "drive"}


def _public_classes() -> list[type]:
    elements = [getattr(E, n) for n in E.__all__ if n not in NOT_PLACED]
    loads = [getattr(L, n) for n in L.__all__]
    loads = [c for c in loads if isinstance(c, type) and issubclass(c, L.Load) and c is not L.Load]
    return elements + loads


def test_every_public_element_and_load_has_its_row() -> None:
    missing = [c.__name__ for c in _public_classes() if c not in BY_CLASS]
    assert not missing, f"classes without a row in tests/elements/test_convention.py: {missing}"
    assert len(BY_CLASS) == len(_public_classes())


def _id(case: Case) -> str:
    return (
        case.cls.__name__
        if case.cls.__module__ != "duhamel.loads"
        else f"loads.{case.cls.__name__}"
    )


def _same(a: Any, b: Any) -> bool:
    """Equal objects: elements by their own equality, loads field by field (arrays by value)."""
    if type(a) is not type(b):
        return False
    if isinstance(a, E.Element | E.PDelta):
        return bool(a == b)
    return all(_equal(getattr(a, f.name), getattr(b, f.name)) for f in dataclasses.fields(a))


def _equal(x: Any, y: Any) -> bool:
    if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
        return bool(np.array_equal(np.asarray(x), np.asarray(y)))
    return bool(x == y)


def _shown(case: Case) -> str:
    """The new signature as the warnings and the page write it: ``Step(dof, *, amplitude,
    t0=0.0)``."""
    parts, star = [], False
    for p in inspect.signature(case.cls).parameters.values():
        if p.kind is p.KEYWORD_ONLY and not star:
            parts.append("*")
            star = True
        parts.append(p.name if p.default is p.empty else f"{p.name}={p.default!r}")
    return f"{case.cls.__name__}({', '.join(parts)})"


@pytest.mark.parametrize("case", CASES, ids=_id)
def test_the_dofs_come_first_and_the_rest_is_keyword_only(case: Case) -> None:
    params = list(inspect.signature(case.cls).parameters.values())
    assert all(p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD) for p in params)
    positional = [p.name for p in params if p.kind is p.POSITIONAL_OR_KEYWORD]
    assert all(p.kind is not p.POSITIONAL_ONLY for p in params)
    assert tuple(positional[: len(case.where)]) == case.where
    # after the dofs only what is not physical (a Python element's function) is positional
    assert tuple(positional[len(case.where) :]) == tuple(n for n in case.extra if n in positional)
    keyword = [p.name for p in params if p.kind is p.KEYWORD_ONLY]
    assert set(keyword) | set(positional) == {p.name for p in params}
    if "j" in case.where:
        assert inspect.signature(case.cls).parameters["j"].default is None  # to the ground


@pytest.mark.parametrize("case", CASES, ids=_id)
def test_required_parameters_have_no_default_and_defaults_are_what_an_object_holds(
    case: Case,
) -> None:
    params = inspect.signature(case.cls).parameters
    required = {n for n, p in params.items() if p.default is p.empty}
    assert required == set(case.minimal), "the physical parameters without a standard value"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the new spelling warns of nothing
        obj = case.make()
    for name, p in params.items():
        if p.default is p.empty:
            continue
        assert _equal(getattr(obj, name), p.default), name
        standard = STANDARD_VALUES.get((case.cls.__name__, name))
        if standard is not None:
            assert p.default == standard, name
        else:  # an absent effect or an option, never a physical value
            assert (
                p.default is None
                or p.default is False
                or isinstance(p.default, str)
                or (p.default == 0.0)
            ), f"{name}={p.default!r} is a physical default"


@pytest.mark.parametrize("case", CASES, ids=_id)
def test_dof_labels_are_taken_wherever_an_index_is(case: Case) -> None:
    if not case.where:
        return
    labels = [(1, "ux"), (1, "uy"), (2, "ux"), (2, "uy")]

    def system() -> duhamel.System:
        s = duhamel.System(np.eye(4), 1e4 * np.eye(4))
        s.label_dofs(labels)
        return s

    def as_labels(value: Any) -> Any:
        if isinstance(value, np.ndarray):  # a support direction: the component's name
            return "ux" if np.array_equal(value, [1.0, 0.0, 1.0, 0.0]) else value
        if isinstance(value, tuple):
            return tuple(as_labels(v) for v in value)
        return labels[value] if isinstance(value, int) else value

    where = {n: case.minimal[n] for n in case.where if n in case.minimal}
    if "direction_vector" in where:
        where["direction_vector"] = np.array([1.0, 0.0, 1.0, 0.0])
    by_index, by_label = (
        case.make(**where),
        case.make(**{n: as_labels(v) for n, v in where.items()}),
    )
    a, b = system(), system()
    add = "add_load" if isinstance(by_index, L.Load) else "add"
    getattr(a, add)(by_index)
    getattr(b, add)(by_label)
    where = "loads" if add == "add_load" else "geometric" if case.cls is E.PDelta else "elements"
    assert _same(getattr(a, where)[-1], getattr(b, where)[-1])
    np.testing.assert_array_equal(a.K, b.K)


OLD = [(case, old) for case in CASES for old in case.old]


@pytest.mark.parametrize(
    ("case", "old"), OLD, ids=[f"{_id(c)}-{k}" for k, (c, _) in enumerate(OLD)]
)
def test_old_spellings_warn_and_give_an_equal_object(case: Case, old: tuple) -> None:
    args, kwargs, new_kwargs = old
    new = case.make(
        **{
            **{n: case.minimal[n] for n in case.where if n in case.minimal},
            **{n: v for n, v in case.minimal.items() if n not in case.where},
            **new_kwargs,
        }
    )
    keywords_were_the_spelling = not args and not set(kwargs) - set(
        inspect.signature(case.cls).parameters
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = case.cls(*args, **kwargs)
    assert _same(got, new), (got, new)
    messages = [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning)]
    if keywords_were_the_spelling:
        assert not messages
        return
    assert messages, "an old spelling must warn"
    for message in messages:
        assert _shown(case) in message, (message, _shown(case))
    assert all(w.filename == __file__ for w in caught), "attributed to the caller"
