"""``duhamel.solve``: run an integrator on a model."""

from __future__ import annotations

import math
import os
import time as _time
from types import SimpleNamespace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._engine.direct import solve_direct
from duhamel._engine.output import check_memory, output_maps, physical
from duhamel._engine.plan import ModalSpec, Plan, mass, modal_loads, plan
from duhamel._engine.run import ModalCallable, Progress, overflow_error, raise_failure, watch
from duhamel._engine.validate import (
    MAX_COUNT,
    as_float_array,
    dof_list,
    finite_float,
    positive_float,
    positive_int,
)
from duhamel.elements.basic import LinearCoupling
from duhamel.integrators import DirectIntegrator, Semianalytic
from duhamel.loads import Callable, support_terms
from duhamel.results.solution import Solution, SolveStats
from duhamel.results.structural import element_histories
from duhamel.system import ModalBasis, System

__all__ = ["solve"]


def _steps(t_end: Any, dt: float, t0: float) -> int:
    t_end = finite_float(t_end, "t_end")
    span = t_end - t0
    if not span >= dt * (1.0 - 1e-9):
        raise ValueError(
            f"`t_end` ({t_end:g}) must be at least one step `dt` ({dt:g}) after `t0` ({t0:g})"
        )
    steps = span / dt * (1.0 + 1e-12) + 1e-9
    if not steps <= MAX_COUNT:
        raise ValueError(
            f"`dt` = {dt:g} is too small for `t_end` - `t0` = {span:g}: that is {steps:.3g} "
            f"steps, more than the {MAX_COUNT:.3g} a run can take; use a larger `dt` or a "
            "shorter run"
        )
    # The step times t0 + n dt must be told apart: the grid's largest time resolves dt.
    largest = max(abs(t0), abs(t_end))
    if float(np.spacing(largest)) > 1e-3 * dt:
        raise ValueError(
            f"`dt` = {dt:g} is below the resolution of the times around `t0` = {t0:g} "
            f"(`t_end` = {t_end:g}): doubles there are {float(np.spacing(largest)):.3g} apart, "
            "so the step times would not be distinct; measure time from a nearer origin "
            "(a smaller `t0`) or use a larger `dt`"
        )
    return max(1, math.floor(steps))


def _initial(value: ArrayLike | None, name: str, system: System, basis: ModalBasis) -> NDArray:
    """Modal coordinates of an initial state: ``Phi^T M x``."""
    if value is None:
        return np.zeros(basis.phi.shape[1])
    x = as_float_array(value, name, ndim=1, shape=(system.n_dof,))
    return np.ascontiguousarray(basis.phi.T @ np.asarray(system.M @ x, dtype=np.float64))


def _run(
    route: Plan,
    spec: ModalSpec,
    integrator: Semianalytic,
    phi_out: NDArray,
    forcing: Any,
    report: Progress | None,
    system: System,
) -> Any:
    """Runs the route in the core; returns its ``RunResult``."""
    if route.route == "uncoupled":
        return _core.solve_uncoupled(spec, forcing, report)
    phi = spec.phi
    if route.route == "first-order":
        fo = route.modes
        assert fo is not None
        eta0 = fo.initial(spec.q0, spec.v0)
        parts = (fo.lam.real, fo.lam.imag, fo.gain.real, fo.gain.imag, eta0.real, eta0.imag)
        names = ("lambda_re", "lambda_im", "gain_re", "gain_im", "eta0_re", "eta0_im")
        modes = SimpleNamespace(
            **{
                n: np.ascontiguousarray(p, dtype=np.float64)
                for n, p in zip(names, parts, strict=True)
            }
        )
        outputs = output_maps(route, phi_out, len(spec.loads))
        nonlinear = (
            SimpleNamespace(
                phi=phi,
                elements=route.elements,
                back=fo.back,
                tol=float(integrator.tol),
                max_iter=int(integrator.max_iter),
            )
            if route.elements
            else None
        )
        return _core.solve_first_order(spec, modes, outputs, nonlinear, forcing, report)
    nonlinear = SimpleNamespace(
        phi=phi,
        elements=route.elements,
        options=integrator,
        coupling_k=route.couplings.k,
        coupling_c=route.couplings.c,
        scaled=route.couplings.scaled,
        mass=mass(system, integrator),
    )
    return _core.solve_pseudo(spec, nonlinear, forcing, report)


def solve(
    system: System,
    integrator: Semianalytic | DirectIntegrator,
    *,
    t_end: float,
    dt: float,
    x0: ArrayLike | None = None,
    v0: ArrayLike | None = None,
    t0: float = 0.0,
    save_every: int = 1,
    dofs: ArrayLike | None = None,
    threads: int | None = None,
    progress: bool | Progress | None = None,
    store: str | os.PathLike[str] | Any = None,
    checkpoint_every: int | None = None,
) -> Solution:
    """Transient response of `system` from `t0` to `t_end` with a fixed step `dt`.

    Parameters
    ----------
    system : System
        The model, with its loads.
    integrator : Semianalytic, Newmark, HHT, GeneralizedAlpha, CentralDifference or CubicHermite
        The time integrator and its options. :class:`Semianalytic` steps the modal
        oscillators exactly (modal reduction possible); the others step the physical
        equations directly (docs/direct.md).
    t_end : float
        End time; the run takes ``floor((t_end - t0) / dt)`` steps of length `dt` (``t_end``
        itself when ``t_end - t0`` is a multiple of `dt`).
    dt : float
        Step length, ``> 0``. For linear systems the result does not depend on it beyond the
        representation of the loads within a step.
    x0, v0 : array_like, shape (n_dof,), optional
        Displacements and velocities at `t0` (zero by default). With modal reduction they
        are projected on the retained modes. Direct integrators start from them as given,
        with the initial acceleration from the equation of motion.
    t0 : float
        Start time (default 0). Loads keep their absolute time axis, so a run can be
        continued from the last state of another: ``solve(..., t0=sol.t[-1], x0=sol.x[-1],
        v0=sol.v[-1])`` (all dofs kept) gives, to round-off, what one longer run gives.
    save_every : int
        Keep every `save_every`-th step (the last step is always kept).
    dofs : sequence of int, optional
        Degrees of freedom to recover (default: all). The modal history is always kept
        (semi-analytic); direct integrators keep only these.
    threads : int, optional
        Worker threads of the semi-analytic linear time loop (default: all cores; at most
        the machine's cores are used); the direct integrators run on one thread.
    progress : bool or callable, optional
        ``True`` shows a tqdm progress bar (steps, rate, ETA) for runs lasting more than
        about a second; a function is called as ``progress(step, n_steps, t)`` between
        blocks of steps (about ten times a second, never per step).
    store : str, os.PathLike or duhamel.store.Store, optional
        Stream the run to a new zarr store at this path (docs/store.md): the run proceeds in
        segments of bounded memory, each appended to the store, with checkpoints that
        :func:`duhamel.resume` continues from after a crash; the returned Solution reads its
        arrays from the store. Semi-analytic integrator only; needs ``duhamel[store]``.
    checkpoint_every : int, optional
        With `store`: write a checkpoint every this many segments (default 1).

    Returns
    -------
    Solution
        ``t``, ``x``, ``v``, ``a`` (computed on first access for the semi-analytic
        integrator), ``modal`` (None for direct integrators) and ``stats``.

    Raises
    ------
    ValueError, TypeError
        Bad input; the message names the parameter.
    SolverError
        The response became non-finite (``reason="nonfinite"``: a diverging system), a step
        equation did not converge (``"convergence"``) or a Python load or element function
        failed (``"callback"``, chained to its exception); ``step`` and ``time`` say where,
        ``partial`` holds the solution up to the last good instant (finite rows only). See
        docs/errors.md.
    KeyboardInterrupt
        Ctrl-C during the run (it stops within a fraction of a second); its ``partial``
        attribute holds the solution computed so far. An exception raised by a `progress`
        function stops the run the same way and is re-raised with ``partial``.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> sys = duhamel.System(np.eye(1), np.array([[4.0]]), zeta=0.02)
    >>> _ = sys.add_load(duhamel.loads.Step(dof=0, amplitude=4.0))
    >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=10.0, dt=0.5)
    >>> w, z = 2.0, 0.02   # exact step response: steps of 0.16 periods lose nothing
    >>> wd = w * np.sqrt(1 - z**2)
    >>> exact = 1 - np.exp(-z * w * sol.t) * (np.cos(wd * sol.t) + z * w / wd * np.sin(wd * sol.t))
    >>> float(np.abs(sol.x[:, 0] - exact).max()) < 1e-13
    True
    >>> rest = duhamel.solve(sys, duhamel.Semianalytic(), t0=10.0, t_end=20.0, dt=0.5,
    ...                      x0=sol.x[-1], v0=sol.v[-1])          # continued from t = 10
    >>> rest.t[0], rest.t[-1]
    (np.float64(10.0), np.float64(20.0))
    """
    started = _time.perf_counter()
    if not isinstance(system, System):
        raise TypeError(f"`system` must be a duhamel.System, got {type(system).__name__}")
    if not isinstance(integrator, Semianalytic | DirectIntegrator):
        raise TypeError(
            f"`integrator` must be a duhamel integrator such as duhamel.Semianalytic() or "
            f"duhamel.Newmark(), got {type(integrator).__name__}"
        )
    dt = positive_float(dt, "dt")
    t0 = finite_float(t0, "t0")
    n_steps = _steps(t_end, dt, t0)
    # A stride beyond the run keeps its first and last instants, as the run's length does.
    save_every = min(positive_int(save_every, "save_every", maximum=2**64), n_steps)
    if threads is not None:
        threads = positive_int(threads, "threads")
    out_dofs = np.arange(system.n_dof) if dofs is None else dof_list(dofs, "dofs", system.n_dof)
    if store is not None:
        from duhamel.store._run import run_stored

        return run_stored(
            system, integrator, store=store, checkpoint_every=checkpoint_every, t0=t0, dt=dt,
            n_steps=n_steps, save_every=save_every, out_dofs=out_dofs, x0=x0, v0=v0,
            threads=threads, progress=progress, started=started,
        )  # fmt: skip
    if isinstance(integrator, DirectIntegrator):
        hysteretic = [
            e for e in system.elements if e._path_dependent or getattr(e, "state", None) is not None
        ]
        if hysteretic and not getattr(integrator, "_commits_state", False):
            raise ValueError(
                f"`integrator`: {type(integrator).__name__} does not yet commit the internal "
                f"variables of path-dependent elements ({type(hysteretic[0]).__name__}); use "
                "duhamel.Semianalytic()"
            )
        n = system.n_dof
        fns = [load.fn for load in system.loads if isinstance(load, Callable)]
        with watch(progress, n_steps) as report:
            return solve_direct(
                system,
                integrator,
                dt=dt,
                n_steps=n_steps,
                x0=np.zeros(n) if x0 is None else as_float_array(x0, "x0", ndim=1, shape=(n,)),
                v0=np.zeros(n) if v0 is None else as_float_array(v0, "v0", ndim=1, shape=(n,)),
                save_every=save_every,
                out_dofs=out_dofs,
                forcing=ModalCallable(fns, n) if fns else None,
                started=started,
                t0=t0,
                progress=report,
            )

    route = plan(system, integrator)
    basis = route.basis
    phi = basis.phi
    specs, fns = modal_loads(system, phi)
    spec = ModalSpec(
        k=np.ascontiguousarray(basis.omega2, dtype=np.float64),
        c=np.ascontiguousarray(basis.c, dtype=np.float64),
        q0=_initial(x0, "x0", system, basis),
        v0=_initial(v0, "v0", system, basis),
        loads=specs,
        t0=t0,
        dt=dt,
        n_steps=n_steps,
        save_every=save_every,
        threads=threads,
        phi=np.ascontiguousarray(phi),
    )
    forcing = ModalCallable(fns, system.n_dof) if fns else None
    phi_out = phi[out_dofs, :]
    # The engine keeps q and v (or the first-order coordinates), loads and pseudo-forces.
    check_memory(n_steps, save_every, len(out_dofs), 4 * basis.n_modes + len(specs))
    with watch(progress, n_steps) as report:
        loop_start = _time.perf_counter()
        result = _run(route, spec, integrator, phi_out, forcing, report, system)
        wall = _time.perf_counter() - loop_start

    patterns = (
        np.stack([s.pattern for s in specs], axis=1) if specs else np.zeros((phi.shape[1], 0))
    )
    kept, x, vel, acc, modal = physical(result, route, phi_out, patterns)
    error = result.error
    solution = Solution(
        t=result.t[:kept],
        x=x,
        v=vel,
        a=acc,
        dofs=np.asarray(out_dofs, dtype=np.int64),
        modal=modal,
        stats=SolveStats(
            steps=n_steps if error is None else error.step - 1,
            wall_time=wall,
            total_time=_time.perf_counter() - started,
            modes=phi.shape[1],
            newton_iterations=int(result.newton_iterations),
            closed_form_steps=int(result.closed_form_steps),
            factorizations=int(result.factorizations),
            subdivided_steps=int(result.subdivided_steps),
            subdivision_depth=int(result.subdivision_depth),
            coupling=route.coupling,
            eigenvector_condition=None if route.modes is None else route.modes.condition,
        ),
        meta={"dt": dt, "t0": t0, "integrator": integrator, "labels": system.dof_labels},
        elements=element_histories(
            [e for e in system.elements if not isinstance(e, LinearCoupling)],
            result.t[:kept],
            result,
            kept,
            route.linear,
        ),
        base=support_terms(system.loads, np.asarray(out_dofs, dtype=np.int64)),
    )
    if error is None and kept < result.t.size:
        raise overflow_error(result.t, kept, dt, t0, solution)
    if error is not None:
        if kept < result.t.size:
            # The outputs of the last states overflowed before the coordinates did.
            error = error.kept_until(float(result.t[kept - 1]) if kept else None)
        raise_failure(error, solution)
    return solution
