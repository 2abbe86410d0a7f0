"""Stability judged against round-off: an eigenvalue's computed real part is trusted only
beyond the error the eigensolver can make in it.

For a matrix ``A`` (balanced first, ``scipy.linalg.matrix_balance``), a computed eigenvalue
is the exact one of ``A + E`` with ``|E| ~ eps |A|``, so it moves by about
``eps |A| kappa`` (first order; ``kappa = |y| |x| / |y^H x|`` its condition number from the
left and right eigenvectors ``y``, ``x``; Wilkinson). An eigenvalue whose real part lies
within :data:`SAFETY` times that bound of zero cannot be told from a marginal one (a
rigid-body mode the bearings hold with zero net stiffness has a zero eigenvalue that the
solver returns as ``+-1e-5 1/s``); beyond it the real part is the model's.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["SAFETY", "Spectrum", "spectrum"]

#: The bound's safety factor over the first-order estimate ``eps |A| kappa``.
SAFETY = 10.0


class Spectrum:
    """Eigenvalues of a matrix with the round-off bound of each (see the module docstring).

    Attributes
    ----------
    eigenvalues : ndarray of complex
    bounds : ndarray
        ``SAFETY eps |A_b|_2 kappa`` per eigenvalue (1/s for a state matrix).
    """

    def __init__(self, eigenvalues: NDArray[np.complex128], bounds: NDArray[np.float64]):
        self.eigenvalues = eigenvalues
        self.bounds = bounds

    @property
    def growing(self) -> NDArray[np.bool_]:
        """Eigenvalues whose real part is positive beyond round-off."""
        return self.eigenvalues.real > self.bounds

    @property
    def marginal(self) -> NDArray[np.bool_]:
        """Eigenvalues whose real part is zero to round-off."""
        return np.abs(self.eigenvalues.real) <= self.bounds

    @property
    def verdict(self) -> str:
        """``"unstable"`` (a growing eigenvalue), ``"marginal"`` (none growing, some on the
        imaginary axis to round-off) or ``"stable"``."""
        if np.any(self.growing):
            return "unstable"
        return "marginal" if np.any(self.marginal) else "stable"

    def describe(self) -> str:
        """One sentence on the verdict, naming the eigenvalues behind it."""
        lam, b = self.eigenvalues, self.bounds
        if self.verdict == "unstable":
            k = int(np.argmax(np.where(self.growing, lam.real, -np.inf)))
            return (
                f"unstable: {int(self.growing.sum())} eigenvalue(s) grow, the fastest "
                f"{lam[k]:.6g} (real part {lam[k].real:.3g} 1/s, round-off bound {b[k]:.2g})"
            )
        if self.verdict == "marginal":
            on = self.marginal
            k = int(np.argmax(np.where(on, lam.real, -np.inf)))
            return (
                f"marginal: {int(on.sum())} eigenvalue(s) have a real part that is zero to "
                f"round-off (largest {lam[k].real:+.3g} 1/s within the bound {b[k]:.2g} 1/s): "
                "motions the loop holds with zero net stiffness (rigid-body modes), neither "
                "growing nor decaying"
            )
        k = int(np.argmax(lam.real))
        return f"stable: the slowest decay is {lam[k].real:.4g} 1/s (bound {b[k]:.2g})"


def spectrum(A: NDArray[np.float64]) -> Spectrum:
    """The eigenvalues of `A` with their round-off bounds.

    Examples
    --------
    A free mass held by a damper only (``x'' = -x'``: eigenvalues 0 and -1):

    >>> import numpy as np
    >>> from duhamel.rotor._roundoff import spectrum
    >>> s = spectrum(np.array([[0.0, 1.0], [0.0, -1.0]]))
    >>> s.verdict, sorted(s.eigenvalues.real.tolist())
    ('marginal', [-1.0, 0.0])
    """
    import scipy.linalg

    _, (scale, _) = scipy.linalg.matrix_balance(A, permute=False, separate=True)
    Ab = A * scale[None, :] / scale[:, None]
    lam, left, right = scipy.linalg.eig(Ab, left=True, right=True, check_finite=False)
    overlap = np.abs(np.sum(left.conj() * right, axis=0))
    size = np.linalg.norm(left, axis=0) * np.linalg.norm(right, axis=0)
    with np.errstate(divide="ignore"):
        kappa = np.where(overlap > 0.0, size / overlap, np.inf)
    norm = float(np.linalg.norm(Ab, 2)) if Ab.shape[0] <= 1000 else float(np.linalg.norm(Ab))
    return Spectrum(lam, SAFETY * np.finfo(float).eps * norm * kappa)
