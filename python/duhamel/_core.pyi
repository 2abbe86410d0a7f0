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
) -> dict[str, Any]:
    """Direct integration of the physical equations. Matrices are ``("dense", array)`` or
    ``("csr", n, indptr, indices, data)``; `method` is ``("alpha", alpha_m, alpha_f, gamma,
    beta)`` or ``("hermite", points)``. Returns ``t``, time-major ``x``, ``v``, ``a`` for
    `out_dofs`, ``error`` and ``stats`` (``newton_iterations``, ``factorizations``)."""

def element_stiffness(
    elements: Sequence[tuple[Any, ...]],
    x: NDArray[np.float64],
    v: NDArray[np.float64],
    t: float,
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """The elements' tangent stiffness ``dr/dx`` at ``(x, v, t)`` as COO triplets."""
