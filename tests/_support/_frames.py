"""A plane moment frame with lumped storey masses and massless joint rotations (tests)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def moment_frame(
    storeys: int = 3, bays: int = 2, *, h: float = 3.2, span: float = 6.0
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """``(M, K, sway)`` of a frame with axially rigid members: per storey one sway dof (the
    storey mass) and one rotation per column line (massless), assembled from Euler-Bernoulli
    beam-column stiffnesses. `sway` lists the sway dofs. Dof order: storey by storey,
    ``[u, theta_0, ..., theta_bays]``."""
    ei_c, ei_b, mass = 8.0e7, 1.2e8, 6.0e4
    per = bays + 2
    n = storeys * per
    K = np.zeros((n, n))

    def u(s: int) -> int | None:  # sway dof of floor s (floor 0 is the ground)
        return None if s == 0 else (s - 1) * per

    def th(s: int, c: int) -> int | None:
        return None if s == 0 else (s - 1) * per + 1 + c

    def add(dofs: list[int | None], k: NDArray) -> None:
        for a, i in enumerate(dofs):
            for b, j in enumerate(dofs):
                if i is not None and j is not None:
                    K[i, j] += k[a, b]

    col = (
        ei_c
        / h**3
        * np.array(
            [
                [12.0, 6 * h, -12.0, 6 * h],
                [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                [-12.0, -6 * h, 12.0, -6 * h],
                [6 * h, 2 * h * h, -6 * h, 4 * h * h],
            ]
        )
    )
    beam = ei_b / span * np.array([[4.0, 2.0], [2.0, 4.0]])
    for s in range(1, storeys + 1):
        for c in range(bays + 1):
            add([u(s - 1), th(s - 1, c), u(s), th(s, c)], col)
        for b in range(bays):
            add([th(s, b), th(s, b + 1)], beam)
    sway = np.arange(0, n, per)
    M = np.zeros((n, n))
    M[sway, sway] = mass
    return M, K, sway


def condensed(M: NDArray, K: NDArray) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """``(M_mm, K_c, T, m)``: the exactly condensed model, formed independently of the
    library (``T = [I; -K_ss^-1 K_sm]`` in the original dof order)."""
    m = np.flatnonzero(np.diag(M) > 0)
    s = np.flatnonzero(np.diag(M) == 0)
    K_ss, K_sm = K[np.ix_(s, s)], K[np.ix_(s, m)]
    T = np.zeros((M.shape[0], m.size))
    T[m] = np.eye(m.size)
    T[s] = -np.linalg.solve(K_ss, K_sm)
    return M[np.ix_(m, m)], T.T @ K @ T, T, m
