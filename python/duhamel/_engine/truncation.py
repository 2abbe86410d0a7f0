"""The error of a reduced basis's truncation (issue 41): what the modes a run left out would
have carried at its elements (and saved dofs), estimated after the run from its own force
histories.

A reduced run (``Semianalytic(modes=n)``) keeps the lowest ``n`` modes of its background;
the structure's other modes respond to the same forces: the load patterns and the elements'
pseudo-forces (their force less the linear part the background took over). To first order
(the element forces taken as the run computed them) the truncation error is the response of
those neglected modes to those force histories. It is computed on a small model of the
neglected space: the block Krylov sequence of the residual flexibility,

    X_1 = P K^-1 B,   X_{j+1} = P K^-1 M X_j   (j < BLOCKS),

with ``B`` the force directions the static correction uses (the elements' deformation
directions and the load patterns) and ``P`` the M-orthogonal projection off the kept modes;
the span's Rayleigh-Ritz modes are uncoupled oscillators (the background's damping law)
whose response to the saved forces (linear between saved instants) is exact. Their first
block is exactly the static correction's vectors: a Ritz model on ``j`` blocks reproduces
the first ``2 j`` moments ``sum_i (a.phi_i)(phi_i.b) / omega_i^(2k)`` of the neglected
modes, so ``BLOCKS`` blocks stand for the neglected modes' response dynamically, not only
quasi-statically.

* Without static correction, the estimate is that response (``BLOCKS`` blocks).
* With it, the run carried the first block as coordinates; the estimate is what the
  ``BLOCKS``-block model adds to the one-block model: the dynamic part of the neglected
  modes that the correction's quasi-static vectors cannot represent (large where a pulse or
  a load near the neglected frequencies excites them: the static correction's assumption
  failing, which the warning then says).

The estimate is relative to the peak (of the saved displacements, of each element's
deformation), like ``duhamel._engine.accuracy``'s; see docs/accuracy.md for how it compares
with the full model's error.
"""

from __future__ import annotations

import warnings
from dataclasses import replace
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from duhamel import _core
from duhamel.errors import AccuracyWarning

__all__ = ["BLOCKS", "attach_truncation", "residual_model", "response"]

Array = NDArray[np.float64]

#: Krylov blocks of the neglected space's model.
BLOCKS = 4
#: Saved rows of the output response formed at a time (memory bound on large models).
CHUNK = 2048
#: Above this many saved dofs the estimate there is the bound ``sum_m |psi_dm| max_t |q_m|``
#: relative to the run's peak (forming the error's history at every dof would cost more
#: than the run).
EXACT_ROWS = 8
#: Values of the error's history formed at a time (with :data:`CHUNK` instants at least).
BUFFER = 1 << 16


def residual_model(system: Any, kept: Any, blocks: int) -> list[tuple[Array, Array, Array]]:
    """Per number of blocks ``1..blocks``, the Ritz model of the space `kept` (a
    :class:`duhamel.modal.ModalBasis` of `system`'s lowest modes) leaves out: ``(omega2, c,
    psi)``, the squared circular frequencies, modal damping and M-orthonormal shapes
    (columns) of the Rayleigh-Ritz modes on the first ``j`` Krylov blocks. Cached on
    `system` (shared with the copies a run makes of it, as the static corrections are)."""
    from duhamel._engine import caches
    from duhamel._engine.correction import _damping, _m_orthonormal, _static, force_directions
    from duhamel.modal import damped

    b = force_directions(system)
    key = (kept.n_modes, blocks, b.shape[1], b.tobytes())
    cache = caches.of(system).setdefault("truncation", {})
    if key in cache:
        return cast(list[tuple[Array, Array, Array]], cache[key])
    phi = np.asarray(kept.phi)
    out: list[tuple[Array, Array, Array]] = []
    cache[key] = out  # filled below (in place)
    if b.shape[1] == 0 or kept.n_modes >= system.n_mass:
        return out
    space = np.zeros((system.n_dof, 0))
    block = b
    for _ in range(blocks):
        try:
            y = _m_orthonormal(system, np.hstack([phi, space]), _static(system, kept, block))
        except np.linalg.LinAlgError:
            break
        if y.shape[1] == 0:
            break
        space = np.hstack([space, y])
        ky = space.T @ np.asarray(system.K @ space)
        theta, w = np.linalg.eigh((ky + ky.T) / 2)
        theta = np.maximum(theta, 0.0)
        psi = space @ w
        basis = damped(theta, psi, _damping(system, 0, np.arange(theta.size)))
        out.append((np.asarray(basis.omega2), np.asarray(basis.c), np.asarray(basis.phi)))
        block = np.asarray(system.M @ y)
    return out


def _combined(
    system: Any, models: list[tuple[Array, Array, Array]], correct: bool
) -> tuple[Array, Array, Array, Array]:
    """The oscillators whose response the estimate sums, ``(omega2, c, psi, signed)``: the
    ``BLOCKS``-block model's, and for a corrected run also the one-block model's (its
    shapes negated in `signed`: the estimate is what the larger model adds), so that one
    pass over the force histories and one run of the oscillators serve both (cached with
    `models`)."""
    from duhamel._engine import caches

    cache = caches.of(system).setdefault("truncation", {})
    key = ("combined", id(models), correct)
    found = cache.get(key)
    if found is not None and found[0] is models:
        return cast(tuple[Array, Array, Array, Array], found[1])
    omega2, c, psi = models[-1]
    signed = psi
    if correct:
        one = models[0]
        omega2 = np.concatenate([omega2, one[0]])
        c = np.concatenate([c, one[1]])
        psi = np.hstack([psi, one[2]])
        signed = np.hstack([signed, -one[2]])
    combined = (omega2, c, np.ascontiguousarray(psi), np.ascontiguousarray(signed))
    cache[key] = (models, combined)  # `models` held: its identity stays its own
    return combined


def _steps(omega2: Array, c: Array, h: float) -> Array:
    """Per mode, the exact step of ``q'' + c q' + omega2 q = g`` with ``g`` linear between
    samples ``h`` apart, from the exponential of the oscillator augmented with the input's
    ramp: rows ``(A00, A01, A10, A11, p0, p1, r0, r1, 1 / s)`` of ``x_{k+1} = A x_k + p g_k
    + r g_{k+1}`` on the state ``x = (s q, q')`` (``s = omega``: the step near normal at any
    ``omega h``), ``q = x[0] / s`` (``duhamel._core.hold_response`` runs it)."""
    import scipy.linalg

    n = omega2.size
    w = np.sqrt(np.maximum(omega2, 0.0))
    s = np.where(w > 0.0, w, 1.0)
    z = np.zeros((n, 4, 4))
    z[:, 0, 1] = s * h
    z[:, 1, 0] = -(omega2 / s) * h
    z[:, 1, 1] = -c * h
    z[:, 1, 2] = h  # v' gets g = a + b tau: states (a + b tau, b h)
    z[:, 2, 3] = 1.0  # (tau/h)' = 1/h: the ramp's state is b h
    e = scipy.linalg.expm(z)
    g_ramp, g_const = e[:, :2, 3], e[:, :2, 2]
    steps = np.empty((n, 9))
    steps[:, :4] = e[:, :2, :2].reshape(n, 4)
    steps[:, 4:6] = g_const - g_ramp  # p: the sample at the step's start
    steps[:, 6:8] = g_ramp  # r: the one at its end
    steps[:, 8] = 1.0 / s
    return steps


def response(
    omega2: Array, c: Array, g: Array, t: Array, cache: dict[Any, Any] | None = None
) -> Array:
    """The modal displacements (rows: the modes; columns: the instants `t`, equally spaced)
    of the oscillators ``q'' + c q' + omega2 q = g(t)``, from rest at ``t[0]``, `g` (rows:
    the modes) linear between its columns, exactly (the steps kept in `cache` by their
    content; the core runs them, ``duhamel._core.hold_response``)."""
    if t.size < 2:
        return np.zeros_like(g)
    h = float(t[1] - t[0])
    key = ("steps", omega2.tobytes(), c.tobytes(), h)
    steps = None if cache is None else cache.get(key)
    if steps is None:
        steps = _steps(omega2, c, h)
        if cache is not None:
            cache[key] = steps
    return np.asarray(_core.hold_response(steps, np.ascontiguousarray(g)))


def _forces(solution: Any, prep: Any, opts: Any, psi: Array, t: Array) -> Array | None:
    """The run's forces on the structure beyond its background, projected on `psi`, at the
    saved instants (rows: the columns of `psi`; None where a force's history is not known:
    a Python load function): one product of the force histories (an element's force less
    its linear part in the background, a load's time function) with their projections."""
    from duhamel.loads import Callable

    linear = prep.route.linear
    histories: list[Array] = []  # rows: one force history each
    patterns: list[Array] = []  # the same rows' projections on `psi`
    for index, history in enumerate(solution.elements):
        dofs = list(getattr(history.element, "_dofs", ()))
        force = np.asarray(history.force)
        if not dofs or force.shape[1] != len(dofs):
            return None
        part = linear[index] if index < len(linear) else None
        if part is not None:
            force = force - part.force(np.asarray(history.x), np.asarray(history.v))
        histories.extend(force.T)
        patterns.append(-psi[dofs])  # the restoring force acts on the structure with a minus
    loads = prep.system.loads if opts.loads is None else opts.loads
    for load in loads:
        if isinstance(load, Callable):
            return None
        for term in load._terms(prep.system):
            histories.append(np.asarray(term.time.values(t)))
            patterns.append((psi.T @ np.asarray(term.pattern))[None, :])
    if not histories:
        return np.zeros((psi.shape[1], t.size))
    return np.vstack(patterns).T @ np.vstack(histories)


def _relative_error(rows: Array, q: Array, run: Array) -> float:
    """``max_t |e(t)| / max_t |run(t) + e(t)|`` with ``e = rows @ q`` the estimated error
    (the full model minus the run) along `rows` (`q`: rows the modes, columns the instants)
    and `run` the run's response there (rows: instants, columns: the rows of `rows`): the
    error relative to the estimated peak of the full model (a run that overshoots is not
    excused by its own peak), formed a block of instants at a time."""
    if rows.shape[0] == 0:
        return 0.0
    run = np.asarray(run, dtype=np.float64).reshape(q.shape[1], -1)
    if rows.shape[0] > EXACT_ROWS:  # many saved dofs: the modes' peaks summed in magnitude
        error = float((np.abs(rows) @ _peaks(q)).max(initial=0.0))
        if error == 0.0:
            return 0.0
        peak = _peak(run)
        return error / peak if peak > 0.0 else float("inf")
    if run.shape[1] != rows.shape[0]:
        run = np.broadcast_to(np.abs(run).max(axis=1, keepdims=True), (q.shape[1], rows.shape[0]))
    error, peak = 0.0, 0.0
    step = max(CHUNK, BUFFER // rows.shape[0])
    for s in range(0, q.shape[1], step):
        e = rows @ q[:, s : s + step]
        error = max(error, float(np.abs(e).max(initial=0.0)))
        e += run[s : s + step].T
        peak = max(peak, float(np.abs(e, out=e).max(initial=0.0)))
    if error == 0.0:
        return 0.0
    return error / peak if peak > 0.0 else float("inf")


def _peak(a: Array) -> float:
    """``max |a|`` without a copy of `a` (a large run's saved displacements)."""
    if a.size == 0:
        return 0.0
    return max(float(a.max()), -float(a.min()), 0.0)


def _peaks(q: Array) -> Array:
    """Per row of `q`, ``max |q|``."""
    peaks: Array = np.maximum(q.max(axis=1, initial=0.0), -q.min(axis=1, initial=0.0))
    return peaks


def _applies(solution: Any, prep: Any, system: Any) -> bool:
    integrator = prep.integrator
    t = solution.t
    uniform = t.size >= 3 and bool(
        np.abs(np.diff(t) - (t[1] - t[0])).max() <= 1e-9 * abs(t[1] - t[0])
    )
    return (
        integrator.modes is not None
        and solution.modal is not None
        and prep.route.route in ("uncoupled", "pseudo-force")
        and prep.route.basis.c_coupling is None
        and not system.couplings
        and system.mass_law is None
        and system._condensation is None
        and uniform
    )


def attach_truncation(solution: Any, prep: Any, opts: Any, warn: bool = True) -> None:
    """Sets ``solution.stats.truncation_estimate`` (saved dofs) and
    ``element_truncation_estimate`` (per element) for a reduced run and warns above the
    integrator's ``error_warning``; leaves them None / empty where not estimated (see the
    module docstring and docs/accuracy.md)."""
    if prep.integrator.modes is None or solution.modal is None:
        return  # all modes kept: nothing left out, and no per-call cost for it
    from duhamel._engine import caches
    from duhamel._engine.background import background

    system = background(prep.system, prep.integrator.linear_parts).system
    if not _applies(solution, prep, system):
        return
    integrator = prep.integrator
    kept = system.modal(integrator.modes)
    correct = integrator.static_correction
    if correct is None:
        correct = bool(system.elements)
    models = residual_model(system, kept, BLOCKS)
    t = np.asarray(solution.t)
    dofs = np.asarray(solution.dofs, dtype=np.intp)
    histories = solution.elements
    if not models:  # nothing left out (all modes kept, or no force direction)
        solution.stats = replace(
            solution.stats,
            truncation_estimate=0.0,
            element_truncation_estimate=tuple(0.0 for _ in histories),
        )
        return

    omega2, c, psi, signed = _combined(system, models, correct)
    g = _forces(solution, prep, opts, psi, t)
    if g is None:
        return
    q = response(omega2, c, g, t, caches.of(system).get("truncation"))
    rows = [signed[dofs]] + [_rows(h, signed) for h in histories]
    at_dofs = _relative_error(rows[0], q, np.asarray(solution.x))
    elements = tuple(
        _relative_error(r, q, _local(h)) for r, h in zip(rows[1:], histories, strict=True)
    )
    if np.isnan(at_dofs) or any(np.isnan(e) for e in elements):
        return
    solution.stats = replace(
        solution.stats, truncation_estimate=at_dofs, element_truncation_estimate=elements
    )
    limit = integrator.error_warning if warn else None
    worst = max((at_dofs, *elements))
    if limit is not None and worst > limit:
        from duhamel._engine.accuracy import _caller_level

        advice = (
            "the truncated modes respond dynamically (a pulse or a load near their "
            "frequencies), which the static correction cannot represent: keep more modes"
            if correct
            else "keep more modes or pass `static_correction=True`"
        )
        warnings.warn(
            f"the reduced basis ({integrator.modes} modes"
            + (" with static correction" if correct else "")
            + f") leaves out an estimated {worst:.2g} of the peak response at the elements "
            f"or saved dofs (above `error_warning`={limit:g}): {advice}; see docs/accuracy.md",
            AccuracyWarning,
            stacklevel=_caller_level(),
        )


def _rows(history: Any, psi: Array) -> Array:
    """The rows of `psi` that give the element's deformation (one for a two-node element,
    one per local dof for the others)."""
    dofs = list(getattr(history.element, "_dofs", ()))
    if len(dofs) == 2 and getattr(history.element, "j", None) is not None:
        return psi[dofs[:1]] - psi[dofs[1:]]
    return psi[dofs]


def _local(history: Any) -> Array:
    dofs = list(getattr(history.element, "_dofs", ()))
    if len(dofs) == 2 and getattr(history.element, "j", None) is not None:
        return np.asarray(history.deformation)
    return np.asarray(history.x)
