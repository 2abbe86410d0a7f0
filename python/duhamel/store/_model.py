"""A modal run's model as plain data: what the core needs to run (or continue) it without
the user's :class:`duhamel.System`, and what its :class:`duhamel.Solution` is built from.

Taken from the system exactly as :func:`duhamel.solve` takes it (the route of
:func:`duhamel._engine.plan.plan`, the loads projected as :func:`~duhamel._engine.plan.
modal_loads` projects them, the elements as their definitions' data), so a stored run steps
the same numbers as the in-memory one.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._core import Callable as PythonElement
from duhamel._core import Element
from duhamel._engine import dispatch
from duhamel._engine.background import LinearPart, background
from duhamel._engine.coupled import FirstOrderModes
from duhamel._engine.plan import Couplings, Plan, ScaledSpec, plan
from duhamel._engine.validate import as_float_array
from duhamel.integrators import Semianalytic
from duhamel.loads import BaseAcceleration, Callable
from duhamel.store import _legacy
from duhamel.store._codec import StoreError
from duhamel.system import System

__all__ = ["Basis", "Model", "capture"]


@dataclass(frozen=True)
class Basis:
    """The retained modes (what the output mapping reads of a ``ModalBasis``)."""

    phi: NDArray[np.float64]
    omega2: NDArray[np.float64]
    omega: NDArray[np.float64]
    c: NDArray[np.float64]

    @property
    def n_modes(self) -> int:
        return int(self.omega2.size)


@dataclass
class Model:
    """A modal run as data (see the module docstring); ``loads`` are ``{"pattern": modal
    pattern, "time": data}`` (the core time function's data, ``_core.TimeFunction.
    _to_value``), ``elements`` the elements a run evaluates (``{"element": data,
    "remainder": c0}``: an element's definition as data, and when the background took its
    linear part, the damping taken out with it), ``devices`` the force elements' data (for
    the element histories); ``scaled`` and ``mass`` hold their laws as data too. A store
    written by the previous release holds ``(kind, params)`` tuples and ``{"class",
    "fields"}`` records instead; both are read (:func:`run_elements`, :func:`load_terms`,
    ``duhamel.store._legacy``)."""

    route: str
    coupling: str | None
    basis: Basis
    q0: NDArray[np.float64]
    v0: NDArray[np.float64]
    loads: list[Any]
    elements: list[Any]
    integrator: dict[str, Any]
    coupling_k: NDArray[np.float64] | None = None
    coupling_c: NDArray[np.float64] | None = None
    scaled: list[tuple[Any, Any, Any]] = field(default_factory=list)
    mass: dict[str, Any] | None = None
    modes: FirstOrderModes | None = None
    devices: list[Any] = field(default_factory=list)
    base: list[tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]] = field(
        default_factory=list
    )
    #: Per force element, the linear part ``(dofs, k0, c0)`` its background took over.
    linear: list[tuple | None] = field(default_factory=list)
    #: The system's dof names (:meth:`duhamel.System.label_dofs`), or None.
    labels: tuple[str, ...] | None = None
    #: Whether the route's pseudo-forces are passive (``Plan.passive``: the growth guard runs).
    passive: bool = False

    # --- data form -------------------------------------------------------------------------
    def to_tree(self) -> dict[str, Any]:
        """The model as nested plain data (arrays, numbers, strings, tuples)."""
        tree = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        tree["basis"] = dataclasses.asdict(self.basis)
        tree["modes"] = None if self.modes is None else dataclasses.asdict(self.modes)
        return tree

    @classmethod
    def from_tree(cls, tree: dict[str, Any]) -> Model:
        """The model of :meth:`to_tree`'s data."""
        tree = dict(tree)
        tree["basis"] = Basis(**tree["basis"])
        if tree["modes"] is not None:
            tree["modes"] = FirstOrderModes(**tree["modes"])
        tree["loads"] = [x if isinstance(x, dict) else tuple(x) for x in tree["loads"]]
        tree["scaled"] = [tuple(x) for x in tree["scaled"]]
        tree["base"] = [tuple(x) for x in tree["base"]]
        return cls(**tree)

    # --- what the core and the outputs read --------------------------------------------------
    def semianalytic(self) -> Semianalytic:
        """The integrator (its fields are plain values)."""
        return Semianalytic(**self.integrator)

    def plan(self) -> Plan:
        """The route, as :func:`duhamel._engine.output.physical` reads it."""
        scaled = [ScaledSpec(k, c, _speed_law(law)) for k, c, law in self.scaled]
        return Plan(
            self.route,
            self.basis,  # type: ignore[arg-type]
            Couplings(self.coupling_k, self.coupling_c, scaled),
            self.modes,
            self.coupling,
            run_elements(self),
            tuple(None if p is None else LinearPart(tuple(p[0]), p[1], p[2]) for p in self.linear),
            passive=bool(self.passive),
        )

    def patterns(self) -> NDArray[np.float64]:
        """The modal load patterns as columns."""
        if not self.loads:
            return np.zeros((self.basis.n_modes, 0))
        return np.stack([_pattern(item) for item in self.loads], axis=1)

    def initial_state(self) -> NDArray[np.float64]:
        """The state the run starts from: ``q0 | v0``, or ``Re eta0 | Im eta0``."""
        if self.route == "first-order":
            assert self.modes is not None
            eta0 = self.modes.initial(self.q0, self.v0)
            return np.concatenate([eta0.real, eta0.imag])
        return np.concatenate([self.q0, self.v0])

    def core(self, route: Plan) -> Any:
        """The core's model of this run (``_core.ModalModel``), as :func:`duhamel.prepare`
        builds it."""
        return dispatch.modal_model(route, load_terms(self), self.semianalytic(), self.core_mass())

    def core_mass(self) -> _core.Mass | None:
        """The run's mass law as the core takes it (None: constant mass)."""
        if self.mass is None:
            return None
        m, law = self.mass, self.mass["law"]
        law = _core.MassLaw._from_value(law) if isinstance(law, str) else _legacy.mass_law(law)
        return _core.Mass(law, m["form"], bool(m["scale_stiffness"]), m["treatment"])

    def element_objects(self) -> list[Any]:
        """The force elements, rebuilt from their data (a stand-in naming the element when it
        cannot be: a record of an unknown class)."""
        return [_device_object(item) for item in self.devices]

    def base_loads(self) -> list[BaseAcceleration]:
        """The support accelerations (for ``Solution.a_absolute``)."""
        return [BaseAcceleration(r, t=t, values=v) for r, t, v in self.base]


@dataclass(frozen=True)
class StoredElement:
    """An element read back from a store whose class could not be rebuilt: its class name
    and fields."""

    kind: str
    fields: dict[str, Any]

    @property
    def j(self) -> Any:
        return self.fields.get("j")


def _initial(value: ArrayLike | None, name: str, system: System, phi: NDArray) -> NDArray:
    """Modal coordinates of an initial state, as ``duhamel.solve`` projects it."""
    if value is None:
        return np.zeros(phi.shape[1])
    x = as_float_array(value, name, ndim=1, shape=(system.n_dof,))
    return np.ascontiguousarray(phi.T @ np.asarray(system.M @ x, dtype=np.float64))


def _refuse(what: str) -> ValueError:
    return ValueError(
        f"`store`: the system has {what}, which is Python code: a store holds the model as "
        "data only (opening one never runs code), so this run cannot be stored; use "
        "built-in loads and elements, or solve without `store`"
    )


def capture(
    system: System, integrator: Semianalytic, x0: ArrayLike | None, v0: ArrayLike | None
) -> Model:
    """The model of a modal run of `system` under `integrator`; raises ValueError naming
    `store` for Python load or element functions."""
    for load in system.loads:
        if isinstance(load, Callable):
            raise _refuse("a `duhamel.loads.Callable` load")
    if any(isinstance(e, PythonElement) for e in system.elements):
        raise _refuse("a `duhamel.elements.Callable` element")
    route = plan(system, integrator)
    run = background(system, integrator.linear_parts)  # (cached by plan)
    basis = route.basis
    phi = np.ascontiguousarray(basis.phi)
    loads = [
        {"pattern": np.ascontiguousarray(phi.T @ term.pattern), "time": term.time._to_value()}
        for load in system.loads
        for term in load._terms(system)
    ]
    forces = system.elements
    varying = [e for e in system.couplings if e.constant_factor() is None]
    scaled = [
        (s.k, s.c, e.scale._to_value())
        for s, e in zip(route.couplings.scaled, varying, strict=True)
    ]
    attached = system.mass_law
    mass = None
    if attached is not None:
        mass = {
            "law": attached.law._law()._to_value(),
            "form": attached.form,
            "scale_stiffness": bool(attached.scale_stiffness),
            "treatment": integrator.mass_treatment,
        }
    return Model(
        route=route.route,
        coupling=route.coupling,
        basis=Basis(
            phi,
            np.ascontiguousarray(basis.omega2, dtype=np.float64),
            np.asarray(basis.omega, dtype=np.float64),
            np.ascontiguousarray(basis.c, dtype=np.float64),
        ),
        q0=_initial(x0, "x0", system, phi),
        v0=_initial(v0, "v0", system, phi),
        loads=loads,
        elements=[_run_element(e) for e in run.system.elements],
        integrator={f.name: getattr(integrator, f.name) for f in dataclasses.fields(integrator)},
        coupling_k=route.couplings.k,
        coupling_c=route.couplings.c,
        scaled=scaled,
        mass=mass,
        modes=route.modes,
        devices=[e._to_value() for e in forces],
        base=[
            (load.direction_vector, load.t, load.values)
            for load in system.loads
            if isinstance(load, BaseAcceleration)
        ],
        linear=[None if p is None else (p.dofs, p.k0, p.c0) for p in run.linear],
        labels=system.dof_labels,
        passive=route.passive,
    )


def _pattern(item: Any) -> NDArray[np.float64]:
    """A stored load's modal pattern (this release's record or a previous one's tuple)."""
    return item["pattern"] if isinstance(item, dict) else item[0]


def _speed_law(law: Any) -> _core.SpeedLaw:
    """A stored speed law: its data, or a previous release's ``(kind, params)``."""
    return _core.SpeedLaw._from_value(law) if isinstance(law, str) else _legacy.speed_law(law)


def load_terms(model: Model) -> list[_core.Load]:
    """The core loads of a stored run (modal patterns), as the run built them."""
    out = []
    for item in model.loads:
        if isinstance(item, dict):
            time = _core.TimeFunction._from_value(item["time"])
        else:
            time = _legacy.time_function(item[1], item[2])
        out.append(_core.Load(np.ascontiguousarray(_pattern(item), dtype=np.float64), time))
    return out


def _run_element(e: Any) -> dict[str, Any]:
    """An element a run evaluates as data: its definition, and for the remainder of one whose
    linear part went into the background, the damping `c0` taken out with it."""
    original = getattr(e, "element", e)
    data: dict[str, Any] = {"element": original._to_value()}
    if original is not e:
        c0 = getattr(e, "c0", None)
        data["remainder"] = None if c0 is None else np.asarray(c0, dtype=np.float64)
    return data


def run_elements(model: Model) -> list[Any]:
    """The core elements of a stored run, rebuilt as the run built them (from a store of the
    previous release: from its element records and linear parts)."""
    if model.elements and not isinstance(model.elements[0], dict):
        return _legacy_elements(model)
    out = []
    for item in model.elements:
        element = Element._from_value(item["element"])
        if "remainder" in item:
            c0 = item["remainder"]
            element = element._remainder(None if c0 is None else np.ravel(c0))
        out.append(element)
    return out


def _legacy_elements(model: Model) -> list[Any]:
    """A previous release's store: its force elements from their ``{"class", "fields"}``
    records, less the linear parts its background took (``Model.linear``)."""
    out = []
    for k, item in enumerate(model.devices):
        element = _device_object(item)
        if not isinstance(element, Element):
            raise StoreError(
                f"the store's element {k} ({item.get('class')!r}) cannot be rebuilt: a store "
                "of the previous release holding it cannot be continued by this one"
            )
        part = model.linear[k] if k < len(model.linear) else None
        if part is not None:
            c0 = np.asarray(part[2], dtype=np.float64)
            element = element._remainder(np.ravel(c0) if np.any(c0 != 0.0) else None)
        out.append(element)
    return out


def _device_object(item: Any) -> Any:
    """A force element from its data (or a previous release's ``{"class", "fields"}``
    record, its old parameter names mapped); a :class:`StoredElement` if it cannot be."""
    import warnings

    from duhamel import elements as catalogue

    if isinstance(item, str):
        return Element._from_value(item)
    cls = getattr(catalogue, str(item["class"]), None)
    try:
        if not (isinstance(cls, type) and issubclass(cls, catalogue.Element)):
            raise TypeError(item["class"])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            return cls(**item["fields"])
    except (TypeError, ValueError):
        return StoredElement(str(item["class"]), dict(item["fields"]))
