"""The Python side of the direct integrators: physical matrices, loads and the run."""

from __future__ import annotations

import time as _time
from typing import Any

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from duhamel import _core
from duhamel.elements import LinearCoupling
from duhamel.errors import SolverError
from duhamel.integrators import CentralDifference, DirectIntegrator
from duhamel.loads import Callable
from duhamel.solution import Solution, SolveStats
from duhamel.system import System

#: Below this order the stability check of the central difference method uses a dense
#: eigensolver, above it (for sparse models) ARPACK.
_DENSE_EIG_MAX_N = 400


def damping_matrix(system: System) -> Any:
    """The physical damping matrix of `system`, or None when undamped.

    ``C`` as given; Rayleigh ``alpha M + beta K`` (sparse stays sparse); modal damping ratios
    ``M Phi diag(c) Phi^T M`` with the mass-normalised modes of the full modal basis (dense:
    it couples every pair of degrees of freedom the modes touch).
    """
    if system.damping == "none":
        return None
    if system.damping == "matrix":
        return system.C
    if system.damping == "rayleigh":
        alpha, beta = system.rayleigh  # type: ignore[misc]
        return alpha * system.M + beta * system.K
    z = system.zeta
    if isinstance(z, np.ndarray) and z.size != system.n_dof:
        raise ValueError(
            f"`zeta` has {z.size} entries, but direct integrators need the damping of every "
            f"mode: pass one damping ratio, or n_dof = {system.n_dof} of them"
        )
    basis = system.modal(None)
    mphi = np.asarray(system.M @ basis.phi)
    return (mphi * basis.c) @ mphi.T


def _matrix(m: Any, sparse: bool) -> tuple:
    """The core's matrix spec: ``("dense", array)`` or ``("csr", n, indptr, indices, data)``."""
    if sparse:
        c = sp.csr_array(m, dtype=np.float64)
        c.sum_duplicates()
        return (
            "csr",
            int(c.shape[0]),
            np.ascontiguousarray(c.indptr, dtype=np.int64),
            np.ascontiguousarray(c.indices, dtype=np.int64),
            np.ascontiguousarray(c.data, dtype=np.float64),
        )
    dense = m.toarray() if sp.issparse(m) else np.asarray(m)
    return ("dense", np.ascontiguousarray(dense, dtype=np.float64))


def _add(a: Any, b: Any) -> Any:
    if a is None:
        return b
    if b is None:
        return a
    if sp.issparse(a) or sp.issparse(b):
        return sp.csr_array(a) + sp.csr_array(b)
    return np.asarray(a) + np.asarray(b)


def _times(m: Any, factor: float) -> Any:
    return m if m is None or factor == 1.0 else factor * m


def physical_matrices(system: System) -> dict[str, Any]:
    """M, K, C, the stiffness that does not scale with a mass law, and the couplings scaled
    by a time-varying speed law (``(K, C, law spec)``), as core specs."""
    # Modal damping ratios give a full C: everything is then dense.
    sparse = system.is_sparse and system.damping != "zeta"
    c = damping_matrix(system)
    kc = None
    scaled = []
    for element in system.elements:
        if isinstance(element, LinearCoupling):
            factor = element.constant_factor()
            if factor is None:
                km, cm = (None if m is None else _matrix(m, sparse) for m in (element.K, element.C))
                scaled.append((km, cm, element.scale._spec()))
                continue
            kc = _add(kc, _times(element.K, factor))
            c = _add(c, _times(element.C, factor))
    k = system.K
    law = system.mass_law
    if kc is not None and (law is None or not law.scale_stiffness):
        k, kc = _add(k, kc), None
    return {
        "m": _matrix(system.M, sparse),
        "k": _matrix(k, sparse),
        "c": None if c is None else _matrix(c, sparse),
        "k_fixed": None if kc is None else _matrix(kc, sparse),
        "scaled": scaled,
        "sparse": sparse,
    }


def _to_scipy(spec: tuple | None, n: int) -> Any:
    if spec is None:
        return sp.csr_array((n, n))
    if spec[0] == "dense":
        return sp.csr_array(spec[1])
    _, n, indptr, indices, data = spec
    return sp.csr_array((data, indices, indptr), shape=(n, n))


def highest_frequency(
    system: System, mats: dict[str, Any], elements: list, x0: NDArray, v0: NDArray, t_end: float
) -> float:
    """``omega_max``: the square root of the largest eigenvalue magnitude of ``(K_t, M)``.

    ``K_t`` is the stiffness plus the linear couplings' and the elements' tangent stiffness at
    the initial state (a coupling scaled by a speed law counts with the largest magnitude of
    its law on the run); with a mass law, the part of it that does not scale with the mass is
    divided by the smallest ``mu`` over the run.
    """
    n = system.n_dof
    k = _to_scipy(mats["k"], n)
    rest = _to_scipy(mats["k_fixed"], n)
    for element in system.elements:
        if isinstance(element, LinearCoupling) and element.constant_factor() is None:
            if element.K is not None:
                # the speed laws are monotonic: the extremes are at the ends of the run
                worst = float(np.max(np.abs(element.scale.omega(np.array([0.0, t_end])))))
                rest = rest + worst * sp.csr_array(element.K)
    if elements:
        rows, cols, vals = _core.element_stiffness(elements, x0, v0, 0.0)
        rest = rest + sp.csr_array((vals, (rows, cols)), shape=(n, n))
    law = system.mass_law
    if law is not None:
        mu = float(np.min(law.law(np.linspace(0.0, t_end, 4097))))
        k = k if law.scale_stiffness else k / mu
        rest = rest / mu
    kt = (k + rest).tocsr()
    m = _to_scipy(mats["m"], n)
    symmetric = abs(kt - kt.T).max() <= 1e-12 * max(abs(kt).max(), 1e-300) if kt.nnz else True
    if n <= _DENSE_EIG_MAX_N or not mats["sparse"]:
        kd, md = kt.toarray(), m.toarray()
        if symmetric:
            lam = scipy.linalg.eigh(kd, md, eigvals_only=True, check_finite=False)
        else:
            lam = scipy.linalg.eigvals(kd, md, check_finite=False)
    elif symmetric:
        lam = spla.eigsh(kt, k=1, M=m.tocsc(), which="LM", return_eigenvectors=False, tol=1e-10)
    else:
        lam = spla.eigs(kt, k=1, M=m.tocsc(), which="LM", return_eigenvectors=False, tol=1e-10)
    return float(np.sqrt(np.max(np.abs(lam))))


def _check_central(
    system: System,
    mats: dict[str, Any],
    elements: list,
    x0: NDArray,
    v0: NDArray,
    dt: float,
    t_end: float,
) -> None:
    omega = highest_frequency(system, mats, elements, x0, v0, t_end)
    if omega == 0.0:
        return
    limit = 2.0 / omega
    if dt > limit * (1.0 + 1e-12):
        raise ValueError(
            f"`dt` = {dt:.6g} exceeds the stability limit of the central difference method, "
            f"2/omega_max = {limit:.6g} (highest natural frequency omega_max = {omega:.6g} "
            "rad/s); reduce `dt` or pass CentralDifference(allow_unstable=True)"
        )


def solve_direct(
    system: System,
    integrator: DirectIntegrator,
    *,
    dt: float,
    n_steps: int,
    x0: NDArray,
    v0: NDArray,
    save_every: int,
    out_dofs: NDArray,
    forcing: Any,
    started: float,
    loads: bool = True,
    a0: NDArray | None = None,
) -> Solution:
    """Runs a direct integrator; see :func:`duhamel.solve`. ``loads=False`` ignores the
    system's loads; `a0` overrides the initial acceleration (see :func:`step_matrix`)."""
    mats = physical_matrices(system)
    elements = [e._spec() for e in system.elements if not isinstance(e, LinearCoupling)]
    if isinstance(integrator, CentralDifference) and not integrator.allow_unstable:
        _check_central(system, mats, elements, x0, v0, dt, n_steps * dt)
    specs = []
    for load in system.loads if loads else []:
        if isinstance(load, Callable):
            continue
        for pattern, kind, params in load._specs(system):
            specs.append((np.ascontiguousarray(pattern, dtype=np.float64), kind, params))
    law = system.mass_law
    mass = None
    if law is not None:
        kind, params = law.law._spec()
        mass = (kind, params, law.form, law.scale_stiffness)
    loop_start = _time.perf_counter()
    raw = _core.solve_direct(
        mats["m"],
        mats["k"],
        np.ascontiguousarray(x0, dtype=np.float64),
        np.ascontiguousarray(v0, dtype=np.float64),
        specs,
        dt,
        n_steps,
        save_every,
        np.ascontiguousarray(out_dofs, dtype=np.int64),
        integrator._method(),
        float(integrator.tol),
        int(integrator.max_iter),
        c=mats["c"],
        k_fixed=mats["k_fixed"],
        scaled=mats["scaled"],
        elements=elements,
        mass=mass,
        forcing=forcing,
        a0=None if a0 is None else np.ascontiguousarray(a0, dtype=np.float64),
    )
    wall = _time.perf_counter() - loop_start
    err = raw["error"]
    stats = raw.get("stats", {})
    solution = Solution(
        t=raw["t"],
        x=raw["x"],
        v=raw["v"],
        a=raw["a"],
        dofs=np.asarray(out_dofs, dtype=np.int64),
        modal=None,
        stats=SolveStats(
            steps=n_steps if err is None else max(0, round(float(err["time"]) / dt) - 1),
            wall_time=wall,
            total_time=_time.perf_counter() - started,
            modes=0,
            newton_iterations=int(stats.get("newton_iterations", 0)),
            factorizations=int(stats.get("factorizations", 0)),
        ),
        meta={"dt": dt, "integrator": integrator},
    )
    if err is not None:
        raise SolverError(
            err["message"], time=float(err["time"]), reason=err["kind"], partial=solution
        )
    return solution


def step_matrix(system: System, integrator: DirectIntegrator, dt: float) -> NDArray[np.float64]:
    """The matrix of one step of a direct integrator on a linear system without loads,
    found by stepping unit states through the engine.

    The generalized-alpha methods carry the acceleration from step to step, so their state is
    ``(x, v, a)`` and the matrix is ``3 n x 3 n`` (the amplification matrix of Chung and
    Hulbert); the cubic Hermite element's state is ``(x, v)`` (``2 n x 2 n``).
    """
    if system.elements or system.mass_law is not None:
        raise ValueError("`system` must be linear (no elements, constant mass)")
    n = system.n_dof
    alpha = integrator._method()[0] == "alpha"
    size = (3 if alpha else 2) * n
    out = np.empty((size, size))
    dofs = np.arange(n)
    for j in range(size):
        e = np.zeros(size)
        e[j] = 1.0
        sol = solve_direct(
            system,
            integrator,
            dt=dt,
            n_steps=1,
            x0=e[:n],
            v0=e[n : 2 * n],
            save_every=1,
            out_dofs=dofs,
            forcing=None,
            started=_time.perf_counter(),
            loads=False,
            a0=e[2 * n :] if alpha else None,
        )
        parts = (sol.x[-1], sol.v[-1], sol.a[-1]) if alpha else (sol.x[-1], sol.v[-1])
        out[:, j] = np.concatenate(parts)
    return out
