"""A modal model prepared for runs (what :class:`duhamel.Prepared` holds for the
semi-analytic integrator), and one run of it up to its :class:`duhamel.Solution`.

The set-up — the route with its basis (and static correction), the first-order modes, the
core's model with its elements and the projected loads — is made once; a run adds only its
grid, its initial state and, when given, its own loads.
"""

from __future__ import annotations

import functools
import time as _time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine import dispatch
from duhamel._engine.accuracy import run_estimate, to_tolerance, warn_above
from duhamel._engine.background import background
from duhamel._engine.correction import substeps
from duhamel._engine.dense import ExactSteps, State
from duhamel._engine.energy_run import (
    EnergyModel,
    energy_model,
    energy_spec,
    stepwise,
)
from duhamel._engine.massless import load_terms
from duhamel._engine.output import check_memory, physical
from duhamel._engine.plan import Plan, mass, modal_loads, plan
from duhamel._engine.relaxation import check_loads, check_state
from duhamel._engine.request import ACCUMULATED, Request
from duhamel._engine.run import ModalCallable, failure_note, overflow_error, raise_failure, watch
from duhamel._engine.segments import Grid, chunked
from duhamel._engine.structure import structure_model
from duhamel._engine.truncation import attach_truncation
from duhamel._engine.validate import as_float_array
from duhamel.errors import SolverError
from duhamel.integrators import Semianalytic
from duhamel.loads import support_terms
from duhamel.results.solution import Solution, SolveStats
from duhamel.results.structural import element_histories
from duhamel.system import System

__all__ = ["ModalSetup", "Outputs", "setup"]


@dataclass(frozen=True, eq=False)
class Outputs:
    """What a run keeps of the physical response: the dofs, their mode-shape rows, the
    first-order route's output maps and the support terms of the absolute accelerations."""

    dofs: NDArray[np.int64]
    phi_out: NDArray[np.float64]
    maps: Any  # _core.Outputs or None
    base: list[tuple[NDArray[np.float64], Any]]


@dataclass(eq=False)
class ModalSetup:
    """A system prepared for semi-analytic runs (see the module docstring)."""

    system: System
    integrator: Semianalytic
    route: Plan
    model: Any  # _core.ModalModel
    loads: list[Any]  # the system's loads as _core.Load (modal patterns)
    fns: list[Any]  # the system's Python load functions
    patterns: NDArray[np.float64]
    forces: list[Any]  # the force elements, couplings left out (for their histories)
    threads: int | None
    _outputs: dict[Any, Outputs] = field(default_factory=dict)
    _zeros: NDArray[np.float64] | None = None
    _substeps: dict[float, int] = field(default_factory=dict)
    _stepwise: Any = None  # the uncoupled route's model stepped one step at a time
    _estimated: bool | None = None  # whether its runs are estimated (accuracy.applies)
    _estimator: tuple[Any, Any] | None = None  # (saved dofs, the core's Estimator)
    _structure: functools.partial[Any] | None = None  # the structure of the system's loads

    def stepwise(self) -> Any:
        """The core's model of a run that accumulates its energy (:func:`_engine.energy_run.
        stepwise`): the uncoupled route's same exact modal step, one step at a time."""
        if self.route.route != "uncoupled":
            return self.model
        if self._stepwise is None:
            self._stepwise = stepwise(self.route, self.loads, self.integrator)
        return self._stepwise

    @property
    def n_modes(self) -> int:
        return int(self.route.basis.n_modes)

    def substeps(self, dt: float) -> int:
        """Internal steps per step `dt` (:func:`duhamel._engine.correction.substeps`), made
        once per step."""
        sub = self._substeps.get(dt)
        if sub is None:
            sub = self._substeps[dt] = substeps(self.route.resolve, dt)
        return sub

    def initial(self, value: Any, name: str) -> NDArray[np.float64]:
        """Modal coordinates of an initial state: ``Phi^T M x`` (zeros for None)."""
        if value is None:
            if self._zeros is None:
                self._zeros = np.zeros(self.n_modes)
            return self._zeros
        system = self.system
        x = as_float_array(value, name, ndim=1, shape=(system.n_dof,))
        phi = self.route.basis.phi
        extra = self.route.massless
        if extra is None:
            return np.ascontiguousarray(phi.T @ np.asarray(system.M @ x, dtype=np.float64))
        # the massless dofs' coordinates hold no mass: psi^T K_b x (their K-orthonormal part)
        check_state(extra, x, name)
        m = phi.shape[1] - extra.initial.shape[0]
        q = np.empty(phi.shape[1])
        q[:m] = phi[:, :m].T @ np.asarray(system.M @ x, dtype=np.float64)
        q[m:] = extra.initial @ x
        return q

    def structure(self, loads: list[Any] | None) -> functools.partial[Any]:
        """The structural model of a run under `loads` (None: the system's), as a function
        made on first access (:func:`_engine.structure.structure_model`); the one of the
        system's loads made once."""
        if loads is None and self._structure is not None:
            return self._structure
        system = self.system
        made = functools.partial(
            structure_model,
            system,
            self.route.basis,
            tuple(system.elements),
            tuple(system.loads if loads is None else loads),
        )
        if loads is None:
            self._structure = made
        return made

    def run(self, req: Request) -> Solution:
        """One run of `req`, kept in memory (:func:`run`)."""
        return run(self, req)

    def outputs(self, dofs: NDArray[np.int64] | None, n_loads: int) -> Outputs:
        """The output maps of `dofs` (None: all), made once per choice of dofs."""
        key = (None if dofs is None else dofs.tobytes(), n_loads)
        out = self._outputs.get(key)
        if out is None:
            n = self.system.n_dof
            chosen = np.arange(n, dtype=np.int64) if dofs is None else dofs.copy()
            chosen.flags.writeable = False  # shared by the solutions of this choice
            phi = self.route.basis.phi
            if dofs is None and phi.flags.c_contiguous:  # every row: `phi[chosen]`'s values
                phi_out = phi.view()
                phi_out.flags.writeable = False
            else:
                phi_out = phi[chosen, :]
            out = Outputs(
                chosen,
                phi_out,
                dispatch.outputs(self.route, phi_out, n_loads),
                support_terms(self.system.loads, chosen),
            )
            if len(self._outputs) >= 16:  # a few choices of dofs are kept, not every one
                self._outputs.clear()
            self._outputs[key] = out
        return out


def setup(system: System, integrator: Semianalytic, threads: int | None = None) -> ModalSetup:
    """Plans the route of `system` under `integrator` and builds the core's model."""
    route = plan(system, integrator)
    phi = route.basis.phi
    loads, fns = modal_loads(system.loads, system, phi)
    model = dispatch.modal_model(route, loads, integrator, mass(system, integrator))
    patterns = _patterns(loads, phi.shape[1])
    forces = list(system.elements)
    return ModalSetup(system, integrator, route, model, loads, fns, patterns, forces, threads)


def _patterns(loads: list[Any], n_modes: int) -> NDArray[np.float64]:
    """The modal patterns of the core's `loads` as the columns of one array."""
    if len(loads) == 1:  # np.stack's values and layout, without its generic path
        pattern: NDArray[np.float64] = loads[0].pattern
        return pattern.reshape(-1, 1).copy()
    return np.stack([s.pattern for s in loads], axis=1) if loads else np.zeros((n_modes, 0))


def run(prep: ModalSetup, opts: Request) -> Solution:
    """One run of a prepared modal model, up to its :class:`duhamel.Solution`: one, or with
    ``Semianalytic(rtol=...)`` as many as the tolerance needs (:func:`to_tolerance`)."""
    if getattr(prep.integrator, "rtol", None) is not None:
        solution: Solution = to_tolerance(_run_once, prep, opts)
        return solution
    return _run_once(prep, opts)


def _run_once(prep: ModalSetup, opts: Request) -> Solution:
    """One run of a prepared modal model."""
    route = prep.route
    system = prep.system
    if opts.loads is None:
        loads, fns, patterns, base = None, prep.fns, prep.patterns, None
    else:
        check_loads(route.massless, system, opts.loads)
        loads, fns = modal_loads(opts.loads, system, route.basis.phi)
        patterns = _patterns(loads, prep.n_modes)
        base = opts.loads
    n_loads = patterns.shape[1]
    out = prep.outputs(opts.dofs, n_loads)
    check_memory(opts.n_steps, opts.save_every, out.dofs.size, 4 * prep.n_modes + n_loads)
    state = (prep.initial(opts.x0, "x0"), prep.initial(opts.v0, "v0"))
    # Static-correction coordinates under nonlinear elements are resolved in time: `sub`
    # internal steps per step, the saved instants unchanged.
    sub = prep.substeps(opts.dt)
    h, n_steps, save_every = opts.dt / sub, opts.n_steps * sub, opts.save_every * sub
    emodel = _energy_model(prep, opts, patterns, bool(fns))
    forcing = ModalCallable(fns, system.n_dof) if fns else None
    if opts.stop is not None and (opts.progress is None or opts.progress is False):
        grid = Grid(route, opts.t0, h, n_steps, save_every, prep.threads, *state)
        stopped = _stopping(prep, opts, grid, sub, loads, out, forcing, patterns, base)
        if stopped is not None:
            sol, joined = stopped
            if opts.interpolant:
                sol._exact = exact_steps(prep, loads, out, patterns, forcing, joined)
            return sol
    # the whole grid from the run's start (what `Grid.whole` makes, without the Grid)
    back = None if route.modes is None else route.modes.back
    energy = None if emodel is None else energy_spec(emodel, None, back)
    run_grid = dispatch.grid(opts.t0, h, n_steps, save_every, 0, prep.threads)
    spec = dispatch.run_spec(route, run_grid, state, energy=energy)
    model = prep.model if emodel is None else prep.stepwise()
    if opts.progress is None or opts.progress is False:
        loop_start = _time.perf_counter()
        result = model.run(spec, loads, out.maps, forcing, None)
        wall = _time.perf_counter() - loop_start
    else:
        with watch(opts.progress, opts.n_steps * sub) as report:
            loop_start = _time.perf_counter()
            result = model.run(spec, loads, out.maps, forcing, report)
            wall = _time.perf_counter() - loop_start
    sol = solution(prep, result, out, patterns, opts, wall, base, sub, emodel)
    if opts.interpolant:
        sol._exact = exact_steps(prep, loads, out, patterns, forcing, result)
    return sol


def _stopping(
    prep: ModalSetup, opts: Request, grid: Grid, sub: int, loads: Any, out: Outputs,
    forcing: Any, patterns: NDArray[np.float64], base: Any,
) -> tuple[Solution, Any] | None:  # fmt: skip
    """The run in chunks, stopped after the chunk where ``opts.stop`` fires (None: a chunk
    failed, the caller runs the whole grid)."""

    def one(spec: Any) -> Any:
        return prep.model.run(spec, loads, out.maps, forcing, None)

    def seen(result: Any, steps: int) -> bool:
        part = solution(
            prep,
            result,
            out,
            patterns,
            replace(opts, n_steps=steps),
            0.0,
            base,
            sub,
            estimate=False,
        )
        return bool(opts.stop(part))

    loop_start = _time.perf_counter()
    try:
        done = chunked(grid, sub, one, seen)
    except (ArithmeticError, SolverError):  # an overflow: the whole run raises it
        return None
    if done is None:
        return None
    joined, steps = done
    wall = _time.perf_counter() - loop_start
    done_opts = replace(opts, n_steps=steps)
    return solution(prep, joined, out, patterns, done_opts, wall, base, sub), joined


def exact_steps(
    prep: ModalSetup,
    loads: list[Any] | None,
    out: Outputs,
    patterns: NDArray[np.float64],
    forcing: Any,
    result: Any,
) -> ExactSteps | None:
    """The exact interpolant of a linear route's run (None on the other routes): one core
    step of a fraction of ``dt`` from a saved state, with the run's loads."""
    route = prep.route
    if route.route not in ("uncoupled", "first-order") or route.elements:
        return None
    q, v, eta = result.q, result.v, result.eta
    zeros = np.zeros(prep.n_modes)

    def one_step(t_n: float, tau: float, n: int) -> Any:
        grid = dispatch.grid(t_n, tau, 1, 1, 0, 1)
        if eta is None:
            state = (np.ascontiguousarray(q[n]), np.ascontiguousarray(v[n]))
            spec = dispatch.run_spec(route, grid, state)
        else:
            spec = dispatch.run_spec(route, grid, (zeros, zeros), eta=eta[n])
        return prep.model.run(spec, loads, out.maps, forcing, None)

    def last_row(res: Any) -> tuple[State, dict[str, NDArray[np.float64]]]:
        kept, x, vel, acc, hist = physical(res, route, out.phi_out, patterns)
        if res.error is not None or kept < 2 or not callable(acc):
            raise FloatingPointError(
                "the response inside a step could not be computed (the one-step run from "
                f"the saved state stopped: {res.error})"
            )
        row = {"load_values": hist.load_values[-1]}
        if hist.forcing is not None:
            row["forcing"] = hist.forcing[-1]
        if eta is None:
            row["q"], row["v"] = hist.q[-1], hist.v[-1]
        else:
            row["eta"] = hist._first_order[0][-1]  # type: ignore[index]
        return (x[-1], vel[-1], acc()[-1]), row

    return ExactSteps(one_step, last_row)


def solution(
    prep: ModalSetup,
    result: Any,
    out: Outputs,
    patterns: NDArray[np.float64],
    opts: Request,
    wall: float,
    base: list[Any] | None,
    sub: int = 1,
    emodel: EnergyModel | None = None,
    estimate: bool = True,
) -> Solution:
    """The :class:`duhamel.Solution` of a core run's `result` (raises the run's failure,
    with the solution up to it as ``partial``)."""
    route = prep.route
    kept, x, vel, acc, modal = physical(result, route, out.phi_out, patterns)
    error = result.error
    t = result.t if kept == result.t.size else result.t[:kept]
    # The static part is K_ss^-1 f_s of the background the run integrated: elements' linear
    # parts at massless dofs moved into it (`linear_parts="auto"/"background"`) belong to K_ss.
    terms = None
    if prep.system._condensation is not None:  # massless dofs (the same in the background)
        terms = load_terms(
            background(prep.system, prep.integrator.linear_parts).system,
            prep.system.loads if base is None else base,
            t,
            out.dofs,
            opts.dt,
            route.carried,
        )
    if terms is not None:  # loads at massless dofs: their static part, which no mode carries
        x, vel = x + terms[0], vel + terms[1]
        acc = _plus(acc, terms[2])
    # the error estimate of a whole successful run (issue 41), computed in the core
    estimated = None  # the error estimate of a whole successful run (issue 41)
    if estimate and error is None and kept == result.t.size:
        h, k = opts.dt / sub, opts.save_every * sub
        estimated = run_estimate(prep, out.dofs, result, h, k, x, opts.elements)
    solution = Solution(
        t=t,
        x=x,
        v=vel,
        a=acc,
        dofs=out.dofs,
        modal=modal,
        stats=SolveStats._of(
            steps=opts.n_steps if error is None else (error.step - 1) // sub,
            wall_time=wall,
            total_time=_time.perf_counter() - opts.started,
            modes=prep.n_modes,
            newton_iterations=int(result.newton_iterations),
            closed_form_steps=int(result.closed_form_steps),
            factorizations=int(result.factorizations),
            subdivided_steps=int(result.subdivided_steps),
            subdivision_depth=int(result.subdivision_depth),
            coupling=route.coupling,
            eigenvector_condition=None if route.modes is None else route.modes.condition,
            loop_time=float(result.loop_time),
            substeps=sub,
            error_estimate=None if estimated is None else estimated[0],
            element_error_estimate=() if estimated is None else estimated[1],
            error_bound=None if estimated is None else estimated[2],
            element_error_bound=() if estimated is None else estimated[3],
        ),
        meta={
            "dt": opts.dt,
            "t0": opts.t0,
            "integrator": prep.integrator,
            "labels": prep.system.dof_labels,
            "save_every": opts.save_every,
        },
        elements=(
            (lambda: element_histories(prep.forces, t, result, kept, route.linear))
            if prep.forces and opts.elements
            else ()
        ),
        base=out.base if base is None else support_terms(base, out.dofs),
        structure=prep.structure(opts.loads),
    )
    if emodel is not None and terms is None and result.energy is not None:
        solution._energy_run = (result.energy[:kept], emodel)
    if estimate and error is None and kept == result.t.size:
        warn = getattr(prep.integrator, "rtol", None) is None  # else the tolerance decides
        if warn and estimated is not None:
            warn_above(prep.integrator, estimated)
        attach_truncation(solution, prep, opts, warn)
    if error is None and kept < result.t.size:
        raise overflow_error(result.t, kept, opts.dt, opts.t0, solution)
    if error is not None:
        if kept < result.t.size:
            # The outputs of the last states overflowed before the coordinates did.
            error = error.kept_until(float(result.t[kept - 1]) if kept else None)
        step = None if sub == 1 else -(-error.step // sub)
        note = failure_note(
            error,
            modal,
            forces=bool(prep.forces),
            route=route.route,
            omega=route.basis.omega,
            correction=route.correction,
            subdivisions=getattr(prep.integrator, "subdivisions", 0),
            dt=opts.dt / sub,
            sub=sub,
        )
        raise_failure(error, solution, note, step)
    return solution


def _energy_model(
    prep: ModalSetup, opts: Request, patterns: NDArray[np.float64], python_loads: bool
) -> EnergyModel | None:
    """The energy model of a run that accumulates its energy in the core (None: not asked
    for, or a run that computes it after the run: a first-order one with elements or
    Python loads)."""
    if not opts.energy or prep.route.route not in ACCUMULATED or opts.stop is not None:
        return None
    if prep.route.route == "first-order" and (prep.route.elements or python_loads):
        if opts.save_every != 1 or opts.dofs is not None:
            raise ValueError(
                "`energy`: a first-order (coupled) run with elements or Python loads has its "
                "energy balance computed after the run from every step and dof: solve with "
                "`save_every=1` and `dofs=None`"
            )
        return None
    system = prep.system
    loads = system.loads if opts.loads is None else opts.loads
    structure = structure_model(system, prep.route.basis, tuple(system.elements), tuple(loads))
    phi = prep.route.basis.phi
    return energy_model(system, phi, patterns, loads, structure, prep.route.linear)


def _plus(acc: Any, extra: NDArray[np.float64]) -> Any:
    """The accelerations `acc` (an array, or a function giving them) plus `extra`."""
    if callable(acc):
        return lambda: acc() + extra
    return acc + extra
