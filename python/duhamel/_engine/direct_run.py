"""The direct integrators' runs: a system prepared once (its physical matrices and the
core's model, ``_core.DirectModel``) and run per case (``_core.DirectRun``)."""

from __future__ import annotations

import functools
import time as _time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import NDArray

from duhamel._engine import dispatch
from duhamel._engine.direct import _check_central, physical_matrices
from duhamel._engine.energy_run import direct_energy_model, energy_spec
from duhamel._engine.plan import core_elements, mass, modal_loads
from duhamel._engine.request import Request
from duhamel._engine.run import ModalCallable, overflow_error, raise_failure, watch
from duhamel._engine.structure import structure_model
from duhamel._engine.validate import as_float_array, issparse
from duhamel.integrators import CentralDifference, CubicHermite, DirectIntegrator
from duhamel.results.solution import Solution, SolveStats
from duhamel.system import System

if TYPE_CHECKING:
    from duhamel._engine.massless import Condensation

__all__ = ["DirectSetup", "prepare_direct", "step_matrix"]


@dataclass(eq=False)
class DirectSetup:
    """A system prepared for a direct integrator: its physical matrices, core elements and
    the core's model; the system's own loads."""

    system: System
    integrator: DirectIntegrator
    mats: dict[str, Any]
    elements: list[Any]
    model: Any  # _core.DirectModel
    loads: list[Any]
    fns: list[Any]

    def run(self, req: Request, a0: NDArray[np.float64] | None = None) -> Solution:
        """One run of `req`, kept in memory (with the integrator's `rtol`, the run whose
        steps meet it: :func:`_to_tolerance`); `a0` overrides the initial acceleration (see
        :func:`step_matrix`)."""
        if getattr(self.integrator, "rtol", None) is None:
            return self._run_once(req, a0)
        return _to_tolerance(self, req, a0)

    def _run_once(self, req: Request, a0: NDArray[np.float64] | None = None) -> Solution:
        """One run of `req` in steps of its `dt`."""
        system, integrator = self.system, self.integrator
        t0, dt, n_steps, save_every = req.t0, req.dt, req.n_steps, req.save_every
        x0, v0, loads, dofs = req.x0, req.v0, req.loads, req.dofs
        progress, started, energy = req.progress, req.started, req.energy
        n = system.n_dof
        x0 = np.zeros(n) if x0 is None else as_float_array(x0, "x0", ndim=1, shape=(n,))
        v0 = np.zeros(n) if v0 is None else as_float_array(v0, "v0", ndim=1, shape=(n,))
        out_dofs = np.arange(n, dtype=np.int64) if dofs is None else dofs
        specs, fns = (self.loads, self.fns) if loads is None else modal_loads(loads, system, None)
        if isinstance(integrator, CentralDifference) and not integrator.allow_unstable:
            span = (t0, t0 + n_steps * dt)
            _check_central(system, self.mats, self.elements, x0, v0, dt, span)
        if a0 is None and system._condensation is not None:
            v0, a0 = _massless_start(self, x0, v0, t0, dt, loads)
        em = None
        if energy:
            run_loads = system.loads if loads is None else loads
            structure = structure_model(system, None, tuple(system.elements), tuple(run_loads))
            em = direct_energy_model(system, run_loads, structure)
        run = dispatch.direct_run(
            dispatch.grid(t0, dt, n_steps, save_every), x0, v0, out_dofs, a0,
            None if em is None else energy_spec(em),
        )  # fmt: skip
        forcing = ModalCallable(fns, n) if fns else None
        with watch(progress, n_steps) as report:
            loop_start = _time.perf_counter()
            result = self.model.run(run, specs, forcing, report)
            wall = _time.perf_counter() - loop_start
        error = result.error
        # Only finite rows are kept (the saved accelerations of a step element are recomputed
        # from the equation of motion and can overflow where the state does not).
        rows = [np.isfinite(arr).all(axis=1) for arr in (result.x, result.v, result.a)]
        finite = np.logical_and.reduce(rows) if result.t.size else np.ones(0, dtype=bool)
        kept = int(finite.size if finite.all() else np.argmin(finite))
        solution = Solution(
            t=result.t[:kept],
            x=result.x[:kept],
            v=result.v[:kept],
            a=result.a[:kept],
            dofs=np.asarray(out_dofs, dtype=np.int64),
            modal=None,
            stats=SolveStats(
                steps=n_steps if error is None else max(0, error.step - 1),
                wall_time=wall,
                total_time=_time.perf_counter() - started,
                modes=0,
                newton_iterations=int(result.newton_iterations),
                factorizations=int(result.factorizations),
                loop_time=float(result.loop_time),
            ),
            meta={
                "dt": dt,
                "t0": t0,
                "integrator": integrator,
                "labels": system.dof_labels,
                "save_every": save_every,
            },
            structure=functools.partial(
                structure_model,
                system,
                None,
                tuple(system.elements),
                tuple(system.loads if loads is None else loads),
            ),
        )
        if em is not None and result.energy is not None:
            solution._energy_run = (result.energy[:kept], em)
        if error is None and kept < result.t.size:
            raise overflow_error(result.t, kept, dt, t0, solution)
        if error is not None:
            if kept < result.t.size:
                error = error.kept_until(float(result.t[kept - 1]) if kept else None)
            raise_failure(error, solution)
        return solution


def _to_tolerance(setup: DirectSetup, req: Request, a0: NDArray[np.float64] | None) -> Solution:
    """The run of `req` in steps of ``dt / 2^k``, ``k = 1, 2, ...`` up to the integrator's
    `subdivisions`, until two successive runs differ by at most ``atol + rtol * peak`` at the
    saved displacements (the difference bounds the finer run's error for a method of order
    1 or more once its steps resolve the response: order p leaves ``1 / (2^p - 1)`` of it);
    the finer run is returned at the user's saved instants. Beyond `subdivisions` a
    ``SolverError(reason="tolerance")`` holding the finest run."""
    from dataclasses import replace

    from duhamel._engine.accuracy import on_users_grid, refined
    from duhamel.errors import SolverError

    integrator: Any = setup.integrator  # one with `rtol` (alpha family, CubicHermite)
    rtol, atol, depth = integrator.rtol, integrator.atol, integrator.subdivisions
    if req.located:
        raise ValueError(
            "`rtol` of a direct integrator refines whole runs: not with `events`, `t_eval` or "
            "`dense` (run with the `dt` it chose, `sol.meta['dt'] / sol.stats.substeps`)"
        )
    coarse = setup._run_once(req, a0)
    for level in range(1, depth + 1):
        k = 2**level
        fine = setup._run_once(refined(req, k), a0)
        diff = float(np.abs(fine.x - coarse.x).max(initial=0.0))
        peak = float(np.abs(fine.x).max(initial=0.0))
        on_users_grid(fine, req, k)
        estimate = diff / peak if peak > 0.0 else (0.0 if diff == 0.0 else float("inf"))
        fine.stats = replace(fine.stats, error_estimate=estimate)
        if diff <= atol + rtol * peak:
            return fine
        coarse = fine
    raise SolverError(
        f"the run cannot meet `rtol`={rtol:g} (`atol`={atol:g}): its runs in steps of "
        f"dt/2^{depth - 1} and dt/2^{depth} = {req.dt / 2**depth:.4g} still differ by "
        f"{diff:.3g} at the saved displacements, {diff / (atol + rtol * peak):.3g} times the "
        f"tolerance (`subdivisions`={depth}); raise `subdivisions` or loosen `rtol`",
        time=float(fine.t[-1]) if fine.t.size else req.t0,
        reason="tolerance",
        partial=fine,
    )


def _massless_start(
    setup: DirectSetup,
    x0: NDArray[np.float64],
    v0: NDArray[np.float64],
    t0: float,
    dt: float,
    loads: list[Any] | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The initial velocity and acceleration of a model with massless dofs, which the
    equation of motion does not leave free (``M`` is singular).

    * Velocities at the massless dofs the damping reaches: they obey a first-order equation,
      so their velocity is that equation's at the initial state (the ``v0`` given there is
      replaced): with ``C_ss Z = K_ss Z diag(tau)``, ``Z^T K_ss Z = I`` and ``v_s = Z u``,
      ``u_i = z_i^T (f_s - K_s x0 - C_sm v_m) / tau_i`` where ``tau_i > 0`` and the static
      relation differentiated once, ``u_i = z_i^T (f_s' - K_sm v_m)``, where ``tau_i = 0``
      (``f'`` a central difference over ``1e-3 dt``). A start inconsistent there would cost
      the trapezoidal rule an error of the order of ``dt`` on those dofs.
    * Accelerations: ``M_mm a_m = (f - C v0 - K x0)_m`` on the dofs with mass and the static
      relation differentiated twice, ``a_s = -K_ss^-1 K_sm a_m``, on the massless ones.

    Elements' forces at the initial state are taken as zero, so a start from a displaced
    state with elements is refused."""
    from duhamel._engine.massless import matrix_relaxation

    system = setup.system
    c = cast("Condensation", system._condensation)  # (a model with massless dofs)
    if (system.elements or system.couplings) and (np.any(x0) or np.any(v0)):
        raise ValueError(
            "`x0`/`v0`: a model with massless dofs and elements starts a direct integrator "
            "from rest only (its initial acceleration is taken from the linear part)"
        )
    run_loads = system.loads if loads is None else loads

    def force(t: float) -> NDArray[np.float64]:
        f = np.zeros(system.n_dof)
        for load in run_loads:
            f += np.asarray(load.evaluate(system, np.array([t]))).reshape(-1)
        return f

    f = force(t0)
    C = setup.mats["c"]
    at_massless = None if C is None else (C[:, c.s] if issparse(C) else np.asarray(C)[:, c.s])
    if at_massless is not None and abs(at_massless).max() > 0.0:
        s, m = c.s, c.m
        h = 1e-3 * dt
        df = (force(t0 + h) - force(t0 - h)) / (2 * h)
        tau, Z = matrix_relaxation(_Physical(system, C))
        Kx = np.asarray(system.K @ x0)
        Cv = np.asarray(C[s][:, m] @ v0[m]) if issparse(C) else np.asarray(C)[np.ix_(s, m)] @ v0[m]
        K_sm_v = np.asarray(c._K_sm @ v0[m])
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.where(tau > 0.0, Z.T @ (f[s] - Kx[s] - Cv) / tau, Z.T @ (df[s] - K_sm_v))
        v0 = v0.copy()
        v0[s] = Z @ u
    r = f - np.asarray(system.K @ x0)
    if C is not None:
        r -= np.asarray(C @ v0)
    M = system.M
    m = c.m
    M_mm = M[m][:, m].toarray() if hasattr(M, "toarray") else np.asarray(M)[np.ix_(m, m)]
    a = np.zeros(system.n_dof)
    a[m] = np.linalg.solve(M_mm, r[m])
    return v0, c.expand(a[m])


class _Physical:
    """A system's condensation and K with the direct integrators' physical damping matrix
    (what :func:`duhamel._engine.massless.matrix_relaxation` reads)."""

    damping = "matrix"

    def __init__(self, system: System, C: Any) -> None:
        self._condensation = system._condensation
        self.K = system.K
        self.C = C


def prepare_direct(system: System, integrator: DirectIntegrator) -> DirectSetup:
    """Prepares `system` for `integrator` (refuses path-dependent elements where the
    integrator does not commit their state, and explicit or Hermite steps of a model with
    massless dofs, whose mass matrix they invert)."""
    if system._condensation is not None and isinstance(
        integrator, CentralDifference | CubicHermite
    ):
        raise ValueError(
            f"`integrator`: {type(integrator).__name__} inverts the mass matrix, and `M` has "
            f"{system.massless_dofs.size} massless dofs (e.g. dof "
            f"{int(system.massless_dofs[0])}); use Newmark(), HHT() or GeneralizedAlpha(), or "
            "duhamel.Semianalytic(), which condense them exactly"
        )
    hysteretic = [e for e in core_elements(system.elements) if e._path_dependent]
    if hysteretic and not getattr(integrator, "_commits_state", False):
        raise ValueError(
            f"`integrator`: {type(integrator).__name__} does not yet commit the internal "
            f"variables of path-dependent elements ({type(hysteretic[0]).__name__}); use "
            "duhamel.Semianalytic()"
        )
    mats = physical_matrices(system)
    elements = core_elements(system.elements)
    model = dispatch.direct_model(mats, elements, mass(system, integrator), integrator)
    specs, fns = modal_loads(system.loads, system, None)
    return DirectSetup(system, integrator, mats, elements, model, specs, fns)


def step_matrix(system: System, integrator: DirectIntegrator, dt: float) -> NDArray[np.float64]:
    """The matrix of one step of a direct integrator on a linear system without loads,
    found by stepping unit states through the engine.

    The generalized-alpha methods carry the acceleration from step to step, so their state is
    ``(x, v, a)`` and the matrix is ``3 n x 3 n`` (the amplification matrix of Chung and
    Hulbert); the cubic Hermite element's state is ``(x, v)`` (``2 n x 2 n``).
    """
    if system.elements or system.couplings or system.mass_law is not None:
        raise ValueError("`system` must be linear (no elements, constant mass)")
    n = system.n_dof
    alpha = not isinstance(integrator, CubicHermite)
    size = (3 if alpha else 2) * n
    out = np.empty((size, size))
    setup = prepare_direct(system, integrator)
    for j in range(size):
        e = np.zeros(size)
        e[j] = 1.0
        req = Request(0.0, dt, 1, 1, None, e[:n], e[n : 2 * n], [], None, _time.perf_counter())
        sol = setup.run(req, a0=e[2 * n :] if alpha else None)
        parts = (sol.x[-1], sol.v[-1], sol.a[-1]) if alpha else (sol.x[-1], sol.v[-1])
        out[:, j] = np.concatenate(parts)
    return out
