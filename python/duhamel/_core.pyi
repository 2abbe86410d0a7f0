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
