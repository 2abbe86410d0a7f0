"""What the material test files share (issue 37): the three deformation histories of the
acceptance, OpenSees' material driven by ``testUniaxialMaterial``/``setStrain``, and the
comparison to 1e-8 of the largest force.

openseespy is imported lazily (``opensees()``): a machine without it skips the comparisons
with the reason printed, and the other tests in the files still run.
"""

from __future__ import annotations

from collections.abc import Callable
from types import ModuleType

import numpy as np
import pytest

from duhamel import elements

#: The acceptance: forces equal OpenSees' to this fraction of the largest force.
RTOL = 1e-8


def element(kind: str, params: dict[str, object], i: int = 0) -> elements.Element:
    """The element class ``kind`` on the deformation of dof ``i`` (to the ground) with the
    keyword parameters ``params``; a part of a wrapper given as a dict with its ``"kind"``
    becomes an element on the same dof."""

    def value(v: object) -> object:
        if isinstance(v, dict) and "kind" in v:
            rest = {k: x for k, x in v.items() if k != "kind"}
            return element(str(v["kind"]), rest, i)
        if isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            return [value(x) for x in v]
        return v

    cls = getattr(elements, kind)
    return cls(i, **{k: value(v) for k, v in params.items()})


def drive(kind: str, params: dict[str, object], u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Force and tangent of the element ``kind`` driven through ``u`` (a commit after each
    point) by :func:`duhamel.elements.drive`."""
    loop = elements.drive(element(kind, params), np.ascontiguousarray(u, dtype=float))
    return loop.force, loop.tangent


def opensees() -> ModuleType:
    """``openseespy.opensees``, or skip the calling test with the reason."""
    try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
        import openseespy.opensees as ops
    except Exception as exc:  # pragma: no cover - depends on the machine
        pytest.skip(reason=f"openseespy cannot be loaded: {exc}")
    return ops


def histories(uy: float) -> dict[str, np.ndarray]:
    """The acceptance's three histories for a law yielding near ``uy``: cycles of growing
    amplitude well past yield, a random walk, and small cycles after a large excursion
    (no point repeated: OpenSees' MultiLinear mishandles a repeated one, docs/materials.md).
    """
    amps = uy * np.array([0.5, 1.0, 2.0, 4.0, 8.0, 12.0, 16.0])
    quarter = np.linspace(0.0, 1.0, 41)[1:]
    cyclic = np.concatenate(
        [
            np.concatenate([a * quarter, a * (1 - quarter), -a * quarter, -a * (1 - quarter)])
            for a in amps
        ]
    )
    cyclic = cyclic + 1e-9 * uy * np.arange(1, cyclic.size + 1) / cyclic.size  # no repeats
    rng = np.random.default_rng(37)
    walk = np.cumsum(rng.uniform(-1.0, 1.0, 800) * 0.6 * uy)
    walk += 4.0 * uy * np.sin(np.linspace(0.0, 6.0 * np.pi, walk.size))
    excursion = np.concatenate(
        [np.linspace(0.0, 10.0 * uy, 80)[1:], np.linspace(10.0 * uy, 3.0 * uy, 40)[1:]]
    )
    small = 3.0 * uy + 0.3 * uy * np.sin(np.linspace(0.0, 40.0 * np.pi, 600)[1:])
    after = np.concatenate(
        [
            excursion,
            small,
            np.linspace(3.0 * uy, -10.0 * uy, 80)[1:],
            -10.0 * uy + 0.2 * uy * np.sin(np.linspace(0, 20 * np.pi, 300)[1:]),
        ]
    )
    return {"cyclic": cyclic, "random": walk, "small after large": after}


def opensees_drive(
    ops: ModuleType, define: Callable[[ModuleType], int], u: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Force and tangent of the OpenSees material ``define(ops)`` builds (returning its
    tag) after ``setStrain`` (trial + commit) at each point of ``u``."""
    ops.wipe()
    tag = define(ops)
    ops.testUniaxialMaterial(tag)
    force, tangent = np.empty(u.size), np.empty(u.size)
    for k, x in enumerate(u):
        ops.setStrain(float(x))
        force[k], tangent[k] = ops.getStress(), ops.getTangent()
    ops.wipe()
    return force, tangent


def assert_matches(
    ours: tuple[np.ndarray, np.ndarray],
    theirs: tuple[np.ndarray, np.ndarray],
    what: str,
    *,
    tangent: bool = True,
) -> None:
    """Forces (and tangents) equal to ``RTOL`` of the largest (printed when they differ)."""
    f, k = ours
    fo, ko = theirs
    scale = np.max(np.abs(fo))
    err = np.max(np.abs(f - fo)) / scale
    worst = int(np.argmax(np.abs(f - fo)))
    assert err <= RTOL, f"{what}: force differs by {err:.2e} of the peak at point {worst}"
    if tangent:
        kscale = np.max(np.abs(ko))
        kerr = np.max(np.abs(k - ko)) / kscale
        assert kerr <= RTOL, f"{what}: tangent differs by {kerr:.2e} of the largest"
