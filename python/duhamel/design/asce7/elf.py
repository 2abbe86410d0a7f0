"""The equivalent lateral force procedure of an isolated structure (ASCE 7-22 section 17.5)
from the isolators' own loops: :func:`isolated_elf` finds the fixed point ``D_M = g S_M1
T_M(D_M) / (4 pi^2 B_M(beta_M(D_M)))`` for the nominal, lower- and upper-bound properties
(section 17.2.8.4) and gives the displacements and shears of sections 17.5.3 and 17.5.4."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from duhamel._engine.validate import positive_float
from duhamel.constants import STANDARD_GRAVITY
from duhamel.design.asce7 import equations as eq
from duhamel.design.effective import EffectiveProperties, effective_properties

__all__ = ["ELFBound", "IsolatedELF", "isolated_elf"]

#: The models of :func:`isolated_elf`, in report order.
MODELS = ("lower", "nominal", "upper")


@dataclass(frozen=True, eq=False)
class ELFBound:
    """The procedure's values for one set of isolator properties.

    Attributes
    ----------
    name : str
        ``'lower'``, ``'nominal'`` or ``'upper'``.
    d_m, t_m, beta_m, b_m, k_m : float
        ``D_M`` (m, Eq. 17.5-1), ``T_M`` (s, Eq. 17.5-2), ``beta_M`` (fraction), ``B_M``
        (Table 17.5-1) and ``k_M`` (N/m) at the fixed point.
    d_tm : float
        ``D_TM`` (m, Eq. 17.5-3, at least 1.15 ``D_M``).
    v_b, v_st, v_s : float
        ``V_b`` (Eq. 17.5-5), ``V_st`` (Eq. 17.5-7), ``V_s`` (Eq. 17.5-6 and the limits of
        section 17.5.4.3) in N.
    activation : float
        The force that activates the isolation system (the isolators' forces at zero
        displacement after a cycle at ``D_M``, summed), N.
    isolators : tuple of EffectiveProperties
        Each isolator's loop at ``D_M``.
    evaluations : int
        Evaluations of the isolators' loops the fixed point took.
    amplitude : float
        ``D``, the amplitude the loops were driven to (the fixed point found); ``k_M`` and
        ``beta_M`` are theirs.
    residual : float
        ``|D_M - D| / D_M``: how well the fixed point holds, the loops' own accuracy as
        functions of the amplitude (about 1e-8).
    """

    name: str
    d_m: float
    t_m: float
    beta_m: float
    b_m: float
    k_m: float
    d_tm: float
    v_b: float
    v_st: float
    v_s: float
    activation: float
    isolators: tuple[EffectiveProperties, ...]
    evaluations: int
    amplitude: float
    residual: float


@dataclass(frozen=True, eq=False)
class IsolatedELF:
    """:func:`isolated_elf`'s result: one :class:`ELFBound` per set of properties and the
    governing values (the largest over them, section 17.2.8.4).

    Attributes
    ----------
    bounds : dict
        ``{"lower": ELFBound, "nominal": ..., "upper": ...}`` (those computed).
    sm1, weight, weight_above, r_i, g : float
        The inputs.
    """

    bounds: dict[str, ELFBound]
    sm1: float
    weight: float
    weight_above: float
    r_i: float
    g: float = STANDARD_GRAVITY
    notes: list[str] = field(default_factory=list)

    def _max(self, name: str) -> float:
        return max(getattr(b, name) for b in self.bounds.values())

    @property
    def d_m(self) -> float:
        """The governing ``D_M`` (m)."""
        return self._max("d_m")

    @property
    def d_tm(self) -> float:
        """The governing ``D_TM`` (m)."""
        return self._max("d_tm")

    @property
    def v_b(self) -> float:
        """The governing ``V_b`` (N)."""
        return self._max("v_b")

    @property
    def v_s(self) -> float:
        """The governing ``V_s`` (N)."""
        return self._max("v_s")

    def period_range(self) -> tuple[float, float]:
        """The period range over which the ground motions are scaled (ASCE 7-22 section
        17.3.3): from 0.75 ``T_M`` of the stiffest properties (upper bound) to 1.25 ``T_M``
        of the softest (lower bound), in s."""
        periods = [b.t_m for b in self.bounds.values()]
        return 0.75 * min(periods), 1.25 * max(periods)


def _isolator_sets(model: Any, lambdas: Mapping[str, Any] | None) -> dict[str, list[Any]]:
    """The isolators of each model (lower, nominal, upper) of `model`."""
    from duhamel.design.building import Building

    if isinstance(model, Mapping):
        if lambdas is not None:
            raise ValueError("`lambdas` applies to a system: pass either it or the bound sets")
        unknown = sorted(set(model) - set(MODELS))
        if unknown or not model:
            raise ValueError(f"`model` as a mapping must have keys among {MODELS}, got {unknown}")
        return {k: list(model[k]) for k in MODELS if k in model}
    if isinstance(model, Building):
        system, chosen = model.system, list(model.isolators)
    elif hasattr(model, "elements") and hasattr(model, "n_dof"):
        system, chosen = model, list(range(len(model.elements)))
    else:
        if lambdas is not None:
            raise ValueError("`lambdas` needs a System or Building (pass the bounds' elements)")
        return {"nominal": list(model)}
    sets = {"nominal": [system.elements[i] for i in chosen]}
    if lambdas is not None:
        from duhamel.ensemble.bounds import property_bounds

        for name, other in property_bounds(system, lambdas).items():
            sets[name] = [other.elements[i] for i in chosen]
    return {k: sets[k] for k in MODELS if k in sets}


def _key(element: Any) -> str:
    """Elements that differ only in their dofs share a loop."""
    params = dict(getattr(element, "parameters", {}) or {})
    for where in ("i", "j", "dofs"):
        params.pop(where, None)
    return f"{type(element).__name__}{sorted(params.items())!r}"


class _Loops:
    """The isolators' loops at a displacement, each distinct isolator driven once."""

    def __init__(self, isolators: list[Any], points: int) -> None:
        self.isolators, self.points, self.evaluations = isolators, points, 0
        self._cache: dict[tuple[str, float], EffectiveProperties] = {}

    def at(self, d: float) -> list[EffectiveProperties]:
        self.evaluations += 1
        out = []
        for element in self.isolators:
            key = (_key(element), d)
            if key not in self._cache:
                self._cache[key] = effective_properties(element, d, points=self.points)
            out.append(self._cache[key])
        return out


def _system_values(loops: list[EffectiveProperties], d: float) -> tuple[float, float]:
    """``k_M`` and ``beta_M = sum E / (2 pi k_M D^2)`` of the isolation system at `d`."""
    k = sum(p.stiffness for p in loops)
    energy = sum(p.energy for p in loops)
    return k, (energy / (2.0 * math.pi * k * d * d) if k > 0 else 0.0)


def _activation(loops: list[EffectiveProperties]) -> float:
    """The isolators' forces at zero displacement on the loading branch of the last cycle."""
    total = 0.0
    for p in loops:
        u, f = p.deformation, p.force
        half = u.size // 2
        up_u, up_f = u[half:], f[half:]  # from -D back to +D
        total += abs(float(np.interp(0.0, up_u, up_f)))
    return total


def _solve(
    name: str,
    isolators: list[Any],
    *,
    sm1: float,
    weight: float,
    weight_above: float,
    r_i: float,
    abrupt: bool,
    torsion: Mapping[str, float],
    g: float,
    points: int,
) -> tuple[ELFBound, float]:
    """The fixed point for one set of properties (Brent's method on ``D - D_M(D)``)."""
    from scipy.optimize import brentq

    loops = _Loops(isolators, points)

    def demand(d: float) -> float:
        k, beta = _system_values(loops.at(d), d)
        return eq.isolation_displacement(sm1, eq.effective_period(weight, k, g=g), beta, g=g)

    lo = 1e-6
    while lo - demand(lo) >= 0.0:
        lo /= 10.0
        if lo < 1e-12:
            raise ValueError(f"{name}: the isolation system is too soft to find D_M")
    hi = max(10.0 * lo, demand(lo))
    while hi - demand(hi) <= 0.0:
        hi *= 2.0
        if hi > 1e3:
            raise ValueError(
                f"{name}: D_M exceeds 1 km: the isolation system has no restoring force at "
                "the MCE_R demand"
            )
    amplitude = float(brentq(lambda d: d - demand(d), lo, hi, xtol=1e-14, rtol=1e-12))
    found = loops.at(amplitude)
    k_m, beta_m = _system_values(found, amplitude)
    t_m = eq.effective_period(weight, k_m, g=g)
    d_m = eq.isolation_displacement(sm1, t_m, beta_m, g=g)  # Eq. 17.5-1 of these loops
    v_b = eq.base_shear(k_m, d_m)
    v_st = eq.unreduced_shear(v_b, weight, weight_above, beta_m, abrupt=abrupt)
    activation = _activation(found)
    bound = ELFBound(
        name,
        d_m,
        t_m,
        beta_m,
        eq.damping_coefficient(beta_m),
        k_m,
        eq.total_displacement(d_m, **torsion),
        v_b,
        v_st,
        eq.structure_shear(v_st, r_i),
        activation,
        tuple(found),
        loops.evaluations,
        amplitude,
        abs(d_m - amplitude) / d_m,
    )
    return bound, activation


def isolated_elf(
    model: Any,
    *,
    sm1: float,
    weight: float | None = None,
    weight_above: float | None = None,
    lambdas: Mapping[str, Any] | None = None,
    r_i: float = 2.0,
    abrupt: bool = False,
    torsion: Mapping[str, float] | None = None,
    v_s_minimum: float = 0.0,
    g: float = STANDARD_GRAVITY,
    points: int = 1000,
) -> IsolatedELF:
    """The equivalent lateral force procedure of ASCE 7-22 section 17.5 for an isolated
    structure, with the isolators' effective properties from their own loops
    (:func:`~duhamel.design.effective_properties`):

    * the fixed point ``D_M = g S_M1 T_M / (4 pi^2 B_M)`` (Eq. 17.5-1) with ``T_M = 2 pi
      sqrt(W / (k_M g))`` (Eq. 17.5-2), ``k_M`` the isolators' effective stiffnesses at
      ``D_M`` summed, ``beta_M = sum E_loop / (2 pi k_M D_M^2)`` and ``B_M`` of Table 17.5-1
      (found by Brent's method on ``D - D_M(D)`` to 1e-12; the values given are the
      equations' at the loops of the root, whose amplitude is ``D_M`` to ``residual``);
    * ``D_TM`` (Eq. 17.5-3, at least 1.15 ``D_M``), ``V_b = k_M D_M`` (Eq. 17.5-5),
      ``V_st = V_b (W_s / W)^(1 - 2.5 beta_M)`` (Eq. 17.5-7; ``1 - 3.5 beta_M`` with
      `abrupt`), ``V_s = V_st / R_I`` (Eq. 17.5-6), not less than (section 17.5.4.3) the
      ``V_st`` of the force that activates the isolation system (the greater of the upper
      bound's and 1.5 times the nominal; here the isolators' forces at zero displacement
      after a cycle at ``D_M``) nor `v_s_minimum` (the fixed-base and wind shears of items
      1 and 2, which the user computes);
    * for the nominal properties and, with `lambdas`, for the lower- and upper-bound ones
      (section 17.2.8.4, :func:`duhamel.ensemble.property_bounds`).

    Parameters
    ----------
    model : Building, System, sequence of elements, or mapping
        A :class:`~duhamel.design.Building` (its isolators, weights), a System (all its
        elements are isolators; give `weight`), the isolators as elements (nominal only), or
        ``{"lower": [...], "nominal": [...], "upper": [...]}``.
    sm1 : float
        ``S_M1`` (g).
    weight, weight_above : float, optional
        ``W`` and ``W_s`` (N); default the Building's (``W_s = W`` otherwise).
    lambdas : mapping, optional
        Property modification factors, as :func:`duhamel.ensemble.property_bounds` takes
        them (``{"mu": (0.85, 1.3)}``).
    r_i : float, optional
        ``R_I`` (default 2.0).
    abrupt : bool, optional
        The exponent of Eq. 17.5-7 for abrupt transitions (sliding systems, 17.5.4.2).
    torsion : mapping, optional
        Keywords of :func:`~duhamel.design.asce7.total_displacement` (``y``,
        ``eccentricity``, ``b``, ``d``, ``p_t``).
    v_s_minimum : float, optional
        A further lower limit of ``V_s`` (N).
    g : float, optional
        Standard gravity by default.
    points : int, optional
        Increments per half cycle of the loops.

    Returns
    -------
    IsolatedELF

    Examples
    --------
    >>> import math, duhamel
    >>> from duhamel.design.asce7 import isolated_elf
    >>> w = 1e7
    >>> fps = [duhamel.elements.FrictionPendulum(0, radius=3.0, mu=0.06, weight=w / 4)] * 4
    >>> elf = isolated_elf(fps, sm1=0.9, weight=w, points=500)
    >>> b = elf.bounds["nominal"]
    >>> round(b.d_m, 4), round(b.t_m, 3), round(b.beta_m, 4), round(b.b_m, 4)
    (0.4573, 2.944, 0.1797, 1.4391)
    >>> round(b.k_m / (w / 3.0 + 0.06 * w / b.d_m), 6)  # k_M = W/R + mu W/D_M
    1.0
    """
    s = positive_float(sm1, "sm1")
    gg = positive_float(g, "g")
    ri = positive_float(r_i, "r_i")
    if not 1.0 <= ri <= 2.0:
        raise ValueError(f"`r_i` must be 3 R / 8 within [1, 2] (section 17.5.4.2), got {ri}")
    from duhamel.design.building import Building

    w = weight if weight is not None else (model.weight if isinstance(model, Building) else None)
    if w is None:
        raise ValueError("`weight` (W, N) is needed unless `model` is a duhamel.design.Building")
    w = positive_float(w, "weight")
    if weight_above is None:
        ws = model.weight_above if isinstance(model, Building) and weight is None else w
    else:
        ws = positive_float(weight_above, "weight_above")
    if ws > w:
        raise ValueError(f"`weight_above` ({ws:g}) exceeds `weight` ({w:g})")
    sets = _isolator_sets(model, lambdas)
    if any(not isolators for isolators in sets.values()):
        raise ValueError("`model` has no isolators")
    kw = {
        "sm1": s,
        "weight": w,
        "weight_above": ws,
        "r_i": ri,
        "abrupt": bool(abrupt),
        "torsion": dict(torsion or {}),
        "g": gg,
        "points": int(points),
    }
    solved = {name: _solve(name, isolators, **kw) for name, isolators in sets.items()}
    # section 17.5.4.3 item 3: V_b the activation force (upper bound, or 1.5 nominal)
    force = max(
        [a for n, (_, a) in solved.items() if n == "upper"]
        + [1.5 * a for n, (_, a) in solved.items() if n == "nominal"]
    )
    out, notes = {}, []
    for name, (bound, _) in solved.items():
        v_act = eq.unreduced_shear(force, w, ws, bound.beta_m, abrupt=bool(abrupt))
        v_s = max(bound.v_s, v_act, float(v_s_minimum))
        if v_s > bound.v_s:
            notes.append(
                f"{name}: V_s raised from {bound.v_s:.6g} N to {v_s:.6g} N (section 17.5.4.3)"
            )
        out[name] = dataclasses.replace(bound, v_s=v_s)
    return IsolatedELF(out, s, w, ws, ri, gg, notes)
