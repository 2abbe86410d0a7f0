"""Uniaxial materials against OpenSees (tests): deformation histories and OpenSees' material
driven by ``testUniaxialMaterial``/``setStrain``, a commit after each point."""

from __future__ import annotations

from types import ModuleType

import numpy as np
import pytest


def load_opensees() -> ModuleType:
    """``openseespy.opensees``, or a skip that prints why it cannot be loaded."""
    try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
        import openseespy.opensees as opensees
    except Exception as exc:  # pragma: no cover - depends on the machine
        pytest.skip(reason=f"openseespy cannot be loaded: {exc}")
    return opensees


def ramp(points: list[float], n: int) -> np.ndarray:
    """Straight legs of ``n`` steps from 0 through ``points``."""
    out = [np.zeros(1)]
    for a, b in zip([0.0, *points[:-1]], points, strict=True):
        out.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(out)


def histories(scale: float, ultimate: float) -> dict[str, np.ndarray]:
    """The three deformation histories for a material yielding near ``scale`` and failing
    at ``ultimate``."""
    amps = [*(scale * np.array([0.25, 0.5, 1, 1.5, 2, 3, 4, 6, 8])), 1.15 * ultimate]
    cyclic = ramp([x for a in amps for x in (a, -a, a, -a)] + [0.0], 40)
    rng = np.random.default_rng(1)
    walk = np.clip(np.cumsum(rng.normal(0.0, 0.4 * scale, 400)), -0.9 * ultimate, 0.9 * ultimate)
    random = ramp(list(walk), 5)
    big = 4.0 * scale
    small = [big, -0.3 * big] + [
        x for k in range(20) for x in (0.02 * big * (1 + k % 3), -0.02 * big)
    ]
    return {"cyclic": cyclic, "random": random, "small": ramp(small, 20)}


def opensees(
    ops: ModuleType, kind: str, args: list, u: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """OpenSees' material driven through ``u`` with ``setStrain`` (a commit each point)."""
    ops.wipe()
    ops.uniaxialMaterial(kind, 1, *args)
    ops.testUniaxialMaterial(1)
    force, tangent = [], []
    for x in u:
        ops.setStrain(float(x))
        force.append(ops.getStress())
        tangent.append(ops.getTangent())
    return np.array(force), np.array(tangent)
