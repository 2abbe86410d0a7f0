"""Type stub of the native module ``duhamel._core`` (Rust, PyO3)."""

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__version__: str

def transfer(
    omega: NDArray[np.float64], zeta: NDArray[np.float64], dt: float, moments: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Exact ``A`` (n, 2, 2) and ``B`` (n, 2, 3) — or moments (n, 2, 4) — from natural
    frequencies ``omega`` and damping ratios ``zeta``."""

def transfer_kc(
    k: NDArray[np.float64], c: NDArray[np.float64], dt: float, moments: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """As :func:`transfer`, from modal stiffness ``k = omega^2`` and damping ``c``."""

def solve_linear(
    k: NDArray[np.float64],
    c: NDArray[np.float64],
    q0: NDArray[np.float64],
    v0: NDArray[np.float64],
    loads: Sequence[tuple[NDArray[np.float64], str, tuple[Any, ...]]],
    dt: float,
    n_steps: int,
    save_every: int,
    threads: int | None = None,
    forcing: Callable[[float], NDArray[np.float64]] | None = None,
    phi_t: NDArray[np.float64] | None = None,
) -> dict[str, Any]:
    """Exact modal time loop; returns ``t``, time-major ``q`` and ``v``, ``load_values``,
    ``forcing`` and ``error``."""

def solve_direct(
    m: tuple[Any, ...],
    k: tuple[Any, ...],
    x0: NDArray[np.float64],
    v0: NDArray[np.float64],
    loads: Sequence[tuple[NDArray[np.float64], str, tuple[Any, ...]]],
    dt: float,
    n_steps: int,
    save_every: int,
    out_dofs: NDArray[np.int64],
    method: tuple[Any, ...],
    tol: float,
    max_iter: int,
    c: tuple[Any, ...] | None = None,
    k_fixed: tuple[Any, ...] | None = None,
    elements: Sequence[tuple[Any, ...]] | None = None,
    mass: tuple[Any, ...] | None = None,
    forcing: Callable[[float], NDArray[np.float64]] | None = None,
    a0: NDArray[np.float64] | None = None,
    scaled: Sequence[tuple[Any, Any, tuple[str, tuple[float, ...]]]] | None = None,
) -> dict[str, Any]:
    """Direct integration of the physical equations. Matrices are ``("dense", array)`` or
    ``("csr", n, indptr, indices, data)``; `method` is ``("alpha", alpha_m, alpha_f, gamma,
    beta)`` or ``("hermite", points)``; `scaled` lists ``(K spec or None, C spec or None,
    speed law spec)`` couplings multiplied by a speed law. Returns ``t``, time-major ``x``,
    ``v``, ``a`` for `out_dofs`, ``error`` and ``stats`` (``newton_iterations``,
    ``factorizations``)."""

def element_stiffness(
    elements: Sequence[tuple[Any, ...]],
    x: NDArray[np.float64],
    v: NDArray[np.float64],
    t: float,
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """The elements' tangent stiffness ``dr/dx`` at ``(x, v, t)`` as COO triplets."""

def solve_nonlinear(
    k: NDArray[np.float64],
    c: NDArray[np.float64],
    q0: NDArray[np.float64],
    v0: NDArray[np.float64],
    loads: Sequence[tuple[NDArray[np.float64], str, tuple[Any, ...]]],
    dt: float,
    n_steps: int,
    save_every: int,
    phi: NDArray[np.float64],
    elements: Sequence[tuple[Any, ...]],
    options: tuple[Any, ...],
    coupling_k: NDArray[np.float64] | None = None,
    coupling_c: NDArray[np.float64] | None = None,
    mass: tuple[Any, ...] | None = None,
    forcing: Callable[[float], NDArray[np.float64]] | None = None,
    phi_t: NDArray[np.float64] | None = None,
    scaled: Sequence[tuple[Any, Any, tuple[str, tuple[float, ...]]]] | None = None,
) -> dict[str, Any]:
    """Nonlinear semi-analytic loop; `scaled` lists ``(modal K or None, modal C or None,
    speed law spec)`` couplings multiplied by a speed law. Returns the dict of
    :func:`solve_linear` with ``pseudo`` and ``stats``."""

def speed_law(
    spec: tuple[str, tuple[float, ...]], t: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """``(omega, omega', theta)`` of the speed law ``("constant", (omega,))`` or
    ``("runup", (omega0, omega1, t1))`` at times `t`."""

def time_function(
    kind: str, params: tuple[Any, ...], t: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The engine's time function of a load spec at times `t` (right limits at jumps)."""
