"""``duhamel.prepare`` and ``duhamel.solve``: a model prepared once for many runs, and the
one-call form of a single run (``solve(...)`` is ``prepare(...).run(...)``)."""

from __future__ import annotations

import functools
import os
import time as _time
from collections.abc import Sequence
from typing import Any

from numpy.typing import ArrayLike

from duhamel._engine import caches, modal
from duhamel._engine.direct_run import DirectSetup, prepare_direct
from duhamel._engine.pipeline import execute
from duhamel._engine.request import Request, request
from duhamel._engine.run import Progress
from duhamel._engine.run_inputs import checked_models, massless_store_check
from duhamel._engine.validate import positive_float, positive_int
from duhamel.events import Event
from duhamel.integrators import DirectIntegrator, Semianalytic
from duhamel.loads import Load
from duhamel.results.solution import Solution
from duhamel.runs import RunSpec, from_keywords
from duhamel.system import System

__all__ = ["Prepared", "prepare", "solve"]


def _fingerprint(system: System) -> tuple:
    """What identifies the state of `system` a preparation was made from."""
    return (
        tuple(map(id, system.loads)),
        tuple(map(id, system.elements)),
        tuple(map(id, system.couplings)),
        id(system.mass_law),
        id(system._modes),
        system._modes.supplied,
        system.dof_labels,
    )


def _with_loads(system: System, loads: list[Load]) -> System:
    """`system` as it is now, with `loads` instead of its own: a copy whose lists of loads
    and elements are its own; the matrices, the modes and the caches of what is derived from
    them (bases, static corrections) are shared with `system`."""
    other = object.__new__(System)
    other.__dict__.update(system.__dict__)
    other.loads = list(loads)
    other.elements = list(system.elements)
    other.couplings = list(system.couplings)
    caches.share(system, other, "background", None, ("corrected", {}), ("truncation", {}))
    return other


class Prepared:
    """A model prepared for runs with one integrator and one step `dt`.

    Made by :func:`duhamel.prepare`. It holds what does not change between runs of the
    model: the modal (or Ritz) basis with its static correction, the route and the
    first-order modes of a coupled background, the core's elements and the loads projected
    on the modes (direct integrators: the physical matrices). :meth:`run` adds a run's
    grid, initial state and, optionally, its own loads.

    What is shared and what is not: the system's matrices, damping, elements (with their
    parameters) and mass law are taken when the model is prepared — changing the system
    afterwards (``add``, ``add_load``, ``set_mass_law``) does not change a `Prepared`; prepare
    it again. Element parameters that vary per run (a friction coefficient, an upper or
    lower bound of a device) need a new `Prepared` (each starts its hysteretic elements from
    their initial state anyway: runs are independent). Loads may change per run
    (``run(loads=[...])``) at the cost of their projection on the modes.

    Attributes
    ----------
    system : System
        The model as it was prepared.
    integrator : Semianalytic or a direct integrator
        The integrator.
    dt : float
        The step.
    route : str
        "uncoupled", "first-order" or "pseudo-force" (semi-analytic), or "direct".
    n_modes : int
        Modal coordinates integrated (0 for a direct integrator).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> frame = duhamel.System(np.eye(2), np.array([[2.0, -1.0], [-1.0, 1.0]]), zeta=0.05)
    >>> run = duhamel.prepare(frame, duhamel.Semianalytic(), dt=0.05)
    >>> records = [duhamel.loads.BaseAcceleration(np.ones(2), t=[0.0, 1.0, 2.0],
    ...                                           values=[0.0, s, 0.0]) for s in (1.0, 2.0)]
    >>> peaks = [np.abs(run.run(t_end=5.0, loads=[r]).x).max() for r in records]
    >>> float(round(peaks[1] / peaks[0], 12))   # linear: twice the record, twice the response
    2.0
    """

    def __init__(self, system: System, integrator: Any, dt: float, threads: int | None) -> None:
        self._source = system
        self._fingerprint = _fingerprint(system)
        # A snapshot: what is added to the system later does not reach this preparation.
        self.system = _with_loads(system, system.loads)
        self.integrator = integrator
        self.dt = dt
        self.threads = threads
        self._modal: modal.ModalSetup | None = None
        self._direct: DirectSetup | None = None
        if isinstance(integrator, DirectIntegrator):
            self._direct = prepare_direct(self.system, integrator)
        else:
            self._modal = modal.setup(self.system, integrator, threads)
            # the system's own cache, as solve() always kept it
            caches.share(self.system, system, "background")

    def matches(self, system: System, integrator: Any, dt: float) -> bool:
        """Whether this is the preparation of `system` as it is now, with `integrator` and
        `dt` (no load, element or mass law added or removed since, no basis supplied)."""
        return (
            system is self._source
            and _fingerprint(system) == self._fingerprint
            and integrator == self.integrator
            and dt == self.dt
        )

    @property
    def route(self) -> str:
        return "direct" if self._modal is None else self._modal.route.route

    @property
    def n_modes(self) -> int:
        return 0 if self._modal is None else self._modal.n_modes

    def __repr__(self) -> str:
        return (
            f"Prepared({type(self.integrator).__name__}, dt={self.dt:g}, route={self.route!r}, "
            f"n_dof={self.system.n_dof}, modes={self.n_modes})"
        )

    def run(
        self,
        *,
        t_end: float,
        t0: float = 0.0,
        x0: ArrayLike | None = None,
        v0: ArrayLike | None = None,
        loads: list[Load] | None = None,
        save_every: int = 1,
        dofs: ArrayLike | None = None,
        store: str | os.PathLike[str] | Any = None,
        checkpoint_every: int | None = None,
        progress: bool | Progress | None = False,
        events: Sequence[Event] | None = None,
        t_eval: ArrayLike | None = None,
        dense: bool = False,
        energy: bool = False,
    ) -> Solution:
        """Runs the prepared model from `t0` to `t_end`.

        Parameters
        ----------
        t_end : float
            End time; the run takes ``floor((t_end - t0) / dt)`` steps.
        t0 : float
            Start time (default 0); loads keep their absolute time axis.
        x0, v0 : array_like, shape (n_dof,), optional
            Initial displacements and velocities (zero by default).
        loads : list of duhamel.loads loads, optional
            The loads of this run instead of the system's (a new record, a scaled record);
            None uses the system's loads.
        save_every : int
            Keep every `save_every`-th step (the last step is always kept).
        dofs : sequence of int, optional
            Degrees of freedom to recover (default: all).
        store : str, os.PathLike or duhamel.store.Store, optional
            Stream the run to a new zarr store (see :func:`duhamel.solve`).
        checkpoint_every : int, optional
            With `store` (refused without it): a checkpoint every this many segments (default 1).
        progress : bool or callable, optional
            A progress bar (``True``) or a function ``(step, n_steps, t)``.
        events, t_eval, dense, energy
            Events, instants, dense output and the energy balance (see :func:`duhamel.solve`).

        Returns
        -------
        Solution
            As :func:`duhamel.solve` returns it (the same numbers, bit for bit).

        Raises
        ------
        ValueError, TypeError, SolverError, KeyboardInterrupt
            As :func:`duhamel.solve`.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> s = duhamel.System(np.eye(1), np.array([[4.0]]))
        >>> p = duhamel.prepare(s, duhamel.Semianalytic(), dt=0.1)
        >>> sol = p.run(t_end=1.0, x0=[1.0])     # x = cos(2 t), exactly at any step
        >>> bool(abs(sol.x[-1, 0] - np.cos(2.0)) < 1e-14)
        True
        """
        started = _time.perf_counter()
        spec = from_keywords(
            t_end=t_end, t0=t0, x0=x0, v0=v0, loads=loads, save_every=save_every, dofs=dofs,
            store=store, checkpoint_every=checkpoint_every, progress=progress, events=events,
            t_eval=t_eval, dense=dense, energy=energy,
        )  # fmt: skip
        return self.execute(spec, _started=started)

    def execute(self, spec: RunSpec, *, _started: float | None = None) -> Solution:
        """Runs the prepared model as `spec` describes the run (what :meth:`run` takes as
        keywords, as values: :class:`duhamel.RunSpec` with its :class:`duhamel.SaveAt`).

        Parameters
        ----------
        spec : RunSpec
            The run: its span and start, its loads, what it keeps and where it goes.

        Returns
        -------
        Solution
            As :meth:`run` returns it for the same run given as keywords (bit for bit).

        Raises
        ------
        ValueError, TypeError, SolverError, KeyboardInterrupt
            As :func:`duhamel.solve`.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> s = duhamel.System(np.eye(2), np.array([[2.0, -1.0], [-1.0, 1.0]]), zeta=0.05)
        >>> p = duhamel.prepare(s, duhamel.Semianalytic(), dt=0.01)
        >>> runs = [duhamel.RunSpec(t_end=2.0, x0=[0.0, a], saveat=duhamel.SaveAt(every=50))
        ...         for a in (1.0, 2.0)]
        >>> peaks = [np.abs(p.execute(r).x).max() for r in runs]
        >>> float(round(peaks[1] / peaks[0], 12))
        2.0
        """
        started = _time.perf_counter() if _started is None else _started
        if not isinstance(spec, RunSpec):
            raise TypeError(f"`spec` must be a duhamel.RunSpec, got {type(spec).__name__}")
        req = request(self.system, self.dt, self.route, spec, started)
        engine = self._direct if self._modal is None else self._modal
        assert engine is not None
        store = spec.store
        if store is None or req.located:
            return execute(engine, req)
        return execute(engine, req, functools.partial(self._stored, store))

    def _stored(self, store: Any, req: Request) -> Solution:
        """The run of `req` streamed into `store` (``duhamel.store``)."""
        from duhamel.store._run import run_stored

        system = self.system
        target = system if req.loads is None else _with_loads(system, req.loads)
        massless_store_check(target)
        return run_stored(target, self.integrator, store, req, self.threads)


def prepare(
    system: System,
    integrator: Semianalytic | DirectIntegrator,
    *,
    dt: float,
    threads: int | None = None,
) -> Prepared:
    """Prepares `system` for runs with `integrator` and step `dt` (see :class:`Prepared`).

    A study of many runs of one model — records of a suite, scale factors of an IDA, initial
    conditions — prepares it once and calls :meth:`Prepared.run` per case: the modal
    analysis, the route and the core's model are not made again.

    Parameters
    ----------
    system : System
        The model, with its elements and (default) loads.
    integrator : Semianalytic, Newmark, HHT, GeneralizedAlpha, CentralDifference or CubicHermite
        The time integrator and its options.
    dt : float
        Step length, ``> 0``.
    threads : int, optional
        Worker threads of the semi-analytic linear time loop (default: all cores).

    Returns
    -------
    Prepared

    Raises
    ------
    ValueError, TypeError
        Bad input; the message names the parameter.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> s = duhamel.System(np.eye(2), np.array([[2.0, -1.0], [-1.0, 1.0]]), zeta=0.02)
    >>> _ = s.add_load(duhamel.loads.Step(dof=1, amplitude=1.0))
    >>> p = duhamel.prepare(s, duhamel.Semianalytic(), dt=0.1)
    >>> a = p.run(t_end=10.0)
    >>> b = duhamel.solve(s, duhamel.Semianalytic(), t_end=10.0, dt=0.1)
    >>> bool(np.array_equal(a.x, b.x))
    True
    """
    checked_models(system, integrator)
    dt = positive_float(dt, "dt")
    if threads is not None:
        threads = positive_int(threads, "threads")
    return Prepared(system, integrator, dt, threads)


def solve(
    system: System,
    integrator: Semianalytic | DirectIntegrator,
    *,
    t_end: float,
    dt: float,
    x0: ArrayLike | None = None,
    v0: ArrayLike | None = None,
    t0: float = 0.0,
    loads: list[Load] | None = None,
    save_every: int = 1,
    dofs: ArrayLike | None = None,
    threads: int | None = None,
    progress: bool | Progress | None = None,
    store: str | os.PathLike[str] | Any = None,
    checkpoint_every: int | None = None,
    events: Sequence[Event] | None = None,
    t_eval: ArrayLike | None = None,
    dense: bool = False,
    energy: bool = False,
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
    loads : list of duhamel.loads loads, optional
        The loads of this run instead of the system's (as :meth:`Prepared.run` takes them);
        None uses the system's loads.
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
        With `store` (refused without it): a checkpoint every this many segments (default 1).
    events : list of duhamel.Event, optional
        Zero crossings located inside their step (``sol.events``); a terminal one ends the
        run at its instant (docs/events.md).
    t_eval : array_like, optional
        Return the response at these instants (increasing, within the run) instead of the
        steps: exact on the linear routes, of the scheme's order otherwise.
    dense : bool
        Keep what ``sol.at(t)`` needs to evaluate the response between the steps.
        `events`, `t_eval` and `dense` need ``save_every=1`` and no `store`.
    energy : bool
        Accumulate the energy balance's work integrals during the run (``sol.energy``, with
        any `save_every`, `dofs` or `store`; pseudo-force route, docs/structural.md). Without
        it ``sol.energy`` is computed after the run and needs every step and dof saved.

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
    prepared = prepare(system, integrator, dt=dt, threads=threads)
    spec = from_keywords(
        t_end=t_end, t0=t0, x0=x0, v0=v0, loads=loads, save_every=save_every, dofs=dofs,
        store=store, checkpoint_every=checkpoint_every, progress=progress, events=events,
        t_eval=t_eval, dense=dense, energy=energy,
    )  # fmt: skip
    return prepared.execute(spec, _started=started)
