"""Rotors on journal bearings: the static equilibrium under gravity (Newton on the exact
tangents, with backtracking that keeps every journal inside its clearance) and the
bearings' stiffness and damping linearised there."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.constants import STANDARD_GRAVITY
from duhamel.rotor.journal import ShortJournalBearing

__all__ = [
    "JournalPart",
    "journal_matrices",
    "journal_parts",
    "split_journals",
    "static_equilibrium",
]

#: Newton iterations of the equilibrium, and its tolerance on the residual force relative to
#: the load.
MAX_ITER = 100
RTOL = 1e-12


def split_journals(bearings: Any) -> tuple[list[Any], tuple[Any, ...]]:
    """`bearings` (one, or a sequence) as the linear ones (checked with the other
    components) and the journal bearings."""
    items = list(bearings) if isinstance(bearings, Sequence) else [bearings]
    journals = tuple(b for b in items if isinstance(b, ShortJournalBearing))
    return [b for b in items if not isinstance(b, ShortJournalBearing)], journals


def check_journal_nodes(journals: Sequence[Any], n_nodes: int) -> None:
    """Every journal (or magnetic) bearing on a node of the rotor."""
    for i, b in enumerate(journals):
        if b.node >= n_nodes:
            kind = "journal" if isinstance(b, ShortJournalBearing) else "magnetic"
            raise ValueError(
                f"the {kind} bearing {i} is at node {b.node}, but the rotor has nodes "
                f"0..{n_nodes - 1}"
            )


def _journal_forces(
    rotor: Any, x: NDArray[np.float64], speed: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The journals' restoring forces at the state `x` (at rest) and their tangents, as
    global vector and matrices."""
    n = x.size
    r, K, C = np.zeros(n), np.zeros((n, n)), np.zeros((n, n))
    for b in rotor.journals:
        d = [rotor.dof(b.node, "x"), rotor.dof(b.node, "y")]
        f, k, c = b.element(d[0], d[1], speed).evaluate(x[d])
        r[d] += f
        K[np.ix_(d, d)] += k
        C[np.ix_(d, d)] += c
    return r, K, C


def _inside(rotor: Any, x: NDArray[np.float64], margin: float = 0.999) -> bool:
    return all(
        np.hypot(x[rotor.dof(b.node, "x")], x[rotor.dof(b.node, "y")]) < margin * b.clearance
        for b in rotor.journals
    )


def static_equilibrium(
    rotor: Any, speed: float, g: float = STANDARD_GRAVITY
) -> NDArray[np.float64]:
    """The state where the linear structure, the linear bearings and the journals' film
    forces (at rest, spinning at `speed`) carry the weight (along ``-y``)."""
    from duhamel.rotor.loads import Gravity

    if speed == 0.0 and rotor.journals:
        raise ValueError(
            "a journal bearing carries no static load at speed 0 (no hydrodynamic film): give "
            "a spin speed"
        )
    mats = rotor._linear_matrices(speed)
    K0 = np.asarray(mats.K)
    f = Gravity(g=g).vector(rotor)
    scale = max(float(np.abs(f).max()), 1e-300)
    x = np.zeros(f.size)
    for b in rotor.journals:  # start each journal below its centre, inside the film
        x[rotor.dof(b.node, "y")] = -0.3 * b.clearance
        x[rotor.dof(b.node, "x")] = 0.3 * b.clearance * np.sign(speed)

    def residual(z: NDArray) -> tuple[NDArray, NDArray]:
        r, K, _ = _journal_forces(rotor, z, speed)
        return K0 @ z + r - f, K0 + K

    res, J = residual(x)
    for _ in range(MAX_ITER):
        norm = float(np.abs(res).max())
        if norm <= RTOL * scale:
            return x
        try:
            step = np.linalg.solve(J, -res)
        except np.linalg.LinAlgError:
            step = np.linalg.lstsq(J, -res, rcond=None)[0]
        t = 1.0
        while t > 1e-12:
            trial = x + t * step
            if _inside(rotor, trial):
                new, Jn = residual(trial)
                if float(np.abs(new).max()) < norm:
                    break
            t *= 0.5
        else:
            break
        x, res, J = trial, new, Jn
    raise ValueError(
        f"the static equilibrium at {speed:g} rad/s was not found (residual "
        f"{float(np.abs(res).max()) / scale:.2e} of the weight after {MAX_ITER} Newton "
        "iterations): the bearings may be unable to carry the weight at this speed"
    )


def journal_matrices(rotor: Any, speed: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The journals' stiffness and damping linearised at the static equilibrium at `speed`
    (global ``n_dof x n_dof``)."""
    x = static_equilibrium(rotor, speed)
    _, K, C = _journal_forces(rotor, x, speed)
    return K, C


@dataclass(frozen=True)
class JournalPart:
    """A journal bearing in a transient system: its force element (minus its linearisation)
    and the linearisation (global ``K``, ``C``) that the background carries."""

    element: Any
    K: NDArray[np.float64]
    C: NDArray[np.float64]


def journal_parts(rotor: Any, speed: Any) -> list[JournalPart]:
    """The journals of a transient at `speed` (rad/s or a speed law): each journal's film
    force as an element on its node, the stiffness and damping linearised at the static
    equilibrium of the initial speed moved into the linear background (the element keeps
    the rest, so the total force is unchanged). The background then carries the bearings'
    main stiffness, as it does for linear bearings, and the pseudo-force only the film's
    nonlinearity. At an initial speed of 0 (no film) nothing is moved."""
    if not rotor.journals:
        return []
    w0 = float(speed) if isinstance(speed, float | int) else float(speed.omega(0.0))
    n = rotor.n_dof
    x = static_equilibrium(rotor, w0) if w0 != 0.0 else None
    parts = []
    for b in rotor.journals:
        d = [rotor.dof(b.node, "x"), rotor.dof(b.node, "y")]
        K, C = np.zeros((n, n)), np.zeros((n, n))
        if x is None:
            parts.append(JournalPart(b.element(d[0], d[1], speed), K, C))
            continue
        k, c = b.coefficients(x[d], w0)
        K[np.ix_(d, d)], C[np.ix_(d, d)] = k, c
        parts.append(JournalPart(b.element(d[0], d[1], speed, k0=k, c0=c), K, C))
    return parts
