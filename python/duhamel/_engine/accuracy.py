"""The error estimate of a semi-analytic run (issue 41): what the pseudo-force quadrature
left out, accumulated over the run, at the saved dofs and at the elements.

The default step (scheme "b", "trapezoid" quadrature) integrates the modal pseudo-force
``Q(t)`` as the straight line between its values at the start and the end of the step. Its
local error is, to leading order, the quadratic part of ``Q`` that the line leaves out,
``4 DDQ s (1 - s)`` with ``DDQ = Q(t + h/2) - (Q(t) + Q(t + h))/2 = -Q'' h^2/8``, entering
each mode through the load-transfer moment of that parabola (the ``DDp`` column of the
exact step, the same moment the loads use). ``Q''`` is read from the second differences of
the pseudo-force the run saved (no extra evaluation during the run: its cost is a few
passes over the modal history). The local errors of every mode are accumulated as
magnitudes (an amplitude, ``sqrt(dq^2 + (dv/omega)^2)``), decaying with the mode's damping
between steps: an upper bound of the global error of a run whose local errors add up in
phase (the drift of an oscillation), the common case. The bound at a dof or an element
sums the modes' bounds times the magnitude of their shapes there. See docs/accuracy.md.
"""

from __future__ import annotations

import functools
import os
import warnings
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.errors import AccuracyWarning

__all__ = ["attach_estimate", "mode_bounds", "parabola_moments"]


def parabola_moments(
    omega: NDArray[np.float64], c: NDArray[np.float64], h: float
) -> NDArray[np.float64]:
    """Per mode, the end state ``(q, v)`` of ``q'' + c q' + omega^2 q = 4 s (1 - s)``,
    ``s = tau / h``, from rest over one step ``h`` (shape ``(n, 2)``): the exponential of
    the oscillator augmented with the polynomial's integrator chain (Van Loan). Zero for the
    quasi-static coordinates of massless dofs (``omega = inf``)."""
    import scipy.linalg  # the solve path's, not `import duhamel`'s

    finite = np.isfinite(omega) & np.isfinite(c)
    if not finite.all():
        out = np.zeros((omega.size, 2))
        if finite.any():
            out[finite] = parabola_moments(omega[finite], c[finite], h)
        return out
    # the state (omega q, v): the oscillator's block near normal (scaling and squaring is
    # then as accurate at large omega h as at small; checked against the closed forms)
    s = np.where(omega > 0.0, omega, 1.0)
    z = np.zeros((omega.size, 5, 5))
    z[:, 0, 1] = s * h
    z[:, 1, 0] = -(omega**2 / s) * h
    z[:, 1, 1] = -c * h
    # the input 4 s - 8 (s^2/2) from the chain u2 = 1, u1 = s, u0 = s^2/2 (u0' = u1, u1' = u2)
    z[:, 1, 2] = -8.0 * h
    z[:, 1, 3] = 4.0 * h
    z[:, 2, 3] = 1.0
    z[:, 3, 4] = 1.0
    end: NDArray[np.float64] = scipy.linalg.expm(z)[:, :2, 4]
    end[:, 0] /= s
    return end


#: The moments of the last runs, by the content of ``(omega, c, h)``: a prepared model's
#: basis and step are the same from run to run, and the batched ``expm`` is most of a short
#: run's estimate (~0.1 ms for 10 modes).
_MOMENTS: dict[tuple[bytes, bytes, float], NDArray[np.float64]] = {}
_MOMENTS_KEPT = 16


def _cached_moments(
    omega: NDArray[np.float64], c: NDArray[np.float64], h: float
) -> NDArray[np.float64]:
    """:func:`parabola_moments`, kept for the last :data:`_MOMENTS_KEPT` contents (read-only:
    shared between runs)."""
    omega = np.ascontiguousarray(omega, dtype=np.float64)
    c = np.ascontiguousarray(c, dtype=np.float64)
    key = (omega.tobytes(), c.tobytes(), float(h))
    got = _MOMENTS.get(key)
    if got is None:
        got = parabola_moments(omega, c, h)
        got.flags.writeable = False
        if len(_MOMENTS) >= _MOMENTS_KEPT:
            _MOMENTS.pop(next(iter(_MOMENTS)))  # the oldest
        _MOMENTS[key] = got
    return got


def effective_omega(
    pseudo: NDArray[np.float64], q: NDArray[np.float64], omega: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Per mode, the circular frequency of the background stiffened by the part of the
    pseudo-force in phase with the mode's own displacement (a secant over the run; never
    below ``omega``): the frequency at which a velocity error turns into a displacement
    error."""
    qq = np.einsum("ij,ij->j", q, q)
    stiffening = -np.einsum("ij,ij->j", pseudo, q) / np.where(qq > 0.0, qq, 1.0)
    result: NDArray[np.float64] = np.sqrt(omega**2 + np.maximum(stiffening, 0.0))
    return result


def mode_bounds(
    pseudo: NDArray[np.float64],
    q: NDArray[np.float64],
    omega: NDArray[np.float64],
    c: NDArray[np.float64],
    h: float,
    k: int,
    span: float,
) -> NDArray[np.float64]:
    """Per mode, the largest accumulated bound of the modal displacement error over the run:
    `pseudo` the saved modal pseudo-force, ``h`` the internal step, ``k`` internal steps
    between saved instants, ``span`` the run's duration."""
    rows, n = pseudo.shape
    if rows < 3:
        return np.zeros(n)
    # |Q''| h^2 per internal step from the second differences (saved spacing k h), mode by
    # mode in contiguous rows
    pt = np.ascontiguousarray(pseudo.T)
    second = pt[:, 2:] + pt[:, :-2]
    second -= 2.0 * pt[:, 1:-1]
    np.abs(second, out=second)
    moments = _cached_moments(omega, c, h)
    # velocity errors read as the displacement amplitude they carry (at least the drift
    # they cause over half the run, for slow and rigid modes)
    finite = np.where(np.isfinite(omega), omega, 0.0)  # massless dofs' coordinates: moments 0
    w = np.maximum(effective_omega(pseudo, q, finite), 2.0 / max(span, h))
    # |DDQ| = |Q''| h^2 / 8 per internal step, k of them per saved interval
    scale = np.hypot(moments[:, 0], moments[:, 1] / w) / (8.0 * k)
    decay = np.exp(-0.5 * np.where(np.isfinite(c) & (c > 0.0), c, 0.0) * k * h)
    # the undamped sums bound the recurrence; the modes that make up 95 % of their total
    # are run through it, the others keep their sum (a bound within 5 % of the total)
    out = scale * second.sum(axis=1)
    order = np.argsort(out)
    small = order[np.cumsum(out[order]) <= 0.05 * out.sum()]
    keep = np.ones(n, dtype=bool)
    keep[small] = False
    big = np.flatnonzero(keep)  # np.setdiff1d(np.arange(n), small), without its sort
    out[big] = scale[big] * _decaying_max(second[big], decay[big])
    result: NDArray[np.float64] = out
    return result


def _decaying_max(x: NDArray[np.float64], decay: NDArray[np.float64]) -> NDArray[np.float64]:
    """Per row ``m``, the largest ``acc_i`` of ``acc_{i+1} = decay[m] acc_i + x[m, i]`` from
    ``acc_0 = 0``: ``acc_{s+i} = decay^i (acc_s + sum_{j<i} decay^(-1-j) x[s+j])`` over
    blocks short enough for ``decay^-len`` to stay below ``e^50`` (all rows at once), of
    groups of rows where the decay allows it (a bound within ``e^0.2``). Rows decaying
    faster than ``e^-0.5`` a step take the bound ``max(x) / (1 - decay)``."""
    n, rows = x.shape
    rate = -np.log(np.clip(decay, 1e-300, 1.0))  # >= 0
    best = np.zeros(n)
    fast = rate > 0.5
    if fast.any():
        best[fast] = x[fast].max(axis=1, initial=0.0) / (1.0 - decay[fast])
    slow = np.flatnonzero(~fast)
    if slow.size == 0 or rows == 0:
        return best
    x, rate = x[slow], rate[slow]
    if not rate.any():  # undamped: running sums
        best[slow] = np.cumsum(x, axis=1).max(axis=1, initial=0.0)
        return best
    # Groups of `g` rows lumped at their ends (g rate <= 0.1): a bound within e^0.2 of the
    # recurrence (an input moved later decays less: e^0.1; a group's inside is below its
    # start plus its sum: e^0.1 more), `g` times fewer rows
    g = int(min(rows, 0.1 // float(rate.max())))
    if g >= 2:
        whole = rows // g * g
        x = np.concatenate(
            [x[:, :whole].reshape(slow.size, -1, g).sum(axis=2), x[:, whole:].sum(axis=1)[:, None]],
            axis=1,
        )
        rate = rate * g
        rows = x.shape[1]
    length = int(min(rows, 50.0 // float(rate.max())))
    grow = np.exp(np.outer(rate, np.arange(1, length + 1)))  # decay^-i
    shrink = 1.0 / grow  # decay^i
    carry, top = np.zeros(slow.size), np.zeros(slow.size)
    for s in range(0, rows, length):
        block = x[:, s : s + length]
        width = block.shape[1]
        acc = np.cumsum(block * grow[:, :width], axis=1)
        acc += carry[:, None]
        acc *= shrink[:, :width]
        top = np.maximum(top, acc.max(axis=1))
        carry = acc[:, -1]
    best[slow] = top * np.exp(rate) if g >= 2 else top
    return best


def _relative(bound: NDArray[np.float64], response: NDArray[np.float64]) -> float:
    worst = float(bound.max()) if bound.size else 0.0  # the methods: np.max's dispatch costs
    if worst == 0.0:
        return 0.0
    peak = float(np.abs(response).max()) if response.size else 0.0
    return worst / peak if peak > 0.0 else float("inf")


def attach_estimate(
    solution: Any,
    prep: Any,
    opts: Any,
    sub: int,
    phi_out: NDArray[np.float64],
    warn: bool = True,
) -> None:
    """Sets ``solution.stats.error_estimate`` (and per element) and warns above the
    integrator's ``error_warning``; None where the estimate does not apply (see the module
    docstring and docs/accuracy.md)."""
    integrator = prep.integrator
    modal = solution.modal
    route = prep.route.route
    default_step = integrator.scheme == "b" and integrator.quadrature == "trapezoid"
    applies = (
        modal is not None
        and modal._first_order is None
        and (route == "uncoupled" or (route == "pseudo-force" and default_step))
    )
    if not applies:
        return
    h = opts.dt / sub
    k = opts.save_every * sub
    span = float(solution.t[-1] - solution.t[0]) if solution.t.size else 0.0
    if modal.pseudo is None:
        bounds = np.zeros(modal.omega.size)
    else:
        bounds = mode_bounds(modal.pseudo_force, modal.q, modal.omega, modal.c, h, k, span)
    phi_out = np.asarray(phi_out)
    dofs_est = None
    if phi_out.ndim == 2 and phi_out.shape[1] == bounds.size:
        dofs_est = _relative(np.abs(phi_out) @ bounds, solution.x)
    elements = _element_estimates(solution, prep.route.basis.phi, bounds)
    if (dofs_est is not None and np.isnan(dofs_est)) or any(np.isnan(e) for e in elements):
        return  # not estimated rather than NaN (a non-finite pseudo-force history)
    solution.stats = replace(
        solution.stats, error_estimate=dofs_est, element_error_estimate=elements
    )
    limit = integrator.error_warning if warn else None
    worst = max([e for e in (dofs_est, *elements) if e is not None], default=None)
    if limit is not None and worst is not None and worst > limit:
        warnings.warn(
            f"the run's estimated error is {worst:.2g} of the peak response (above "
            f"`error_warning`={limit:g}): reduce `dt` (the error falls like dt^2), see "
            "docs/accuracy.md",
            AccuracyWarning,
            stacklevel=_caller_level(),
        )


def _caller_level() -> int:
    """The ``stacklevel`` of the first frame outside the duhamel package (the user's call
    of ``solve`` or ``Prepared.run``, whatever the path to here)."""
    import sys

    frame: Any = sys._getframe(1)
    level = 1
    while frame is not None and _inside_package(frame.f_code.co_filename):
        frame, level = frame.f_back, level + 1
    return level


@functools.lru_cache(maxsize=256)
def _inside_package(filename: str) -> bool:
    """Whether `filename` (a code object's) is a file of the duhamel package."""
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    return os.path.abspath(filename).startswith(package)


def _element_estimates(
    solution: Any, phi: NDArray[np.float64], bounds: NDArray[np.float64]
) -> tuple[float, ...]:
    """Per element, the bound of its deformation's error relative to its peak deformation."""
    phi = np.asarray(phi)
    if phi.ndim != 2 or phi.shape[1] != bounds.size:
        return ()
    out = []
    for history in solution.elements:
        dofs = list(getattr(history.element, "_dofs", ()))
        if not dofs or max(dofs) >= phi.shape[0]:
            return ()  # an element the basis's rows do not reach: none rather than some
        rows = phi[dofs]
        if len(dofs) == 2 and getattr(history.element, "j", None) is not None:
            rows = rows[:1] - rows[1:]
        deformation = history.deformation
        out.append(_relative(np.abs(rows) @ bounds, np.asarray(deformation)))
    return tuple(out)


def tolerance_ratio(solution: Any, rtol: float, atol: float) -> float | None:
    """The largest ratio of the estimated error to what ``rtol`` and ``atol`` allow, at the
    saved dofs (``atol + rtol * peak``) and at every element's deformation; None where the
    run has no estimate."""
    st = solution.stats
    if st.error_estimate is None:
        return None

    def ratio(estimate: float, response: NDArray[np.float64]) -> float:
        peak = float(np.max(np.abs(response))) if response.size else 0.0
        if estimate == 0.0:
            return 0.0
        allowed = rtol + (atol / peak if peak > 0.0 else np.inf)
        return estimate / allowed

    worst = ratio(st.error_estimate, solution.x)
    for estimate, history in zip(st.element_error_estimate, solution.elements, strict=False):
        worst = max(worst, ratio(estimate, np.asarray(history.deformation)))
    return worst


def to_tolerance(run_once: Any, prep: Any, opts: Any) -> Any:
    """Runs with steps of ``dt / 2^k``, ``k`` raised as the error estimate requires (the
    error falls like ``dt^2``) until it meets ``rtol``/``atol``, the saved instants the
    user's; at ``k = subdivisions`` a run still above stops with ``SolverError(reason=
    "tolerance")``."""
    from duhamel.errors import SolverError

    integrator = prep.integrator
    rtol, atol, depth = integrator.rtol, integrator.atol, integrator.subdivisions
    level = 0
    while True:
        k = 2**level
        grid = {"dt": opts.dt / k, "n_steps": opts.n_steps * k, "save_every": opts.save_every * k}
        sol = run_once(prep, replace(opts, **grid) if k > 1 else opts)
        worst = tolerance_ratio(sol, rtol, atol)
        if worst is None:
            raise ValueError(
                "`rtol`: this run has no error estimate to choose its steps by (the coupled "
                "route, `coupling='exact'` with couplings: pass `coupling='pseudo-force'`)"
            )
        if level:
            sol.meta["dt"] = opts.dt
            sol.meta["save_every"] = opts.save_every
            sol.stats = replace(
                sol.stats, steps=sol.stats.steps // k, substeps=sol.stats.substeps * k
            )
        if worst <= 1.0:
            return sol
        if level >= depth:
            raise SolverError(
                f"the run cannot meet `rtol`={rtol:g} (`atol`={atol:g}): its estimated error "
                f"is still {worst:.3g} times the tolerance in steps of dt/2^{level} = "
                f"{opts.dt / k:.4g} (`subdivisions`={depth}); raise `subdivisions` or "
                "loosen `rtol` (docs/accuracy.md)",
                time=float(sol.t[-1]),
                reason="tolerance",
                partial=sol,
            )
        # the error falls like dt^2: 4x per level; at least one level more
        level = min(depth, level + max(1, int(np.ceil(np.log(worst) / np.log(4.0)))))
