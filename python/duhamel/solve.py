"""``duhamel.solve``: run an integrator on a model."""

from __future__ import annotations

import math
import time as _time
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._direct import solve_direct
from duhamel._validate import as_float_array, dof_list, positive_float, positive_int
from duhamel.elements import LinearCoupling
from duhamel.errors import SolverError
from duhamel.integrators import DirectIntegrator, Semianalytic
from duhamel.loads import Callable
from duhamel.solution import ModalHistory, Solution, SolveStats
from duhamel.system import ModalBasis, System

__all__ = ["solve"]


def _steps(t_end: Any, dt: float) -> int:
    t_end = positive_float(t_end, "t_end")
    if t_end < dt * (1.0 - 1e-9):
        raise ValueError(f"`t_end` ({t_end:g}) must be at least one step `dt` ({dt:g})")
    return max(1, math.floor(t_end / dt * (1.0 + 1e-12) + 1e-9))


def _initial(value: ArrayLike | None, name: str, system: System, basis: ModalBasis) -> NDArray:
    """Modal coordinates of an initial state: ``Phi^T M x``."""
    if value is None:
        return np.zeros(basis.phi.shape[1])
    x = as_float_array(value, name, ndim=1, shape=(system.n_dof,))
    return np.ascontiguousarray(basis.phi.T @ np.asarray(system.M @ x, dtype=np.float64))


class _ModalCallable:
    """Sums the Python load functions (physical load vectors); called by the core with the GIL."""

    def __init__(self, fns: list[Any], n_dof: int) -> None:
        self.fns = fns
        self.n_dof = n_dof

    def __call__(self, t: float) -> NDArray:
        total = np.zeros(self.n_dof)
        for fn in self.fns:
            f = np.asarray(fn(t))
            if f.dtype.kind not in "iuf":
                raise TypeError(f"the `Callable` load returned dtype {f.dtype} at t = {t}")
            if f.shape != (self.n_dof,):
                raise ValueError(
                    f"the `Callable` load returned shape {f.shape} at t = {t}, "
                    f"expected ({self.n_dof},)"
                )
            if not np.all(np.isfinite(f)):
                raise ValueError(f"the `Callable` load returned NaN or inf at t = {t}")
            total += f
        return total


def _completed(error: dict, dt: float) -> int:
    """Steps completed before a failure at ``error["time"]`` (the end of the failed step)."""
    return max(0, round(float(error["time"]) / dt) - 1)


def _is_linear(system: System, basis: ModalBasis) -> bool:
    """Whether the exact linear loop applies: no elements, classical damping, constant mass."""
    return not system.elements and basis.c_coupling is None and system.mass_law is None


def _couplings(system: System, basis: ModalBasis) -> dict[str, Any]:
    """Modal coupling matrices: LinearCoupling elements plus non-classical damping (constant
    ones summed, a constant scale folded in), and the couplings scaled by a time-varying
    speed law as ``(K, C, law spec)``."""
    total: dict[str, NDArray | None] = {"coupling_k": None, "coupling_c": basis.c_coupling}
    scaled = []
    for element in system.elements:
        if isinstance(element, LinearCoupling):
            mats = element.modal(basis.phi)
            factor = element.constant_factor()
            if factor is None:
                k, c = (None if m is None else np.ascontiguousarray(m) for m in mats)
                scaled.append((k, c, element.scale._spec()))
                continue
            for key, m in zip(("coupling_k", "coupling_c"), mats, strict=True):
                if m is not None:
                    m = m if factor == 1.0 else factor * m
                    prev = total[key]
                    total[key] = m if prev is None else prev + m
    out: dict[str, Any] = {
        k: None if v is None else np.ascontiguousarray(v) for k, v in total.items()
    }
    out["scaled"] = scaled
    return out


def _mass(system: System, integrator: Semianalytic) -> tuple | None:
    attached = system.mass_law
    if attached is None:
        return None
    kind, params = attached.law._spec()
    return (kind, params, attached.form, attached.scale_stiffness, integrator.mass_treatment)


def solve(
    system: System,
    integrator: Semianalytic | DirectIntegrator,
    *,
    t_end: float,
    dt: float,
    x0: ArrayLike | None = None,
    v0: ArrayLike | None = None,
    save_every: int = 1,
    dofs: ArrayLike | None = None,
    threads: int | None = None,
) -> Solution:
    """Transient response of `system` from ``t = 0`` to `t_end` with a fixed step `dt`.

    Parameters
    ----------
    system : System
        The model, with its loads.
    integrator : Semianalytic, Newmark, HHT, GeneralizedAlpha, CentralDifference or CubicHermite
        The time integrator and its options. :class:`Semianalytic` steps the modal
        oscillators exactly (modal reduction possible); the others step the physical
        equations directly (docs/direct.md).
    t_end : float
        End time; the run takes ``floor(t_end / dt)`` steps of length `dt` (``t_end`` itself
        when it is a multiple of `dt`).
    dt : float
        Step length, ``> 0``. For linear systems the result does not depend on it beyond the
        representation of the loads within a step.
    x0, v0 : array_like, shape (n_dof,), optional
        Initial displacements and velocities (zero by default). With modal reduction they
        are projected on the retained modes. Direct integrators start from them as given,
        with the initial acceleration from the equation of motion.
    save_every : int
        Keep every `save_every`-th step (the last step is always kept).
    dofs : sequence of int, optional
        Degrees of freedom to recover (default: all). The modal history is always kept
        (semi-analytic); direct integrators keep only these.
    threads : int, optional
        Worker threads of the semi-analytic linear time loop (default: all cores); the
        direct integrators run on one thread.

    Returns
    -------
    Solution
        ``t``, ``x``, ``v``, ``a``, ``modal`` (None for direct integrators) and ``stats``.

    Raises
    ------
    ValueError, TypeError
        Bad input; the message names the parameter.
    SolverError
        The response became non-finite (a diverging system), a step equation did not
        converge, or a load or element function failed; the exception's ``partial``
        attribute holds the solution up to the last good instant.

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
    n_steps = _steps(t_end, dt)
    save_every = positive_int(save_every, "save_every")
    if threads is not None:
        threads = positive_int(threads, "threads")
    out_dofs = np.arange(system.n_dof) if dofs is None else dof_list(dofs, "dofs", system.n_dof)
    if isinstance(integrator, DirectIntegrator):
        n = system.n_dof
        fns = [load.fn for load in system.loads if isinstance(load, Callable)]
        return solve_direct(
            system,
            integrator,
            dt=dt,
            n_steps=n_steps,
            x0=np.zeros(n) if x0 is None else as_float_array(x0, "x0", ndim=1, shape=(n,)),
            v0=np.zeros(n) if v0 is None else as_float_array(v0, "v0", ndim=1, shape=(n,)),
            save_every=save_every,
            out_dofs=out_dofs,
            forcing=_ModalCallable(fns, n) if fns else None,
            started=started,
        )

    basis = system.modal(integrator.modes)
    phi = basis.phi
    q0 = _initial(x0, "x0", system, basis)
    qd0 = _initial(v0, "v0", system, basis)

    specs = []
    fns = []
    for load in system.loads:
        if isinstance(load, Callable):
            fns.append(load.fn)
            continue
        for physical, kind, params in load._specs(system):
            specs.append((np.ascontiguousarray(phi.T @ physical), kind, params))
    forcing = _ModalCallable(fns, system.n_dof) if fns else None

    loop_start = _time.perf_counter()
    common = (
        np.ascontiguousarray(basis.omega2, dtype=np.float64),
        np.ascontiguousarray(basis.c, dtype=np.float64),
        q0,
        qd0,
        specs,
        dt,
        n_steps,
        save_every,
    )
    phi_t = np.ascontiguousarray(phi.T) if forcing is not None else None
    if _is_linear(system, basis):
        raw = _core.solve_linear(*common, threads, forcing, phi_t)
    else:
        raw = _core.solve_nonlinear(
            *common,
            np.ascontiguousarray(phi),
            [e._spec() for e in system.elements if not isinstance(e, LinearCoupling)],
            integrator._options(),
            **_couplings(system, basis),
            mass=_mass(system, integrator),
            forcing=forcing,
            phi_t=phi_t,
        )
    wall = _time.perf_counter() - loop_start

    # Back-transform once, by matrix products, for the requested dofs only. Accelerations
    # come from the modal equations: a = Phi_d (P s(t) + forcing - c v - omega^2 q).
    phi_out = phi[out_dofs, :]
    q, v = raw["q"], raw["v"]
    patterns = (
        np.stack([spec[0] for spec in specs], axis=1) if specs else np.zeros((phi.shape[1], 0))
    )
    # A diverged run's partial history ends near overflow: its accelerations may overflow.
    quiet = raw["error"] is not None
    n_out = phi_out.shape[0]
    with np.errstate(over="ignore" if quiet else "warn", invalid="ignore" if quiet else "warn"):
        # One pass over each history array: [x | k-part of a] from q, [v | c-part] from v.
        xq = q @ np.concatenate([phi_out, -phi_out * basis.omega2]).T
        vv = v @ np.concatenate([phi_out, -phi_out * basis.c]).T
        acc = xq[:, n_out:] + vv[:, n_out:] + raw["load_values"] @ (phi_out @ patterns).T
        for extra in ("forcing", "pseudo"):
            if raw.get(extra) is not None:
                acc += raw[extra] @ phi_out.T
    solution = Solution(
        t=raw["t"],
        x=xq[:, :n_out],
        v=vv[:, :n_out],
        a=acc,
        dofs=np.asarray(out_dofs, dtype=np.int64),
        modal=ModalHistory(
            q=q,
            v=v,
            omega=basis.omega,
            c=basis.c,
            load_values=raw["load_values"],
            patterns=patterns,
            forcing=raw["forcing"],
            pseudo=raw.get("pseudo"),
        ),
        stats=SolveStats(
            steps=n_steps if raw["error"] is None else _completed(raw["error"], dt),
            wall_time=wall,
            total_time=_time.perf_counter() - started,
            modes=phi.shape[1],
            newton_iterations=int(raw.get("stats", {}).get("newton_iterations", 0)),
            closed_form_steps=int(raw.get("stats", {}).get("closed_form_steps", 0)),
        ),
        meta={"dt": dt, "integrator": integrator},
    )
    err = raw["error"]
    if err is not None:
        raise SolverError(
            err["message"], time=float(err["time"]), reason=err["kind"], partial=solution
        )
    return solution
