"""``duhamel.solve``: run an integrator on a model."""

from __future__ import annotations

import math
import time as _time
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._coupled import (
    CONDITION_LIMIT,
    FirstOrderModes,
    back_transform,
    first_order_modes,
    keep_finite_rows,
    output_maps,
)
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


def _has_couplings(system: System, basis: ModalBasis) -> bool:
    """Whether the modes are coupled: LinearCoupling elements or non-classical damping."""
    return basis.c_coupling is not None or any(
        isinstance(e, LinearCoupling) for e in system.elements
    )


def _constant_couplings_only(system: System, basis: ModalBasis) -> bool:
    """Whether the modal couplings are constant (no LinearCoupling scaled by a time-varying
    speed law) and the mass too."""
    if system.mass_law is not None:
        return False
    return all(
        e.constant_factor() is not None for e in system.elements if isinstance(e, LinearCoupling)
    )


def _first_order(
    system: System, basis: ModalBasis, integrator: Semianalytic
) -> tuple[FirstOrderModes, dict[str, Any]] | None:
    """The first-order modes for the exact coupled route, or None for the pseudo-force
    route; raises when ``coupling="exact"`` cannot be honoured."""
    if integrator.coupling == "pseudo-force" or not _has_couplings(system, basis):
        return None
    nonlinear = any(not isinstance(e, LinearCoupling) for e in system.elements)
    why = None
    if not _constant_couplings_only(system, basis):
        why = (
            "needs constant couplings and mass: no mass law, no coupling scaled by a "
            "time-varying speed law"
        )
    elif nonlinear and (integrator.scheme, integrator.quadrature) != ("b", "trapezoid"):
        why = (
            "with nonlinear elements needs scheme='b' and quadrature='trapezoid' (the element "
            "forces on the exact coupled background)"
        )
    if why is not None:
        if integrator.coupling == "exact":
            raise ValueError(
                f"`coupling`='exact' {why} (those cases enter as pseudo-forces; use "
                "coupling='auto' or 'pseudo-force')"
            )
        return None
    couplings = _couplings(system, basis)
    modes = first_order_modes(
        basis.omega2, basis.c, couplings["coupling_k"], couplings["coupling_c"]
    )
    if modes.condition > CONDITION_LIMIT:
        if integrator.coupling == "exact":
            raise ValueError(
                f"`coupling`='exact': the coupled system is (nearly) defective, its first-order "
                f"eigenvector matrix has condition number {modes.condition:.3g} > "
                f"{CONDITION_LIMIT:g}, so its modes would lose digits (about condition^2 * "
                f"1e-17 of the response); use coupling='pseudo-force'"
            )
        return None
    return modes, couplings


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


def _back_transform(
    raw: dict[str, Any], basis: ModalBasis, phi_out: NDArray
) -> tuple[NDArray, NDArray, NDArray]:
    """``x``, ``v`` and the state part of ``a`` from the modal history, by matrix products."""
    n_out = phi_out.shape[0]
    # One pass over each history array: [x | k-part of a] from q, [v | c-part] from v.
    xq = raw["q"] @ np.concatenate([phi_out, -phi_out * basis.omega2]).T
    vv = raw["v"] @ np.concatenate([phi_out, -phi_out * basis.c]).T
    return xq[:, :n_out], vv[:, :n_out], xq[:, n_out:] + vv[:, n_out:]


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
    coupled = None if _is_linear(system, basis) else _first_order(system, basis, integrator)
    if _is_linear(system, basis):
        raw = _core.solve_linear(*common, threads, forcing, phi_t)
    elif coupled is not None:
        fo = coupled[0]
        eta0 = fo.initial(q0, qd0)
        parts = [fo.lam.real, fo.lam.imag, fo.gain.real, fo.gain.imag, eta0.real, eta0.imag]
        out_map, out_loads, *acc_maps = output_maps(basis, phi[out_dofs, :], specs, *coupled)
        element_specs = [e._spec() for e in system.elements if not isinstance(e, LinearCoupling)]
        raw = _core.solve_coupled(
            *common,
            *(np.ascontiguousarray(x, dtype=np.float64).ravel() for x in parts),
            out_map=out_map.ravel(),
            out_loads=out_loads.ravel(),
            n_out=out_map.shape[1],
            threads=threads,
            forcing=forcing,
            phi_t=phi_t,
            phi=np.ascontiguousarray(phi) if element_specs else None,
            elements=element_specs or None,
            back=fo.back.ravel() if element_specs else None,
            tol=float(integrator.tol),
            max_iter=int(integrator.max_iter),
        )
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
    patterns = (
        np.stack([spec[0] for spec in specs], axis=1) if specs else np.zeros((phi.shape[1], 0))
    )
    # A diverged run's partial history ends near overflow: its accelerations may overflow.
    quiet = raw["error"] is not None
    if quiet and coupled is not None:
        keep_finite_rows(raw, len(out_dofs))
    with np.errstate(over="ignore" if quiet else "warn", invalid="ignore" if quiet else "warn"):
        if coupled is None:
            x, vel, acc = _back_transform(raw, basis, phi_out)
            modal = ModalHistory(
                q=raw["q"],
                v=raw["v"],
                omega=basis.omega,
                c=basis.c,
                load_values=raw["load_values"],
                patterns=patterns,
                forcing=raw["forcing"],
                pseudo=raw.get("pseudo"),
            )
            acc += raw["load_values"] @ (phi_out @ patterns).T
        else:
            x, vel, acc, modal = back_transform(
                raw, basis, phi_out, patterns, *coupled, tuple(acc_maps)
            )
        if coupled is None:
            for extra in ("forcing", "pseudo"):
                if raw.get(extra) is not None:
                    acc += raw[extra] @ phi_out.T
    solution = Solution(
        t=raw["t"],
        x=x,
        v=vel,
        a=acc,
        dofs=np.asarray(out_dofs, dtype=np.int64),
        modal=modal,
        stats=SolveStats(
            steps=n_steps if raw["error"] is None else _completed(raw["error"], dt),
            wall_time=wall,
            total_time=_time.perf_counter() - started,
            modes=phi.shape[1],
            newton_iterations=int(raw.get("stats", {}).get("newton_iterations", 0)),
            closed_form_steps=int(raw.get("stats", {}).get("closed_form_steps", 0)),
            coupling=(
                None
                if not _has_couplings(system, basis)
                else ("exact" if coupled is not None else "pseudo-force")
            ),
            eigenvector_condition=None if coupled is None else coupled[0].condition,
        ),
        meta={"dt": dt, "integrator": integrator},
    )
    err = raw["error"]
    if err is not None:
        raise SolverError(
            err["message"], time=float(err["time"]), reason=err["kind"], partial=solution
        )
    return solution
