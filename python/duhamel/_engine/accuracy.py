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
sums the modes' bounds times the magnitude of their shapes there. Force jumps inside a step
(a ``MinMax`` material failing) make a first-order error the parabola does not measure: the
core finds softening jumps in the saved pseudo-force and adds their expected error (the
exact step's response to a step load anywhere in the step, carried by the mode's dynamics
after the jump; ``duhamel_core::accuracy::jumps``). See docs/accuracy.md.
"""

from __future__ import annotations

import os
import sys
import warnings
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel import _core
from duhamel.errors import AccuracyWarning

__all__ = [
    "applies",
    "estimator",
    "mode_bounds",
    "on_users_grid",
    "parabola_moments",
    "refined",
    "run_estimate",
    "warn_above",
]


def parabola_moments(
    omega: NDArray[np.float64], c: NDArray[np.float64], h: float
) -> NDArray[np.float64]:
    """Per mode, the end state ``(q, v)`` of ``q'' + c q' + omega^2 q = 4 s (1 - s)``,
    ``s = tau / h``, from rest over one step ``h`` (shape ``(n, 2)``): the exponential of
    the oscillator augmented with the polynomial's integrator chain (Van Loan). Zero for the
    quasi-static coordinates of massless dofs (``omega = inf``). The runs' estimate takes
    these moments from the core's exact step (``_core.parabola_moments``, the ``DDp`` column
    of its load transfer); this independent construction is its reference."""
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
    between saved instants, ``span`` the run's duration (computed in the core,
    ``duhamel_core::accuracy::mode_bounds``: the second differences of `pseudo`, the
    effective frequencies, the parabola moments, the decaying accumulation of
    :func:`_decaying_max`)."""
    return _core.mode_bounds(
        np.ascontiguousarray(pseudo, dtype=np.float64),
        np.ascontiguousarray(q, dtype=np.float64),
        np.ascontiguousarray(omega, dtype=np.float64),
        np.ascontiguousarray(c, dtype=np.float64),
        (float(h), int(k), float(span)),
    )


def _decaying_max(x: NDArray[np.float64], decay: NDArray[np.float64]) -> NDArray[np.float64]:
    """Per row ``m``, the largest ``acc_i`` of ``acc_{i+1} = decay[m] acc_i + x[m, i]`` from
    ``acc_0 = 0`` (computed in the core): rows decaying faster than ``e^-0.5`` a step take
    the bound ``max(x) / (1 - decay)``; the others, where the slowest-decaying of them
    allows it, are lumped in groups of ``g`` values (``g rate <= 0.1``), a bound within
    ``e^0.2`` of the recurrence."""
    return _core.decaying_max(
        np.ascontiguousarray(x, dtype=np.float64), np.ascontiguousarray(decay, dtype=np.float64)
    )


def applies(prep: Any) -> bool:
    """Whether runs of `prep` are estimated: the uncoupled route, and the pseudo-force route
    with the default step (scheme "b", "trapezoid" quadrature), for a run whose history is
    second-order (not the first-order modes' coordinates: the caller checks)."""
    integrator = prep.integrator
    route = prep.route.route
    default_step = integrator.scheme == "b" and integrator.quadrature == "trapezoid"
    return bool(route == "uncoupled" or (route == "pseudo-force" and default_step))


def estimator(prep: Any, dofs: NDArray[np.int64]) -> Any:
    """The core's ``Estimator`` of runs of `prep` saving `dofs`: the modes, the magnitudes of
    the mode shapes at those dofs and along every element's deformation (``phi_i - phi_j``
    for a two-node element, the rows of its dofs otherwise; none for the elements when one
    of them is not reached by the basis's rows). Shared by the models whose basis arrays
    are the same objects (systems with the same matrices share their first modal analysis,
    ``_engine.shared``) and whose elements act on the same dofs."""
    basis = prep.route.basis
    omega, c, phi = basis.omega, basis.c, basis.phi
    elements = tuple(
        (tuple(getattr(e, "_dofs", ())), getattr(e, "j", None) is not None) for e in prep.forces
    )
    key = (id(omega), id(c), id(phi), dofs.tobytes(), elements)
    got = _ESTIMATORS.get(key)
    if got is None or got[0] is not omega or got[1] is not c or got[2] is not phi:
        core = _core.Estimator(
            np.ascontiguousarray(omega, dtype=np.float64),
            np.ascontiguousarray(c, dtype=np.float64),
            np.ascontiguousarray(phi, dtype=np.float64),
            np.ascontiguousarray(dofs, dtype=np.int64),
            [(list(d), two_node) for d, two_node in elements],
        )
        if len(_ESTIMATORS) >= 16:
            _ESTIMATORS.pop(next(iter(_ESTIMATORS)))  # the oldest
        got = _ESTIMATORS[key] = (omega, c, phi, core)  # the arrays kept: ids not reused
    return got[3]


#: What :func:`run_estimate` returns: the estimates at the saved dofs and per element, then
#: the bounds.
Estimates = tuple[float | None, tuple[float, ...], float | None, tuple[float, ...]]

#: The last estimators made, by the identity of their basis arrays (held with them), the
#: saved dofs and the elements' dofs (:func:`estimator`).
_ESTIMATORS: dict[tuple[Any, ...], tuple[Any, Any, Any, Any]] = {}


def run_estimate(
    prep: Any,
    dofs: NDArray[np.int64],
    result: Any,
    h: float,
    k: int,
    x: NDArray[np.float64],
    elements: bool,
) -> Estimates | None:
    """``(error_estimate, element_error_estimate, error_bound, element_error_bound)`` of a
    whole successful core run `result`
    of the prepared modal model `prep` (internal steps `h`, `k` of them between saved
    instants; `x` the response of the saved `dofs`; `elements`: the element histories are
    kept), or None where the run is not estimated (see :func:`applies`; a history that is
    not finite)."""
    estimated = prep._estimated
    if estimated is None:
        estimated = prep._estimated = applies(prep)
    if not estimated or result.eta is not None:
        return None
    if result.pseudo is None and not prep.forces:
        return 0.0, (), 0.0, ()  # no pseudo-force and no element: nothing left out (exact)
    last = prep._estimator  # the last estimator of this model, by its saved dofs' array
    if last is not None and last[0] is dofs:
        core = last[1]
    else:
        core = estimator(prep, dofs)
        prep._estimator = (dofs, core)
    keeps = elements and bool(prep.forces)
    if not isinstance(result, _core.RunResult):  # a run joined from segments (stopped)
        return _joined_estimate(prep, dofs, result, h, k, x, keeps)
    got = core.estimate(result, h, k, np.ascontiguousarray(x), keeps)
    return None if got is None else (got[0], tuple(got[1]), got[2], tuple(got[3]))


def _joined_estimate(
    prep: Any,
    dofs: NDArray[np.int64],
    result: Any,
    h: float,
    k: int,
    x: NDArray[np.float64],
    keeps: bool,
) -> Estimates | None:
    """:func:`run_estimate` of a history joined from segments (a run stopped by a terminal
    event): the same estimates (``_core.row_errors``), bounds (``_core.mode_bounds``) and
    ratios, from its arrays."""
    basis = prep.route.basis
    t = result.t
    span = float(t[-1] - t[0]) if t.size else 0.0
    phi = np.asarray(basis.phi)
    shapes = [phi[dofs]]  # the saved dofs' rows, then each element's
    responses = [x]
    widths = None if result.element_force is None else list(result.element_widths)
    if keeps and widths is not None and len(widths) == len(prep.forces):
        ex, at = np.asarray(result.element_x), 0
        for element, width in zip(prep.forces, widths, strict=True):
            dofs_e = list(getattr(element, "_dofs", ()))
            if not dofs_e or max(dofs_e) >= phi.shape[0]:
                del shapes[1:], responses[1:]  # an element the basis's rows do not reach
                break
            rows, local = phi[dofs_e], ex[:, at : at + width]
            two_node = getattr(element, "j", None) is not None
            if len(dofs_e) == 2 and two_node:
                rows = rows[:1] - rows[1:]
            shapes.append(rows)
            responses.append(local[:, 0] - local[:, 1] if width == 2 and two_node else local)
            at += width
    signed = np.ascontiguousarray(np.concatenate(shapes, axis=0), dtype=np.float64)
    if result.pseudo is None:
        errors = bounds = np.zeros(signed.shape[0])
    else:
        pseudo = np.ascontiguousarray(result.pseudo, dtype=np.float64)
        q = np.ascontiguousarray(result.q, dtype=np.float64)
        omega = np.ascontiguousarray(basis.omega, dtype=np.float64)
        c = np.ascontiguousarray(basis.c, dtype=np.float64)
        errors = _core.row_errors(pseudo, q, omega, c, signed, (float(h), int(k), span))
        bounds = np.abs(signed) @ mode_bounds(pseudo, q, omega, c, h, k, span)
    ratios = []
    at = 0
    for rows, response in zip(shapes, responses, strict=True):
        part = slice(at, at + rows.shape[0])
        ratios.append((_relative(errors[part], response), _relative(bounds[part], response)))
        at += rows.shape[0]
    if any(np.isnan(r).any() for r in ratios):
        return None  # not estimated rather than NaN (a non-finite history)
    elements = ratios[1:]
    return (
        ratios[0][0],
        tuple(e[0] for e in elements),
        ratios[0][1],
        tuple(e[1] for e in elements),
    )


def _relative(bound: NDArray[np.float64], response: NDArray[np.float64]) -> float:
    worst = float(bound.max()) if bound.size else 0.0
    if worst == 0.0:
        return 0.0
    peak = float(np.abs(response).max()) if response.size else 0.0
    return worst / peak if peak > 0.0 else float("inf")


def warn_above(integrator: Any, estimated: Estimates) -> None:
    """Warns (:class:`duhamel.AccuracyWarning`, at the user's line) when the largest error
    bound of `estimated` (:func:`run_estimate`'s) is above the integrator's
    ``error_warning``: the bound, never below the error in the family of docs/accuracy.md,
    so that no run above the threshold is silent."""
    limit = integrator.error_warning
    if limit is None:
        return
    estimate, bound = _worst(estimated[0], estimated[1]), _worst(estimated[2], estimated[3])
    if bound is not None and bound > limit:
        warnings.warn(
            f"the run's error bound is {bound:.2g} of the peak response (above "
            f"`error_warning`={limit:g}; its estimated error {estimate:.2g}): reduce `dt` "
            "(the error falls like dt^2, like dt where element forces jump), see "
            "docs/accuracy.md",
            AccuracyWarning,
            stacklevel=_caller_level(),
        )


def _worst(dofs: float | None, elements: tuple[float, ...]) -> float | None:
    """The largest of an estimate at the saved dofs and at the elements (None: neither)."""
    worst = max(elements) if elements else None
    if dofs is not None and (worst is None or dofs > worst):
        worst = dofs
    return worst


def _caller_level() -> int:
    """The ``stacklevel`` of the first frame outside the duhamel package (the user's call
    of ``solve`` or ``Prepared.run``, whatever the path to here)."""
    frame: Any = sys._getframe(1)
    level = 1
    inside = _INSIDE
    while frame is not None:
        filename = frame.f_code.co_filename
        known = inside.get(filename)
        if known is None:
            if len(inside) >= 1024:
                inside.clear()
            known = inside[filename] = _inside_package(filename)
        if not known:
            break
        frame, level = frame.f_back, level + 1
    return level


#: Whether a code object's file is one of the package's, by file name (a dict: the frames
#: of every warned run are looked up).
_INSIDE: dict[str, bool] = {}


def _inside_package(filename: str) -> bool:
    """Whether `filename` (a code object's) is a file of the duhamel package."""
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    return os.path.abspath(filename).startswith(package)


def tolerance_ratio(solution: Any, rtol: float, atol: float) -> float | None:
    """The largest ratio of the error bound to what ``rtol`` and ``atol`` allow, at the
    saved dofs (``atol + rtol * peak``) and at every element's deformation; None where the
    run has no estimate."""
    st = solution.stats
    if st.error_bound is None:
        return None

    def ratio(estimate: float, response: NDArray[np.float64]) -> float:
        peak = float(np.max(np.abs(response))) if response.size else 0.0
        if estimate == 0.0:
            return 0.0
        allowed = rtol + (atol / peak if peak > 0.0 else np.inf)
        return estimate / allowed

    worst = ratio(st.error_bound, solution.x)
    for estimate, history in zip(st.element_error_bound, solution.elements, strict=False):
        worst = max(worst, ratio(estimate, np.asarray(history.deformation)))
    return worst


def refined(opts: Any, k: int) -> Any:
    """The request `opts` in steps of ``dt / k``, saving at the same instants."""
    grid = {"dt": opts.dt / k, "n_steps": opts.n_steps * k, "save_every": opts.save_every * k}
    return replace(opts, **grid)


def on_users_grid(sol: Any, opts: Any, k: int) -> None:
    """States the run `sol` of :func:`refined` ``(opts, k)`` on the user's grid: its
    ``meta`` the user's ``dt`` and ``save_every``, its ``stats`` counting steps of ``dt``,
    ``k`` times more substeps each."""
    sol.meta["dt"] = opts.dt
    sol.meta["save_every"] = opts.save_every
    sol.stats = replace(sol.stats, steps=sol.stats.steps // k, substeps=sol.stats.substeps * k)


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
        sol = run_once(prep, refined(opts, k) if k > 1 else opts)
        worst = tolerance_ratio(sol, rtol, atol)
        if worst is None:
            raise ValueError(
                "`rtol`: this run has no error estimate to choose its steps by (the coupled "
                "route, `coupling='exact'` with couplings: pass `coupling='pseudo-force'`)"
            )
        if level:
            on_users_grid(sol, opts, k)
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
