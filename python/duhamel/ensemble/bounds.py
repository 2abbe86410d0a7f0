"""Property modification factors (ASCE 7-22 section 17.2.8.4): the lower- and upper-bound
models of a system's isolators and dampers from lambda factors on their nominal properties,
and both runs through :func:`~duhamel.ensemble.solve_many`."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from duhamel._engine.validate import finite_float
from duhamel.ensemble.run import Ensemble, solve_many

__all__ = ["BOUNDS", "property_bounds", "solve_bounds"]

#: The cases of :func:`solve_bounds`, in order.
BOUNDS = ("lower", "upper")

#: Fields that say where an element acts, never scaled.
_PLACEMENT = {"i", "j", "dof", "dof_x", "dof_y", "dof_z", "dofs"}


def _factors(lambdas: Mapping[str, Any]) -> dict[str, tuple[float, float]]:
    out = {}
    if not isinstance(lambdas, Mapping) or not lambdas:
        raise TypeError(
            "`lambdas` must be a non-empty mapping from a property ('mu', or "
            "'FrictionPendulum.mu') to its (lower, upper) factors"
        )
    for key, pair in lambdas.items():
        if not isinstance(key, str):
            raise TypeError(
                f"`lambdas` keys must be property names ('mu', 'FrictionPendulum.mu'), got {key!r}"
            )
        if isinstance(pair, str | bytes) or not isinstance(pair, Sequence | np.ndarray):
            raise TypeError(f"`lambdas[{key!r}]` must be a (lower, upper) pair of factors")
        if len(pair) != 2:
            raise TypeError(
                f"`lambdas[{key!r}]` must be a (lower, upper) pair of factors, got "
                f"{len(pair)} values"
            )
        # numbers only: a string '0.8' is refused as the other parameters refuse it
        low, high = (finite_float(v, f"lambdas[{key!r}]") for v in pair)
        if not (0 < low <= high):
            raise ValueError(
                f"`lambdas[{key!r}]` must be finite factors with 0 < lower <= upper, got "
                f"({low}, {high})"
            )
        if key.rpartition(".")[2] in _PLACEMENT:
            raise ValueError(f"`lambdas[{key!r}]`: {key!r} places the element, it is no property")
        out[str(key)] = (low, high)
    return out


def _parameters(element: Any) -> dict[str, Any]:
    """An element's parameters by name (none for a coupling or a Python element's function)."""
    return dict(getattr(element, "parameters", {}) or {})


def _modified(element: Any, factors: dict[str, tuple[float, float]], which: int) -> Any:
    """`element` with its properties scaled (`which`: 0 lower, 1 upper)."""
    name = type(element).__name__
    changes = {}
    for field, value in _parameters(element).items():
        key = f"{name}.{field}"
        pair = factors.get(key, factors.get(field))
        if pair is None or field in _PLACEMENT or value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, int | float):
            continue
        changes[field] = pair[which] * float(value)
    return element.replace(**changes) if changes else element


def _available(elements: Any) -> str:
    """The numeric properties of `elements` that factors can scale, per class, for a message."""
    by_class: dict[str, set[str]] = {}
    for element in elements:
        names = list(_parameters(element))
        numeric = by_class.setdefault(type(element).__name__, set())
        for n in names:
            value = getattr(element, n, None)
            if n not in _PLACEMENT and isinstance(value, int | float):
                if not isinstance(value, bool):
                    numeric.add(n)
    if not by_class:
        return "the system has no elements"
    return "; ".join(f"{c}: {', '.join(sorted(n)) or 'none'}" for c, n in sorted(by_class.items()))


def property_bounds(system: Any, lambdas: Mapping[str, Any]) -> dict[str, Any]:
    """The lower- and upper-bound models of `system`: its elements with every property named
    in `lambdas` multiplied by the lower and by the upper factor.

    Parameters
    ----------
    system : System
        The nominal model (left unchanged).
    lambdas : mapping
        Property name -> ``(lambda_min, lambda_max)``. A bare name (``"mu"``, ``"fy"``,
        ``"k"``, ``"c"``) applies to every element with that field; ``"Class.field"``
        (``"FrictionPendulum.mu"``) to that class only and wins over the bare name. Each
        factor is the product of the code's ones (testing, aging, environment). Keys that
        match no element's numeric field are refused (a misspelt property would leave the
        bounds equal to the nominal model).

    Returns
    -------
    dict
        ``{"lower": System, "upper": System}``: copies with the same matrices, damping and
        loads.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.ensemble import property_bounds
    >>> s = duhamel.System(np.eye(1), np.zeros((1, 1)))
    >>> s = s.add(duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.05, weight=9.81))
    >>> models = property_bounds(s, {"mu": (0.8, 1.3)})
    >>> round(models["lower"].elements[0].mu, 4), round(models["upper"].elements[0].mu, 4)
    (0.04, 0.065)
    """
    from duhamel.system import System

    if not isinstance(system, System):
        raise TypeError(f"`system` must be a duhamel.System, got {type(system).__name__}")
    factors = _factors(lambdas)
    known = set()
    for element in system.elements:
        for field in _parameters(element):
            known |= {field, f"{type(element).__name__}.{field}"}
    unknown = sorted(set(factors) - known)
    if unknown:
        raise ValueError(
            f"`lambdas`: {unknown} name no property of the system's elements; the properties "
            f"available are {_available(system.elements)} (a bare name, or 'Class.name')"
        )
    out = {}
    for which, name in enumerate(BOUNDS):
        other = system._with_stiffness(system.K)
        for load in system.loads:
            other.add_load(load)
        for element in system.elements:
            other.add(_modified(element, factors, which))
        out[name] = other
    return out


def solve_bounds(
    system: Any,
    integrator: Any,
    lambdas: Mapping[str, Any],
    *,
    t_end: float,
    dt: float,
    **options: Any,
) -> Ensemble:
    """Runs the lower- and upper-bound models of `system` (:func:`property_bounds`) through
    :func:`~duhamel.ensemble.solve_many`; ``params`` of the result are ``["lower",
    "upper"]``. `options` go to :func:`solve_many` (``reduce``, ``workers``, ``save_every``,
    ``dofs``...).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.ensemble import solve_bounds
    >>> s = duhamel.System(np.eye(1), np.zeros((1, 1)))
    >>> s = s.add(duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.05, weight=9.81))
    >>> ens = solve_bounds(s, duhamel.Semianalytic(), {"mu": (0.8, 1.3)}, t_end=2.0,
    ...                    dt=0.01, v0=[0.5], reduce=lambda sol: float(np.abs(sol.x).max()))
    >>> ens.params, ens.results[0] > ens.results[1]
    (['lower', 'upper'], True)
    """
    models = property_bounds(system, lambdas)
    return solve_many(models.__getitem__, list(BOUNDS), integrator, t_end=t_end, dt=dt, **options)
