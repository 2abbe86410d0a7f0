"""The rotor's structural damping: Rayleigh, or modal from the undamped modes, or none."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float

__all__ = ["damping_spec", "structural_damping"]

#: Structural damping as given: a modal damping ratio (one, or one per mode) and Rayleigh's
#: ``(alpha, beta)``, at most one of them not None.
DampingSpec = tuple["float | NDArray[np.float64] | None", "tuple[float, float] | None"]


def damping_spec(
    zeta: float | ArrayLike | None, rayleigh: tuple[float, float] | None, n_dof: int
) -> DampingSpec:
    """Check a rotor's `zeta` (one value, or one per mode: `n_dof` values) and `rayleigh`
    (``(alpha, beta)``), at most one given.

    Examples
    --------
    >>> from duhamel.rotor.damping import damping_spec
    >>> damping_spec(0.02, None, n_dof=8), damping_spec(None, (0.0, 1e-5), n_dof=8)
    ((0.02, None), (None, (0.0, 1e-05)))
    """
    if zeta is not None and rayleigh is not None:
        raise ValueError("give at most one of `zeta` and `rayleigh`")
    z: float | NDArray[np.float64] | None = None
    r: tuple[float, float] | None = None
    if zeta is not None:
        if np.ndim(zeta) == 0:
            z = finite_float(zeta, "zeta")
        else:
            z = as_float_array(zeta, "zeta", ndim=1)
            if z.size != n_dof:
                raise ValueError(
                    f"`zeta` must be one value or one per mode (n_dof = {n_dof}), got {z.size}"
                )
    if rayleigh is not None:
        a, b = as_float_array(rayleigh, "rayleigh", shape=(2,)).tolist()
        r = (a, b)
    return z, r


def structural_damping(
    M: NDArray[np.float64],
    k_sym: NDArray[np.float64],
    *,
    zeta: float | NDArray[np.float64] | None = None,
    rayleigh: tuple[float, float] | None = None,
    massless_nodes: list[int] | None = None,
) -> NDArray[np.float64]:
    """``alpha M + beta K_sym``, or ``M Phi diag(2 zeta omega) Phi^T M`` from the
    mass-normalised undamped modes of ``(K_sym, M)`` (rigid-body modes get none), or zero.

    Parameters
    ----------
    M, k_sym : ndarray, shape (n, n)
        Mass and symmetric stiffness.
    zeta : float or ndarray, optional
        Keyword only. Modal damping ratio (one, or one per mode).
    rayleigh : (float, float), optional
        Keyword only. ``(alpha, beta)``; takes precedence over `zeta`.
    massless_nodes : list of int, optional
        Keyword only. Nodes without mass, which modal damping cannot handle (named in the
        error).

    Returns
    -------
    ndarray, shape (n, n)

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.rotor.damping import structural_damping
    >>> C = structural_damping(np.eye(2), np.diag([1.0, 4.0]), zeta=0.1)
    >>> np.round(C, 12).tolist()
    [[0.2, 0.0], [0.0, 0.4]]
    """
    if rayleigh is not None:
        a, b = rayleigh
        return a * M + b * k_sym
    if zeta is not None:
        if massless_nodes:
            raise ValueError(
                "modal damping `zeta` needs mass at every node; the rotor has massless "
                f"nodes {massless_nodes} (use `rayleigh` or give them mass)"
            )
        import scipy.linalg

        try:
            lam, phi = scipy.linalg.eigh(k_sym, M)
        except (np.linalg.LinAlgError, ValueError) as exc:
            raise ValueError(
                f"the rotor's modes for its modal damping `zeta` cannot be computed "
                f"({type(exc).__name__}: {exc}): its shaft, disk and bearing values are beyond "
                "what double precision can analyse (check `bearings` and the shafts' units)"
            ) from None
        scale = max(float(np.max(np.abs(lam))), 1.0)
        omega = np.sqrt(np.where(lam > 1e-12 * scale, lam, 0.0))
        mphi = M @ phi
        return (mphi * (2.0 * np.asarray(zeta) * omega)) @ mphi.T
    return np.zeros_like(M)
