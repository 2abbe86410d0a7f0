"""The Python side of the direct integrators: physical matrices, loads and the run."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel import _core
from duhamel._engine.eigen import DENSE_EIGH_ARRAYS
from duhamel._engine.memory import check_fits
from duhamel._engine.run import callback_error
from duhamel._engine.validate import issparse
from duhamel.couplings import LinearCoupling
from duhamel.feedback import Feedback
from duhamel.results.solution import Solution, SolveStats
from duhamel.system import System

#: Dense ``n x n`` arrays a direct run with modal damping ratios holds besides the
#: eigendecomposition: the damping matrix, ``M Phi``, and M, K, C densified for the core (the
#: peak resident memory of a whole run measured 10.6 and 11.4 of them at n = 1,500 and 3,000).
_MODAL_DAMPING_ARRAYS = 6

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
    n = system.n_dof
    check_fits(
        (DENSE_EIGH_ARRAYS + _MODAL_DAMPING_ARRAYS) * 8.0 * n * n,
        f"`zeta` (modal damping ratios) on a direct integrator forms the damping matrix "
        f"M Phi diag(2 zeta omega) Phi^T M from every mode: for the {n:,}-dof model a full "
        f"dense eigendecomposition and dense {n:,} x {n:,} matrices, which",
        "use Rayleigh damping (`rayleigh=(alpha, beta)`, or duhamel.Rayleigh.from_periods), "
        "which keeps the direct route sparse, or duhamel.Semianalytic(modes=...), which damps "
        "each mode by its ratio without forming C",
    )
    basis = system.modal(None)
    mphi = np.asarray(system.M @ basis.phi)
    return (mphi * basis.c) @ mphi.T


def _add(a: Any, b: Any) -> Any:
    if a is None:
        return b
    if b is None:
        return a
    if issparse(a) or issparse(b):
        import scipy.sparse as sp

        return sp.csr_array(a) + sp.csr_array(b)
    return np.asarray(a) + np.asarray(b)


def _times(m: Any, factor: float) -> Any:
    return m if m is None or factor == 1.0 else factor * m


def physical_matrices(system: System) -> dict[str, Any]:
    """M, K, C, the stiffness that does not scale with a mass law, and the couplings scaled
    by a time-varying speed law (``(K, C, speed law)``), as numpy or scipy.sparse matrices;
    ``sparse`` says whether the core gets them sparse
    (:func:`duhamel._engine.dispatch.matrices`)."""
    # Modal damping ratios give a full C: everything is then dense.
    sparse = system.is_sparse and system.damping != "zeta"
    c = damping_matrix(system)
    kc = None
    scaled = []
    for element in system.elements:
        if isinstance(element, Feedback):
            raise ValueError(
                "the system has feedback states (duhamel.feedback.Feedback: controllers): the "
                "direct integrators step second-order equations only; use duhamel.Semianalytic()"
            )
        if isinstance(element, LinearCoupling):
            factor = element.constant_factor()
            if factor is None:
                scaled.append((element.K, element.C, element.scale))
                continue
            kc = _add(kc, _times(element.K, factor))
            c = _add(c, _times(element.C, factor))
    k = system.K
    law = system.mass_law
    if kc is not None and (law is None or not law.scale_stiffness):
        k, kc = _add(k, kc), None
    return {"m": system.M, "k": k, "c": c, "k_fixed": kc, "scaled": scaled, "sparse": sparse}


def _to_scipy(m: Any, n: int) -> Any:
    import scipy.sparse as sp

    return sp.csr_array((n, n)) if m is None else sp.csr_array(m)


def highest_frequency(
    system: System,
    mats: dict[str, Any],
    elements: list,
    x0: NDArray,
    v0: NDArray,
    t_span: tuple[float, float],
) -> float:
    """``omega_max``: the square root of the largest eigenvalue magnitude of ``(K_t, M)``.

    ``K_t`` is the stiffness plus the linear couplings' and the elements' tangent stiffness at
    the initial state (a coupling scaled by a speed law counts with the largest magnitude of
    its law on the run); with a mass law, the part of it that does not scale with the mass is
    divided by the smallest ``mu`` over the run.
    """
    import scipy.linalg
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    n = system.n_dof
    t0, t_end = t_span
    k = _to_scipy(mats["k"], n)
    rest = _to_scipy(mats["k_fixed"], n)
    for element in system.elements:
        if isinstance(element, LinearCoupling) and element.constant_factor() is None:
            if element.K is not None:
                # the speed laws are monotonic: the extremes are at the ends of the run
                worst = float(np.max(np.abs(element.scale.omega(np.array([t0, t_end])))))
                rest = rest + worst * sp.csr_array(element.K)
    if elements:
        try:
            rows, cols, vals = _core.element_stiffness(elements, x0, v0, t0)
        except Exception as exc:  # a Python element function failed on the initial state
            empty = Solution(
                t=np.empty(0),
                x=np.empty((0, 0)),
                v=np.empty((0, 0)),
                a=np.empty((0, 0)),
                dofs=np.empty(0, dtype=np.int64),
                modal=None,
                stats=SolveStats(steps=0, wall_time=0.0, total_time=0.0, modes=0),
            )
            raise callback_error(f"{type(exc).__name__}: {exc}", t0, 0, empty) from exc
        rest = rest + sp.csr_array((vals, (rows, cols)), shape=(n, n))
    law = system.mass_law
    if law is not None:
        mu = float(np.min(law.law(np.linspace(t0, t_end, 4097))))
        if not (np.isfinite(mu) and mu > 0.0):
            # the law reaches 0 on the run: the engine refuses it with its own message
            return 0.0
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
    t_span: tuple[float, float],
) -> None:
    import numpy.linalg
    import scipy.sparse.linalg as spla

    try:
        omega = highest_frequency(system, mats, elements, x0, v0, t_span)
    except (numpy.linalg.LinAlgError, spla.ArpackError, ValueError) as exc:
        if isinstance(exc, ValueError) and str(exc).startswith("`"):
            raise  # our own, naming its parameter
        raise ValueError(
            "the stability limit of the central difference method cannot be computed for "
            f"this `M` and `K` ({type(exc).__name__}: {exc}); their scales are beyond what "
            "double precision can analyse: rescale the model's units, or pass "
            "CentralDifference(allow_unstable=True)"
        ) from None
    if not np.isfinite(omega):
        raise ValueError(
            "the highest natural frequency of this `M` and `K` overflows the double range; "
            "rescale the model's units"
        )
    if omega == 0.0:
        return
    limit = 2.0 / omega
    if dt > limit * (1.0 + 1e-12):
        raise ValueError(
            f"`dt` = {dt:.6g} exceeds the stability limit of the central difference method, "
            f"2/omega_max = {limit:.6g} (highest natural frequency omega_max = {omega:.6g} "
            "rad/s); reduce `dt` or pass CentralDifference(allow_unstable=True)"
        )
