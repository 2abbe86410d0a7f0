"""What a structure sends to its supports: the model a run's forces are recovered with
(:class:`StructureModel`), base shear and storey shears (:func:`base_shear`)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["StructureModel", "base_shear", "columns", "floor_groups", "real_array"]

#: The array kinds that are no real numbers, by name (for the messages).
_KINDS = {"b": "bool", "c": "complex", "O": "object", "U": "string", "S": "bytes"}


def real_array(value: Any, name: str) -> NDArray[np.float64]:
    """`value` as a float64 array (NaN and inf kept: the caller checks them), or a
    TypeError naming `name` for strings, bools, complex and object data, a ValueError for a
    ragged sequence: the check of the results' own array parameters (this package sits
    below ``duhamel._engine`` and does not import its validation)."""
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"`{name}` could not be converted to an array: {exc}") from None
    if arr.dtype.kind not in "fiu":
        kind = _KINDS.get(arr.dtype.kind, str(arr.dtype))
        raise TypeError(f"`{name}` must contain real numbers, got dtype {kind}")
    return arr.astype(np.float64)


@dataclass(frozen=True, eq=False)
class StructureModel:
    """The physical model behind a run, as plain data (made by
    ``duhamel._engine.structure.structure_model``).

    Attributes
    ----------
    m, k, c : ndarray or scipy.sparse array
        Mass, stiffness (constant linear couplings included) and damping matrices (``c`` None
        when undamped); modal damping ratios give the full ``M Phi diag(2 zeta omega)
        Phi^T M`` of the run's modes.
    alpha : float
        The mass-proportional part ``alpha M`` of Rayleigh damping (0 for other damping):
        dashpots from every mass to the moving ground, not through the supports.
    elements : tuple of (element, ndarray of int)
        The force elements in the order of the solution's element histories, with the global
        dofs of their local columns.
    base : list of (ndarray, callable)
        Per support-acceleration load: its influence vector over all dofs and ``a_g(t)``.
    other_loads : int
        How many loads of the system are not support accelerations.
    """

    m: Any
    k: Any
    c: Any
    alpha: float
    elements: tuple[tuple[Any, NDArray[np.int64]], ...]
    base: list[tuple[NDArray[np.float64], Callable[[Any], Any]]]
    other_loads: int = 0

    @property
    def n_dof(self) -> int:
        return int(self.m.shape[0])

    def structural_damping(self) -> Any:
        """``C`` without its mass-proportional Rayleigh part (None when nothing is left)."""
        if self.c is None:
            return None
        if self.alpha == 0.0:
            return self.c
        return self.c - self.alpha * self.m

    def default_direction(self) -> NDArray[np.float64]:
        """The base excitation's direction: the influence vector of the support loads (they
        must share it)."""
        if not self.base:
            raise ValueError(
                "`direction` must be given: the system has no BaseAcceleration load whose "
                "direction could be the default"
            )
        first = self.base[0][0]
        for r, _ in self.base[1:]:
            if not np.array_equal(r, first):
                raise ValueError(
                    "`direction` must be given: the system's BaseAcceleration loads act along "
                    "different directions (pass one influence vector)"
                )
        return np.asarray(first, dtype=np.float64)


def columns(dofs: NDArray[np.int64], wanted: Sequence[int], name: str) -> list[int]:
    """The columns of the saved `dofs` that hold the dofs `wanted`, or ValueError naming
    `name`."""
    position = {int(d): k for k, d in enumerate(dofs)}
    out = []
    for d in wanted:
        if isinstance(d, bool) or not isinstance(d, int | np.integer):
            raise TypeError(f"`{name}` must contain dof indices (integers), got {d!r}")
        if int(d) not in position:
            raise ValueError(
                f"`{name}`: dof {d} is not among the saved dofs; solve with `dofs=` "
                "including it (or all dofs)"
            )
        out.append(position[int(d)])
    return out


def dof_sequence(value: Any, name: str) -> list[Any]:
    """`value` as a list (its items checked by the caller), or a TypeError naming `name`
    when it is no sequence (a number, a string, None)."""
    if (
        isinstance(value, str | bytes)
        or not isinstance(value, Sequence | np.ndarray)
        or (isinstance(value, np.ndarray) and value.ndim == 0)
    ):
        raise TypeError(f"`{name}` must be a sequence of dof indices, got {type(value).__name__}")
    return list(np.asarray(value).ravel()) if isinstance(value, np.ndarray) else list(value)


def floor_groups(floors: Sequence[Any], name: str = "floors") -> list[list[int]]:
    """`floors` (each a dof or a sequence of dofs: one per column line) as lists of ints."""
    groups = []
    for f in dof_sequence(floors, name):
        try:
            group = [f] if np.ndim(f) == 0 else list(np.asarray(f).ravel())
        except ValueError:  # a ragged sequence
            raise TypeError(f"`{name}` must contain dofs or sequences of dofs, got {f!r}") from None
        if not group:
            raise ValueError(f"`{name}`: a floor lists no dof")
        for d in group:
            if isinstance(d, bool) or not isinstance(d, int | np.integer):
                raise TypeError(f"`{name}` must contain dof indices (integers), got {d!r}")
        groups.append([int(d) for d in group])
    if not groups:
        raise ValueError(f"`{name}` must list at least one floor")
    return groups


def _full(sol: Any, quantity: str, needed: NDArray[np.bool_], what: str) -> NDArray[np.float64]:
    """The history of `quantity` over all dofs (zeros where `needed` is False)."""
    data = np.asarray(getattr(sol, quantity))
    n = needed.size
    out = np.zeros((data.shape[0], n))
    position = {int(d): k for k, d in enumerate(sol.dofs)}
    missing = [int(d) for d in np.flatnonzero(needed) if int(d) not in position]
    if missing:
        raise ValueError(
            f"{what} needs the dofs {missing[:10]} that the run did not save: solve with "
            "`dofs=None` (all dofs) or with these included"
        )
    for d in np.flatnonzero(needed):
        out[:, d] = data[:, position[int(d)]]
    return out


def _row(matrix: Any, r: NDArray[np.float64]) -> NDArray[np.float64]:
    """``r^T A`` for a dense or sparse `matrix` A."""
    return np.asarray(matrix.T @ r, dtype=np.float64).ravel()


def element_force(
    model: StructureModel, histories: Sequence[Any], r: NDArray[np.float64]
) -> NDArray[np.float64] | None:
    """``sum_e r[dofs_e] . force_e(t)``: the elements' forces along `r` (None without any)."""
    total = None
    if len(histories) != len(model.elements):
        raise ValueError(
            "the run kept no element histories (a direct integrator or a stored run without "
            "them): the element forces, hence this output, are not available"
        )
    for history, (_, dofs) in zip(histories, model.elements, strict=True):
        weights = r[dofs]
        if not np.any(weights):
            continue
        part = np.asarray(history.force) @ weights
        total = part if total is None else total + part
    return total


def base_shear(
    sol: Any, model: StructureModel, direction: Any, storeys: Sequence[Any] | None
) -> NDArray[np.float64]:
    """See :meth:`duhamel.Solution.base_shear`."""
    n = model.n_dof
    if direction is None:
        r = model.default_direction()
    else:
        if isinstance(direction, str):  # a label ('x') names no dofs: the vector does
            raise TypeError(
                f"`direction` must be an influence vector over the {n} dofs of the model "
                f"(ones on the dofs along the direction), or None for the BaseAcceleration "
                f"loads' direction, got the string {direction!r}"
            )
        r = real_array(direction, "direction")
        if r.shape != (n,) or not np.all(np.isfinite(r)):
            raise ValueError(
                f"`direction` must be a finite vector over the {n} dofs of the model, got "
                f"shape {r.shape}"
            )
    if storeys is None:
        return _finite(_shear(sol, model, r))
    groups = floor_groups(storeys, "storeys")
    for group in groups:
        for d in group:
            if not 0 <= d < n:
                raise ValueError(f"`storeys`: dof {d} is not a dof of the model (0 to {n - 1})")
    out = []
    for s in range(len(groups)):
        above = np.zeros(n, dtype=bool)
        for group in groups[s:]:
            above[group] = True
        out.append(_shear(sol, model, np.where(above, r, 0.0)))
    return _finite(np.stack(out, axis=1))


def _finite(shear: NDArray[np.float64]) -> NDArray[np.float64]:
    """`shear` if finite, else a ValueError: the forces along `direction` overflow."""
    if not np.all(np.isfinite(shear)):
        raise ValueError(
            "the forces along `direction` overflow the double range: scale the influence "
            "vector (ones on the dofs along the direction)"
        )
    return shear


def _from_equilibrium(
    sol: Any, model: StructureModel, r: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The cut force from the equation of motion, ``-r^T M (a_abs + alpha v)``, for a run
    that kept no element histories (a direct integrator's): only without other loads."""
    if model.other_loads:
        raise ValueError(
            "this run kept no element histories (a direct integrator's) and the system has "
            "loads other than support motion: its base shear is not available (use "
            "duhamel.Semianalytic())"
        )
    mr = _row(model.m, r)
    total = _full(sol, "a_absolute", mr != 0.0, "the base shear") @ mr
    if model.alpha:
        total = total + model.alpha * (_full(sol, "v", mr != 0.0, "the base shear") @ mr)
    return -np.asarray(total, dtype=np.float64)


def _shear(sol: Any, model: StructureModel, r: NDArray[np.float64]) -> NDArray[np.float64]:
    """``r^T (K x + C_s x' + r_el(x, x'))``: the force across the cut that `r` selects."""
    if model.elements and len(sol.elements) != len(model.elements):
        return _from_equilibrium(sol, model, r)
    kr = _row(model.k, r)
    cs = model.structural_damping()
    cr = np.zeros_like(kr) if cs is None else _row(cs, r)
    tol = 0.0
    x = _full(sol, "x", kr != tol, "the base shear")
    total = x @ kr
    if np.any(cr != 0.0):
        total = total + _full(sol, "v", cr != 0.0, "the base shear") @ cr
    forces = element_force(model, sol.elements, r) if model.elements else None
    if forces is not None:
        total = total + forces
    return np.asarray(total, dtype=np.float64)
