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


def _filters(omega2: Array, c: Array, h: float) -> tuple[Array, Array]:
    """Per mode, the recursion of ``q'' + c q' + omega2 q = g`` with ``g`` linear between
    samples ``h`` apart, exact (first-order hold, from rest): numerator and denominator
    coefficients in ``z^-1`` (shape ``(n, 3)`` each), from the exponential of the oscillator
    augmented with the input's ramp."""
    import scipy.linalg

    n = omega2.size
    w = np.sqrt(np.maximum(omega2, 0.0))
    s = np.where(w > 0.0, w, 1.0)  # the state (w q, v): the block near normal at any w h
    z = np.zeros((n, 4, 4))
    z[:, 0, 1] = s * h
    z[:, 1, 0] = -(omega2 / s) * h
    z[:, 1, 1] = -c * h
    z[:, 1, 2] = h  # v' gets g = a + b tau: states (a + b tau, b h)
    z[:, 2, 3] = 1.0  # (tau/h)' = 1/h: the ramp's state is b h
    e = scipy.linalg.expm(z)
    a = e[:, :2, :2]
    g_ramp, g_const = e[:, :2, 3], e[:, :2, 2]
    b0, b1 = g_const - g_ramp, g_ramp  # x_{k+1} = A x_k + b0 g_k + b1 g_{k+1}
    # q = (w q) / s: the transfer of the first state, (z I - A)^-1 (b0 + z b1)
    a00, a01, a10, a11 = a[:, 0, 0], a[:, 0, 1], a[:, 1, 0], a[:, 1, 1]
    num = np.stack(
        [b1[:, 0], b0[:, 0] - a11 * b1[:, 0] + a01 * b1[:, 1], -a11 * b0[:, 0] + a01 * b0[:, 1]],
        axis=1,
    )
    den = np.stack([np.ones(n), -(a00 + a11), a00 * a11 - a01 * a10], axis=1)
    return num / s[:, None], den


def response(
    omega2: Array, c: Array, g: Array, t: Array, cache: dict[Any, Any] | None = None
) -> Array:
    """The modal displacements (rows: the instants `t`, equally spaced) of the oscillators
    ``q'' + c q' + omega2 q = g(t)``, from rest, `g` linear between its rows (the filters
    kept in `cache` by their content)."""
    from scipy.signal import lfilter

    q = np.zeros_like(g)
    if t.size < 2:
        return q
    h = float(t[1] - t[0])
    key = ("filters", omega2.tobytes(), c.tobytes(), h)
    found = None if cache is None else cache.get(key)
    if found is None:
        found = _filters(omega2, c, h)
        if cache is not None:
            cache[key] = found
    num, den = found
    for m in range(omega2.size):
        q[:, m] = lfilter(num[m], den[m], g[:, m])
    return q


def _forces(solution: Any, prep: Any, opts: Any, psi: Array, t: Array) -> Array | None:
    """The run's forces on the structure beyond its background, projected on `psi`, at the
    saved instants (None where a force's history is not known: a Python load function)."""
    from duhamel.loads import Callable

    g = np.zeros((t.size, psi.shape[1]))
    linear = prep.route.linear
    for index, history in enumerate(solution.elements):
        dofs = list(getattr(history.element, "_dofs", ()))
        force = np.asarray(history.force)
        if not dofs or force.shape[1] != len(dofs):
            return None
        part = linear[index] if index < len(linear) else None
        if part is not None:
            force = force - part.force(np.asarray(history.x), np.asarray(history.v))
        g -= force @ psi[dofs]  # the restoring force acts on the structure with a minus
    loads = prep.system.loads if opts.loads is None else opts.loads
    for load in loads:
        if isinstance(load, Callable):
            return None
        for term in load._terms(prep.system):
            g += np.outer(np.asarray(term.time.values(t)), psi.T @ np.asarray(term.pattern))
    return g


def _relative_error(rows: Array, q: Array, run: Array) -> float:
    """``max_t |e(t)| / max_t |run(t) + e(t)|`` with ``e = q @ rows.T`` the estimated error
    (the full model minus the run) along `rows` and `run` the run's response there (rows:
    instants, columns: the rows of `rows`): the error relative to the estimated peak of the
    full model (a run that overshoots is not excused by its own peak), formed :data:`CHUNK`
    instants at a time."""
    if rows.shape[0] == 0:
        return 0.0
    run = np.asarray(run, dtype=np.float64).reshape(q.shape[0], -1)
    if rows.shape[0] > EXACT_ROWS:  # many saved dofs: the modes' peaks summed in magnitude
        error = float((np.abs(rows) @ np.abs(q).max(axis=0)).max(initial=0.0))
        peak = float(np.abs(run).max(initial=0.0))
        if error == 0.0:
            return 0.0
        return error / peak if peak > 0.0 else float("inf")
    if run.shape[1] != rows.shape[0]:
        run = np.broadcast_to(np.abs(run).max(axis=1, keepdims=True), (q.shape[0], rows.shape[0]))
    error, peak = 0.0, 0.0
    for s in range(0, q.shape[0], CHUNK):
        e = q[s : s + CHUNK] @ rows.T
        error = max(error, float(np.abs(e).max(initial=0.0)))
        peak = max(peak, float(np.abs(run[s : s + CHUNK] + e).max(initial=0.0)))
    if error == 0.0:
        return 0.0
    return error / peak if peak > 0.0 else float("inf")


def _applies(solution: Any, prep: Any, system: Any) -> bool:
    integrator = prep.integrator
    t = solution.t
    uniform = t.size >= 3 and np.allclose(np.diff(t), t[1] - t[0], rtol=1e-9, atol=0.0)
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

    def deflection(model: tuple[Array, Array, Array]) -> tuple[Array, list[Array]]:
        omega2, c, psi = model
        g = _forces(solution, prep, opts, psi, t)
        if g is None:
            raise LookupError
        q = response(omega2, c, g, t, caches.of(system).get("truncation"))
        return q, [psi[dofs]] + [_rows(h, psi) for h in histories]

    try:
        q_all, rows_all = deflection(models[-1])
        if correct:
            q_one, rows_one = deflection(models[0])
            q = np.hstack([q_all, q_one])
            rows = [np.hstack([a, -b]) for a, b in zip(rows_all, rows_one, strict=True)]
        else:
            q, rows = q_all, rows_all
    except LookupError:
        return
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
