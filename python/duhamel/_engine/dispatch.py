"""The one path from a model to the core: a planned route becomes a typed
``_core.ModalModel`` (or ``_core.DirectModel``), a run's options a ``_core.RunSpec`` (or
``_core.DirectRun``) on a ``_core.Grid``.

:func:`duhamel.prepare`, :func:`duhamel.solve` (through it) and the streaming store
(``duhamel.store``) build the core's inputs here and nowhere else; every value is checked
once, by the class that takes it (``duhamel-py``), so a mismatch between the two languages
is a ``TypeError`` at the call, never an attribute missed at run time.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel import _core
from duhamel._engine.plan import Plan, ScaledSpec
from duhamel._engine.validate import issparse

__all__ = [
    "direct_model",
    "direct_run",
    "eta0",
    "grid",
    "matrices",
    "matrix",
    "modal_model",
    "options",
    "outputs",
    "run_spec",
    "scaled",
]


def _c(a: Any) -> NDArray[np.float64]:
    return np.ascontiguousarray(a, dtype=np.float64)


def _dense(a: Any) -> Any:
    """A dense ``_core.Matrix`` of `a`, or None."""
    return None if a is None else _core.Matrix.dense(_c(a))


def growth_limit(route: Plan | None, integrator: Any) -> float | None:
    """The growth guard's limit of a run: the integrator's, when the route's pseudo-forces are
    passive (``Plan.passive``; otherwise, or without a route, the guard's bound does not
    hold: None)."""
    return integrator.growth_limit if route is not None and route.passive else None


def options(integrator: Any, route: Plan | None = None) -> Any:
    """The step-equation settings of a :class:`duhamel.Semianalytic` on `route` (None: no
    growth guard)."""
    return _core.Options(
        integrator.scheme,
        integrator.quadrature,
        float(integrator.tol),
        int(integrator.max_iter),
        integrator.solver,
        int(integrator.subdivisions),
        growth_limit(route, integrator),
    )


def scaled(specs: list[ScaledSpec]) -> list[Any]:
    """Couplings scaled by a speed law (modal or physical matrices) as the core takes them."""
    return [_core.ScaledCoupling(_dense(s.k), _dense(s.c), s.law) for s in specs]


def modal_model(route: Plan, loads: list[Any], integrator: Any, mass: Any) -> Any:
    """The core's model of a planned modal run: its background, its route's corrector, and
    its default `loads` (``_core.Load``s with modal patterns); `mass` is a ``_core.Mass`` or
    None."""
    basis = route.basis
    core_route: Any = None
    if route.route == "first-order":
        fo = route.modes
        assert fo is not None
        corrector = None
        if route.elements:
            corrector = _core.Corrector(
                route.elements,
                _c(fo.back),
                float(integrator.tol),
                int(integrator.max_iter),
                growth_limit(route, integrator),
            )
        core_route = _core.FirstOrderRoute(
            _c(fo.lam.real), _c(fo.lam.imag), _c(fo.gain.real), _c(fo.gain.imag), corrector
        )
    elif route.route == "pseudo-force":
        c = route.couplings
        core_route = _core.PseudoForceRoute(
            route.elements,
            options(integrator, route),
            _dense(c.k),
            _dense(c.c),
            scaled(c.scaled),
            mass,
        )
    return _core.ModalModel(_c(basis.omega2), _c(basis.c), _c(basis.phi), loads, core_route)


def grid(
    t0: float, dt: float, n_steps: int, save_every: int, step0: int = 0, threads: int | None = None
) -> Any:
    """The time grid of a run."""
    return _core.Grid(t0, dt, n_steps, save_every, step0, threads)


def eta0(route: Plan, q0: NDArray, v0: NDArray) -> NDArray[np.float64]:
    """The first-order coordinates ``Re | Im`` of the modal state ``(q0, v0)``."""
    assert route.modes is not None
    eta = route.modes.initial(q0, v0)
    return np.concatenate([eta.real, eta.imag])


def run_spec(
    route: Plan,
    run_grid: Any,
    state: tuple[NDArray, NDArray],
    element_state: NDArray | None = None,
    eta: NDArray | None = None,
    guard_state: NDArray | None = None,
    energy: Any = None,
) -> Any:
    """One run from the modal `state` ``(q0, v0)``; on the first-order route from `eta`
    (``Re | Im``, computed from the state when None); a continued run's growth guard from
    `guard_state` (the run before's ``RunResult.guard_state``); the energy integrals to
    accumulate, `energy` (a ``_core.EnergySpec``, :mod:`duhamel._engine.energy_run`)."""
    q0, v0 = state
    if route.route == "first-order" and eta is None:
        eta = eta0(route, q0, v0)
    return _core.RunSpec(
        run_grid,
        q0,
        v0,
        None if eta is None else _c(eta),
        None if element_state is None else _c(element_state),
        None if guard_state is None else _c(guard_state),
        energy,
    )


def outputs(route: Plan, phi_out: NDArray, n_loads: int) -> Any:
    """What the engine maps during a first-order run: ``[x | v]`` of the output dofs from
    ``[Re eta | Im eta]`` (the loads add nothing to them); None on the other routes."""
    if route.route != "first-order":
        return None
    modes = route.modes
    assert modes is not None
    m = route.basis.n_modes
    tq, tv = modes.back[:, :m], modes.back[:, m:]
    out_map = np.ascontiguousarray(np.concatenate([tq @ phi_out.T, tv @ phi_out.T], axis=1))
    return _core.Outputs(out_map, np.zeros((n_loads, out_map.shape[1])), out_map.shape[1])


def matrix(m: Any, sparse: bool) -> Any:
    """A matrix as the core takes it (a ``_core.Matrix``: CSR when `sparse`, else dense)."""
    if sparse:
        import scipy.sparse as sp

        c = sp.csr_array(m, dtype=np.float64)
        c.sum_duplicates()
        return _core.Matrix.csr(
            int(c.shape[0]),
            np.ascontiguousarray(c.indptr, dtype=np.int64),
            np.ascontiguousarray(c.indices, dtype=np.int64),
            np.ascontiguousarray(c.data, dtype=np.float64),
        )
    dense = m.toarray() if issparse(m) else np.asarray(m)
    return _core.Matrix.dense(np.ascontiguousarray(dense, dtype=np.float64))


def matrices(mats: dict[str, Any]) -> Any:
    """The physical matrices of :func:`duhamel._engine.direct.physical_matrices` as the core
    takes them (``_core.Matrices``)."""
    sparse = mats["sparse"]
    m, k, c, k_fixed = (
        None if mats[key] is None else matrix(mats[key], sparse)
        for key in ("m", "k", "c", "k_fixed")
    )
    scaled = [
        _core.ScaledCoupling(
            None if ks is None else matrix(ks, sparse),
            None if cs is None else matrix(cs, sparse),
            law._law(),
        )
        for ks, cs, law in mats["scaled"]
    ]
    return _core.Matrices(m, k, c, k_fixed, scaled)


def direct_model(mats: dict[str, Any], elements: list[Any], mass: Any, integrator: Any) -> Any:
    """The core's model of a direct integrator's runs (``_core.DirectModel``)."""
    return _core.DirectModel(
        matrices(mats),
        elements,
        mass,
        integrator._method(),
        float(integrator.tol),
        int(integrator.max_iter),
    )


def direct_run(
    run_grid: Any, x0: NDArray, v0: NDArray, dofs: NDArray, a0: NDArray | None = None,
    energy: Any = None,
) -> Any:  # fmt: skip
    """One direct run from `x0`, `v0` (and `a0`), keeping the dofs `dofs`; `energy` the
    integrals to accumulate (a ``_core.EnergySpec``)."""
    return _core.DirectRun(
        run_grid, _c(x0), _c(v0), np.ascontiguousarray(dofs, dtype=np.int64),
        None if a0 is None else _c(a0), energy,
    )  # fmt: skip
