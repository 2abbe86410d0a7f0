"""The elements' linear parts in the linear background (the effective link stiffness of the
"Fast Nonlinear Analysis").

A `Spring`'s ``k``, a `Polynomial`'s linear coefficient, the initial stiffness of a
`Bilinear` or `BoucWen` and a `FrictionPendulum`'s gravity stiffness ``W / R`` are stiffness
the modes should see: the run's basis is computed from ``K`` plus those parts, and only the
remainder of each element is a pseudo-force. The equation of motion is unchanged: with
Rayleigh damping ``alpha M + beta K`` the background is damped with ``beta (K + K_e)`` and
each remainder gives back ``-beta k_e x'``; a damping matrix ``C`` stays as given. Modal
damping ratios (``zeta``) are those of the background's modes — the modes of the structure
with its links at their initial stiffness, as in FNA.

Kept as pseudo-forces instead (the system is run as given): with
``Semianalytic(linear_parts="pseudo-force")``, a mass law that scales the stiffness, or a
basis supplied with ``System.use_basis`` (its modes are those of ``K`` alone).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from duhamel._engine import caches
from duhamel._engine.protocols import Model
from duhamel._engine.validate import issparse
from duhamel.system import System

__all__ = ["Background", "LinearPart", "background"]


@dataclass(frozen=True)
class LinearPart:
    """What an element gave to the background: ``k0 x + c0 x'`` at its `dofs`."""

    dofs: tuple[int, ...]
    k0: NDArray[np.float64]
    c0: NDArray[np.float64]

    def force(self, x: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
        """The part's force along histories of the local ``x`` and ``v`` (rows: instants)."""
        return x @ self.k0.T + v @ self.c0.T


@dataclass(frozen=True, eq=False)
class _Remainder:
    """An element without its linear part: `core` is what the run's pseudo-force evaluates,
    `element` the model's element it came from."""

    element: Any
    core: Any
    #: The damping ``c0`` taken out with the linear part (local, flat), or None.
    c0: Any = None

    @property
    def _path_dependent(self) -> bool:
        return bool(self.element._path_dependent)

    def _validate(self, system: Model) -> None:
        self.element._validate(system)

    def _tangent_bound(self) -> tuple[float, float] | None:
        inner = self.element._tangent_bound()  # the element minus its linear part k0 x
        linear = self.element._linear()
        if inner is None:
            return None
        k0 = 0.0 if linear is None else float(np.linalg.norm(linear[1], 2))
        return inner[0] + k0, inner[1]

    @property
    def _dofs(self) -> list[int]:
        return list(self.element._dofs)

    def _passive(self) -> bool:
        return bool(self.element._passive())

    def _stored_energy(self, u: Any, f: Any) -> Any:
        return self.element._stored_energy(u, f)

    def _directions(self) -> list[tuple[int, int | None]]:
        return cast(list[tuple[int, int | None]], self.element._directions())


@dataclass(frozen=True)
class Background:
    """The system a modal run integrates, and per force element (couplings left out, in
    order) the linear part moved into its background (None: none)."""

    system: System
    linear: tuple[LinearPart | None, ...]


def _parts(system: System) -> list[tuple[tuple[int, ...], NDArray[np.float64]] | None]:
    return [e._linear() for e in system.elements]  # type: ignore[misc]


def background(system: System, linear_parts: str = "auto") -> Background:
    """The background of a modal run of `system` (cached on it: its modes are reused by
    later runs while the elements stay the same)."""
    parts = _parts(system)
    law = system.mass_law
    if linear_parts == "auto" and system.damping == "zeta":
        linear_parts = "pseudo-force"  # the ratios are those of the modes of K
    if (
        linear_parts not in ("auto", "background")
        or all(p is None for p in parts)
        or (law is not None and law.scale_stiffness)
        or system._modes.supplied
    ):
        return Background(system, (None,) * len(system.elements))
    key = (tuple(map(id, system.elements)), tuple(map(id, system.couplings)))
    held = caches.of(system)
    cached = held.get("background")
    if cached is None or cached[0] != key:
        kept = (tuple(system.elements), tuple(system.couplings))  # the ids stay theirs
        cached = held["background"] = (key, *_derive(system, parts), kept)
    derived, linear = cached[1], cached[2]
    derived.loads, derived.mass_law = list(system.loads), system.mass_law
    return Background(derived, linear)


def _derive(
    system: System, parts: list[tuple[tuple[int, ...], NDArray[np.float64]] | None]
) -> tuple[System, tuple[LinearPart | None, ...]]:
    n = system.n_dof
    rows, cols, vals = [], [], []
    for part in parts:
        if part is None:
            continue
        dofs, k0 = part
        idx = np.asarray(dofs)
        rows.append(np.repeat(idx, idx.size))
        cols.append(np.tile(idx, idx.size))
        vals.append(np.asarray(k0, dtype=np.float64).ravel())
    r, c, v = np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)
    if not issparse(system.K) and np.unique(r * n + c).size == r.size:
        # Dense, no entry from two parts: one addition per entry, as the sparse sum makes it
        # (`+ 0.0` everywhere first, as adding the sparse matrix's zeros does: -0.0 -> 0.0).
        K = np.asarray(system.K) + 0.0
        K[r, c] += v
    else:
        import scipy.sparse as sp

        added = sp.coo_array((v, (r, c)), shape=(n, n)).tocsr()
        K = system.K + added if issparse(system.K) else np.asarray(system.K) + added.toarray()
    if issparse(K):
        K = sp.csr_array(K)
    derived = system._with_stiffness(K)
    beta = system.rayleigh[1] if system.damping == "rayleigh" else 0.0  # type: ignore[index]
    linear: list[LinearPart | None] = []
    derived.couplings = list(system.couplings)
    for element, part in zip(system.elements, parts, strict=True):
        if part is None:
            derived.elements.append(element)
            linear.append(None)
            continue
        dofs, k0 = part
        c0 = beta * k0
        damping = np.ascontiguousarray(c0, dtype=np.float64).ravel() if beta != 0.0 else None
        derived.elements.append(_Remainder(element, element._remainder(damping), damping))  # type: ignore[arg-type]
        linear.append(LinearPart(dofs, k0, c0))
    return derived, tuple(linear)
