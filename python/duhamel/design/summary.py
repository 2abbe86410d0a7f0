"""What a report says about the model and its inputs: the damping as stated, the modes with
the isolators at their initial and at their effective stiffness (periods, participation),
and the digests that identify the model and the records (:func:`modes`, :func:`damping`,
:func:`digests`)."""

from __future__ import annotations

import hashlib
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["damping", "digests", "effective_stiffness", "modes"]


def _dense(matrix: Any) -> NDArray[np.float64]:
    return np.asarray(matrix.toarray() if hasattr(matrix, "toarray") else matrix, dtype=float)


def damping(system: Any) -> str:
    """The damping as the model states it, in words."""
    kind = system.damping
    if kind == "zeta":
        z = np.atleast_1d(np.asarray(system.zeta, dtype=np.float64))
        text = f"{100 * z[0]:g} %" if z.size == 1 else ", ".join(f"{100 * v:g} %" for v in z)
        return f"modal damping ratios zeta = {text} (on the modes of K)"
    if kind == "rayleigh":
        a, b = system.rayleigh
        return f"Rayleigh damping C = {a:.6g} M + {b:.6g} K"
    if kind == "matrix":
        return "a damping matrix C given with the model (e.g. OpenSees' Rayleigh damping)"
    return "none (undamped structure; the isolators dissipate)"


def _placements(element: Any) -> list[tuple[int, int | None]]:
    """The (dof, other dof or None) pairs an isolator acts on, by its public names."""
    dofs = getattr(element, "dofs", None)
    if dofs is not None:  # a bearing: its horizontal dofs (a third one is its vertical dof)
        return [(int(d), None) for d in dofs[:2] if d is not None]
    j = getattr(element, "j", None)
    return [(int(element.i), None if j is None else int(j))]


def effective_stiffness(system: Any, isolators: list[Any], k_eff: list[float]) -> Any:
    """``K`` plus each isolator's effective stiffness on its dofs (a spring to the ground or
    between its two dofs, in each of its directions)."""
    k = _dense(system.K).copy()
    for element, value in zip(isolators, k_eff, strict=True):
        for i, j in _placements(element):
            k[i, i] += value
            if j is not None:
                k[j, j] += value
                k[i, j] -= value
                k[j, i] -= value
    return k


def modes(study: Any, count: int = 6) -> list[dict[str, float]]:
    """The first `count` modes: ``period_initial`` and ``zeta`` with the isolators at their
    initial stiffness (as the run integrates them, :meth:`duhamel.System.damping_summary`),
    and ``period_effective``, ``ratio`` and ``cumulative`` (the x direction's effective
    modal mass share) with the isolators at their effective stiffness at the nominal
    ``D_M``."""
    import duhamel

    system = study.building.system
    summary = system.damping_summary()
    nominal = study.elf.bounds["nominal"]
    k_eff = [p.stiffness for p in nominal.isolators]
    k = effective_stiffness(system, study.building.isolator_elements, k_eff)
    basis = duhamel.System(_dense(system.M), k).modal()
    part = basis.participation(study.building.x)
    out = []
    for i in range(min(count, summary.omega.size, basis.omega.size)):
        w0 = float(summary.omega[i])
        out.append(
            {
                "period_initial": 2 * np.pi / w0 if w0 > 0 else float("inf"),
                "zeta": float(summary.zeta[i]),
                "period_effective": float(2 * np.pi / basis.omega[i]),
                "ratio": float(part.ratio[i]),
                "cumulative": float(part.cumulative[i]),
            }
        )
    return out


def _hash(parts: list[bytes]) -> str:
    h = hashlib.sha256()
    for part in parts:
        h.update(len(part).to_bytes(8, "little"))
        h.update(part)
    return h.hexdigest()[:16]


def digests(study: Any) -> dict[str, str]:
    """SHA-256 digests (16 hex digits) of the model (matrices, damping, elements), of the
    records and their factors, and of the run settings."""
    s = study.building.system
    model = [_dense(s.M).tobytes(), _dense(s.K).tobytes(), repr(s.damping).encode()]
    if s.damping == "matrix":
        model.append(_dense(s.C).tobytes())
    model += [repr(e).encode() for e in s.elements]
    records = []
    for r, f in zip(study.suite.records, study.suite.factors, strict=True):
        motions = (r.first, r.second) if hasattr(r, "first") else (r,)
        for motion in motions:
            records += [np.asarray(motion.a).tobytes(), repr(float(motion.dt)).encode()]
        records.append(repr(float(f)).encode())
    settings = [
        repr(study.integrator).encode(),
        repr((study.dt, study.t_end, study.orientations, study.bounds)).encode(),
    ]
    return {"model": _hash(model), "records": _hash(records), "settings": _hash(settings)}
