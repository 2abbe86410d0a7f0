"""Banded solves of the dynamic stiffness: a rotor's finite-element matrices couple only
neighbouring nodes, so ``K - w^2 M + i w (C + w G)`` is banded (half-bandwidths of about 7
for 4 dofs per node); LAPACK's banded LU with partial pivoting (``gbsv``) then costs
``O(n b^2)`` per speed instead of ``O(n^3)``."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "banded_responses",
    "banded_solves",
    "bandwidths",
    "refined_banded_solves",
    "worth_banding",
]


def bandwidths(mats: tuple) -> tuple[int, int]:
    """Lower and upper half-bandwidths of the union of the patterns of `mats`."""
    pattern = np.zeros(np.asarray(mats[0]).shape, dtype=bool)
    for a in mats:
        pattern |= np.asarray(a) != 0.0
    i, j = np.nonzero(pattern)
    if i.size == 0:
        return 0, 0
    return int(max(0, (i - j).max())), int(max(0, (j - i).max()))


def worth_banding(n: int, lower: int, upper: int) -> bool:
    """Whether the banded solve beats the dense one (measured crossover: matrices of 128
    dofs and more whose band is at most a quarter of them)."""
    return n >= 128 and 4 * (lower + upper + 1) <= n


def banded_responses(
    mats: tuple, ws: NDArray[np.float64], F0: NDArray[np.complex128], lower: int, upper: int
) -> NDArray[np.complex128]:
    """``(K - w^2 M + i w (C + w G))^-1 w^2 F0`` for each speed of `ws` (LAPACK ``gbsv``)."""
    rhs = (ws * ws)[:, None, None] * F0[None, :, None]
    return banded_solves(mats, ws, ws, rhs, lower, upper)[..., 0]


def banded_solves(
    mats: tuple,
    ws: NDArray[np.float64],
    spins: NDArray[np.float64],
    rhs: NDArray[np.complex128],
    lower: int,
    upper: int,
) -> NDArray[np.complex128]:
    """``(K - w^2 M + i w (C + Omega G))^-1 rhs[s]`` for each frequency ``w = ws[s]`` and spin
    speed ``Omega = spins[s]`` (LAPACK ``gbsv``); `rhs` of shape ``(ws.size, n, n_rhs)``."""
    import scipy.linalg

    M, K, C, G = (np.asarray(a, dtype=float) for a in mats)
    n = M.shape[0]
    rows = lower + upper + 1
    # band storage: ab[upper + i - j, j] = A[i, j]
    offset = np.subtract.outer(np.arange(n), np.arange(n))  # i - j
    i, j = np.nonzero((offset <= lower) & (offset >= -upper))
    r = upper + i - j

    def band(a: NDArray) -> NDArray:
        out = np.zeros((rows, n))
        out[r, j] = a[i, j]
        return out

    Mb, Kb, Cb, Gb = band(M), band(K), band(C), band(G)
    out = np.empty(rhs.shape, dtype=complex)
    for s, (w, spin) in enumerate(zip(ws, spins, strict=True)):
        ab = Kb - w * w * Mb + 1j * w * (Cb + spin * Gb)
        try:
            out[s] = scipy.linalg.solve_banded(
                (lower, upper), ab, rhs[s], overwrite_ab=True, check_finite=False
            )
        except np.linalg.LinAlgError:
            raise ValueError(
                f"the dynamic stiffness is singular at {w:g} rad/s (an undamped resonance, or "
                "a rigid-body mode at speed 0): add damping or move the speeds off it"
            ) from None
    return out


def _band_matvec(ab: NDArray, x: NDArray, lower: int, upper: int) -> NDArray:
    """``A x`` from the band storage ``ab[upper + i - j, j] = A[i, j]`` (any dtype)."""
    n = ab.shape[1]
    y = np.zeros(x.shape, dtype=np.result_type(ab, x))
    for r in range(lower + upper + 1):
        d = r - upper  # i - j
        j0, j1 = max(0, -d), min(n, n - d)
        y[j0 + d : j1 + d] += ab[r, j0:j1, None] * x[j0:j1]
    return y


def refined_banded_solves(
    mats: tuple,
    ws: NDArray[np.float64],
    spins: NDArray[np.float64],
    B: NDArray[np.complex128],
    lower: int,
    upper: int,
) -> NDArray[np.complex128]:
    """``(K - w^2 M + i w (C + Omega G))^-1 B`` for each ``w = ws[s]``, ``Omega = spins[s]``
    by banded LU (LAPACK ``zgbtrf``/``zgbtrs``) and one step of iterative refinement with
    the residual in extended precision (``clongdouble``): the solution of the rounded
    dynamic stiffness to about round-off, not to its condition number times round-off."""
    from scipy.linalg.lapack import zgbtrf, zgbtrs

    M, K, C, G = (np.asarray(a, dtype=float) for a in mats)
    n = M.shape[0]
    rows = lower + upper + 1
    offset = np.subtract.outer(np.arange(n), np.arange(n))  # i - j
    i, j = np.nonzero((offset <= lower) & (offset >= -upper))
    r = upper + i - j

    def band(a: NDArray) -> NDArray:
        out = np.zeros((rows, n))
        out[r, j] = a[i, j]
        return out

    Mb, Kb, Cb, Gb = band(M), band(K), band(C), band(G)
    Bl = B.astype(np.clongdouble)
    out = np.empty((ws.size, *B.shape), dtype=complex)
    work = np.zeros((2 * lower + upper + 1, n), dtype=complex)
    for s, (w, spin) in enumerate(zip(ws, spins, strict=True)):
        ab = Kb - w * w * Mb + 1j * w * (Cb + spin * Gb)
        work[:lower] = 0.0
        work[lower:] = ab
        lu, piv, info = zgbtrf(work, lower, upper)
        if info > 0:
            raise ValueError(
                f"the dynamic stiffness is singular at {w:g} rad/s (an undamped resonance, or "
                "a rigid-body mode at zero frequency): add damping or move the frequencies off it"
            )
        x, _ = zgbtrs(lu, lower, upper, B, piv)
        res = Bl - _band_matvec(ab.astype(np.clongdouble), x.astype(np.clongdouble), lower, upper)
        dx, _ = zgbtrs(lu, lower, upper, res.astype(complex), piv)
        out[s] = x + dx
    return out
