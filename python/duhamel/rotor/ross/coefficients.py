"""ROSS's speed-dependent matrices as a constant part plus its bearings' coefficient curves.

ROSS assembles ``K(frequency)``, ``C(frequency)`` and ``M(frequency)`` anew at every call
(about 20 ms for the compressor, most of it in its unit decorators). Only the bearing and
seal elements depend on the frequency, so on the lateral dofs

    K(w) = K_0 + sum_b P_b K_b(w) P_b^T

with ``K_0 = K(w_0) - sum_b P_b K_b(w_0) P_b^T`` taken once at ``w_0 = 700`` rad/s (away
from zero, where a magnetic bearing's integral action makes ``c_eq`` large; less the magnetic
bearings,
whose closed loops replace them) and ``K_b(w)`` the element's own ``K(w)`` (its coefficient
interpolants) on its lateral dofs; likewise ``C`` and ``M``. The split is checked once
against ROSS's own assembly at another frequency (1e-13 of its largest entry, and
no coupling of the lateral dofs to the others); a model it does not reproduce (an element
type whose matrices depend on the frequency some other way, ROSS >= 3's speed arguments)
keeps reading ROSS at every speed.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["SPLIT_RTOL", "Split", "split"]

#: The split's largest difference from ROSS's assembly, relative to the matrix's largest entry.
SPLIT_RTOL = 1e-13
NAMES = ("M", "K", "C")


class Split:
    """The lateral ``M(w)``, ``K(w)``, ``C(w)`` from the constant parts and the bearings'
    curves (each bearing: its element and its x and y dofs' positions among the lateral
    ones; its ``m..``, ``k..``, ``c..`` interpolants called directly, as its ``M``, ``K``,
    ``C`` call them, without ROSS's unit decorators). The cubic splines that share knots
    (ROSS's ``UnivariateSpline`` of one element's frequency table) are evaluated together,
    as one :class:`scipy.interpolate.BSpline` with stacked coefficients (the same de Boor
    evaluation; the compressor's 182 curves cost 15 calls instead of 182)."""

    def __init__(self, base: dict[str, NDArray], parts: list[tuple[Any, list[int], int]]):
        self.base = base
        self.parts = parts
        self._terms = _terms(parts)
        self._groups, self._single = _stacked(self._terms)

    def at(self, w: float) -> dict[str, NDArray[np.float64]]:
        """The matrices at frequency `w`."""
        out = {name: a.copy() for name, a in self.base.items()}
        for spline, where in self._groups:
            values = spline(w)
            for (name, r, c), v in zip(where, values.tolist(), strict=True):
                out[name][r, c] += v
        for fn, (name, r, c) in self._single:
            out[name][r, c] += float(fn(w))
        return out


def _terms(parts: list[tuple[Any, list[int], int]]) -> list[tuple[Any, tuple[str, int, int]]]:
    """Each interpolant of each bearing with the matrix entry it adds to."""
    terms = []
    for b, pos, z in parts:
        for name, p in (("M", "m"), ("K", "k"), ("C", "c")):
            for i, r in enumerate("xy"):
                for j, c in enumerate("xy"):
                    terms.append((getattr(b, f"{p}{r}{c}_interpolated"), (name, pos[i], pos[j])))
            if z >= 0:  # the axial coefficient, when the model keeps z
                terms.append((getattr(b, f"{p}zz_interpolated"), (name, z, z)))
    return terms


def _stacked(terms: list[tuple[Any, tuple[str, int, int]]]) -> tuple[list[Any], list[Any]]:
    """The terms whose interpolant is a ``UnivariateSpline`` (or a subclass that evaluates as
    it does) that extrapolates (``ext`` 0)
    grouped by knots and degree into one ``BSpline`` each; the others kept apart."""
    from scipy.interpolate import BSpline, UnivariateSpline

    groups: dict[tuple[bytes, int], list[Any]] = {}
    single = []
    for fn, where in terms:
        args = getattr(fn, "_eval_args", None)
        plain = isinstance(fn, UnivariateSpline) and type(fn).__call__ is UnivariateSpline.__call__
        if plain and getattr(fn, "ext", None) == 0 and args is not None:
            t, c, k = np.asarray(args[0], dtype=float), np.asarray(args[1], dtype=float), args[2]
            groups.setdefault((t.tobytes(), int(k)), []).append((t, c[: t.size - k - 1], where))
            continue
        single.append((fn, where))
    stacked = []
    for (_, k), members in groups.items():
        t = members[0][0]
        coeffs = np.stack([c for _, c, _ in members], axis=1)
        stacked.append((BSpline(t, coeffs, k, extrapolate=True), [w for _, _, w in members]))
    return stacked, single


def split(
    source: Any,
    keep: NDArray[np.intp],
    bearings: list[Any],
    removed: list[Any],
    w0: float = 700.0,
    w1: float = 1500.0,
) -> Split | None:
    """The :class:`Split` of ROSS's rotor `source` on its lateral dofs `keep` over
    `bearings` (the elements whose matrices follow the frequency), less the `removed` ones
    (its magnetic bearings), or None when it does not reproduce ROSS's assembly at `w1`."""
    where = {int(g): i for i, g in enumerate(keep)}
    try:
        full = {name: np.asarray(getattr(source, name)(w0), dtype=float) for name in NAMES}
        ref = {name: np.asarray(getattr(source, name)(w1), dtype=float) for name in NAMES}
        # the tolerance's scale: ROSS's assembly with every bearing (removing the magnetic
        # ones leaves round-off of their size)
        scales = {name: float(np.max(np.abs(a), initial=0.0)) for name, a in ref.items()}
        for b in (*bearings, *removed):
            idx = list(b.dof_global_index.values())
            for name in NAMES:
                full[name][np.ix_(idx, idx)] -= np.asarray(getattr(b, name)(w0), dtype=float)
        for b in removed:
            idx = list(b.dof_global_index.values())
            for name in NAMES:
                ref[name][np.ix_(idx, idx)] -= np.asarray(getattr(b, name)(w1), dtype=float)
        parts = []
        for b in bearings:  # grounded bearings: (x, y, z) with z decoupled (checked below)
            if getattr(b, "n_link", None) is not None:
                return None
            names = {k.split("_")[0]: int(g) for k, g in b.dof_global_index.items()}
            z = where.get(names["z"], -1) if "z" in names else -1
            parts.append((b, [where[names["x"]], where[names["y"]]], z))
        dropped = np.setdiff1d(np.arange(full["M"].shape[0]), keep)
        for a in full.values():
            if np.any(a[np.ix_(keep, dropped)]) or np.any(a[np.ix_(dropped, keep)]):
                return None
        out = Split({name: a[np.ix_(keep, keep)] for name, a in full.items()}, parts)
        check = out.at(w1)
    except (AttributeError, TypeError, ValueError, IndexError, KeyError):
        return None
    for name, a in ref.items():
        lat = a[np.ix_(keep, keep)]
        scale = max(scales[name], 1e-300)
        if float(np.max(np.abs(check[name] - lat), initial=0.0)) > SPLIT_RTOL * scale:
            return None
    return out
